"""``impedax remaining`` and ``impedax gap --remaining``: the remainder Z_total − Z_skin − Z_TS
(Sirin eq 5) written as a spectrum file, checked against the subtraction done by hand in NumPy
on SYNTHETIC trials, and read back by ``impedax fit``."""

from __future__ import annotations

import json
from types import SimpleNamespace

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from gap_files import saved_gap_files

N_TRIALS = 4


@pytest.fixture(scope="module")
def synthetic_parts():
    """SYNTHETIC total, skin, screen: 4 trials × 9 frequencies of random passive-looking
    spectra (Re > 0, Im < 0; the total well above skin + screen so the remainder is passive)."""
    rng = np.random.default_rng(7)
    f = np.geomspace(10.0, 1e5, 9)
    base = {"total": (5e6, -8e6), "skin": (2e5, -3e5), "ts": (1e4, -2e4)}
    parts = {}
    for name, (re, im) in base.items():
        z = re * (1 + 0.05 * rng.normal(size=(N_TRIALS, f.size))) + 1j * im * (1 + 0.05 * rng.normal(size=(N_TRIALS, f.size)))
        parts[name] = (f, z)
    return parts


def _datasets(parts):
    return [ix.make_spectrum(f, z, dims=("trial",), coords={"trial": np.arange(1, N_TRIALS + 1)}) for f, z in parts.values()]


def _by_hand(parts):
    """Trial means subtracted; sigma = √((Σ SEM_Re² + Σ SEM_Im²)/2), SEM with ddof 1 (docs/models.md)."""
    zs = [z for _, z in parts.values()]
    z_rem = zs[0].mean(0) - zs[1].mean(0) - zs[2].mean(0)
    var_re = sum(z.real.std(0, ddof=1) ** 2 / N_TRIALS for z in zs)
    var_im = sum(z.imag.std(0, ddof=1) ** 2 / N_TRIALS for z in zs)
    return z_rem, np.sqrt((var_re + var_im) / 2)


@pytest.mark.parametrize("suffix", [".nc", ".csv"])
def test_remaining_writes_the_trial_mean_remainder(tmp_path, capsys, synthetic_parts, suffix):
    paths = saved_gap_files(tmp_path, _datasets(synthetic_parts))
    out = tmp_path / f"rem{suffix}"
    assert main(["remaining", *paths, "--out", str(out)]) == 0
    assert "4 total, 4 skin, 4 touchscreen" in capsys.readouterr().err
    written = ix.load(out)
    z_rem, sigma = _by_hand(synthetic_parts)
    f = synthetic_parts["total"][0]
    np.testing.assert_allclose(written["frequency"].values, f, rtol=1e-14)
    np.testing.assert_allclose(written["Z"].values, z_rem, rtol=1e-12)
    np.testing.assert_allclose(written["sigma"].values, sigma, rtol=1e-12)


def test_remaining_trials_keep_the_trial_dimension(tmp_path, capsys, synthetic_parts):
    paths = saved_gap_files(tmp_path, _datasets(synthetic_parts))
    out = tmp_path / "trials.nc"
    assert main(["remaining", *paths, "--trials", "--out", str(out)]) == 0
    written = ix.load(out)
    zs = [z for _, z in synthetic_parts.values()]
    expected = zs[0] - zs[1].mean(0) - zs[2].mean(0)
    assert written["Z"].dims == ("trial", "frequency") and list(written["trial"].values) == [1, 2, 3, 4]
    np.testing.assert_allclose(written["Z"].values, expected, rtol=1e-12)


def test_remaining_is_read_by_fit(tmp_path, capsys, synthetic_parts):
    paths = saved_gap_files(tmp_path, _datasets(synthetic_parts))
    out = tmp_path / "rem.csv"
    assert main(["remaining", *paths, "--out", str(out)]) == 0
    capsys.readouterr()
    assert main(["fit", str(out), "--model", "R1 + C1", "--weighting", "sigma", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["weighting"] == "sigma" and summary["n_points"] == 9 and summary["source"].endswith("rem.csv")


def test_remaining_trials_to_csv_is_refused_before_any_file(tmp_path, capsys, synthetic_parts):
    paths = saved_gap_files(tmp_path, _datasets(synthetic_parts))
    out = tmp_path / "trials.csv"
    assert main(["remaining", *paths, "--trials", "--out", str(out)]) == 2
    assert "--trials" in capsys.readouterr().err and not out.exists()


def test_remaining_refuses_swapped_files_and_writes_nothing(tmp_path, capsys, synthetic_parts):
    total, skin, ts = saved_gap_files(tmp_path, _datasets(synthetic_parts))
    out = tmp_path / "rem.nc"
    assert main(["remaining", skin, total, ts, "--out", str(out)]) == 2
    assert "check the order of the files" in capsys.readouterr().err and not out.exists()


def test_gap_remaining_saves_the_remainder_it_fitted(tmp_path, capsys, monkeypatch, synthetic_parts):
    """``gap --remaining`` writes the result's own remainder (the sampling is replaced by a stub)."""
    import impedax.models.gap as gap_module
    from impedax.models.sirin import remaining_impedance

    datasets = _datasets(synthetic_parts)
    stub = SimpleNamespace(remaining=remaining_impedance(*datasets), warnings=(), report=lambda: "stub report", plot=None)
    monkeypatch.setattr(gap_module, "gap_analysis", lambda *a, **k: stub)
    paths = saved_gap_files(tmp_path, datasets)
    out = tmp_path / "rem.nc"
    assert main(["gap", *paths, "--area", "130e-6", "--remaining", str(out)]) == 0
    z_rem, sigma = _by_hand(synthetic_parts)
    written = ix.load(out)
    np.testing.assert_allclose(written["Z"].values, z_rem, rtol=1e-12)
    np.testing.assert_allclose(written["sigma"].values, sigma, rtol=1e-12)
