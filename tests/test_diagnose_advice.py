"""The advice of ``impedax diagnose`` runs as printed (the run's file, --select, --fmin, --fmax
and --weighting carried into its ``impedax fit`` line), and ``--noise`` of diagnose and refine
takes a fraction or a percentage and refuses a bare 5 (500 %). REAL data: the AutoEIS battery
cycles and tests/fixtures/real/exampleData.csv."""

import json
import shlex
from pathlib import Path
from types import SimpleNamespace

import pytest

import impedax as ix

from impedax.cli import main
from impedax.cli.common import fit_command, relative_noise
from impedax.errors import ParameterError

ROOT = Path(__file__).resolve().parents[1]
CYCLES = ROOT / "examples" / "data" / "autoeis_battery_cycles.nc"
EXAMPLE = ROOT / "tests" / "fixtures" / "real" / "exampleData.csv"

# the keys of ``impedax diagnose --json`` before the advice named the file (keys may be added)
DIAGNOSE_KEYS = {
    "model", "baseline", "kk", "noise", "masked_points", "failing_bands", "verdict", "reason", "suggestions",
    "candidates", "thresholds", "notes", "drt_peaks", "drt_summary",
}


@pytest.mark.slow  # (the suite's 15-minute budget, 2026-12-01: make test-all runs it)
def test_the_advice_fits_the_selected_spectrum_on_the_run_s_points(tmp_path, capsys):
    """A range that picks one cycle (cycles 0, 64, 129: 100:200 is 129) is advised as that
    cycle's label: `impedax fit` reads a range as a batch (of one)."""
    summary = tmp_path / "diagnosis.json"
    argv = ["diagnose", str(CYCLES), "--select", "cycle=100:200", "--fmin", "0.05", "--weighting", "proportional",
            "--model", "R0 + R1 || CPE1 + W1", "--effects", "extra_relaxation", "--out", str(summary)]
    assert main(argv) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if "to apply 1." in x)
    command = shlex.split(line[line.index("impedax fit "):])
    assert command[:5] == ["impedax", "fit", str(CYCLES), "--select", "cycle=129"] and "DATA" not in command
    diagnosis = json.loads(summary.read_text())
    assert set(diagnosis) >= DIAGNOSE_KEYS
    best = diagnosis["suggestions"][0]
    assert main([*command[1:], "--json"]) == 0
    fitted = json.loads(capsys.readouterr().out)
    assert "n_spectra" not in fitted  # one spectrum (cycle 129), not the file's three
    assert fitted["model"] == best["model"] and fitted["weighting"] == "proportional"
    assert fitted["n_points"] == diagnosis["baseline"]["n_points"]  # the points above --fmin
    assert fitted["rms_rel"] == pytest.approx(best["rms_rel"], rel=1e-3)


def test_fit_command_quotes_the_file_and_leaves_out_the_defaults():
    args = SimpleNamespace(data="my data/cell 1.csv", select=["cycle=129"], weighting="modulus", fmin=None, fmax=1000.0)
    assert fit_command(args) == "impedax fit 'my data/cell 1.csv' --select cycle=129 --fmax 1000.0"
    assert fit_command() == "impedax fit DATA"  # (the Python API's report)


def test_fit_command_gives_a_list_or_range_that_picked_one_spectrum_as_its_label():
    """The labels the picks name (by value: 4:4, 3:5, 4.0:4.5 and 'a,b' whole) and, where a
    dimension has no labels, the position a range's first end names; a plain label, and a
    dimension the data still have, are repeated as written."""
    import numpy as np

    from impedax.cli.common import select_spectra

    f = np.geomspace(1.0, 1e4, 4)
    z = np.arange(1.0, 13.0).reshape(3, 4) + 0j
    cycles = ix.make_spectrum(f, z, dims=("cycle",), coords={"cycle": [2, 4, 8]})
    sheets = ix.make_spectrum(f, z, dims=("sheet",), coords={"sheet": ["a", "a,b", "c"]})
    trials = ix.make_spectrum(f, z, dims=("trial",)).drop_vars("trial", errors="ignore")
    cases = [
        (cycles, "cycle=4:4", "cycle=4"), (cycles, "cycle=3:5", "cycle=4"), (cycles, "cycle=4.0:4.5", "cycle=4"), (cycles, "cycle=5:", "cycle=8"),
        (cycles, "cycle=4", "cycle=4"), (sheets, "sheet=a,b", "sheet=a,b"),
        (trials, "trial=1:1", "trial=1"), (trials, "trial=2:", "trial=2"), (trials, "trial=:0", "trial=0"),
    ]
    for data, item, expected in cases:
        picked = select_spectra(data, "f.nc", [item], single="impedax diagnose")
        assert picked["Z"].dims == ("frequency",)
        assert fit_command(SimpleNamespace(data="f.nc", select=[item]), data=picked) == f"impedax fit f.nc --select {expected}"
    several = select_spectra(cycles, "f.nc", ["cycle=3:9"])  # (two spectra: the range stays)
    assert fit_command(SimpleNamespace(data="f.nc", select=["cycle=3:9"]), data=several) == "impedax fit f.nc --select cycle=3:9"


@pytest.mark.parametrize("text, value", [("0.05", 0.05), ("5%", 0.05), (" 2.5 %", 0.025), ("99.5%", 0.995), (None, None)])
def test_noise_is_a_fraction_or_a_percentage(text, value):
    assert relative_noise(text) == pytest.approx(value)


@pytest.mark.parametrize("text", ["0", "-0.01", "nan", "inf%", "abc", "%", "150%", "100%"])
def test_noise_that_is_no_level_is_refused(text):
    with pytest.raises(ParameterError, match="--noise"):
        relative_noise(text)


@pytest.mark.parametrize("command", ["diagnose", "refine"])
def test_a_bare_noise_of_1_or_more_is_refused(command, capsys):
    assert main([command, str(EXAMPLE), "--model", "R0 + R1 || C1", "--noise", "5"]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.splitlines() == [f"impedax {command}: error: --noise 5: a bare value is a fraction of |Z| (0.05 for 5 %), so 5 would be 500 %; write 5% or 0.05"]


@pytest.mark.slow  # (10 s; the suite's budget: relative_noise's parsing is tested above)
def test_noise_in_percent_is_the_fraction(capsys):
    assert main(["diagnose", str(EXAMPLE), "--model", "R0 + R1 || C1", "--noise", "5%", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) >= DIAGNOSE_KEYS
    assert out["noise"]["level"] == pytest.approx(0.05) and out["noise"]["source"] == "given"


@pytest.mark.slow  # (the suite's 15-minute budget, 2026-12-01: make test-all runs it)
def test_a_term_that_ran_open_in_the_advice_is_named_with_the_model_without_it(capsys):
    """REAL exampleData.csv with ``R0 + R1 || CPE1``: R1 runs open (1.19e+282 Ω) in the
    suggestion's fit too, so its "to apply" line needs ``--init R1=1.19e+282``. A note names the
    open R1 and gives the model without it, which fits as well with one parameter fewer, every
    parameter determined; its command runs as printed. ``R0 + R1 || C1 + L_lead`` (R1 finite): no note."""
    assert main(["diagnose", str(EXAMPLE), "--model", "R0 + R1 || CPE1", "--effects", "series_inductance"]) == 0
    lines = capsys.readouterr().out.splitlines()
    i = next(k for k, x in enumerate(lines) if "to apply 1." in x)
    note = lines[i + 1]
    assert note.strip().startswith("note: R1 carries at most") and "R1 = 1.19e+282 Ω, at its bound" in note
    applied = json.loads(_fitted(shlex.split(lines[i][lines[i].index("impedax fit "):]), capsys))
    simpler = json.loads(_fitted(shlex.split(note[note.index("impedax fit "):]), capsys))
    assert simpler["model"] == "R0 + CPE1 + L_lead" and simpler["n_params"] == applied["n_params"] - 1
    assert simpler["rms_rel"] == pytest.approx(applied["rms_rel"], rel=1e-3)
    assert all(p["stderr"] is not None and p["stderr"] < abs(p["value"]) for p in simpler["params"].values())
    # a suggestion whose terms all stay (R1 finite beside C1 with a lead added): no note
    from impedax.fitting.diagnosis.diagnosis import _without_vanished_lines

    kept = ix.fit("R0 + R1 || C1 + L_lead", ix.load(EXAMPLE))
    assert kept.values["R1"] < 1.0 and _without_vanished_lines(kept, "impedax fit DATA") == []


def _fitted(command: list[str], capsys) -> str:
    assert command[:2] == ["impedax", "fit"]
    capsys.readouterr()
    assert main([*command[1:], "--json"]) == 0
    return capsys.readouterr().out
