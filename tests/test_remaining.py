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
    err = capsys.readouterr().err
    assert "4 total, 4 skin, 4 touchscreen" in err and "sigma from their standard errors: fit with --weighting sigma to use it" in err
    assert "Re Z < 0" not in err  # (a passive remainder: no subtraction note)
    written = ix.load(out)
    z_rem, sigma = _by_hand(synthetic_parts)
    f = synthetic_parts["total"][0]
    np.testing.assert_allclose(written["frequency"].values, f, rtol=1e-14)
    np.testing.assert_allclose(written["Z"].values, z_rem, rtol=1e-12)
    np.testing.assert_allclose(written["sigma"].values, sigma, rtol=1e-12)
    if suffix == ".nc":  # the three paths as attrs (a CSV holds none): a fit of the file knows it is a remainder
        assert {k: written.attrs[k] for k in ("total", "skin", "touchscreen")} == dict(zip(("total", "skin", "touchscreen"), paths))


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


@pytest.mark.parametrize("trials", [False, True])
def test_remaining_of_the_total_alone_is_a_single_contact_s_trial_mean(tmp_path, capsys, synthetic_parts, trials):
    """The total alone (a gripper pad, as ``impedax gap PAD``): nothing subtracted, the trial mean
    with sigma = √((SEM_Re² + SEM_Im²)/2) by hand, or the trials themselves; the three-file
    command's checks and JSON (until 2026-12-03 ``impedax remaining`` needed three files)."""
    total = _datasets(synthetic_parts)[0]
    path = tmp_path / "pad.nc"
    ix.save(total, path)
    out = tmp_path / "rem.nc"
    assert main(["remaining", str(path), *(["--trials"] if trials else []), "--out", str(out), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["single_contact"] is True and summary["n_trials"] == {"total": N_TRIALS} and summary["source"] == {"total": str(path)}
    written = ix.load(out)
    z = synthetic_parts["total"][1]
    if trials:
        np.testing.assert_allclose(written["Z"].values, z, rtol=1e-12)
    else:
        sigma = np.sqrt((z.real.std(0, ddof=1) ** 2 + z.imag.std(0, ddof=1) ** 2) / N_TRIALS / 2)
        np.testing.assert_allclose(written["Z"].values, z.mean(0), rtol=1e-12)
        np.testing.assert_allclose(written["sigma"].values, sigma, rtol=1e-12)
    assert written.attrs["single_contact"] == 1 and "skin" not in written.attrs
    assert main(["remaining", str(path)]) == 0  # the text line says what it wrote
    captured = capsys.readouterr()
    assert "a single contact, Z_total at 9 frequencies from 4 total spectra (their trial mean, sigma from their standard errors" in captured.err
    assert captured.out.startswith("frequency_hz,z_real_ohm,z_imag_ohm,sigma_ohm")


def test_remaining_refuses_one_file_after_the_total(tmp_path, capsys, synthetic_parts):
    total, skin, _ = saved_gap_files(tmp_path, _datasets(synthetic_parts))
    out = tmp_path / "rem.nc"
    assert main(["remaining", total, skin, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "one spectrum file after DATA_TOTAL: give DATA_SKIN and DATA_TS both" in err and "impedax remaining PAD" in err and not out.exists()


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
    # the same path attrs as impedax remaining writes (`remainder_with_paths`): a fit of the file knows it is a remainder
    assert {k: written.attrs[k] for k in ("total", "skin", "touchscreen")} == dict(zip(("total", "skin", "touchscreen"), paths))


@pytest.mark.parametrize("name", ["rem.json", "rem.xyz"])
def test_remaining_refuses_an_unknown_out_extension_before_any_work(tmp_path, capsys, synthetic_parts, name):
    paths = saved_gap_files(tmp_path, _datasets(synthetic_parts))
    out = tmp_path / name
    assert main(["remaining", *paths, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert f"--out: unknown spectrum extension {out.suffix!r}" in err and ".nc" in err and ".csv" in err and not out.exists()
    # .txt is the spectrum CSV, as in every command writing spectra (docs/io.md, "Writing spectra")
    txt = tmp_path / "rem.txt"
    assert main(["remaining", *paths, "--out", str(txt)]) == 0
    assert txt.read_text().startswith("frequency_hz,z_real_ohm,z_imag_ohm,sigma_ohm")
    np.testing.assert_allclose(ix.load(txt)["Z"].values, _by_hand(synthetic_parts)[0], rtol=1e-12)


TOP_NEGATIVE = 2  # the remainder's last frequencies with Re Z < 0


@pytest.fixture(scope="module")
def negative_top_parts():
    """SYNTHETIC total, skin, screen whose remainder 1e5·(1 − 0.5j) Ω has Re Z = −3e4 Ω at its
    last `TOP_NEGATIVE` frequencies (0.1 % trial scatter: far beyond its sigma and 5 % of |Z|)."""
    rng = np.random.default_rng(11)
    f = np.geomspace(10.0, 1e5, 9)
    remainder = np.full(f.size, 1e5 - 5e4j)
    remainder[-TOP_NEGATIVE:] = -3e4 - 5e4j

    def scattered(z):
        return z * (1 + 0.001 * rng.normal(size=(N_TRIALS, f.size)))

    skin, ts = scattered(np.full(f.size, 2e5 - 3e5j)), scattered(np.full(f.size, 1e4 - 2e4j))
    total = skin.mean(0) + ts.mean(0) + scattered(remainder)
    return {"total": (f, total), "skin": (f, skin), "ts": (f, ts)}


def test_a_remainder_with_re_z_below_zero_blames_the_subtraction(tmp_path, capsys, negative_top_parts):
    paths = saved_gap_files(tmp_path, _datasets(negative_top_parts))
    out = tmp_path / "rem.nc"
    assert main(["remaining", *paths, "--out", str(out)]) == 0
    (warning,) = [line for line in capsys.readouterr().err.splitlines() if "warning:" in line]
    f = negative_top_parts["total"][0]
    np.testing.assert_allclose(f[-TOP_NEGATIVE:], [10**4.5, 1e5])
    shown = "31.6 kHz, 100 kHz"  # (as impedax writes frequencies; "3.162e+04 Hz, 1e+05 Hz" until 2026-12-06)
    assert f"Re Z < 0 beyond its sigma at {TOP_NEGATIVE} of {f.size} frequencies ({shown})" in warning
    assert "series resistance scatters between trials" in warning and "--exclude" in warning
    # the fit of the written file names the subtraction; the same data without the path attrs, the instrument
    data = ix.load(out)
    (remainder_note,) = [w for w in ix.fit("R1 + C1", data).warnings if "Re Z < 0" in w]
    (plain_note,) = [w for w in ix.fit("R1 + C1", _without_paths(data)).warnings if "Re Z < 0" in w]
    # (what was counted is said: below −5 % of |Z| and below −kσ of the data's sigma, k = 3.06 for 9 points)
    counted = f"{TOP_NEGATIVE} of {f.size} points have Re Z < 0 by more than 5 % of |Z| and 3.1σ of the noise (the data's sigma;"
    assert remainder_note.startswith(counted) and f"({shown}), which no passive circuit reaches" in remainder_note and f"{TOP_NEGATIVE} of {f.size} points" in plain_note
    assert "in a remainder, the cause is the subtraction" in remainder_note and "measurement artifact" not in remainder_note
    assert "measurement artifact" in plain_note and "subtraction" not in plain_note


def _without_paths(data):
    out = data.copy()
    out.attrs = {k: v for k, v in data.attrs.items() if k not in ("total", "skin", "touchscreen")}
    return out


def test_remaining_of_one_real_sweep_says_one_spectrum_and_no_mean(capsys):
    """REAL data.dfr holds one sweep: its line said "from 1 total spectra (their trial mean, …)"
    until 2026-12-06; the remainder's own ``quantity`` attribute says "one spectrum"."""
    from pathlib import Path

    path = Path(__file__).parent / "fixtures" / "real" / "data.dfr"
    assert main(["remaining", str(path)]) == 0
    err = capsys.readouterr().err
    assert "from 1 total spectrum (one spectrum, nothing averaged, no sigma: total is one spectrum without a sigma of its own" in err, err
    assert "spectra" not in err and "mean" not in err


def test_remaining_of_three_sweeps_each_says_one_spectrum_each(tmp_path, capsys, synthetic_parts):
    """Total, skin and screen of one sweep each: nothing is averaged, so no "trial means"."""
    one_each = {name: ds.isel(trial=0) for name, ds in zip(("total", "skin", "touchscreen"), _datasets(synthetic_parts))}
    paths = saved_gap_files(tmp_path, tuple(one_each.values()))
    assert main(["remaining", *paths]) == 0
    err = capsys.readouterr().err
    assert "from 1 total, 1 skin, 1 touchscreen spectrum (one spectrum each, no sigma: total, skin and touchscreen are one spectrum each without a sigma" in err, err


def test_files_measured_over_different_bands_meet_on_the_one_they_share(tmp_path, capsys, synthetic_parts):
    """SYNTHETIC: the skin measured from 31.6 Hz only, the touchscreen up to 31.6 kHz only (the
    total over 10 Hz–100 kHz): users could not run impedax remaining or impedax gap without
    trimming the files in Python ("measure all three on one frequency grid"). Now the error names
    the shared band and the options that keep it, and --fmin/--fmax keep it: the remainder is eq 5
    by hand on those 5 frequencies."""
    f = synthetic_parts["total"][0]
    keep = {"total": slice(None), "skin": slice(2, None), "ts": slice(None, 7)}
    narrowed = {k: (fz[0][keep[k]], fz[1][:, keep[k]]) for k, fz in synthetic_parts.items()}
    paths = saved_gap_files(tmp_path, _datasets(narrowed))
    out = tmp_path / "rem.nc"
    assert main(["remaining", *paths, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    low, high = f[2], f[6]
    assert f"the grids agree on the 5 frequencies {low:.6g}–{high:.6g} Hz that all of them cover: impedax gap and impedax remaining keep that band with --fmin {low:g} --fmax {high:g}" in err
    assert not out.exists()
    assert main(["remaining", *paths, "--fmin", f"{low:g}", "--fmax", f"{high:g}", "--out", str(out)]) == 0
    shared = {k: (f[2:7], z[:, 2:7] if k == "total" else z[:, : 5] if k == "skin" else z[:, 2:]) for k, (_, z) in narrowed.items()}
    z_rem, sigma = _by_hand(shared)
    written = ix.load(out)
    np.testing.assert_allclose(written["frequency"].values, f[2:7], rtol=1e-14)
    np.testing.assert_allclose(written["Z"].values, z_rem, rtol=1e-12)
    np.testing.assert_allclose(written["sigma"].values, sigma, rtol=1e-12)
    # impedax gap takes the same options, checked before any fit: a band that leaves a file empty is named
    assert main(["gap", *paths, "--area", "130e-6", "--fmin", "2e5"]) == 2
    assert f"--fmin 200000 Hz leaves no frequency of {paths[0]}" in capsys.readouterr().err


def test_a_band_below_the_papers_cutoff_is_said_so(tmp_path, capsys, synthetic_parts):
    """The paper reads C_gap = |Y_R|/ω above 30 Hz (Sirin §2.3). impedax gap --fmax 20 on the
    SYNTHETIC files (10 Hz–100 kHz) stopped after reading them with "no frequencies between the
    cutoff 30 Hz and 10 Hz", naming neither the paper's method nor --fmax; gap_capacitance_paper on
    data below 30 Hz said the same. Now --fmax below 30 Hz is refused before any file is read,
    and the function names the data's band and the reason."""
    from impedax.models import sirin

    paths = saved_gap_files(tmp_path, _datasets(synthetic_parts))
    assert main(["gap", *paths, "--area", "130e-6", "--fmax", "20", "--pooled"]) == 2
    err = capsys.readouterr().err
    assert "--fmax 20 Hz leaves no frequency above 30 Hz, where the paper's method reads C_gap = |Y_R|/ω" in err
    f = np.geomspace(1.0, 20.0, 10)
    with pytest.raises(ix.DataError, match=r"no measured frequency at or above the cutoff 30 Hz: the paper's C_gap is the mean of \|Y_R\|/ω above its cutoff .* the data span 1–20 Hz"):
        sirin.gap_capacitance_paper(1 / (2j * np.pi * f * 4e-10), f)


@pytest.mark.parametrize("command", ["remaining", "gap"])
def test_a_screen_file_of_another_rig_is_refused_before_any_fit(tmp_path, capsys, synthetic_parts, command):
    """A screen spectrum whose reactance exceeds the total's (here 30× it, its resistance small,
    one trial: another rig's file) leaves a remainder with Im Z > 0 at every frequency, where the gap's capacitance
    makes it capacitive; gap sampled for minutes and ended MODEL DOES NOT FIT at rms_rel 100 %
    (walkthrough 2026-12-07). Refused at once, nothing written; the files in order still run."""
    f, z = synthetic_parts["total"]
    screen = ix.make_spectrum(f, 1e4 + 30j * z.mean(0).imag)
    total, skin, _ = _datasets(synthetic_parts)
    paths = saved_gap_files(tmp_path, [total, skin, screen])
    out = tmp_path / ("rem.nc" if command == "remaining" else "gap.json")
    extra = ["--area", "130e-6"] if command == "gap" else []
    assert main([command, *paths, *extra, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"has Im Z > 0 at {f.size} of {f.size} frequencies" in err and "TOTAL SKIN SCREEN" in err
    assert not out.exists()
    good = saved_gap_files(tmp_path, _datasets(synthetic_parts))
    assert main(["remaining", *good, "--out", str(tmp_path / "good.nc")]) == 0


def test_a_contact_with_some_inductive_points_is_not_refused():
    """The SYNTHETIC stationary example's remainder has Im Z > 0 at 19 of its 61 frequencies
    (noise about zero where the gap is small): below the share that marks a wrong file, it is
    analysed as before."""
    from impedax.models import example_spectra
    from impedax.models.gap import INDUCTIVE_REMAINDER_SHARE, gap_remainder

    s = example_spectra()
    total, skin, screen = s["total_stationary"], s["skin"], s["touchscreen"]
    by_hand = total["Z"].mean(("session", "trial")) - skin["Z"].mean(("session", "trial")) - screen["Z"].mean(("session", "trial"))
    inductive = int((by_hand.values.imag > 0).sum())
    assert 0 < inductive < INDUCTIVE_REMAINDER_SHARE * by_hand.size
    remaining, _ = gap_remainder(total, skin, screen)
    np.testing.assert_allclose(remaining["Z"].values, by_hand.values, rtol=1e-12)
