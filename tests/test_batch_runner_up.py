"""A large batch offers its spectra the reference spectrum's other minima (`batch._runner_ups`,
`batch._tried_runner_up`): where a batch holds two kinds of spectra, the optimum of the other
kind is often the reference's second minimum. Found on AutoEIS's 130 REAL battery cycles with
`R0 + R1 || CPE1 + R2 || CPE2 + Ws1`: the reference (cycle 106) has its optimum at Ws τ ≈ 0.2 s,
and 27 later cycles, whose own optimum is at τ ≈ 50 s (3.6× above the reference's best on the
reference), were left in the reference's basin (χ² up to 2.8× that of the W model, which Ws
contains) — docs/fitting.md, "Batches".

The bookkeeping tests replace the solver by a stand-in (as tests/test_batch_outlier_rounds.py);
the last test fits REAL cycles, with the nesting of the models for oracle.
"""

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.least_squares import batch
from impedax.fitting.least_squares.solvers import SolverOutput, SolverStatus

B, N = 100, 30
FREQ = np.geomspace(1e-1, 1e5, N)
ARC = 100 / (1 + 2j * np.pi * FREQ * 100 * 1e-5)  # R ∥ C, 100 Ω, 10 µF
BATTERY = Path(__file__).resolve().parents[1] / "benchmarks" / "data" / "autoeis_battery_130.nc"


def _outputs(misfit, x=None):
    """Fits whose model is the arc scaled by (1 + misfit): rms_rel = misfit, χ² = misfit²."""
    misfit = np.asarray(misfit, float)
    n = misfit.size
    return SolverOutput(
        x=np.zeros((n, 1)) if x is None else x, chi2=misfit**2, jacobian=np.zeros((n, 2 * N, 1)), z_model=ARC[None, :] * (1 + misfit[:, None]),
        code=np.full(n, int(SolverStatus.CONVERGED)), steps=np.ones(n, int), steps_total=np.ones(n, int),
    )


class _StandIn:
    """A solver whose fit of spectrum i from the runner-up ends at ``misfit_from[i]`` rms_rel,
    converged where ``converges[i]``; records the spectra it solves."""

    def __init__(self, misfit_from, converges=None):
        self.misfit_from = np.asarray(misfit_from, float)
        self.converges = np.ones(B, bool) if converges is None else converges
        self.solved = []

    def solve(self, u0, spectra, budget, *, cold=False):
        self.solved.append(np.asarray(spectra).tolist())
        return np.array(u0, float), None, self.converges[spectra], np.full(len(spectra), 7)

    def outputs(self, u, spectra, done, steps, steps_total):
        return _outputs(self.misfit_from[spectra], x=np.ones((len(spectra), 1)))


def _tried(misfit, misfit_from, converges=None):
    solver = _StandIn(misfit_from, converges)
    n = len(misfit)
    out, u, tried = batch._tried_runner_up(_outputs(misfit), np.zeros((n, 1)), np.ones(1), solver, np.broadcast_to(ARC, (n, N)), np.ones(n), 400)
    return out, tried, solver.solved


def test_a_runner_up_that_lowers_a_fit_of_the_sample_is_tried_on_every_spectrum():
    misfit = np.full(B, 0.01)
    misfit[57] = 0.03  # the worst fit: in the sample
    better = np.full(B, 0.02)
    better[[57, 58, 59]] = 0.005  # the runner-up's basin is the optimum of 57–59
    out, tried, solved = _tried(misfit, better)
    assert 57 in solved[0] and 58 not in solved[0] and len(solved[0]) < 2 * batch.RUNNER_UP_SAMPLE + 1
    assert len(solved) == 2 and sorted(solved[0] + solved[1]) == list(range(B))
    np.testing.assert_allclose(np.sqrt(out.chi2[[57, 58, 59]]), 0.005)
    others = np.setdiff1d(np.arange(B), [57, 58, 59])
    np.testing.assert_allclose(np.sqrt(out.chi2[others]), misfit[others])  # the worse fits are not taken
    assert (out.x[[57, 58, 59]] == 1).all() and (out.x[others] == 0).all()
    assert tried.tolist() == list(range(B))


def test_a_runner_up_that_lowers_no_fit_of_the_sample_is_solved_there_alone():
    misfit = np.full(B, 0.01)
    out, tried, solved = _tried(misfit, np.full(B, 0.02))
    assert len(solved) == 1 and tried.tolist() == solved[0]
    spread = np.unique(np.linspace(0, B - 1, batch.RUNNER_UP_SAMPLE).round().astype(int))
    assert set(spread) <= set(tried)
    np.testing.assert_allclose(np.sqrt(out.chi2), 0.01)


def test_a_batch_no_larger_than_the_sample_is_solved_once():
    """16 spectra (`REFERENCE_MIN_SPECTRA`): the sample is the whole batch, and nothing is left
    to solve after it (an empty solve raised a ValueError from numpy's array_split)."""
    n = batch.REFERENCE_MIN_SPECTRA
    better = np.full(B, 0.02)
    better[:n] = 0.005
    out, tried, solved = _tried(np.full(n, 0.01), better)
    assert solved == [list(range(n))] and tried.tolist() == list(range(n))
    np.testing.assert_allclose(np.sqrt(out.chi2), 0.005)


def test_a_gain_below_the_threshold_tries_no_other_spectrum():
    """χ² lower by 1 % (below `RUNNER_UP_GAIN`, 2 %) on every spectrum of the sample: those
    fits are kept, the others are not solved."""
    misfit = np.full(B, 0.01)
    out, tried, solved = _tried(misfit, np.full(B, 0.01 * np.sqrt(0.99)))
    assert len(solved) == 1
    np.testing.assert_allclose(out.chi2[tried], 0.99e-4)


def test_a_fit_from_the_runner_up_that_did_not_converge_is_not_kept():
    misfit = np.full(B, 0.01)
    misfit[57] = 0.03
    converges = np.ones(B, bool)
    converges[57] = False
    better = np.full(B, 0.02)
    better[57] = 0.001
    out, tried, solved = _tried(misfit, better, converges)
    assert len(solved) == 1 and np.sqrt(out.chi2[57]) == pytest.approx(0.03)


class _Basins:
    """A solver that takes every point to the minimum of its basin: basin k = round(u[0]), with
    χ² ``chi2[k]``; records how many points it solves."""

    def __init__(self, chi2):
        self.chi2 = chi2
        self.n_solved = 0

    def solve(self, u0, spectra, budget, *, cold=False):
        self.n_solved += len(u0)
        k = np.round(np.asarray(u0)[:, 0]).astype(int)
        return np.stack([k.astype(float), np.zeros(len(k))], axis=1), np.array([self.chi2[i] for i in k]), np.ones(len(k), bool), np.ones(len(k), int)


def test_the_runner_ups_are_distinct_minima_within_the_factor_of_the_best():
    """Basins: 0 the optimum (χ² 1); 1 a second minimum (3); 2 one too high (20 > 10×); 3 the
    optimum again (1.004, e.g. its blocks exchanged); 4 a third minimum (5). Screened points
    near the optimum (within `DISTINCT_BASIN`) are not continued."""
    rng = np.random.default_rng(0)
    basin_of_start = np.array([0] * 30 + [1] * 5 + [2] * 5 + [3] * 5 + [4] * 5)
    points = np.stack([basin_of_start + rng.uniform(-0.1, 0.1, basin_of_start.size), rng.normal(size=basin_of_start.size)], axis=1)
    screen_chi2 = np.where(basin_of_start == 0, 1.0, 2.0) + rng.uniform(0, 0.5, basin_of_start.size)
    solver = _Basins({0: 1.0, 1: 3.0, 2: 20.0, 3: 1.004, 4: 5.0})
    found = batch._runner_ups(np.zeros(2), [(points[None], screen_chi2[None])], solver, 400)
    assert sorted(found[:, 0].tolist()) == [1.0, 4.0]
    # the optimum and at most `RUNNER_UP_CANDIDATES` screened points, none of basin 0 but the optimum
    assert solver.n_solved <= batch.RUNNER_UP_CANDIDATES + 1
    assert batch._runner_ups(np.zeros(2), [], solver, 400).shape == (0, 2)


@pytest.mark.slow  # (~15 s: two batches of 32 REAL cycles, compilation included)
def test_a_batch_of_real_cycles_reaches_the_second_kind_of_optimum():
    """The 32 last REAL battery cycles: Ws contains W (τ → ∞), so no Ws fit of a cycle may end
    above that cycle's W fit. Before the runner-up, 9 of the 32 did (χ² up to 3.3×)."""
    cycles = ix.load(BATTERY).isel(cycle=slice(98, 130))
    base = "R0 + R1 || CPE1 + R2 || CPE2 + "
    chi2_w = ix.fit(base + "W1", cycles).dataset["chi2"].values
    chi2_ws = ix.fit(base + "Ws1", cycles).dataset["chi2"].values
    np.testing.assert_array_less(chi2_ws, chi2_w * (1 + 1e-6))


@pytest.mark.slow  # (~15 s: W and Gerischer batches of 16 REAL cycles, a single fit; compilation included)
def test_a_batch_of_sixteen_real_cycles_takes_the_runner_up_where_it_is_lower():
    """16 REAL cycles (56–71) with `G1`: the reference's second minimum lowers 5 fits of the
    sample, which is the whole batch (an empty solve after it raised a ValueError). Oracles:
    G contains W (τ → ∞), so no G fit ends above its W fit; cycle 64's fit is no higher than its
    single fit (whose ladder ends 7.3 % higher)."""
    cycles = ix.load(BATTERY).isel(cycle=slice(56, 72))
    base = "R0 + R1 || CPE1 + R2 || CPE2 + "
    fits = ix.fit(base + "G1", cycles, progress=False)
    chi2_w = ix.fit(base + "W1", cycles, progress=False).dataset["chi2"].values
    np.testing.assert_array_less(fits.dataset["chi2"].values, chi2_w * (1 + 1e-4))  # (G's W limit: a flat stop, 4e-5 above on cycle 23)
    single = ix.fit(base + "G1", cycles.sel(cycle=64), progress=False)
    assert float(fits.dataset["chi2"].sel(cycle=64)) <= single.chi2 * (1 + 1e-6)
