"""VersaStudio's settings of its EIS action (``Start Frequency (Hz)=100000``, ``End Frequency
(Hz)=0.001``, ``Potential (V),Value=0`` with ``Potential (V),Versus=vs Ref``, ``Amplitude (mV
RMS)=20``, ``Working Electrode Area (cm2)=1``) are kept under the names Gamry's are, and the REAL
exampleDataVersaStudio.par, whose points stop at 21.5 mHz of a sweep planned to 1 mHz, is told
so. The oracle is the file's bytes."""

from pathlib import Path

import impedax as ix
from impedax.cli import main
from impedax.data import format_frequency

PAR = Path(__file__).parent / "fixtures" / "real" / "exampleDataVersaStudio.par"


def _setting(key: str) -> str:
    return next(line.split("=", 1)[1] for line in PAR.read_text(encoding="utf-8").splitlines() if line.startswith(key + "="))


def test_the_eis_settings_are_kept():
    attrs = ix.load(PAR).attrs
    assert attrs["initial_frequency_hz"] == float(_setting("Start Frequency (Hz)")) == 1e5
    assert attrs["final_frequency_hz"] == float(_setting("End Frequency (Hz)")) == 1e-3
    assert attrs["dc_voltage_v"] == float(_setting("Potential (V),Value")) and _setting("Potential (V),Versus") == "vs Ref"
    assert attrs["dc_voltage_vs"] == "reference electrode"
    assert attrs["ac_voltage_mv_rms"] == float(_setting("Amplitude (mV RMS)")) == 20.0
    assert attrs["area_cm2"] == float(_setting("Working Electrode Area (cm2)")) == 1.0


def test_points_short_of_the_planned_sweep_are_told(capsys):
    f = ix.load(PAR)["frequency"].values
    note = ix.load(PAR).attrs["frequency_plan_note"]
    assert note == (f"the settings plan a sweep from 100 kHz to 1 mHz; the file's points span 100 kHz–{format_frequency(f.min())} "
                    f"(none below {format_frequency(f.min())})"), note
    assert main(["inspect", str(PAR)]) == 0
    assert f"  frequency plan note: {note}\n" in capsys.readouterr().out
