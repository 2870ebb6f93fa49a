"""Small fixes, each pinned by a test that failed before it: the notebook display's rms_rel in
percent (as the text reports), the bound note's wording off the bound, and ``impedax gap
--select``. Spectra from closed-form formulas (tests/spectra.py); results built by hand where
a fit is not what is tested."""

import math
import re

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.fitting.least_squares import FitResult
from impedax.fitting.least_squares.batch import BatchFitResult
from impedax.fitting.least_squares.result import NUMERICALLY_ON_FRACTION, ON_BOUND_FRACTION, at_bound_names, fit_notes, on_bound, stack_notes
from impedax.fitting.parameters import ParameterTable
from spectra import r_cpe, rc

RC = {"R0": 50.0, "R1": 2000.0, "C1": 1e-7}
F = np.geomspace(1.0, 1e6, 30)


def _misfit_by(z, rms_rel, seed=0):
    """z moved by complex relative residuals of modulus exactly ``rms_rel`` (random phases)."""
    phase = np.random.default_rng(seed).uniform(0, 2 * np.pi, z.shape)
    return z * (1 + rms_rel * np.exp(1j * phase))


def _fit_result(rms_rel=0.0472, **changes):
    """A FitResult of R0 + R1 || C1 built by hand: model = the formula, data off by ``rms_rel``."""
    circuit = ix.parse("R0 + R1 || C1")
    z_model = rc(F, RC)
    # residual (z_model − z_data)/|z_data| of modulus rms_rel at every point
    z_data = z_model / (1 + rms_rel * np.exp(1j * np.random.default_rng(1).uniform(0, 2 * np.pi, F.size)))
    fields = dict(
        circuit=circuit, values=dict(RC), stderr={"R0": 1.0, "R1": 20.0, "C1": 1e-9}, fixed={n: False for n in RC}, free_names=tuple(RC),
        covariance=np.eye(3), correlation=np.eye(3), frequency=F, z_data=z_data, z_model=z_model, weighting="modulus", chi2=1.0,
        converged=True, message="converged", n_evaluations=10,
    )
    fields.update(changes)
    return FitResult(**fields)


# -- 1. notebook summaries: rms_rel in percent, as the text reports ---------------------------------------


def test_fit_result_html_shows_rms_rel_in_percent_as_its_report():
    result = _fit_result()
    assert result.rms_rel == pytest.approx(0.0472, rel=1e-12)
    html = result._repr_html_()
    assert "rms_rel 4.72 %" in html and "rms_rel 0.0472" not in html
    assert re.search(r"rms_rel +4\.72 %", result.report())  # the same number as the text report
    assert result.summary()["rms_rel"] == pytest.approx(0.0472, rel=1e-12)  # the JSON stays a fraction


def test_batch_html_shows_the_median_rms_rel_in_percent():
    cells = ["a", "b", "c"]
    value = np.array([[50.0, 51.0, 52.0], [2000.0, 2100.0, 2200.0], [1e-7, 1e-7, 1e-7]])
    ds = xr.Dataset(
        {
            "value": (("param", "cell"), value),
            "stderr": (("param", "cell"), value * 0.01),
            "fixed": ("param", [False] * 3),
            "at_bound": (("param", "cell"), np.zeros((3, 3), bool)),
            "rms_rel": ("cell", [0.0100, 0.0472, 0.2000]),
            "converged": ("cell", [True] * 3),
        },
        coords={"param": list(RC), "cell": cells},
    )
    batch = BatchFitResult(circuit=ix.parse("R0 + R1 || C1"), dataset=ds, weighting="modulus", warnings={})
    html = batch._repr_html_()
    assert "median rms_rel 4.72 %" in html and "0.0472" not in html
    assert "median rms_rel 4.72 %" in batch.report()
    assert batch.summary()["rms_rel_median"] == pytest.approx(0.0472)


@pytest.fixture(scope="module")
def misfit_data():
    """An R‖C spectrum off by 3 % at every point: a KK test and a DRT of it leave ~1–3 %."""
    return ix.make_spectrum(F, _misfit_by(rc(F, RC), 0.03, seed=2))


def test_kk_html_shows_rms_rel_and_noise_in_percent(misfit_data):
    result = ix.kk_test(misfit_data)
    html = result._repr_html_()
    rms, noise = f"{result.rms_rel * 100:.3g}", f"{result.noise_estimate * 100:.3g}"
    assert f"rms_rel = {rms} %" in result.report() and f"noise estimate = {noise} %" in result.report()
    assert f"<td>rms_rel [%]</td><td>{rms}</td>" in html
    assert f"<td>noise estimate [%]</td><td>{noise}</td>" in html
    assert f"{result.rms_rel:.5g}" not in html  # the fraction is gone
    assert result.summary()["rms_rel"] == result.rms_rel


def test_drt_html_shows_rms_rel_in_percent(misfit_data):
    result = ix.drt(misfit_data)
    html = result._repr_html_()
    rms = f"{result.rms_rel * 100:.3g}"
    assert f"rms_rel = {rms} %" in result.report()
    assert f"rms_rel {rms} %;" in html and f"rms_rel {result.rms_rel:.3g};" not in html
    assert result.summary()["rms_rel"] == result.rms_rel


# -- 2. bound notes: "at its bound" only when on it; else "cannot be told from it" ----------------------------


def _r_cpe_case():
    """R0 + R1 || CPE1 with R0 fixed at 1e9 Ω (the `impedax fit ... --fix R0=1e9` case) and a
    closed-form R‖CPE spectrum of |Z| 30–3000 Ω: R1 = 7.96e7 Ω and α = 1 − 1e-12 flagged."""
    table = ParameterTable.build(ix.parse("R0 + R1 || CPE1"), fixed={"R0": 1e9})
    f = np.geomspace(0.1, 1e5, 25)
    z = r_cpe(f, {"R0": 30.0, "R1": 3000.0, "CPE1.Q": 1e-6, "CPE1.alpha": 0.9})
    values = {"R0": 1e9, "R1": 7.96e7, "CPE1.Q": 5e-4, "CPE1.alpha": 1 - 1e-12}
    stderr = {"R0": math.nan, "R1": 1.3e18, "CPE1.Q": 1e-5, "CPE1.alpha": 0.5}
    sides = np.array([-1, 0, 1], np.int8)  # over the free parameters R1, CPE1.Q, CPE1.alpha
    return table, f, z, values, stderr, sides


def test_bound_note_off_the_bound_gives_value_and_stderr():
    table, f, z, values, stderr, sides = _r_cpe_case()
    notes = fit_notes(table, values, stderr, np.eye(3), [], 1.0, finite=True, converged=True, message="", sides=sides, freq=f, z=z)
    assert "R1 = 79.6 MΩ cannot be told from its lower bound 0 (linearised standard error 1.3e+18 Ω, bounds ignored)" in notes
    assert "CPE1.alpha is at its upper bound 1 (CPE1 with alpha = 1 is a capacitor: the model with C1 in its place may be enough)" in notes  # within 1e-4 of 1: on it
    assert not any(n.startswith("R1 is at") for n in notes)
    # a value at rounding level against |Z| ≥ 30 Ω is on the bound 0, whatever its stderr
    on_zero = fit_notes(table, {**values, "R1": 1.2e-15}, {**stderr, "R1": 1.2e-15}, np.eye(3), [], 1.0, finite=True, converged=True, message="", sides=sides, freq=f, z=z)
    assert "R1 is at its lower bound 0" in on_zero
    # on it but not negligible to the solver: the single fit's note gives the value the table shows
    near_zero = fit_notes(table, {**values, "R1": 2.5e-3}, stderr, np.eye(3), [], 1.0, finite=True, converged=True, message="", sides=sides, freq=f, z=z)
    assert any(n.startswith("R1 = 2.5 mΩ runs to its lower bound 0") for n in near_zero)
    # the same rule for a stack of fits, and the JSON's at_bound is the flags, as before
    x = np.array([[values[n] for n in table.names], [1e9, 1e-3, 5e-4, 1 - 1e-12]])
    e = np.array([[stderr[n] for n in table.names]] * 2)
    stacked = stack_notes(table, x, e, np.stack([np.eye(3)] * 2), np.stack([sides, sides]), freq=f, z=np.stack([z, z]))
    assert "R1 = 79.6 MΩ cannot be told from its lower bound 0 (linearised standard error 1.3e+18 Ω, bounds ignored)" in stacked[0]
    # 1e-3 Ω ≤ 1e-4 · 30 Ω: on it, but above 1e-8 · 30 Ω (NUMERICALLY_ON_FRACTION), so the note gives the value
    assert "R1 = 1 mΩ runs to its lower bound 0 (fitted in log space, it approaches 0 without reaching it; to the data it is 0)" in stacked[1]
    assert not any("R1 is at its" in n for n in stacked[1])
    assert at_bound_names(table, sides) == ("R1", "CPE1.alpha")


def test_on_bound_scales_by_unit():
    table, f, z, values, stderr, sides = _r_cpe_case()
    x = np.array([[1e9, 1e-3, 1e-12, 0.5], [1e9, 1.0, 10.0, 0.5]])
    flags = np.array([[-1, -1, 0], [-1, -1, 0]], np.int8)
    on = on_bound(table, x, flags, f, np.stack([z, z]))
    # R1: 1e-3 Ω vs min |Z| ≈ 32 Ω (on), 1 Ω (off); Q: 1e-12 vs the CPE's scale min 1/(|Z| ω) ≈ 5e-8 (on), 10 (off)
    np.testing.assert_array_equal(on, [[True, True, False], [False, False, False]])
    # without the data every flagged parameter reads as on it (the old wording)
    np.testing.assert_array_equal(on_bound(table, x, flags), flags != 0)


def test_shared_bound_note_has_the_same_wording():
    from impedax.fitting.least_squares.shared import _sharing_notes, shared_layout

    table, f, z, values, stderr, sides = _r_cpe_case()
    layout = shared_layout(table, ("trial",), ["R1"], ["trial"])
    spectra = np.stack([z, 2 * z])  # one global fit over two spectra: R1's scale is the smaller |Z|
    x = np.array([[values[n] for n in table.names]] * 2)
    flags = np.array([[-1, 0, 0]] * 2, np.int8)

    def notes(r1):
        x[:, 1] = r1
        on, exactly = (on_bound(table, x[:1], flags[:1], np.tile(f, 2), spectra.reshape(1, -1), fraction)[0, list(layout.shared_slots)] for fraction in (ON_BOUND_FRACTION, NUMERICALLY_ON_FRACTION))
        return _sharing_notes(layout, np.array([r1]), np.array([1.3e18]), flags[0, list(layout.shared_slots)], table, math.nan, math.nan, 0.0, True, 10, on=on, exactly=exactly)

    assert notes(7.96e7) == ("shared R1 = 79.6 MΩ cannot be told from its lower bound 0 (linearised standard error 1.3e+18 Ω, bounds ignored)",)
    assert notes(1e-5) == ("shared R1 = 10 µΩ runs to its lower bound 0 (fitted in log space, it approaches 0 without reaching it; to the data it is 0)",)
    assert notes(1e-9) == ("shared R1 is at its lower bound 0",)  # below 1e-8 × 30 Ω: where the solver stopped


def test_results_print_in_a_few_lines_with_arrays_as_their_shape():
    """The generated dataclass repr printed every array (thousands of characters for one fit
    of 20 points); now arrays show as their shape and the scalars as they are."""
    import impedax as ix

    f = np.geomspace(1, 1e4, 20)
    data = ix.make_spectrum(f, 10 + 100 / (1 + (2j * np.pi * f * 1e-4) ** 0.9))
    fit = ix.fit("R0 + R1 || CPE1", data)
    for result in (fit, ix.kk_test(data), ix.drt(data)):
        text = repr(result)
        assert text.startswith(type(result).__name__ + "(") and len(text) < 1500, text
        assert "<complex128 array (20,)>" in text and "array([" not in text
    assert f"chi2={fit.chi2!r}" in repr(fit) and "converged=True" in repr(fit)
