"""The Python API review (2026-11-29): narrow bounds around an optimum, refine's max_steps,
swapped arguments, raw errors, labels of fits with fixed values, n_starts, short reprs and the
smaller items. REAL data: impedance.py's example files (tests/fixtures/real, MIT)."""

from __future__ import annotations

import csv
import json
import math
import pathlib

import numpy as np
import pytest
import xarray as xr
from scipy.optimize import least_squares

import impedax as ix
from impedax.errors import CircuitError, DataError, ParameterError

REAL = pathlib.Path(__file__).parent / "fixtures" / "real"
MODEL = "R0 + R1 || CPE1"


@pytest.fixture(scope="module")
def biologic():
    return ix.load(REAL / "exampleDataBioLogic.mpt")


@pytest.fixture(scope="module")
def free_fit(biologic):
    return ix.fit(MODEL, biologic)


@pytest.fixture(scope="module")
def bounded_fit(biologic):
    """``bounded_fit(bounds)``: the fit of `MODEL` to the BioLogic file within ``bounds``, each
    computed once per module (several tests read the same bounded fits; none changes them)."""
    fits = {}

    def fit_within(bounds):
        key = tuple(sorted(bounds.items()))
        if key not in fits:
            fits[key] = ix.fit(MODEL, biologic, bounds=bounds)
        return fits[key]

    return fit_within


@pytest.fixture(scope="module")
def alpha_held_at_1(biologic):
    """`MODEL` fitted with CPE1.alpha fixed at 1 (read by the label and notebook-display tests)."""
    return ix.fit(MODEL, biologic, fixed={"CPE1.alpha": 1})


# ---------------------------------------------------------------- the oracle: R0 + R1 || CPE1 in numpy


def _z_rcpe(p, f):
    r0, r1, q, alpha = p
    return r0 + 1.0 / (1.0 / r1 + q * (2j * np.pi * f) ** alpha)


def _residuals(p, f, z):
    """Modulus weighting, as impedax's default: both parts over |Z_data|."""
    d = (_z_rcpe(p, f) - z) / np.abs(z)
    return np.concatenate([d.real, d.imag])


def _scipy_fit(data, bounds, start):
    """scipy's trust-region reflective least squares with the same bounds (an independent
    solver: no log or logistic coordinates)."""
    f, z = data["frequency"].values, data["Z"].values
    names = ["R0", "R1", "CPE1.Q", "CPE1.alpha"]
    natural = {"R0": (0, np.inf), "R1": (0, np.inf), "CPE1.Q": (0, np.inf), "CPE1.alpha": (0, 1)}
    natural.update(bounds)
    lo, hi = np.array([natural[n][0] for n in names]), np.array([natural[n][1] for n in names])
    x0 = np.clip(np.array([start[n] for n in names]), lo, np.where(np.isfinite(hi), hi * (1 - 1e-9), np.inf))
    out = least_squares(_residuals, x0, bounds=(lo, hi), args=(f, z), x_scale="jac", xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=20000)
    return dict(zip(names, out.x)), float(np.sum(out.fun**2))


# ---------------------------------------------------------------- 1. narrow bounds around the optimum


@pytest.mark.parametrize("bounds", [{"R0": (63.0, 64.0)}, {"CPE1.Q": (0.008368, 0.01023)}])
def test_narrow_bounds_around_the_optimum_give_the_free_optimum(biologic, free_fit, bounded_fit, bounds):
    """The data-driven guess lay outside these bounds (R0 65.5 > 64, Q 0.01027 > 0.01023) and
    was clipped to 1e-6 below the upper bound, where the solver's logistic coordinate is flat:
    the fit stopped there, "converged" and "at its upper bound", χ² 3 % and 8.8 % above the
    optimum that lies inside the bounds."""
    r = bounded_fit(bounds)
    assert r.converged and r.at_bound == ()
    assert r.chi2 == pytest.approx(free_fit.chi2, rel=1e-7)
    for n, v in free_fit.values.items():
        assert r.values[n] == pytest.approx(v, rel=1e-4)
    # the oracle: scipy with the same bounds, started from the same clipped corner
    corner = {**free_fit.values, **{n: hi * (1 - 1e-6) for n, (lo, hi) in bounds.items()}}
    values, chi2 = _scipy_fit(biologic, bounds, corner)
    assert r.chi2 <= chi2 * (1 + 1e-7)
    for n, v in values.items():
        assert r.values[n] == pytest.approx(v, rel=1e-3)


def test_an_exponent_bounded_around_its_optimum_is_not_reported_at_its_bound():
    data = ix.load(REAL / "exampleData.csv")
    free = ix.fit(MODEL, data)
    a = free.values["CPE1.alpha"]
    r = ix.fit(MODEL, data, bounds={"CPE1.alpha": (0.9 * a, min(1.0, 1.1 * a))})
    assert "CPE1.alpha" not in r.at_bound and r.converged
    assert r.chi2 <= free.chi2 * (1 + 1e-6)
    assert r.values["CPE1.alpha"] == pytest.approx(a, rel=1e-3)


def test_a_true_bound_optimum_is_still_at_its_bound(biologic, free_fit, bounded_fit):
    """R0 ≤ 63 (the free optimum is 63.56): the constrained optimum is on the bound, χ² falls
    outward there; scipy agrees."""
    r = bounded_fit({"R0": (60.0, 63.0)})
    assert r.converged and r.at_bound == ("R0",)
    assert r.values["R0"] == pytest.approx(63.0, rel=1e-9)
    values, chi2 = _scipy_fit(biologic, {"R0": (60.0, 63.0)}, free_fit.values)
    assert values["R0"] == pytest.approx(63.0, rel=1e-6)
    assert r.chi2 == pytest.approx(chi2, rel=1e-6)


def test_a_fit_left_at_a_bound_while_chi2_falls_inward_is_not_converged(biologic, monkeypatch):
    """Without the restarts, a start on the edge of the bounds (init 63.99999 in (63, 64))
    leaves the solver where its coordinate is flat: the at-bound verdict now asks that χ² not
    fall inward, and the fit says it did not converge instead of "R0 is at its upper bound"."""
    from impedax.fitting.least_squares import single

    monkeypatch.setattr(single, "BOUND_RESTARTS", 0)
    r = ix.fit(MODEL, biologic, bounds={"R0": (63.0, 64.0)}, init={"R0": 63.99999}, n_starts=1)
    f, z = biologic["frequency"].values, biologic["Z"].values
    p = np.array([r.values[n] for n in ("R0", "R1", "CPE1.Q", "CPE1.alpha")])
    inward = p.copy()
    inward[0] -= 0.05
    # the oracle: moving R0 inward alone lowers χ² (numpy, no impedax)
    assert np.sum(_residuals(inward, f, z) ** 2) < np.sum(_residuals(p, f, z) ** 2) - 1e-5
    assert r.values["R0"] > 63.99
    assert not r.converged and "R0" not in r.at_bound
    assert "chi² falls away from the bound" in r.message and r.warnings[0].startswith("fit did not converge")


def test_the_restart_from_inside_reaches_the_optimum_from_a_start_on_the_bound(biologic, free_fit):
    r = ix.fit(MODEL, biologic, bounds={"R0": (63.0, 64.0)}, init={"R0": 63.99999}, n_starts=1)
    assert r.converged and r.at_bound == ()
    assert r.chi2 == pytest.approx(free_fit.chi2, rel=1e-7)


def test_a_cpe_started_as_a_capacitor_leaves_alpha_1():
    """init CPE1.alpha = 1 ("start as a capacitor") on a SYNTHETIC R0 + R1 ∥ CPE1 (numpy
    formula, α = 0.99, 0.5 % noise, seed 3): the fit had stayed at α = 1 − 1e-6, "converged, at
    its upper bound", χ² 2.8× the optimum's. Moving α alone to the restart point (0.9)
    with Q held raises χ²; its Newton step lowers it, and that now counts. Batch: the same."""
    rng = np.random.default_rng(3)
    f = np.geomspace(0.1, 1e5, 31)
    truth = np.array([10.0, 100.0, 1e-5, 0.99])
    z = _z_rcpe(truth, f) * (1 + 0.005 * (rng.standard_normal(31) + 1j * rng.standard_normal(31)) / np.sqrt(2))
    data = ix.make_spectrum(f, z)
    values, chi2 = _scipy_fit(data, {}, dict(zip(["R0", "R1", "CPE1.Q", "CPE1.alpha"], truth)))
    r = ix.fit(MODEL, data, init={"CPE1.alpha": 1.0}, n_starts=1)
    assert r.converged and r.at_bound == ()
    assert r.chi2 == pytest.approx(chi2, rel=1e-6)
    assert r.values["CPE1.alpha"] == pytest.approx(values["CPE1.alpha"], abs=1e-5)
    stack = ix.fit(MODEL, xr.concat([data] * 3, dim="cycle"), init={"CPE1.alpha": 1.0}, n_starts=1).to_xarray()
    np.testing.assert_allclose(stack["value"].sel(param="CPE1.alpha").values, values["CPE1.alpha"], atol=1e-5)
    assert not stack["at_bound"].any()


@pytest.mark.slow  # (the suite's 15-minute budget, 2026-12-01: make test-all runs it)
def test_a_batch_reaches_the_single_fits_optimum_and_flags(biologic, bounded_fit):
    stack = xr.concat([biologic] * 3, dim="cycle").assign_coords(cycle=[0, 1, 2])
    for bounds in ({"R0": (63.0, 64.0)}, {"CPE1.Q": (0.008368, 0.01023)}, {"R0": (60.0, 63.0)}):
        single = bounded_fit(bounds)
        ds = ix.fit(MODEL, stack, bounds=bounds).to_xarray()
        assert bool(ds["converged"].all()) == single.converged
        for n, v in single.values.items():
            np.testing.assert_allclose(ds["value"].sel(param=n).values, v, rtol=1e-5)
            assert list(ds["at_bound"].sel(param=n).values) == [n in single.at_bound] * 3


def test_a_start_outside_the_bounds_is_placed_well_inside():
    from impedax.fitting.least_squares.starts import INSIDE_FRACTION, _clip_inside
    from impedax.fitting.parameters import ParameterTable

    table = ParameterTable.build(ix.parse(MODEL), bounds={"R0": (63.0, 64.0), "CPE1.alpha": (0.5, 0.9)})
    x = _clip_inside(np.array([[65.0, 10.0, 1e-3, 0.95], [62.0, 10.0, 1e-3, 0.2], [63.5, 10.0, 1e-3, 0.7]]), table)
    # the oracle: a tenth of the span of log R0 (R0 > 0, both bounds) and of α (an exponent, linear)
    assert x[0, 0] == pytest.approx(math.exp(math.log(64) - INSIDE_FRACTION * math.log(64 / 63)))
    assert x[1, 0] == pytest.approx(math.exp(math.log(63) + INSIDE_FRACTION * math.log(64 / 63)))
    assert x[0, 3] == pytest.approx(0.9 - INSIDE_FRACTION * 0.4) and x[1, 3] == pytest.approx(0.5 + INSIDE_FRACTION * 0.4)
    assert list(x[2]) == [63.5, 10.0, 1e-3, 0.7]  # inside: unchanged


# ---------------------------------------------------------------- 2. refine's max_steps


@pytest.fixture
def refine_calls(monkeypatch):
    """refine's first diagnose replaced by a stub that records its step limit and stops."""
    from impedax.fitting.diagnosis import refinement

    calls = []

    class Stop(Exception):
        pass

    def stub(*args, **kwargs):
        calls.append(kwargs)
        raise Stop

    monkeypatch.setattr(refinement, "diagnose", stub)
    return calls, Stop


def test_refine_max_steps_is_the_step_limit_as_in_fit_and_the_cli(biologic, refine_calls):
    calls, stop = refine_calls
    with pytest.raises(stop):
        ix.refine(biologic, MODEL, max_steps=60, max_effects=2)
    with pytest.raises(stop):
        ix.refine(biologic, MODEL, max_steps=60)
    with pytest.raises(stop):
        ix.refine(biologic, MODEL)
    assert [c["max_steps"] for c in calls] == [60, 60, 100]


def test_refine_max_steps_in_the_old_meaning_is_refused_with_max_effects_named(biologic, refine_calls):
    """max_steps was once refine's number of effects: a small value given alone, no step limit a
    candidate fit could converge within, is refused naming max_effects; with max_effects given it
    is a step limit whatever its size (as impedax refine --max-steps passes it); solver_steps,
    the step limit's old name, still works."""
    calls, stop = refine_calls
    for old in (3, 9):
        with pytest.raises(ParameterError, match=rf"refine\(max_steps={old}\): max_steps is the step limit .*\(max_effects={old}\)"):
            ix.refine(biologic, MODEL, max_steps=old)
    with pytest.raises(ParameterError, match="max_steps must be at least 1"):
        ix.refine(biologic, MODEL, max_steps=0, max_effects=1)
    with pytest.raises(stop):
        ix.refine(biologic, MODEL, max_steps=5, max_effects=2)
    with pytest.warns(FutureWarning, match="solver_steps"), pytest.raises(stop):
        ix.refine(biologic, MODEL, solver_steps=50)
    with pytest.raises(stop):
        ix.refine(biologic, MODEL, max_steps=10)
    assert [c["max_steps"] for c in calls] == [5, 50, 10]


# ---------------------------------------------------------------- 3. swapped arguments


def test_circuit_text_in_the_data_slot_says_the_arguments_look_swapped(biologic):
    with pytest.raises(DataError, match=r"look swapped \(diagnose takes \(data, circuit\)\)"):
        ix.diagnose(MODEL, biologic)
    with pytest.raises(DataError, match=r"look swapped \(refine takes \(data, circuit\)\)"):
        ix.refine(MODEL, biologic)
    with pytest.raises(DataError, match=r"look swapped \(fit takes \(circuit, data\)\)"):
        ix.fit(biologic, MODEL)
    with pytest.raises(DataError, match="file not found"):  # a path that is no circuit: as before
        ix.fit(MODEL, "no_such_file.csv")


def test_a_dataset_in_the_circuit_slot_says_the_arguments_look_swapped(biologic):
    with pytest.raises(CircuitError) as e:
        ix.sample(biologic, "R0 + R1 || C1")
    text = str(e.value)
    assert "look swapped" in text and "sample takes (circuit, data)" in text
    assert len(text) < 200 and "Dimensions" not in text  # no Dataset repr


# the walkthrough's swaps (2026-12-02): a Circuit object or impedance.py text in the data slot
# and a spectrum in the circuit slot was told "data must be a spectrum Dataset … got
# Series([Element('R0')…" or "file not found"; every function taking both names its own order
SWAPS = [
    ("fit", "(circuit, data)", "data", "a circuit"),
    ("sample", "(circuit, data)", "data", "a circuit"),
    ("diagnose", "(data, circuit)", "a circuit", "data"),
    ("refine", "(data, circuit)", "a circuit", "data"),
]


@pytest.mark.parametrize("circuit", [ix.parse(MODEL), "R0-p(R1,CPE1)", MODEL], ids=["Circuit", "impedance.py-text", "impedax-text"])
@pytest.mark.parametrize("spectrum", ["dataset", "path", "path-text"])
@pytest.mark.parametrize("function, order, first, second", SWAPS, ids=[s[0] for s in SWAPS])
def test_a_circuit_and_data_in_each_others_places_name_the_functions_order(biologic, circuit, spectrum, function, order, first, second):
    data = {"dataset": biologic, "path": REAL / "exampleDataBioLogic.mpt", "path-text": str(REAL / "exampleDataBioLogic.mpt")}[spectrum]
    swapped = (data, circuit) if order == "(circuit, data)" else (circuit, data)
    with pytest.raises(ix.errors.ArgumentsSwapped) as e:
        getattr(ix, function)(*swapped)
    text = str(e.value)
    assert text.startswith(f"the arguments look swapped ({function} takes {order}): the first argument looks like {first} ")
    assert f"and the second like {second} " in text and text.endswith(f"call impedax.{function}{order}")
    assert "Element(" not in text and "Dimensions" not in text and len(text) < 300
    assert isinstance(e.value, DataError) and isinstance(e.value, CircuitError)  # (what the two messages it replaced were)


def test_a_circuit_alone_where_the_data_go_says_where_it_goes():
    with pytest.raises(DataError, match=r"got a circuit \('R0 \+ R1 \|\| CPE1'\): the circuit goes in the other argument \(fit and sample take \(circuit, data\), diagnose and refine take \(data, circuit\)\)"):
        ix.refine(ix.parse(MODEL))


# ---------------------------------------------------------------- 4. raw errors


def test_batch_values_and_undetermined_name_the_parameters(biologic):
    batch = ix.fit(MODEL, xr.concat([biologic] * 2, dim="cycle").assign_coords(cycle=[0, 64]), n_starts=1)
    for method in (batch.values, batch.undetermined):
        with pytest.raises(ParameterError, match="unknown parameter 'r1'.*did you mean R1\\?.*R0, R1, CPE1.Q, CPE1.alpha"):
            method("r1")
        with pytest.raises(ParameterError, match="unknown parameter 'R9'"):
            method("R9")
    np.testing.assert_array_equal(batch.values("R1").values, batch.to_xarray()["value"].sel(param="R1").values)


@pytest.mark.parametrize("bad", [{"R0": 1.0}, None, "dataset"])
def test_write_result_takes_a_result(biologic, tmp_path, bad):
    bad = biologic if bad == "dataset" else bad
    for name in ("x.json", "x.nc", "x.csv"):
        with pytest.raises(ParameterError, match=f"write_result takes a result .*got {type(bad).__name__ if bad is not None else 'None'}"):
            ix.write_result(bad, tmp_path / name)
        assert not (tmp_path / name).exists()


# ---------------------------------------------------------------- 5. labels of fits with fixed values


def test_a_fit_with_fixed_values_is_labelled_by_them(free_fit, alpha_held_at_1, tmp_path):
    held = alpha_held_at_1
    c = ix.compare([free_fit, held])
    assert [r["label"] for r in c.rows] == [MODEL, f"{MODEL} [CPE1.alpha=1]"]
    assert f"F-test {MODEL} [CPE1.alpha=1]  ⊂  {MODEL}:" in c.table()
    ds = c.to_xarray()
    assert list(ds["model"].values) == [MODEL, f"{MODEL} [CPE1.alpha=1]"] and list(ds["circuit"].values) == [MODEL, MODEL]
    s = c.summary()
    # the JSON keeps its keys and values ("model": the circuit) and adds the labels
    assert [m["model"] for m in s["models"]] == [MODEL, MODEL] and s["best"] == MODEL
    assert [m["label"] for m in s["models"]] == [MODEL, f"{MODEL} [CPE1.alpha=1]"] and s["best_label"] == MODEL
    assert s["f_tests"][0]["simple"] == MODEL and s["f_tests"][0]["simple_label"] == f"{MODEL} [CPE1.alpha=1]"
    ix.write_result(c, tmp_path / "c.json")
    assert json.loads((tmp_path / "c.json").read_text())["models"][1]["label"] == f"{MODEL} [CPE1.alpha=1]"
    fig = c.plot()  # the legend names them apart too
    legend = [t.get_text() for ax in fig.axes if ax.get_legend() for t in ax.get_legend().get_texts()]
    assert any(t.startswith(f"{MODEL} [CPE1.alpha=1] (rms_rel") for t in legend) and any(t.startswith(f"{MODEL} (rms_rel") for t in legend)
    import matplotlib.pyplot as plt

    plt.close(fig)
    # a fit passed twice: each F-test names the row it came from
    twice = ix.compare([held, free_fit, held])
    assert {(t["simple_label"], t["complex_label"]) for t in twice.summary()["f_tests"]} == {(f"{MODEL} [CPE1.alpha=1]", MODEL), (f"{MODEL} [CPE1.alpha=1] (2)", MODEL)}


def test_a_bounded_fit_is_labelled_by_its_bounds(free_fit, alpha_held_at_1, bounded_fit, tmp_path):
    """Before, the bounded fit read "M (2)", the label of the same fit given twice, and neither
    report() nor the CSV said what it was bounded to."""
    bounded = bounded_fit({"R0": (60.0, 63.0)})
    c = ix.compare([free_fit, bounded, alpha_held_at_1])
    assert [r["label"] for r in c.rows] == [MODEL, f"{MODEL} [R0 within 60..63]", f"{MODEL} [CPE1.alpha=1]"]
    assert f"bounded in {MODEL} [R0 within 60..63]: R0 within 60 Ω..63 Ω" in c.report().splitlines()
    ix.write_result(c, tmp_path / "c.csv")
    rows = list(csv.DictReader(open(tmp_path / "c.csv")))
    assert [r["bounds"] for r in rows] == ["", "R0 within 60..63", ""] and rows[1]["label"] == f"{MODEL} [R0 within 60..63]"
    # the dataset and the notebook display say it too (they did not)
    assert list(c.to_xarray()["bounds"].values) == ["", "R0 within 60..63", ""]
    assert f"bounded in {MODEL} [R0 within 60..63]: R0 within 60 Ω..63 Ω" in c._repr_html_()


def test_fits_without_fixed_values_keep_their_labels(biologic, free_fit):
    c = ix.compare([free_fit, ix.fit("R0 + R1 || C1", biologic)])
    assert [r["label"] for r in c.rows] == [r["model"] for r in c.rows] == [MODEL, "R0 + R1 || C1"]
    assert list(c.to_xarray()["model"].values) == [MODEL, "R0 + R1 || C1"]
    # the same fit twice: still one coordinate value each
    assert list(ix.compare([free_fit, free_fit]).to_xarray()["model"].values) == [MODEL, f"{MODEL} (2)"]


# ---------------------------------------------------------------- 6. n_starts


def test_n_starts_is_the_size_of_one_rung_of_the_ladder():
    """exampleData.csv with R0 + R1 || CPE1 misses the data (16 % against the KK test's
    0.18 %), so the fit climbs every rung: n_starts × (1 + 4 + 16) starts."""
    from impedax.fitting.least_squares.starts import ESCALATION_RUNGS

    data = ix.load(REAL / "exampleData.csv")
    r = ix.fit(MODEL, data, n_starts=2)
    assert sum(ESCALATION_RUNGS) == 21 and r.n_starts == 2 * 21 == 42
    assert ix.fit(MODEL, data, n_starts=1).n_starts == 1
    assert "21 × ``n_starts``" in ix.fit.__doc__ and "n_starts − 1" not in ix.fit.__doc__


# ---------------------------------------------------------------- 7. short reprs


def test_registry_and_effect_catalog_reprs_are_short_and_say_what_they_hold():
    reg, eff = repr(ix.DEFAULT_REGISTRY), repr(ix.DEFAULT_EFFECTS)
    assert len(reg) < 120 and reg.startswith(f"Registry({len(ix.DEFAULT_REGISTRY.specs)} elements: R, C, L, CPE")
    assert len(eff) < 200 and eff.startswith(f"EffectCatalog({len(ix.DEFAULT_EFFECTS)} effects: ") and ix.DEFAULT_EFFECTS.ids()[0] in eff
    import pydoc

    for fn in (ix.fit, ix.diagnose, ix.refine):
        signature = pydoc.render_doc(fn, renderer=pydoc.plaintext).split("\n")[2]
        assert len(signature) < 1200 and "ElementSpec(" not in signature and "Effect(" not in signature


# ---------------------------------------------------------------- 8. the smaller items


def test_comparison_has_a_notebook_display(free_fit, alpha_held_at_1):
    c = ix.compare([free_fit, alpha_held_at_1])
    h = c._repr_html_()
    assert h.startswith('<div class="impedax-result">') and "<table>" in h and "data:image/png;base64," in h
    assert f"<td>{MODEL} [CPE1.alpha=1]</td>" in h and "best by AIC" in h and "F-test" in h


def test_a_nan_in_a_batch_is_named_by_its_coordinates(biologic):
    stack = xr.concat([biologic] * 2, dim="cycle").assign_coords(cycle=[0, 64])
    z = stack["Z"].values.copy()
    z[1, 5] = np.nan
    stack["Z"] = (stack["Z"].dims, z)
    f5 = float(biologic["frequency"].values[5])
    with pytest.raises(DataError, match=rf"non-finite value at cycle=64, f={f5:.3g} Hz \(point 5\)"):
        ix.fit(MODEL, stack)


def test_init_for_a_fixed_parameter_is_refused(biologic, free_fit):
    with pytest.raises(ParameterError, match="init: R0 .*is fixed"):
        ix.fit(MODEL, biologic, init={"R0": 60.0, "R1": 40.0}, fixed={"R0": 63.0})
    # a fit result as init starts the parameters two circuits share, fixed ones included
    r = ix.fit(MODEL, biologic, init=free_fit, fixed={"R0": 63.0})
    assert r.values["R0"] == 63.0 and r.fixed["R0"]


def test_a_one_parameter_element_may_have_a_suffix():
    assert ix.parse("R0 + W1").parameter_names() == ("R0", "W1.sigma")
    text = (pathlib.Path(__file__).parent.parent / "docs" / "circuits.md").read_text(encoding="utf-8")
    assert "`W1.sigma`, not `W1`" in text and "when the element has one parameter" not in text



def test_fit_says_its_stages_to_progress_and_fits_the_same():
    """``fit(..., progress=callback)`` says each stage as it begins (a batch's first call of a
    circuit compiled for 10-15 s without a word from Python), and the fits are those without it.
    SYNTHETIC: R0 + R1 ∥ C1 by hand, 1 % noise, seed 2, a stack of 16 (`REFERENCE_MIN_SPECTRA`:
    the batch's reference spectrum climbs the start ladder, as a stack of one, said once)."""
    import numpy as np

    import impedax as ix

    rng = np.random.default_rng(2)
    f = np.geomspace(1.0, 1e5, 30)
    r1 = np.linspace(500.0, 1500.0, 16)[:, None]
    z = (20.0 + r1 / (1 + 2j * np.pi * f * r1 * 1e-6)) * (1 + 0.01 * (rng.normal(size=(16, 30)) + 1j * rng.normal(size=(16, 30))))
    stack = ix.make_spectrum(f, z, dims=("cell",))
    from impedax.fitting.least_squares.single import FITTED_CIRCUITS

    FITTED_CIRCUITS.clear()  # (as in a new process: its first fit says it compiles)
    lines: list[str] = []
    said = ix.fit("R0 + R1 || C1", stack, progress=lines.append)
    assert lines[0] == "fitting R0 + R1 || C1 to 16 spectra together (a circuit's first batch compiles its solvers)"
    assert lines[1] == "the start search on a reference spectrum, whose optimum every spectrum is offered"
    assert "local fits of the 16 spectra" in lines and lines[-1] == "standard errors, bounds and warnings of the 16 fits"
    assert not any("of the 1 spectra" in line for line in lines)  # (the reference's own stack of one is not said)
    quiet = ix.fit("R0 + R1 || C1", stack)
    np.testing.assert_array_equal(said.dataset["value"].values, quiet.dataset["value"].values)
    one: list[str] = []
    ix.fit("R0 + R1 || C1", stack.isel(cell=0), progress=one.append)
    assert one[0] == "fitting R0 + R1 || C1 (a circuit's first fit compiles its solvers)"
    again: list[str] = []
    ix.fit("R0 + R1 || C1", stack.isel(cell=1), progress=again.append)
    assert again[0] == "fitting R0 + R1 || C1"  # (said once per process: a walkthrough read "compiles" on every warm run)
    with pytest.raises(ix.ParameterError, match="progress must be a function of one line of text"):
        ix.fit("R0 + R1 || C1", stack.isel(cell=0), progress=True)
