"""A large batch gives its rung of starts to the fits that are poor against the other spectra,
and the yardstick moves as that rung improves fits (`batch._outliers_restarted`): a fit that
was better than the typical one before the rung, and is the outlier after it, gets its starts
too. Found on AutoEIS's 130 REAL battery cycles with `L0 + R0 + R1 || CPE1 + R2 || CPE2 + Ws1`
(cycle 33: 3.06 % in the batch, 0.77 % fitted alone; docs/fitting.md, "Batches").

The solver is replaced by a stand-in whose rung brings every spectrum it is given to 0.5 %
rms_rel: the test is of the rounds' bookkeeping, with rms_rel and the gross-misfit rule
computed on a spectrum written here (an R ∥ C arc: a Kramers–Kronig-consistent model fits it
exactly, so a fit at 10 % misses it grossly).
"""

from types import SimpleNamespace

import numpy as np

import impedax as ix
from impedax.fitting.parameters import ParameterTable
from impedax.fitting.kk import KKChains
from impedax.fitting.least_squares import batch
from impedax.fitting.least_squares.solvers import SolverOutput, SolverStatus

B, N = 20, 40
FREQ = np.geomspace(1e-1, 1e5, N)
ARC = 100 / (1 + 2j * np.pi * FREQ * 100 * 1e-5)  # R ∥ C, 100 Ω, 10 µF
GOOD = 0.005
# the circuit's parameter table (the rung's count of starts reads it: `starts.draw_size`), nothing
# given, and every value given (a draw then runs the given start once: 9 of 16)
TABLE = ParameterTable.build(ix.parse("R1 || C1"))
TABLE_GIVEN = ParameterTable.build(ix.parse("R1 || C1"), init={"R1": 100.0, "C1": 1e-5})


def _output(misfit):
    """Fits whose model is the arc scaled by (1 + misfit): rms_rel = misfit."""
    z_model = ARC[None, :] * (1 + np.asarray(misfit)[:, None])
    return SolverOutput(x=np.zeros((B, 1)), chi2=np.asarray(misfit, float) ** 2, jacobian=None, z_model=z_model, code=np.full(B, int(SolverStatus.CONVERGED)))


def _restarted(monkeypatch, misfit, table=TABLE):
    given = []

    def rung(out, solver, circuit, table, features, poor, n_starts, multiple, rung, seed, scale, max_steps, registry):
        given.append(sorted(poor.tolist()))
        fixed = np.array(np.sqrt(out.chi2))
        fixed[poor] = GOOD
        return _output(fixed)

    monkeypatch.setattr(batch, "_multistart_rung", rung)
    monkeypatch.setattr(batch, "_from_neighbours", lambda out, u, *rest: (out, u))
    monkeypatch.setattr(batch, "to_solver_space", lambda table, x: x)
    used = np.ones(B, int)
    z = np.broadcast_to(ARC, (B, N))
    out = batch._outliers_restarted(_output(misfit), np.zeros((B, 1)), used, SimpleNamespace(kk_chains=KKChains()), None, table, None, FREQ, z, 16, 0, np.ones(B), 400, None)
    return out, used, given


def test_a_fit_that_becomes_the_outlier_after_the_rung_gets_its_starts(monkeypatch):
    misfit = np.full(B, 0.10)  # most fits miss the arc grossly (≥ 5 %, far above the KK misfit)
    misfit[:6] = GOOD
    misfit[17] = 0.03  # below the gross-misfit rule and the typical 10 %: no outlier at first
    out, used, given = _restarted(monkeypatch, misfit)
    first = sorted(set(range(6, B)) - {17})
    assert given == [first, [17]]  # the second round: the one that became the outlier
    np.testing.assert_allclose(np.sqrt(out.chi2), GOOD)
    assert used[17] == 16 and (used[:6] == 1).all()


def test_a_rung_with_every_value_given_counts_the_starts_it_runs(monkeypatch):
    """With every free parameter given, a draw of 16 runs the given start once and 8 random
    starts (`starts.draw_size`): the rung's fits count 9, not 16."""
    misfit = np.full(B, 0.10)
    misfit[:6] = GOOD
    _, used, given = _restarted(monkeypatch, misfit, TABLE_GIVEN)
    assert given and (used[given[0]] == 9).all() and (used[:6] == 1).all()


def test_a_batch_with_no_poor_fit_gives_no_starts(monkeypatch):
    out, used, given = _restarted(monkeypatch, np.full(B, GOOD))
    assert given == [] and (used == 1).all()


def test_rounds_stop_when_the_rung_moved_nothing(monkeypatch):
    """A rung that improves no fit leaves the yardstick where it was: no second round."""
    misfit = np.full(B, GOOD)
    misfit[3] = 0.02  # an outlier (4× the median), not gross

    def rung(out, solver, circuit, table, features, poor, *rest):
        given.append(sorted(poor.tolist()))
        return out

    given = []
    monkeypatch.setattr(batch, "_multistart_rung", rung)
    monkeypatch.setattr(batch, "_from_neighbours", lambda out, u, *rest: (out, u))
    z = np.broadcast_to(ARC, (B, N))
    batch._outliers_restarted(_output(misfit), np.zeros((B, 1)), np.ones(B, int), SimpleNamespace(kk_chains=KKChains()), None, TABLE, None, FREQ, z, 16, 0, np.ones(B), 400, None)
    assert given == [[3]]
