"""``--json`` gives a result's warnings in the words of the command's text output: the
command line's options (``--weighting modulus``, ``--steps 2000``), not Python's keywords
(``weighting='modulus'``, ``steps=2000``), which only the Python API says. Until 2026-12-06 the
JSON of ``impedax fit`` and ``impedax sample`` kept Python's words where the text said the
option. Oracle: the text output of the same command on the same file; the values and keys are
unchanged."""

import json

import numpy as np
import pytest

from cli_run import run
from impedax.cli.common import json_in_command_words


def _crossing_spectrum(path):
    """SYNTHETIC R0 + L1 + R1 ∥ C1 (10 Ω, 1 kΩ, 1 µF) whose Im Z crosses zero at its 31st
    point, set to Im Z = 1e-9 Ω there: proportional weighting gives that point all the weight
    (1/Im² ≈ 1e18), so the fit warns that it is dominated by it."""
    f = np.logspace(0, 6, 41)
    w = 2 * np.pi * f
    r1, c1 = 1e3, 1e-6
    inductance = r1 * r1 * c1 / (1 + (w[30] * r1 * c1) ** 2)  # (Im of the R1 ∥ C1 arc cancelled by ωL at f[30])
    z = 10 + 1j * w * inductance + r1 / (1 + 1j * w * r1 * c1)
    z[30] = z[30].real + 1e-9j
    np.savetxt(path, np.c_[f, z.real, z.imag], delimiter=",", header="frequency_hz,z_real_ohm,z_imag_ohm", comments="")
    return path


def test_fit_json_warning_says_the_weighting_option_as_the_text_does(tmp_path, capsys):
    data = _crossing_spectrum(tmp_path / "cross.csv")
    argv = ["fit", data, "--model", "R0 + L1 + R1 || C1", "--weighting", "proportional", "-q"]
    code, text, err = run(argv, capsys)
    assert code == 0
    said = [line.split("warning: ", 1)[1] for line in (text + err).splitlines() if "proportional weighting gives" in line]
    assert said and said[0].endswith("consider --weighting modulus")
    code, out, _ = run(argv + ["--json"], capsys)
    assert code == 0
    summary = json.loads(out)
    (warned,) = [w for w in summary["warnings"] if "proportional weighting gives" in w]
    assert warned == said[0]
    assert "weighting='" not in out
    assert summary["weighting"] == "proportional" and summary["provenance"]["settings"]["weighting"] == "proportional"  # (values unchanged)


@pytest.mark.slow
def test_sample_json_warning_says_the_steps_option_as_the_text_does(tmp_path, capsys):
    f = np.logspace(4, -1, 30)
    z = 20.0 + 1.0 / (1.0 / 500.0 + 1j * 2 * np.pi * f * 1e-5)  # SYNTHETIC R0 + R1 ∥ C1, 1 % noise
    z = z * (1 + 0.01 * np.random.default_rng(0).standard_normal(f.size))
    data = tmp_path / "rc.csv"
    np.savetxt(data, np.c_[f, z.real, z.imag], delimiter=",", header="frequency_hz,z_real_ohm,z_imag_ohm", comments="")
    argv = ["sample", data, "--model", "R0 + R1 || C1", "--steps", "600", "--seed", "1", "-q"]
    code, out, _ = run(argv + ["--json"], capsys)
    assert code == 0
    summary = json.loads(out)
    (warned,) = [w for w in summary["warnings"] if "autocorrelation times" in w]
    assert "--steps auto (the default)" in warned and "(--steps " in warned
    assert "steps=" not in warned and "steps='auto'" not in warned
    assert summary["steps"] == 600  # (the key and its value unchanged)
    code, text, err = run(argv, capsys)
    assert warned in text + err  # (the same words as the text output)


def test_only_prose_is_translated_and_per_command():
    summary = {"warnings": {"steps=3": ["consider weighting='modulus'"]}, "warning_kinds": [{"warning": "raise max_steps", "spectra": ["steps=3"]}],
               "weighting": "modulus", "model": "R0 + R1 || C1", "source": "runs/max_steps.csv", "notes": ["use noise='proportional' otherwise"]}
    fit = json_in_command_words(summary, "fit")
    assert fit["warnings"] == {"steps=3": ["consider --weighting modulus"]}  # (a label as a key is kept)
    assert fit["warning_kinds"] == [{"warning": "raise --max-steps", "spectra": ["steps=3"]}]  # (a label is no prose)
    assert fit["source"] == "runs/max_steps.csv" and fit["weighting"] == "modulus"
    assert fit["notes"] == ["use noise='proportional' otherwise"]  # (fit has no --noise)
    assert json_in_command_words(summary, "sample")["notes"] == ["use --noise proportional otherwise"]
    assert json_in_command_words(summary, "gap")["warnings"] == summary["warnings"]  # (gap has no --weighting: its text keeps Python's words)
    assert json_in_command_words(summary, None) is summary


def test_out_json_is_the_json_document_and_the_csv_says_the_option(tmp_path, capsys):
    """``--out FILE.json`` is the ``--json`` document (docs/robustness.md), in the same words;
    the CSV's warnings column says what the text says. Read back with json and csv."""
    import csv

    data = _crossing_spectrum(tmp_path / "cross.csv")
    argv = ["fit", data, "--model", "R0 + L1 + R1 || C1", "--weighting", "proportional", "-q"]
    code, out, _ = run(argv + ["--json", "--out", tmp_path / "fit.json"], capsys)
    assert code == 0
    printed, written = json.loads(out), json.loads((tmp_path / "fit.json").read_text(encoding="utf-8"))
    assert written["warnings"] == printed["warnings"] and any(w.endswith("consider --weighting modulus") for w in written["warnings"])
    code, _, _ = run(argv + ["--out", tmp_path / "fit.csv"], capsys)
    assert code == 0
    with open(tmp_path / "fit.csv", newline="", encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    assert rows and all("consider --weighting modulus" in r["warnings"] and "weighting='" not in r["warnings"] for r in rows)
    assert all(r["weighting"] == "proportional" for r in rows)
