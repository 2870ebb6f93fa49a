"""The note on an idle branch: a parameter undetermined because its element is a branch of a
parallel block that carries next to none of the block's current, or a term of a series chain
that takes next to none of its voltage (`least_squares.branches`,
docs/fitting.md, "Warnings"). SYNTHETIC spectra written here as formulas."""

import numpy as np
import pytest
import xarray as xr

import impedax as ix

F = np.geomspace(0.1, 1e5, 50)
JW = 2j * np.pi * F


def noisy(z, seed=0, rel=0.002):
    rng = np.random.default_rng(seed)
    return ix.make_spectrum(F, z * (1 + rel * (rng.normal(size=z.size) + 1j * rng.normal(size=z.size)) / np.sqrt(2)))


def blocking():
    """A blocking electrode: R0 + a CPE with nothing in parallel (Z = R0 + 1/(Q (jω)^α))."""
    return noisy(50.0 + 1 / (2e-5 * JW**0.85))


def arc():
    """R0 + R1 ∥ CPE1 whose arc closes inside the band (R1 Q ω^α = 1 near 30 Hz)."""
    return noisy(50.0 + 1000.0 / (1 + 1000.0 * 2e-5 * JW**0.85), seed=1)


def idle_notes(warnings):
    return [w for w in warnings if "the current through" in w]


def test_a_resistor_beside_a_cpe_of_a_blocking_electrode_is_named_idle():
    r = ix.fit("R0 + R1 || CPE1", blocking())
    notes = idle_notes(r.warnings)
    assert len(notes) == 1, r.warnings
    assert notes[0].startswith("R1 carries at most ") and "the current through R1 || CPE1 over the band" in notes[0]
    assert "R0 + CPE1, the model without it" in notes[0]
    share = float(notes[0].split("at most ")[1].split("×")[0])
    assert share < 1e-3
    # the claim holds: the model without R1 fits as well (the data were written without it)
    assert ix.fit("R0 + CPE1", blocking()).rms_rel <= r.rms_rel * 1.001


def test_an_arc_that_closes_in_the_band_has_no_idle_branch():
    r = ix.fit("R0 + R1 || CPE1", arc())
    assert idle_notes(r.warnings) == [], r.warnings
    assert r.values["R1"] == pytest.approx(1000.0, rel=0.05)


def test_single_batch_and_global_fits_give_the_idle_note():
    # the first spectrum's R1 runs open in each kind of fit; the second's stops at 7.6e7 Ω in
    # the global fit with a standard error of 90 % (determined by the rule), so it gets the note
    # where the fit calls R1 undetermined
    data = [blocking(), noisy(50.0 + 1 / (2e-5 * JW**0.85), seed=2)]
    stack = xr.concat(data, dim="trial")
    single = [ix.fit("R0 + R1 || CPE1", d).warnings for d in data]
    batch = ix.fit("R0 + R1 || CPE1", stack)
    shared = ix.fit("R0 + R1 || CPE1", stack, shared=["CPE1.alpha"])
    for i in range(2):
        for warnings in (single[i], batch.warnings.get(f"trial={i}", ()), shared.warnings.get(f"trial={i}", ())):
            notes = idle_notes(warnings)
            undetermined = any(w.startswith(("R1 has a relative standard error", "R1 is at its upper bound ∞")) for w in warnings)
            assert undetermined or i == 1, warnings
            assert len(notes) == int(undetermined), warnings
            assert all(n.startswith("R1 carries at most ") and "R0 + CPE1, the model without it" in n for n in notes), notes


def test_a_shared_parameter_s_idle_branch_is_said_once_for_the_global_fit():
    # R1 shared over two blocking electrodes: undetermined in the global fit, idle in both
    # spectra; the note comes once, under the global fit's key, as its other shared notes do
    stack = xr.concat([blocking(), noisy(50.0 + 1 / (2e-5 * JW**0.85), seed=2)], dim="trial")
    shared = ix.fit("R0 + R1 || CPE1", stack, shared=["R1"])
    own = shared.warnings["shared over trial"]
    assert any(w.startswith("shared R1 has a relative standard error") for w in own), own
    notes = idle_notes(own)
    assert len(notes) == 1 and notes[0].startswith("shared R1 carries at most ") and "R0 + CPE1, the model without it" in notes[0]
    assert not any(idle_notes(w) for key, w in shared.warnings.items() if key != "shared over trial")
    assert "warning (shared over trial): shared R1 carries at most" in shared.report()


def wo(r, tau):
    """Finite-length Warburg, reflective boundary, written here: Z = R coth(√(jωτ))/√(jωτ)."""
    x = np.sqrt(JW * tau)
    return r / np.tanh(x) / x


def chain_notes(warnings):
    return [w for w in warnings if "the voltage across" in w]


def test_a_warburg_term_that_runs_to_nothing_is_named_idle_in_its_chain():
    # an arc without diffusion fitted with a finite Warburg in series: Wo1 ends far below the
    # arc's impedance, its R and tau undetermined. The note names the share of the voltage Wo1
    # takes, which the formula above gives from the fitted values, and the model without it
    r = ix.fit("R0 + R1 || CPE1 + Wo1", arc())
    notes = chain_notes(r.warnings)
    assert len(notes) == 1, r.warnings
    assert notes[0].startswith("Wo1 takes at most ") and "the voltage across R0 + R1 || CPE1 + Wo1 over the band" in notes[0]
    assert "R0 + R1 || CPE1, the model without it" in notes[0] and notes[0].endswith("fraction of the chain's impedance")
    v = r.values
    z_wo = wo(v["Wo1.R"], v["Wo1.tau"])
    z_total = v["R0"] + 1 / (1 / v["R1"] + v["CPE1.Q"] * JW ** v["CPE1.alpha"]) + z_wo
    share = float(notes[0].split("at most ")[1].split("×")[0])
    assert share == pytest.approx(np.max(np.abs(z_wo / z_total)), rel=0.06)  # printed to 2 digits
    assert share < 1e-3
    assert ix.fit("R0 + R1 || CPE1", arc()).rms_rel <= r.rms_rel * 1.001


def test_a_series_branch_that_runs_open_is_named_once_as_a_whole():
    # a blocking electrode fitted with a Randles circuit: R1 runs open, so the branch R1 + W1
    # carries no current. The branch is named as a whole, and W1 inside it is not named again
    r = ix.fit("R0 + CPE1 || (R1 + W1)", blocking())
    notes = idle_notes(r.warnings) + chain_notes(r.warnings)
    assert len(notes) == 1, r.warnings
    assert notes[0].startswith("R1 + W1 carries at most ") and "the current through CPE1 || (R1 + W1) over the band" in notes[0]
    assert "R0 + CPE1, the model without it" in notes[0]
    assert ix.fit("R0 + CPE1", blocking()).rms_rel <= r.rms_rel * 1.001


@pytest.mark.parametrize(
    "circuit, z",
    [
        ("R0 + R1 || CPE1 + Wo1", 50.0 + 1000.0 / (1 + 1000.0 * 2e-5 * JW**0.85) + wo(500.0, 2.0)),
        ("R0 + CPE1 || (R1 + W1)", 50.0 + 1 / (2e-5 * JW**0.85 + 1 / (1000.0 + 300.0 / np.sqrt(JW)))),
    ],
    ids=["arc_and_finite_warburg", "randles"],
)
def test_no_idle_note_where_every_element_is_in_the_data(circuit, z):
    r = ix.fit(circuit, noisy(z, seed=3))
    assert idle_notes(r.warnings) + chain_notes(r.warnings) == [], r.warnings


def test_batch_fits_give_the_chain_note_of_single_fits():
    data = [arc(), noisy(50.0 + 1000.0 / (1 + 1000.0 * 2e-5 * JW**0.85), seed=2)]
    batch = ix.fit("R0 + R1 || CPE1 + Wo1", xr.concat(data, dim="trial"))
    for i, d in enumerate(data):
        single = chain_notes(ix.fit("R0 + R1 || CPE1 + Wo1", d).warnings)
        batch_notes = chain_notes(batch.warnings.get(f"trial={i}", ()))
        assert len(single) == len(batch_notes) == 1, (single, batch_notes)
        assert all(n.startswith("Wo1 takes at most ") and "R0 + R1 || CPE1, the model without it" in n for n in single + batch_notes)


def test_diagnose_names_an_element_of_the_user_s_circuit_that_the_data_do_not_need():
    # the arc fitted with a Warburg it does not hold: the diagnosis' notes carry its baseline
    # fit's idle note, so that a modeler learns the element can go
    d = ix.diagnose(arc(), "R0 + R1 || CPE1 + Wo1")
    notes = [n for n in d.notes if n.startswith("the baseline fit: ")]
    assert len(notes) == 1 and "Wo1 takes at most " in notes[0] and "R0 + R1 || CPE1, the model without it" in notes[0], d.notes
    assert "note: the baseline fit: Wo1 takes at most" in d.report()


def test_an_undetermined_term_that_takes_its_share_of_the_voltage_is_not_called_idle():
    # two series resistors: neither is determined (only their sum is), yet each takes about
    # half the voltage at high frequency, so neither is idle; the series rule runs (the
    # parameters are undetermined) and must stay silent
    r = ix.fit("R0 + R1 || CPE1 + R_a", arc())
    assert r.stderr["R0"] > r.values["R0"] and r.stderr["R_a"] > r.values["R_a"]
    assert idle_notes(r.warnings) + chain_notes(r.warnings) == [], r.warnings


def test_undetermined_notes_write_the_relative_error_as_the_table_does():
    from impedax.fitting.least_squares.result import undetermined_note

    assert undetermined_note("R1", 1.26) == "R1 has a relative standard error of 126 %: it is not determined by the data"
    assert undetermined_note("R1", 3.88e13) == "R1 has a relative standard error of 3.9e+15 %: it is not determined by the data"
    assert undetermined_note("R1", float("inf")) == "R1 has no finite standard error: it is not determined by the data"


def test_an_open_branch_on_exact_data_is_at_its_bound_whatever_its_standard_error():
    """Exact data (no noise): residuals of ~1e-14 make every standard error small, also that of
    an R1 run open beside the CPE of a blocking electrode (1e20 Ω, relative error 10 % before).
    Its branch carries < 1e-6 of the current (`VANISHING_SHARE`) and a larger R1 carries less:
    R1 is at its upper bound ∞, with the idle note, in single and batch fits alike; R0 and the
    CPE keep their errors. A CPE whose Q vanishes leaves its α undetermined."""
    exact = ix.make_spectrum(F, 50.0 + 1 / (2e-5 * JW**0.85))
    single = ix.fit("R0 + R1 || CPE1", exact)
    assert single.values["R1"] > 1e12  # open: |Z_CPE| ≤ 6e4 Ω over the band, R1 ≥ 1e12 carries < 1e-7
    assert single.at_bound == ("R1",) and "R1 is at its upper bound ∞" in single.warnings
    assert len(idle_notes(single.warnings)) == 1
    assert single.stderr["R0"] / 50.0 < 1e-6 and single.values["CPE1.alpha"] == pytest.approx(0.85, rel=1e-8)
    batch = ix.fit("R0 + R1 || CPE1", xr.concat([exact, noisy(50.0 + 1000.0 / (1 + 1000.0 * 2e-5 * JW**0.85), seed=1)], dim="trial"))
    assert batch.dataset["at_bound"].sel(param="R1").values.tolist() == [True, False]
    assert set(batch.warnings["trial=0"]) == set(single.warnings) and idle_notes(batch.warnings.get("trial=1", ())) == []
    # a CPE beside a resistor with Q next to 0: Q at its lower bound 0, α (an exponent) undetermined;
    # its branch carries |Q (jω)^α R| ≤ 1e-20·1e3·(2π·1e5)^0.7 ≈ 1e-13 of the current
    from impedax.fitting.least_squares.branches import VANISHED, vanishing_parameters
    from impedax.fitting.parameters import ParameterTable

    circuit = ix.parse("R1 || CPE1")
    table = ParameterTable.build(circuit)
    codes = vanishing_parameters(circuit, ix.DEFAULT_REGISTRY, table, np.array([[1000.0, 1e-20, 0.7]]), F, np.ones((1, 3), bool))
    assert dict(zip(table.free_names, codes[0].tolist())) == {"R1": 0, "CPE1.Q": -1, "CPE1.alpha": VANISHED}
    # a determined term with a small share is not touched: a 1e-4 share of the block's current
    small = ix.make_spectrum(F, 50.0 + 1 / (1 / 1e9 + 2e-5 * JW**0.85))
    r = ix.fit("R0 + R1 || CPE1", small, init={"R0": 50.0, "R1": 1e9, "CPE1.Q": 2e-5, "CPE1.alpha": 0.85})
    assert np.isfinite(r.stderr["R1"]) and r.at_bound == () and r.values["R1"] == pytest.approx(1e9, rel=1e-3)


def test_a_warburg_absent_from_exact_data_is_not_reported_determined():
    # exact R0 + R1 ∥ C1 + R2 ∥ CPE2 (no diffusion) fitted with a Warburg in series: W1.sigma
    # ends ~1e-11 Ω s^-1/2, |Z_W| = σ√2/√ω below 1e-12 of |Z| at every point, yet its column
    # ∂Z/∂σ = (1−j)/√ω does not shrink with σ and exact data make every standard error small.
    # The fit must not call it determined: at its bound 0 (no standard error) with the chain note
    f = np.geomspace(0.01, 1e5, 29)
    jw = 2j * np.pi * f
    z = 100.0 + 200.0 / (1 + 200.0 * 8e-7 * jw) + 500.0 / (1 + 500.0 * 4e-4 * jw**0.5)
    r = ix.fit("R0 + R1 || CPE1 + R2 || CPE2 + W1", ix.make_spectrum(f, z))
    sigma = r.values["W1.sigma"]
    assert sigma * np.sqrt(2 / (2 * np.pi * f[0])) < 1e-6 * np.abs(z).min()  # (the term is absent)
    assert "W1.sigma" in r.at_bound and r.to_table()[-1]["stderr"] is None, r.report()
    notes = chain_notes(r.warnings)
    assert len(notes) == 1 and notes[0].startswith("W1 takes at most "), r.warnings


def test_a_resistor_run_open_to_floating_points_end_is_coded_open_without_an_overflow_warning():
    # R1 = 1e308 beside a CPE (random command lines reached it): ten times it lies beyond float64;
    # taken as ∞, its branch carries no current at all, so the code is +1 (open), as at 1e12
    import warnings

    from impedax.fitting.least_squares.branches import vanishing_parameters
    from impedax.fitting.parameters import ParameterTable

    circuit = ix.parse("R1 || CPE1")
    table = ParameterTable.build(circuit)
    for r1 in (1e12, 1e308):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            codes = vanishing_parameters(circuit, ix.DEFAULT_REGISTRY, table, np.array([[r1, 2e-5, 0.85]]), F, np.ones((1, 3), bool))
        assert dict(zip(table.free_names, codes[0].tolist()))["R1"] == 1, r1


@pytest.mark.parametrize("n_fits", [5, 81, 300])
def test_each_of_many_fits_gets_its_own_rows_idle_share(n_fits):
    # the shares are evaluated on rows padded to a shared shape (`branches._shares`): each fit's
    # named idle R1 and its share must still be its own, the closed form of R0 + R1 || C1:
    # |Y_R1 / (Y_R1 + Y_C1)| = 1 / |1 + jωR1C1|, largest at the band's lowest ω
    from impedax.fitting.least_squares.branches import IDLE_BRANCH_SHARE, idle_branches
    from impedax.fitting.parameters import ParameterTable

    circuit = ix.parse("R0 + R1 || C1")
    table = ParameterTable.build(circuit)
    rng = np.random.default_rng(3)
    values = np.zeros((n_fits, len(table.names)))
    r1, c1 = 10.0 ** rng.uniform(2, 12, n_fits), 10.0 ** rng.uniform(-7, -4, n_fits)
    for name, column in (("R0", np.full(n_fits, 50.0)), ("R1", r1), ("C1", c1)):
        values[:, table.names.index(name)] = column
    mask = np.zeros((n_fits, len(table.free_names)), bool)
    mask[:, table.free_names.index("R1")] = True
    share = 1 / np.abs(1 + 2j * np.pi * F.min() * r1 * c1)
    found = idle_branches(circuit, ix.DEFAULT_REGISTRY, table, values, mask, F)
    assert sorted(b.row for b in found) == np.flatnonzero(share < IDLE_BRANCH_SHARE).tolist()
    assert 0 < len(found) < n_fits  # (the seed gives both kinds of fit at each size)
    for b in found:
        assert b.element == "R1"
        assert b.share == pytest.approx(share[b.row], rel=1e-9)
