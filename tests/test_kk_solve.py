"""The KK test's linear solves against numpy's least squares, written apart from impedax: the
fast path (back substitution when the scaled system is well conditioned) and the pseudo-inverse
path (a rank-deficient design: two equal time constants) give numpy's minimum-norm solution,
and `kk_misfits` gives `kk_test_batch`'s rms_rel on the REAL battery cycles."""

from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.fitting import kk
from impedax.fitting.kk import kk_misfits, kk_test_batch

CYCLES = Path(__file__).resolve().parents[1] / "benchmarks" / "data" / "autoeis_battery_130.nc"


def _oracle(freq, z, tau):
    """Coefficients [R0, L, R_1..R_M] and Σ|Δ|² of the 1/|Z|-weighted fit, by numpy's lstsq
    of the column-scaled real system (singular values below P·eps of the largest cut)."""
    w = 2 * np.pi * freq
    design = np.column_stack([np.ones_like(w), 1j * w] + [1 / (1 + 1j * w * t) for t in tau]).astype(complex)
    weight = 1 / np.abs(z)
    a = np.vstack([(design * weight[:, None]).real, (design * weight[:, None]).imag])
    b = np.concatenate([(z * weight).real, (z * weight).imag])
    norms = np.linalg.norm(a, axis=0)
    y, *_ = np.linalg.lstsq(a / norms, b, rcond=a.shape[1] * np.finfo(float).eps)
    x = y / norms
    return x, float(np.sum((a @ x - b) ** 2))


def _spectra(freq, n, seed=0):
    """n two-arc spectra with 1 % noise, from the formula (not impedax's circuits)."""
    rng = np.random.default_rng(seed)
    s = 2j * np.pi * freq
    out = []
    for _ in range(n):
        r0, r1, r2 = 10 ** rng.uniform(0, 2, 3)
        t1, t2 = 10 ** rng.uniform(-5, -1, 2)
        z = r0 + r1 / (1 + s * t1) + r2 / (1 + (s * t2) ** 0.8)
        out.append(z * (1 + 0.01 * (rng.normal(size=freq.size) + 1j * rng.normal(size=freq.size))))
    return np.array(out)


@pytest.mark.parametrize("repeated", [False, True], ids=["full rank", "two equal time constants"])
def test_solves_match_numpy_least_squares(repeated):
    freq = np.geomspace(1e-1, 1e5, 40)
    z = _spectra(freq, 5)
    tau = 1 / (2 * np.pi * np.geomspace(1e-1, 1e5, 9))
    if repeated:
        tau = np.concatenate([tau, tau[4:5]])  # a column repeated: the design is rank-deficient
    coef, rss = kk._solve_streamed(2 * np.pi * freq, z, tau, True, False)
    for i in range(len(z)):
        x, rss_oracle = _oracle(freq, z[i], tau)
        fitted = np.column_stack([np.ones_like(freq), 2j * np.pi * freq] + [1 / (1 + 2j * np.pi * freq * t) for t in tau]) @ coef[i]
        oracle_fit = np.column_stack([np.ones_like(freq), 2j * np.pi * freq] + [1 / (1 + 2j * np.pi * freq * t) for t in tau]) @ x
        assert np.allclose(fitted, oracle_fit, rtol=1e-8, atol=0)
        assert rss[i] == pytest.approx(rss_oracle, rel=1e-8)
        if repeated:  # the minimum-norm solution shares the repeated column's weight equally
            assert coef[i][2 + 4] == pytest.approx(coef[i][-1], rel=1e-6)
            assert np.allclose(coef[i], x, rtol=1e-6, atol=1e-9 * np.abs(x).max())


def test_kk_misfits_equal_the_batch_test_on_real_cycles():
    cycles = ix.load(CYCLES).isel(cycle=slice(0, 130, 13))
    batch = kk_test_batch(cycles)
    assert np.array_equal(kk_misfits(cycles), np.array([r.rms_rel for r in batch.results]))


def test_chains_fitted_once_give_the_batch_tests_misfits_and_verdicts(monkeypatch):
    """A fit call's `KKChains` fits each spectrum's chain once, for its misfit and for its full
    test, and both are `kk_test_batch`'s on those spectra (REAL battery cycles, rows out of order)."""
    cycles = ix.load(CYCLES)
    freq, z = cycles["frequency"].values, cycles["Z"].transpose("cycle", "frequency").values
    rows = [7, 64, 3]
    batch = kk_test_batch(cycles.isel(cycle=rows))
    fitted = []
    arrays = kk._kk_arrays
    monkeypatch.setattr(kk, "_kk_arrays", lambda f, stack, **options: fitted.append(len(stack)) or arrays(f, stack, **options))
    chains = kk.KKChains()
    misfits = chains.misfits(freq, z, rows)
    verdicts = chains.verdicts(freq, z, rows[::-1])
    assert fitted == [3]  # one stack of the three; the full test fitted none of its own (no stray points here)
    np.testing.assert_allclose(misfits, [r.rms_rel for r in batch.results], rtol=1e-12)
    series = 3  # (R_0, L and 1/C: kk_test's defaults)
    assert verdicts == [(bool(r.valid), r.sign_hint, r.n_rc + series) for r in batch.results[::-1]]
    assert chains.misfit(64) == misfits[1] and chains.misfit(5) is None


def test_chains_where_the_test_cannot_run():
    """Three frequencies are too few for the chain (R_0, L, 1/C and one RC): misfit 0, no verdict."""
    freq = np.array([1.0, 10.0, 100.0])
    z = np.array([[3 - 1j, 2 - 1j, 1 - 0.5j]])
    chains = kk.KKChains()
    assert chains.misfits(freq, z, [0]).tolist() == [0.0]
    assert chains.verdicts(freq, z, [0]) == [(None, None, None)]
    assert chains.misfit(0) == 0.0
