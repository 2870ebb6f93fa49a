"""``--exclude F,F`` of the commands that fit, and the advice of ``diagnose`` and ``refine`` when
their diagnosis masked points: the printed ``impedax fit`` command leaves the same points out
(``--fmin``/``--fmax`` at the band's ends, ``--exclude`` inside it) and reaches the rms_rel the
advice promised. REAL data: tests/fixtures/real (PowerSuite: 2 points with Re Z < 0 at the top;
BioLogic: 4 KK-flagged points inside the band)."""

import importlib
import json
import shlex
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.cli.common import exclude_points
from impedax.errors import ParameterError
from impedax.fitting.diagnosis.diagnosis import left_out_options

REAL = Path(__file__).resolve().parent / "fixtures" / "real"
POWERSUITE = REAL / "exampleDataPowersuite.txt"
BIOLOGIC = REAL / "exampleDataBioLogic.mpt"


def _run_json(argv, capsys) -> dict:
    capsys.readouterr()
    assert main(argv + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


def _command(line: str) -> list[str]:
    """The argv of the ``impedax fit`` command a line of advice ends with."""
    return shlex.split(line[line.index("impedax fit "):])[1:]


def test_left_out_options_cut_the_ends_and_name_the_inside():
    f = np.geomspace(0.1, 1e5, 25)
    masked = (f[0], f[10], f[23], f[24])
    kept = np.delete(f, [0, 10, 23, 24])
    options = dict(left_out_options(kept, masked))
    assert set(options) == {"--fmin", "--fmax", "--exclude"}
    assert f[0] < float(options["--fmin"]) <= f[1] and f[22] <= float(options["--fmax"]) < f[23]
    assert [float(x) for x in options["--exclude"].split(",")] == pytest.approx([f[10]], rel=5e-3)
    assert left_out_options(f, ()) == []


def test_exclude_names_the_nearest_measured_frequency_and_refuses_what_names_none(capsys):
    data = ix.load(BIOLOGIC)
    f = data["frequency"].values
    # the three digits the report prints (5.34 Hz for 5.336 Hz) and an SI prefix
    i, j = int(np.argmin(abs(f - 5.34))), int(np.argmax(f))
    kept = exclude_points(data, f"{f[i]:.3g},{f[j] / 1e3:.4g}k")
    assert kept.sizes["frequency"] == f.size - 2 and f[i] not in kept["frequency"].values and f[j] not in kept["frequency"].values
    with pytest.raises(ParameterError, match=r"--exclude 5\.0: no measured frequency within 0\.5 % of 5 Hz; the nearest are 4\.\d+ Hz and 5\.33\d+ Hz"):
        exclude_points(data, "5.0")
    with pytest.raises(ParameterError, match="name the same measured frequency"):
        exclude_points(data, f"{f[i]:.3g},{f[i]:.5g}")
    # the command line: one message, exit 2
    assert main(["fit", str(BIOLOGIC), "--model", "R0 + R1 || C1", "--exclude", "5.0"]) == 2
    assert "--exclude 5.0: no measured frequency" in capsys.readouterr().err


@pytest.mark.slow  # (the suite's 15-minute budget, 2026-12-01: make test-all runs it)
def test_the_diagnose_advice_leaves_out_the_masked_points_and_reaches_the_promised_rms(tmp_path, capsys):
    summary = tmp_path / "diagnosis.json"
    assert main(["diagnose", str(POWERSUITE), "--model", "R0 + R1 || CPE1 + R2 || CPE2", "--out", str(summary)]) == 0
    text = capsys.readouterr().out
    diagnosis = json.loads(summary.read_text())
    assert len(diagnosis["masked_points"]) == 2 and min(diagnosis["masked_points"]) > 1e6  # (1.12 MHz, 2 MHz: Re Z < 0)
    promised = diagnosis["suggestions"][0]["rms_rel"]
    assert f"rms_rel {promised * 100:.3g} %" in text
    argv = _command(next(x for x in text.splitlines() if "to apply 1." in x))
    assert "--fmax" in argv and "--exclude" not in argv
    out = _run_json(argv, capsys)
    assert out["n_points"] == diagnosis["baseline"]["n_points"]
    assert out["rms_rel"] == pytest.approx(promised, rel=5e-3)  # (before: 40.6 % against 13.6 % promised)


@pytest.mark.slow  # (an end-to-end run of ~10 s: make test-all; the fast suite's 15-minute budget)
def test_refine_keeps_the_interior_points_the_kk_test_flags_and_its_final_fit_reproduces(tmp_path, capsys):
    """BioLogic's real file: the KK test flags 4 points inside the band (5.34, 56.2, 123, 270 Hz).
    Since 2026-12-02 refine leaves out only a flagged run at an end of the band, so these are kept
    and named on the data line (until then they were masked, and the reproduce line carried
    --exclude); the final fit is then ``impedax fit`` of the final model on every point, or the
    line refine prints, with no --exclude."""
    summary = tmp_path / "refinement.json"
    assert main(["refine", str(BIOLOGIC), "--out", str(summary)]) == 0
    text = capsys.readouterr().out
    refinement = json.loads(summary.read_text())
    assert refinement["masked_points"] == []
    data_line = next(x for x in text.splitlines() if x.startswith("data: "))
    assert "the KK test flags 4 points inside the band (5.34 Hz, 56.2 Hz, 123 Hz, 270 Hz): kept in every fit" in data_line
    line = next((x for x in text.splitlines() if x.startswith("to reproduce the final fit")), None)
    argv = _command(line) if line else ["fit", str(BIOLOGIC), "--model", refinement["final_model"]]
    assert not {"--exclude", "--fmin", "--fmax"} & set(argv), argv
    out = _run_json(argv, capsys)
    assert out["model"] == refinement["final_model"] and out["n_points"] == refinement["n_points_judged"]
    assert out["rms_rel"] == pytest.approx(refinement["final_rms_rel"], rel=1e-4)


def test_kk_and_drt_take_the_exclude_that_refine_recommends(capsys, monkeypatch):
    """The points refine masks on BioLogic's real file (``--exclude 5.34,56.2,123,270``) left out
    of the KK test and the DRT as by hand (numpy: the measured frequencies within 0.5 % of each)."""
    drt_module = importlib.import_module("impedax.fitting.drt")  # (the module: `impedax.fitting.drt` the attribute is its function)

    data = ix.load(BIOLOGIC)
    f, z = data["frequency"].values, data["Z"].values
    given = [5.34, 56.2, 123.0, 270.0]
    drop = np.array([np.any(np.abs(fk / np.array(given) - 1) <= 5e-3) for fk in f])
    assert drop.sum() == len(given)
    by_hand = ix.make_spectrum(f[~drop], z[~drop])
    argv = ["--exclude", ",".join(f"{g:g}" for g in given)]
    kk = _run_json(["kk", str(BIOLOGIC), *argv], capsys)
    oracle = ix.kk_test(by_hand).summary()
    assert kk["frequency_hz"] == pytest.approx(f[~drop].tolist(), rel=1e-12)
    assert kk["rms_rel"] == pytest.approx(oracle["rms_rel"], rel=1e-9) and kk["n_rc"] == oracle["n_rc"] and kk["valid"] == oracle["valid"]
    # the DRT is given the same points (its solve, ~6 s on this file, left out: stopped at the call)
    given_to_drt = []

    def stop(spectrum, **options):
        given_to_drt.append(spectrum)
        raise ParameterError("stopped here by the test")

    monkeypatch.setattr(drt_module, "drt", stop)
    assert main(["drt", str(BIOLOGIC), *argv]) == 2 and "stopped here by the test" in capsys.readouterr().err
    (spectrum,) = given_to_drt
    assert np.array_equal(spectrum["frequency"].values, f[~drop]) and np.array_equal(spectrum["Z"].values, z[~drop])
    monkeypatch.undo()
    # a value that names no measured frequency: one message, exit 2, as fit's
    for command in ("kk", "drt"):
        assert main([command, str(BIOLOGIC), "--exclude", "5.0"]) == 2
        assert "--exclude 5.0: no measured frequency within 0.5 % of 5 Hz" in capsys.readouterr().err


def test_a_repeated_exclude_joins_its_lists(capsys):
    """``--exclude 5.34 --exclude 56.2`` leaves out both points, as ``--exclude 5.34,56.2`` does
    (the last one alone was kept, without a word: 2026-12-03 walkthrough). REAL BioLogic data:
    43 points, the oracle the frequencies read from the file."""
    freq = ix.load(BIOLOGIC)["frequency"].values
    assert main(["kk", str(BIOLOGIC), "--exclude", "5.34", "--exclude", "56.2", "--json"]) == 0
    kept = np.array(json.loads(capsys.readouterr().out)["frequency_hz"])
    assert kept.size == freq.size - 2
    for gone in (5.34, 56.2):
        assert np.min(np.abs(kept / gone - 1)) > 0.005 and np.min(np.abs(freq / gone - 1)) < 0.005
    assert main(["kk", str(BIOLOGIC), "--exclude", "5.34,56.2", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["frequency_hz"] == kept.tolist()
