"""EC-Lab's PEIS settings (``fi 1.000`` ``unit fi kHz``, ``ff 10.000`` ``unit ff mHz``,
``E (V) 0.0000`` ``vs. Ref``, ``Va (mV) 20.0``) are kept under the names the other readers use,
and the REAL exampleDataBioLogic.mpt, whose points stop at 16.9 mHz of a sweep planned to 10 mHz,
is told so. The oracle is the file's bytes: its setting lines (a name, then the value after two
or more spaces) and its last data row."""

import re
from pathlib import Path

import impedax as ix
from impedax.cli import main

MPT = Path(__file__).parent / "fixtures" / "real" / "exampleDataBioLogic.mpt"


def _settings() -> dict[str, str]:
    out = {}
    for line in MPT.read_bytes().decode("latin-1").splitlines()[:61]:
        m = re.fullmatch(r"(\S.*?)\s{2,}(\S+)\s*", line)
        if m:
            out[m.group(1)] = m.group(2)
    return out


def test_the_peis_settings_are_kept():
    s = _settings()
    assert (s["fi"], s["unit fi"], s["ff"], s["unit ff"], s["vs."], s["Va (mV)"]) == ("1.000", "kHz", "10.000", "mHz", "Ref", "20.0")
    attrs = ix.load(MPT).attrs
    assert attrs["initial_frequency_hz"] == 1e3 and attrs["final_frequency_hz"] == 10e-3
    assert attrs["dc_voltage_v"] == float(s["E (V)"]) and attrs["dc_voltage_vs"] == "reference electrode"
    assert attrs["ac_amplitude_mv"] == 20.0


def test_points_short_of_the_planned_sweep_are_told(capsys):
    last = MPT.read_bytes().decode("latin-1").splitlines()[-1].split("\t")[0]
    assert float(last) == 1.6895540e-2
    note = ix.load(MPT).attrs["frequency_plan_note"]
    assert note == "the settings plan a sweep from 1 kHz to 10 mHz; the file's points span 1 kHz–16.9 mHz (none below 16.9 mHz)", note
    assert main(["inspect", str(MPT)]) == 0
    assert f"  frequency plan note: {note}\n" in capsys.readouterr().out


def test_a_setting_line_with_several_techniques_values_is_not_kept(tmp_path):
    """Linked techniques write one column of values per technique ('fi  1.000  2.000'): which
    is this spectrum's is not told, so none is kept."""
    raw = MPT.read_bytes().replace(b"fi                  1.000               ", b"fi                  1.000               2.000               ")
    path = tmp_path / "linked.mpt"
    path.write_bytes(raw)
    attrs = ix.load(path).attrs
    assert "initial_frequency_hz" not in attrs and "frequency_plan_note" not in attrs and attrs["final_frequency_hz"] == 10e-3
