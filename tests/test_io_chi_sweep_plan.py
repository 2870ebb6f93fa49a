"""CH Instruments' settings (``High Frequency (Hz) = 2e+6``, ``Low Frequency (Hz) = 0.1``,
``Init E (V) = 0``, ``Amplitude (V) = 0.025``) are kept, and a file whose points stop short of
the sweep they plan is told so: the REAL exampleDataCHInstruments.txt plans 2 MHz to 0.1 Hz, and
its first point is 99.6 kHz. The oracle is the file's bytes: its setting lines and its first
data row."""

from pathlib import Path

import impedax as ix
from impedax.cli import main

CHI = Path(__file__).parent / "fixtures" / "real" / "exampleDataCHInstruments.txt"


def _settings() -> dict[str, float]:
    out = {}
    for line in CHI.read_text().splitlines():
        key, sep, value = line.partition(" = ")
        if sep:
            out[key.strip()] = float(value)
    return out


def test_the_settings_are_kept_as_numbers():
    settings = _settings()
    attrs = ix.load(CHI).attrs
    assert attrs["initial_frequency_hz"] == settings["High Frequency (Hz)"] == 2e6
    assert attrs["final_frequency_hz"] == settings["Low Frequency (Hz)"] == 0.1
    assert attrs["dc_voltage_v"] == settings["Init E (V)"] and attrs["ac_amplitude_mv"] == 1e3 * settings["Amplitude (V)"] == 25.0


def test_points_short_of_the_planned_sweep_are_told(capsys):
    first_row = next(line for line in CHI.read_text().splitlines() if line[:1].isdigit() and "," in line)
    assert float(first_row.split(",")[0]) == 9.961e4
    note = ix.load(CHI).attrs["frequency_plan_note"]
    assert note == "the settings plan a sweep from 2 MHz to 100 mHz; the file's points span 99.6 kHz–100 mHz (none above 99.6 kHz)", note
    assert main(["inspect", str(CHI)]) == 0
    assert f"  frequency plan note: {note}\n" in capsys.readouterr().out


def test_no_setting_of_the_real_files_reads_as_a_drive_voltage():
    """The gap analysis takes an attribute whose name says a voltage for its drive V0 (not a DC,
    rms, mV, OCP value): the settings kept here must not be taken so."""
    from impedax.models.gap_inputs import is_voltage_name

    real = CHI.parent
    for path in sorted(real.iterdir()):
        if path.suffix in (".md", ".json", ".py", ".npz") or path.name.startswith("LICENSE"):
            continue
        taken = [key for key in ix.load(path).attrs if is_voltage_name(key)]
        assert not taken, (path.name, taken)
