"""Gamry's FREQINIT and FREQFINAL plan the sweep; the REAL exampleDataGamry.DTA's points cover it
(200 kHz to 15.9 mHz of 200 kHz to 20 mHz) and nothing is said; the same file with its rows below
1 Hz cut away (a sweep stopped early) is told short of the plan."""

from pathlib import Path

import impedax as ix
from impedax.data import format_frequency

GAMRY = Path(__file__).parent / "fixtures" / "real" / "exampleDataGamry.DTA"


def test_a_sweep_that_covers_its_plan_is_not_told():
    assert "frequency_plan_note" not in ix.load(GAMRY).attrs


def test_a_sweep_stopped_early_is_told(tmp_path):
    lines = GAMRY.read_bytes().split(b"\r\n") if b"\r\n" in GAMRY.read_bytes() else GAMRY.read_bytes().split(b"\n")
    start = next(k for k, line in enumerate(lines) if line.startswith(b"ZCURVE\t"))
    kept = [line for k, line in enumerate(lines) if not (k > start + 2 and line.startswith(b"\t") and float(line.split(b"\t")[3]) < 1.0)]
    path = tmp_path / "stopped.DTA"
    path.write_bytes(b"\n".join(kept))
    f = ix.load(path)["frequency"].values
    assert f.min() >= 1.0
    assert ix.load(path).attrs["frequency_plan_note"] == (
        f"the settings plan a sweep from 200 kHz to 20 mHz; the file's points span {format_frequency(f.max())}–{format_frequency(f.min())} "
        f"(none below {format_frequency(f.min())})")
