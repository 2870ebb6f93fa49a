"""One circuit written in two orders gets the same flags when its branch R1 + W1 runs open.

On CH Instruments' real file (impedance.py 1.7.1's example, tests/fixtures/real/)
``R0 + (R1 + W1) || CPE1`` stopped at R1 = 2.1e16 Ω, W1.sigma = 6.6e7 and said "R1 = 2.12e+16 Ω
cannot be told from its lower bound 0", while ``R0 + CPE1 || (R1 + W1)`` stopped at R1 = 1.5e70 Ω,
W1.sigma = 1.9e7 and called R1 undetermined: two points of one flat valley (the branch is open
whenever R1 or W1.sigma is large). With W1.sigma = 6.6e7 the branch stays open at R1 = 0, so the
bound rule confirmed R1's lower bound; the bound is not what makes the branch vanish, and the
parameter is undetermined (`result.vanishing_term_sides`).
"""

from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.fitting.comparison import undetermined_names

REAL = Path(__file__).resolve().parent / "fixtures" / "real"
ORDERS = ("R0 + (R1 + W1) || CPE1", "R0 + CPE1 || (R1 + W1)")


def branch_share(f, v):
    """max over f of |Y_branch / (Y_branch + Y_CPE)| for R1 + W1 beside CPE1, written here:
    Z_W = σ(1 − j)/√ω, Y_CPE = Q (jω)^α."""
    w = 2 * np.pi * np.asarray(f)
    y_branch = 1 / (v["R1"] + v["W1.sigma"] * (1 - 1j) / np.sqrt(w))
    y_cpe = v["CPE1.Q"] * (1j * w) ** v["CPE1.alpha"]
    return float(np.max(np.abs(y_branch / (y_branch + y_cpe))))


def flags(fit):
    return {
        "at_bound": set(fit.at_bound),
        "undetermined": set(undetermined_names(fit)),
        "bound notes": sorted(w.split(" ")[0] for w in fit.warnings if "bound" in w),
        "idle": any(w.startswith(("R1 + W1 carries at most", "W1 + R1 carries at most")) for w in fit.warnings),
    }


# five writings of one circuit; their fits stop at four points of the valley (R1 = 2e16, 1.5e70,
# 8e71 Ω, or W1.sigma = 2.6e106 with R1 = 4e8 Ω)
WRITINGS = ORDERS + ("R0 + CPE1 || (W1 + R1)", "CPE1 || (R1 + W1) + R0", "R0 + (W1 + R1) || CPE1")


DETERMINED = ("R0", "CPE1.Q", "CPE1.alpha")


def reduced_stderr(fit):
    """Standard errors of R0, Q, α with the open branch held (numpy alone): √diag of
    χ²_red (JᵀJ)⁻¹ over the columns of R0 + CPE1, Z = R0 + 1/(Q (jω)^α), modulus weighting
    (residuals over |Z_data|), χ²_red over the fit's 2N − 5 degrees of freedom."""
    v, z, w = fit.values, fit.z_data, 2 * np.pi * fit.frequency
    jw_a = (1j * w) ** v["CPE1.alpha"]
    model = v["R0"] + 1 / (v["CPE1.Q"] * jw_a)
    columns = [np.ones_like(model), -1 / (v["CPE1.Q"] ** 2 * jw_a), -np.log(1j * w) / (v["CPE1.Q"] * jw_a)]
    j = np.concatenate([np.stack([c.real for c in columns], 1), np.stack([c.imag for c in columns], 1)]) / np.concatenate([np.abs(z)] * 2)[:, None]
    chi2 = np.sum(np.abs(model - z) ** 2 / np.abs(z) ** 2)
    return np.sqrt(np.diag(chi2 / (2 * z.size - 5) * np.linalg.inv(j.T @ j)))


def test_the_writing_stopped_where_w1_sigma_ran_open_gives_the_reduced_circuit_s_errors():
    """CPE1 || (R1 + W1) + R0 stops at R1 = 4.2e8 Ω, W1.sigma = 2.6e106: its branch's columns,
    a capacitance's there, inflated the others' errors ~15× (R0 ± 7.49 Ω, Q ± 7.65e-05, α ± 0.076)
    while the other writings gave R0 ± 2.16; held, all give the reduced circuit's (± 2.02 Ω)."""
    fit = ix.fit(WRITINGS[3], ix.load(REAL / "exampleDataCHInstruments.txt"))
    assert fit.values["W1.sigma"] > 1e100 and set(undetermined_names(fit)) == {"R1", "W1.sigma"}
    np.testing.assert_allclose([fit.stderr[n] for n in DETERMINED], reduced_stderr(fit), rtol=0.01)
    assert fit.stderr["R0"] == pytest.approx(2.02, rel=0.01)
    assert not any("bound" in w or "strongly correlated" in w for w in fit.warnings), fit.warnings


@pytest.mark.slow  # (13 s; the suite's budget)
def test_every_order_on_ch_instruments_real_file_gives_the_same_flags():
    data = ix.load(REAL / "exampleDataCHInstruments.txt")
    fits = [ix.fit(m, data) for m in WRITINGS]
    for fit in fits:
        # the premise: the branch is open at the fitted values (numpy formula), R1 + |Z_W| far above |Z|
        assert branch_share(fit.frequency, fit.values) < 1e-6
        assert max(fit.values["R1"], fit.values["W1.sigma"]) > 1e12
        # no bound for the open branch's R1 nor for W1.sigma beside it
        assert not any("bound" in w for w in fit.warnings), fit.warnings
    # the determined parameters' errors do not depend on where along the valley the fit stopped:
    # each is the reduced circuit's (the branch held), within 1 % (CPE1 || (R1 + W1) + R0 stopped
    # at W1.sigma = 2.6e106 and gave errors ~15× these, CPE1.Q "within 2 standard errors of 0")
    for fit in fits:
        np.testing.assert_allclose([fit.stderr[n] for n in DETERMINED], reduced_stderr(fit), rtol=0.01)
    batch = ix.fit(WRITINGS[3], xr.concat([data, data], dim="copy"), init=dict(fits[3].values), n_starts=1)
    np.testing.assert_allclose(batch.dataset["stderr"].isel(copy=0).sel(param=list(DETERMINED)).values, reduced_stderr(fits[3]), rtol=0.01)
    seen = [flags(f) for f in fits]
    assert all(s == seen[0] for s in seen), seen
    assert seen[0] == {"at_bound": set(), "undetermined": {"R1", "W1.sigma"}, "bound notes": [], "idle": True}
    # compare says the same of the two writings of the user's tour
    c = ix.compare(fits[:2])
    assert c.best_determined is None and "leaves R1, W1.sigma undetermined" in c.table()


def _valley_fits(data, rule):
    """The two writings started (and left, the valley being flat) at the two points the real
    file's fits reached."""
    import impedax.fitting.least_squares.result as result

    starts = ((ORDERS[0], 2e16, 6.6e7), (ORDERS[1], 1.5e70, 1.9e7))
    if rule is None:  # the rule before: the sides as `confirm_bounds` gave them
        original = result.vanishing_term_sides
        result.vanishing_term_sides = lambda circuit, registry, table, values, sides, *a, **k: np.asarray(sides)
    try:
        return [ix.fit(m, data, init={"R0": 100.0, "CPE1.Q": 1e-4, "CPE1.alpha": 0.6, "R1": r1, "W1.sigma": s}) for m, r1, s in starts]
    finally:
        if rule is None:
            result.vanishing_term_sides = original


def test_both_orders_on_a_synthetic_blocking_electrode_give_the_same_flags():
    """SYNTHETIC: R0 + CPE1 (100 Ω, Q = 1e-4, α = 0.6), numpy formula, 1 % noise, 60 points."""
    f = np.geomspace(0.1, 1e5, 60)
    jw = 2j * np.pi * f
    rng = np.random.default_rng(0)
    z = (100 + 1 / (1e-4 * jw**0.6)) * (1 + 0.01 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2))
    data = ix.make_spectrum(f, z)
    before = _valley_fits(data, None)
    for fit in before:
        assert branch_share(f, fit.values) < 1e-6
    # the rule before gave the two orders different flags (the case reproduces the real file's)
    assert flags(before[0])["at_bound"] == {"R1", "W1.sigma"} and flags(before[1])["at_bound"] == {"W1.sigma"}
    assert "R1" in flags(before[1])["undetermined"]
    after = _valley_fits(data, "now")
    assert [f.values["R1"] for f in after] == pytest.approx([2e16, 1.5e70], rel=1e-6)  # (the same two points)
    assert flags(after[0]) == flags(after[1]) == {"at_bound": set(), "undetermined": {"R1", "W1.sigma"}, "bound notes": [], "idle": True}


def test_an_off_bound_side_outside_a_vanishing_term_is_kept():
    """R0 + R1 || CPE1 with R0 fixed at 1e9 Ω (the `--fix R0=1e9` case of test_small_fixes):
    R1 = 7.96e7 Ω cannot be told from its lower bound 0, and its block takes ~3e-6 of the
    chain's voltage (above 1e-6): the side stays. At the open-branch point the side goes."""
    from impedax.fitting.least_squares.result import vanishing_term_sides
    from impedax.fitting.parameters import ParameterTable

    f = np.geomspace(0.1, 1e5, 25)
    jw = 2j * np.pi * f
    z = 30.0 + 1 / (1 / 3000.0 + 1e-6 * jw**0.9)
    circuit = ix.parse("R0 + R1 || CPE1")
    table = ParameterTable.build(circuit, fixed={"R0": 1e9})
    values = np.array([[1e9, 7.96e7, 5e-4, 0.9]])
    sides = np.array([[-1, 0, 0]], np.int8)
    np.testing.assert_array_equal(vanishing_term_sides(circuit, ix.DEFAULT_REGISTRY, table, values, sides, f, z[None]), sides)
    # the real file's first point: R1 and W1.sigma off their lower bound 0, the branch open
    circuit = ix.parse(ORDERS[0])
    table = ParameterTable.build(circuit)
    values = np.array([[95.77, 2.116e16, 6.612e7, 9.4985e-5, 0.6067]])
    sides = np.array([[0, -1, -1, 0, 0]], np.int8)
    z = 95.77 + 1 / (9.4985e-5 * jw**0.6067)
    np.testing.assert_array_equal(vanishing_term_sides(circuit, ix.DEFAULT_REGISTRY, table, values, sides, f, z[None]), np.zeros((1, 5)))


@pytest.mark.slow  # (an end-to-end run of ~10 s: make test-all; the fast suite's 15-minute budget)
def test_a_batch_of_the_real_spectrum_gives_the_single_fits_flags():
    """The same rule in batch fits: a stack of CH Instruments' spectrum, fitted from the single
    fit's values, flags no bound for the open branch, as the single fit does."""
    data = ix.load(REAL / "exampleDataCHInstruments.txt")
    single = ix.fit(ORDERS[0], data)
    assert single.at_bound == ()
    batch = ix.fit(ORDERS[0], xr.concat([data, data], dim="copy"), init=dict(single.values), n_starts=1)
    assert not bool(batch.dataset["at_bound"].any())
    assert not any("bound" in w for notes in batch.warnings.values() for w in notes), batch.warnings
