"""`impedax gap --exclude` and `impedax remaining --exclude` (added 2026-12-06), as fit, diagnose,
refine and sample take it: the points named are dropped from every input file before the
subtraction and every fit, so a run with them equals a run on files from which they were removed
beforehand. SYNTHETIC Sirin-style trials (tests/spectra.py, numpy formulas) with a spike written
at two known frequencies of the total."""

import json

import numpy as np
import pytest

import impedax as ix
from cli_run import run
from gap_files import saved_gap_files
from spectra import sirin_measurements

SPIKED = (10, 25)  # indices of the spiked frequencies on the 41-point 1 Hz–1 MHz grid


class _Result:
    """A stand-in `GapAnalysis`: what the command prints of it."""

    warnings, alarms, settings, v0 = (), (), None, 75.0

    def summary(self):
        return {"v0": self.v0}

    def plot(self):  # (not called without --plot)
        raise AssertionError("no figure asked for")

    remaining = None


def stopped_analysis(monkeypatch, result=False):
    """`gap_analysis` replaced by a stand-in recording the spectra and options it is given; it
    stops the run (a DataError: exit 2) or, with ``result``, returns `_Result`."""
    import impedax.models.gap as gap_module
    from impedax.errors import DataError

    seen = {}

    def reached(total, skin, touchscreen, **options):
        seen.update(data=(total, skin, touchscreen), options=options)
        if result:
            return _Result()
        raise DataError("stand-in: the analysis was reached")

    monkeypatch.setattr(gap_module, "gap_analysis", reached)
    return seen


def _sets(drop=()):
    """(total, skin, touchscreen) with the total's Re Z tripled at `SPIKED` in every trial; the
    indices ``drop`` removed from all three with numpy, independent of impedax."""
    f, total, skin, ts = sirin_measurements(np.random.default_rng(3), 4)
    total = total.copy()
    total[:, list(SPIKED)] = 3 * total[:, list(SPIKED)].real + 1j * total[:, list(SPIKED)].imag
    keep = np.setdiff1d(np.arange(f.size), drop)
    return f[keep], [ix.make_spectrum(f[keep], z[:, keep], dims=("trial",)) for z in (total, skin, ts)]


def _spike_text():
    f, _ = _sets()
    return f, ",".join(f"{f[i]:.3g}" for i in SPIKED)  # (three digits, as a report prints them: matched within 0.5 %)


@pytest.fixture
def folders(tmp_path):
    (tmp_path / "spiked").mkdir()
    (tmp_path / "removed").mkdir()
    return saved_gap_files(tmp_path / "spiked", _sets()[1]), saved_gap_files(tmp_path / "removed", _sets(SPIKED)[1])


def test_gap_exclude_passes_the_data_without_the_points(folders, capsys, monkeypatch):
    """What reaches `gap_analysis` with --exclude is what reaches it from the files written
    without those points."""
    spiked, removed = folders
    _, text = _spike_text()
    with_exclude = stopped_analysis(monkeypatch)
    assert run(["gap", *spiked, "--area", "130e-6", "--pooled", "--quiet", "--exclude", text], capsys)[0] == 2
    beforehand = stopped_analysis(monkeypatch)
    assert run(["gap", *removed, "--area", "130e-6", "--pooled", "--quiet"], capsys)[0] == 2
    f_kept, _ = _sets(SPIKED)
    for got, want in zip(with_exclude["data"], beforehand["data"]):
        np.testing.assert_array_equal(got["frequency"].values, f_kept)
        np.testing.assert_array_equal(got["Z"].values, want["Z"].values)
    assert with_exclude["options"] == beforehand["options"]


def test_gap_exclude_repeated_joins_and_is_recorded_in_the_json(folders, capsys, monkeypatch):
    """--exclude repeated joins its lists (as fit's); the JSON's provenance settings record it
    as every command's do (settings.exclude, the option as given)."""
    spiked, _ = folders
    f, text = _spike_text()
    first, second = text.split(",")
    seen = stopped_analysis(monkeypatch, result=True)
    code, out, err = run(["gap", *spiked, "--area", "130e-6", "--pooled", "--quiet", "--json", "--exclude", first, "--exclude", second], capsys)
    assert code == 0, err
    assert json.loads(out)["provenance"]["settings"]["exclude"] == text
    assert seen["data"][0].sizes["frequency"] == f.size - len(SPIKED)


def test_gap_exclude_of_no_measured_frequency_names_the_file(folders, capsys):
    spiked, _ = folders
    code, out, err = run(["gap", *spiked, "--area", "130e-6", "--pooled", "--quiet", "--exclude", "7"], capsys)
    assert code == 2 and out == ""
    assert "total.nc: --exclude 7: no measured frequency within 0.5 % of 7 Hz" in err and "Traceback" not in err
    code, _, err = run(["gap", *spiked, "--area", "130e-6", "--pooled", "--quiet", "--exclude", "5M"], capsys)
    assert code == 2 and "--exclude 5M: beyond the measured band of every input file" in err and "skin.nc 1–1e+06 Hz" in err
    for value in ("0", "inf"):  # (the option's error, naming no file)
        code, _, err = run(["gap", *spiked, "--area", "130e-6", "--pooled", "--quiet", f"--exclude={value}"], capsys)
        assert code == 2 and err.strip().endswith(f"impedax gap: error: --exclude: frequencies are positive and finite, got {value}")


def test_remaining_exclude_equals_the_remainder_of_the_files_without_the_points(folders, capsys):
    """End to end, no stand-in: the remainder CSV with --exclude is the one of the pre-removed files."""
    spiked, removed = folders
    _, text = _spike_text()
    code, with_exclude, err = run(["remaining", *spiked, "--exclude", text], capsys)
    assert code == 0, err
    code, beforehand, err = run(["remaining", *removed], capsys)
    assert code == 0, err
    assert with_exclude == beforehand
    assert with_exclude.count("\n") == 1 + 41 - len(SPIKED)  # (a header and one row per kept frequency)


@pytest.mark.slow
def test_gap_exclude_end_to_end_equals_the_run_on_the_files_without_the_points(folders, capsys):
    """No stand-in: the --pooled JSON (same seed) with --exclude equals the one of the files
    written without the spiked points, but for the file names and the run's record."""
    spiked, removed = folders
    _, text = _spike_text()
    runs = []
    for paths, extra in ((spiked, ["--exclude", text]), (removed, [])):
        code, out, err = run(["gap", *paths, "--area", "130e-6", "--pooled", "--steps", "200", "--quiet", "--json", *extra], capsys)
        assert code == 0, err
        summary = json.loads(out)
        assert summary.pop("provenance")["settings"]["exclude"] == (text if extra else None)
        for spectra in summary["trials"].values():
            spectra.pop("source")  # (the file each trial set came from)
        runs.append(summary)
    assert runs[0] == runs[1]
    np.testing.assert_allclose(runs[0]["force_n"]["frequency_hz"], _sets(SPIKED)[0], rtol=1e-12)


def _negative_top(tmp_path):
    """SYNTHETIC trials whose remainder (R_EP ∥ C_gap, 1 GΩ ∥ 400 pF) is pushed to Re Z = −5 kΩ at
    the two top frequencies (10^5.5 and 10^6 Hz) of the total, 0.1 % noise: files and those two."""
    rng = np.random.default_rng(0)
    f = np.geomspace(1.0, 1e6, 13)
    remainder = 1 / (1 / 1e9 + 2j * np.pi * f * 400e-12)
    remainder[-2:] = -5e3 + 1j * remainder[-2:].imag
    skin, ts = 300 + 2e5 / (1 + 2j * np.pi * f * 2e5 * 3e-8), 50 + 2e4 / (1 + 2j * np.pi * f * 2e4 * 8e-11)
    trials = [z * (1 + 1e-3 * rng.normal(size=(3, f.size))) for z in (skin + ts + remainder, skin, ts)]
    return saved_gap_files(tmp_path, [ix.make_spectrum(f, z, dims=("trial",)) for z in trials]), f[-2:]


def test_the_re_z_below_zero_advice_names_the_options_and_works(tmp_path, capsys):
    """The note on a remainder's Re Z < 0 says Python's words in Python and the options on the
    command line, where it sent users to impedax fit --exclude alone; following it, impedax
    remaining --exclude with the two frequencies, leaves no such warning."""
    from impedax.models.gap import gap_remainder

    paths, top = _negative_top(tmp_path)
    _, notes = gap_remainder(*(ix.load(p) for p in paths))
    (note,) = [n for n in notes if "Re Z < 0" in n]
    assert note.endswith("leave them out (data.drop_sel(frequency=[...]) of each input spectrum, or a narrower band of all)") and "--" not in note
    code, _, err = run(["remaining", *paths, "--out", tmp_path / "rem.csv"], capsys)
    assert code == 0 and "leave them out (--exclude F,F or --fmin/--fmax, which impedax gap, remaining and fit take)" in err
    code, _, err = run(["remaining", *paths, "--out", tmp_path / "rem2.csv", "--exclude", ",".join(f"{v:.3g}" for v in top)], capsys)
    assert code == 0 and "Re Z < 0" not in err
