"""The stacked statistics of batch fits: `covariances` against the SVD of the Jacobian itself,
`stack_notes` against the warnings of one fit (`fit_notes`), and a batch's warnings against
one-by-one fits of the same spectra.

Spectra come from the numpy formulas of tests/spectra.py, not from impedax's compiler.
"""

from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.least_squares.result import CORRELATION_LIMIT, fit_notes, stack_notes
from impedax.fitting.statistics import _column_peaks, covariances
from impedax.fitting.parameters import ParameterTable
from spectra import CASES, noisy


def jacobian(rng, condition, m=40, k=5):
    """J = A·diag(d): A with singular values spread log-evenly over ``condition``, columns
    scaled by d over twelve decades (as parameters in ohms, farads and exponents); and the
    oracle (JᵀJ)⁻¹ = diag(1/d)·(AᵀA)⁻¹·diag(1/d) from the SVD of A, which the scaling does not
    spoil."""
    u, _ = np.linalg.qr(rng.normal(size=(m, k)))
    v, _ = np.linalg.qr(rng.normal(size=(k, k)))
    s = np.geomspace(1, 1 / condition, k)
    d = 10.0 ** rng.uniform(-6, 6, k)
    return u @ np.diag(s) @ v.T * d, v @ np.diag(1 / s**2) @ v.T / np.outer(d, d)


@pytest.mark.parametrize("condition", [1.0, 30.0, 1e3, 1e5])
def test_covariances_match_the_svd_of_the_jacobian(condition, rng):
    """Well-conditioned Jacobians take the inverse of JᵀJ, the others its eigendecomposition
    or the SVD (cond(J) 1e5: JᵀJ at 1e10); every way agrees with the oracle to the accuracy
    its conditioning allows, correlations included."""
    jacs, inverses = zip(*[jacobian(rng, condition) for _ in range(6)])
    chi2_red = rng.uniform(0.5, 2.0, 6)
    cov, corr, _, _ = covariances(np.stack(jacs), chi2_red, "modulus")
    for i in range(6):
        expected = inverses[i] * chi2_red[i]
        d = np.sqrt(np.diag(expected))
        # errors grow with the conditioning of J: relative to each entry's scale σ_i σ_j
        assert np.abs(cov[i] - expected) / np.outer(d, d) == pytest.approx(np.zeros((5, 5)), abs=1e-12 * condition**2 + 1e-13)
        assert corr[i] == pytest.approx(expected / np.outer(d, d), abs=1e-12 * condition**2 + 1e-13)


def test_sigma_weighting_is_not_scaled_by_chi2(rng):
    jac, inverse = jacobian(rng, 10.0)
    assert covariances(jac, 3.0, "sigma")[0] == pytest.approx(inverse, rel=1e-10)


def test_covariances_of_a_stack_equal_each_alone_singular_members_included(rng):
    """A stack mixing regular, proportional-column, zero-column and all-zero Jacobians: each
    member's covariance is what it would be alone, and the undetermined ones are reported
    (huge variances, ±1 correlation, near-zero singular values), never NaN."""
    regular, inverses = zip(*[jacobian(rng, 10.0) for _ in range(3)])
    proportional = jacobian(rng, 10.0)[0]
    proportional[:, 1] = -3.0 * proportional[:, 0]
    zero_column = jacobian(rng, 10.0)[0]
    zero_column[:, 2] = 0.0
    members = list(regular) + [proportional, zero_column, np.zeros((40, 5))]
    chi2_red = np.linspace(0.8, 1.3, len(members))
    stack = covariances(np.stack(members), chi2_red, "modulus")
    for i, jac in enumerate(members):
        alone = covariances(jac, chi2_red[i], "modulus")
        for got, want in zip(stack[:2], alone[:2]):
            assert np.isfinite(got[i]).all() or np.isinf(got[i]).any()
            assert got[i] == pytest.approx(want, rel=1e-10, abs=1e-300)
    cov, corr, s, _ = stack
    for i in range(3):
        assert cov[i] == pytest.approx(inverses[i] * chi2_red[i], rel=1e-10)
    assert corr[3, 0, 1] == pytest.approx(1.0, abs=1e-6)  # (x0, x1) and (x0, −3 x0) move together
    # in units of the columns' sizes (1 for a well-determined parameter)
    assert cov[3, 0, 0] * np.sum(proportional[:, 0] ** 2) > 1e20
    assert cov[4, 2, 2] * np.sum(zero_column[:, 2] ** 2) == 0 and cov[4, 2, 2] > 1e20
    assert s[3, -1] < 1e-8 * s[3, 0] and s[4, -1] < 1e-8 * s[4, 0]
    assert not np.isnan(cov).any() and not np.isnan(corr).any()


def test_covariances_of_columns_beyond_the_square_root_of_the_float_range(rng):
    """A column of norm 1e155 (a start far out on a Warburg's τ: JᵀJ would overflow) and a
    Jacobian with an inf entry: the first is equilibrated like any column and agrees with the
    oracle rescaled by hand; the second has a NaN covariance; neither raises."""
    jac, inverse = jacobian(rng, 10.0)
    c = np.ones(5)
    c[1] = 1e155 / np.linalg.norm(jac[:, 1])
    huge = jac * c
    bad = jac.copy()
    bad[3, 2] = np.inf
    cov, corr, _, _ = covariances(np.stack([huge, bad, jac]), np.ones(3), "modulus")
    d = np.sqrt(np.diag(inverse))
    assert (cov[0] * c[:, None] * c[None, :] - inverse) / np.outer(d, d) == pytest.approx(np.zeros((5, 5)), abs=1e-9)
    assert corr[0] == pytest.approx(corr[2], abs=1e-9)
    assert np.isnan(cov[1]).all()
    assert cov[2] == pytest.approx(inverse, rel=1e-10)


@pytest.mark.parametrize("rows", [1, 2, 3, 7, 40, 114])
def test_column_peaks_are_the_largest_entries_exactly(rows, rng):
    """The equilibration's column scales (`_column_peaks`, by halving the rows) are NumPy's
    column maxima bit for bit, for odd and even row counts, over 400 decades, a NaN included
    (it propagates, as np.max's does): the covariances do not move by a rounding."""
    magnitudes = np.abs(rng.normal(size=(6, rows, 5))) * 10.0 ** rng.uniform(-200, 200, (6, rows, 5))
    magnitudes[2, rows // 2, 3] = np.nan
    expected = np.array([[np.nan if np.isnan(column).any() else max(column.tolist()) for column in m.T] for m in magnitudes])
    np.testing.assert_array_equal(_column_peaks(magnitudes), expected)


# a circuit with a fixed parameter and bounds on either side: notes of every kind can be due
TABLE = ParameterTable.build(ix.parse("R0 + R1 || CPE1 + R2 || C2"), fixed={"R2": 100.0}, bounds={"R0": (1.0, 50.0), "CPE1.alpha": (0.5, 0.95)})


def random_notes_inputs(rng, n):
    """Values, stderr (n, P) and correlations (n, K, K) that earn each note now and then:
    strong correlations of either sign, relative errors above 100 %, infinite or NaN errors,
    values on the bounds."""
    names, free = TABLE.names, TABLE.free_index
    k = free.size
    values = np.exp(rng.uniform(-5, 5, (n, len(names))))
    values[:, names.index("CPE1.alpha")] = rng.uniform(0.5, 0.95, n)
    values[:, names.index("R2")] = 100.0
    at = rng.integers(0, 4, n)
    values[at == 1, names.index("R0")] = 50.0 * (1 - 1e-6)
    values[at == 2, names.index("R0")] = 1.0 * (1 + 1e-6)
    values[at == 3, names.index("CPE1.alpha")] = 0.95
    stderr = values * np.exp(rng.normal(-2, 1.5, values.shape))
    stderr[rng.random(stderr.shape) < 0.03] = np.inf
    stderr[rng.random(stderr.shape) < 0.03] = np.nan
    stderr[:, ~np.isin(np.arange(len(names)), free)] = np.nan
    corr = np.tile(np.eye(k), (n, 1, 1))
    for b in range(n):
        for _ in range(rng.integers(0, 3)):
            i, j = rng.choice(k, 2, replace=False)
            corr[b, i, j] = corr[b, j, i] = rng.choice([-1, 1]) * rng.uniform(0.98, 1.0)
    return values, stderr, corr


def test_stack_notes_equal_the_notes_of_one_fit(rng):
    values, stderr, corr = random_notes_inputs(rng, 300)
    got = stack_notes(TABLE, values, stderr, corr)
    names = TABLE.names
    kinds = set()
    for b in range(300):
        one = fit_notes(TABLE, dict(zip(names, values[b].tolist())), dict(zip(names, stderr[b].tolist())), corr[b], [], 1.0, finite=True, converged=True, message="")
        assert got.get(b, ()) == one and (b in got) == bool(one)
        kinds |= {w.split(" ")[-1] for w in one} | {" ".join(w.split(" ")[-4:]) for w in one if " bound " in w}
    # every kind of note was exercised: correlation (both texts; a CPE's Q and α with their errors), undetermined, either bound, near a bound
    # (a bound with its unit since 2026-12-06: "upper bound 50 Ω", not "50")
    assert {"posterior's", "sample)", "correlation)", "data", "0.95", "upper bound 50 Ω", "lower bound 1 Ω"} <= kinds, kinds  # ("posterior's": two elements' pair, `correlated_note`)
    assert np.any(np.abs(corr) > CORRELATION_LIMIT)


# two R ∥ CPE arcs and an open Warburg (the REAL battery cycles' Wo circuit): near-null groups of
# every kind can be due, two arcs at one τ among them
ARCS_TABLE = ParameterTable.build(ix.parse("R0 + R1 || CPE1 + R2 || CPE2 + Wo1"))


def test_stack_notes_with_near_null_groups_equal_the_notes_of_one_fit(rng):
    """Fits with near-null directions (`null_sets`: random groups of one to four parameters,
    infinite standard errors where a fit gives them, and every parameter of two arcs relaxing at
    one τ) built for the stack at once: each fit's notes are `fit_notes`' of that fit alone, with
    its groups and ratio, text for text and in order, as are those of the fits without a group
    beside them; the groups silence the correlations and relative errors inside them."""
    table, n = ARCS_TABLE, 240
    names, free = table.names, table.free_names
    values = np.exp(rng.uniform(-6, 4, (n, len(names))))
    for alpha in ("CPE1.alpha", "CPE2.alpha"):
        values[:, names.index(alpha)] = rng.uniform(0.5, 1.0, n)
    values[rng.random(n) < 0.1, names.index("CPE2.alpha")] = 1.0  # (at its upper bound)
    same_tau = rng.random(n) < 0.2  # R2 ∥ CPE2 a copy of R1 ∥ CPE1: one arc to the data
    for a, b in (("R1", "R2"), ("CPE1.Q", "CPE2.Q"), ("CPE1.alpha", "CPE2.alpha")):
        values[same_tau, names.index(b)] = values[same_tau, names.index(a)]
    stderr = values * np.exp(rng.normal(-2, 1.5, values.shape))
    stderr[rng.random(stderr.shape) < 0.05] = np.inf
    k = len(free)
    corr = np.tile(np.eye(k), (n, 1, 1))
    groups, ratios = [], 10.0 ** rng.uniform(-16, -9, n)
    for b in range(n):
        found = []
        if same_tau[b] and rng.random() < 0.8:
            found.append(["R1", "CPE1.Q", "CPE1.alpha", "R2", "CPE2.Q", "CPE2.alpha"])
        for _ in range(rng.choice(3, p=[0.5, 0.35, 0.15])):
            group = sorted(rng.choice(k, rng.integers(1, 5), replace=False).tolist())
            if [free[i] for i in group] not in found:
                found.append([free[i] for i in group])
        groups.append(found)
        for _ in range(rng.integers(0, 4)):
            i, j = rng.choice(k, 2, replace=False)
            corr[b, i, j] = corr[b, j, i] = rng.choice([-1, 1]) * rng.uniform(0.98, 1.0)
    sides = np.zeros((n, k), np.int8)
    sides[:, free.index("CPE2.alpha")] = values[:, names.index("CPE2.alpha")] == 1.0
    f = np.geomspace(1e-2, 1e4, 40)
    z = (values[:, :1] + values[:, 1:2] / (1 + 2j * np.pi * f * 1e-3)).astype(complex)
    got = stack_notes(table, values, stderr, corr, sides, freq=f, z=z, null_sets=groups, ratios=ratios)
    without = stack_notes(table, values, stderr, corr, sides, freq=f, z=z)
    silenced = 0
    for b in range(n):
        one = fit_notes(table, dict(zip(names, values[b].tolist())), dict(zip(names, stderr[b].tolist())), corr[b], groups[b], float(ratios[b]),
                        finite=True, converged=True, message="", sides=sides[b], freq=f, z=z[b])
        assert got.get(b, ()) == one and (b in got) == bool(one)
        in_group = {n for g in groups[b] for n in g}
        # (a note of a grouped parameter's relative error or of a pair of one group's, said without the groups)
        silenced += sum(1 for w in without.get(b, ()) if w not in one and any(w.startswith(f"{p} ") for p in in_group))
    said = [w for notes in got.values() for w in notes]
    assert any("relax at the same τ" in w for w in said)
    assert any("is not determined by the data (near-singular Jacobian" in w for w in said)
    assert any("are not separately determined by the data (near-singular Jacobian" in w for w in said)
    assert any("strongly correlated" in w for w in said) and any("relative standard error of" in w for w in said)
    assert silenced > 10


def test_batch_warnings_equal_single_fits(rng):
    """Two-arc spectra whose CPE Q and α correlate: the batch builds these texts for the stack,
    and each must be the single fit's, number for number (notes of the other kinds are
    compared with `fit_notes` above)."""
    text, fn, truth, (lo, hi) = CASES["two_arcs"]
    f = np.geomspace(lo, hi, 60)
    z = np.stack([noisy(fn(f, dict(truth, R1=r1)), 0.01, rng) for r1 in (300.0, 400.0, 600.0)])
    data = ix.make_spectrum(f, z, dims=("trial",), coords={"trial": [3, 5, 8]})
    batch = ix.fit(text, data)
    assert len(batch.warnings) == 3
    for i, trial in enumerate((3, 5, 8)):
        single = ix.fit(text, data.isel(trial=i))
        assert batch.warnings[f"trial={trial}"] == single.warnings
        assert any("strongly correlated (r = " in w for w in single.warnings)


@pytest.mark.slow  # (the suite's 15-minute budget, 2026-12-01: make test-all runs it)
def test_one_spectrum_of_a_batch_as_a_whole_fit():
    """`BatchFitResult.fit_of(cycle=64)`: the REAL battery cycle (AutoEIS's, MIT) as a
    `FitResult` at the batch's optimum — values within 1e-4, rms_rel within 1e-4 relative — and
    clear errors for a label that is not there or a dimension that is not the batch's."""
    import impedax as ix

    ds = ix.load(Path(__file__).parents[1] / "examples" / "data" / "autoeis_battery_cycles.nc")
    batch = ix.fit("R0 + R1 || CPE1 + R2 || CPE2 + W1", ds)
    one = batch.fit_of(cycle=64)
    assert isinstance(one, ix.FitResult) and one.converged
    for name, value in one.values.items():
        assert value == pytest.approx(float(batch.dataset["value"].sel(param=name, cycle=64)), rel=1e-4)
    assert one.rms_rel == pytest.approx(float(batch.dataset["rms_rel"].sel(cycle=64)), rel=1e-4)
    np.testing.assert_array_equal(one.z_data, ds["Z"].sel(cycle=64).values)
    with pytest.raises(ix.ParameterError, match=r"cycle=5 is not among the batch's labels \(nearest labels: 0, 64, 129\)"):
        batch.fit_of(cycle=5)
    with pytest.raises(ix.ParameterError, match=r"one label for each batch dimension \(cycle\); unknown: trial; missing: cycle"):
        batch.fit_of(trial=1)


def test_fit_of_keeps_the_data_s_sigma_and_refuses_a_global_fit():
    """A batch weighted by the data's own σ refits one spectrum with it (the σ is kept in the
    batch's Dataset); a global fit's spectrum alone would move its shared parameters: refused.
    SYNTHETIC R0 + R1 ∥ CPE1 written here, 4 trials scaled 1 %, 2 %, 3 % apart."""
    f = np.geomspace(1, 1e4, 30)
    z = 10 + 100 / (1 + (2j * np.pi * f * 1e-4) ** 0.9)
    zs = np.stack([z * (1 + 0.01 * k) for k in range(4)])
    data = ix.make_spectrum(f, zs, dims=("trial",), sigma=0.01 * np.abs(zs))
    batch = ix.fit("R0 + R1 || CPE1", data, weighting="sigma")
    np.testing.assert_array_equal(batch.dataset["sigma"].values, 0.01 * np.abs(zs))
    one = batch.fit_of(trial=2)
    assert one.weighting == "sigma" and one.values["R0"] == pytest.approx(10.2, rel=1e-6)
    shared = ix.fit("R0 + R1 || CPE1", data, shared=["CPE1.alpha"], over="trial")
    with pytest.raises(ix.ParameterError, match="would move the shared parameters"):
        shared.fit_of(trial=1)
