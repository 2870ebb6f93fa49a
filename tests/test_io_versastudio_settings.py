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


def _data_rows() -> list[list[str]]:
    lines = PAR.read_text(encoding="utf-8").splitlines()
    start, end = lines.index("<Segment1>"), lines.index("</Segment1>")
    return [line.split(",") for line in lines[start:end] if line[:1].isdigit() or line[:1] == "-"]


def test_what_number_of_points_means_is_told(capsys):
    """The REAL file's header says ``Number of Points=30`` beside ``Point Spacing=Logarithmic`` and
    ``Points Per Decade=9``; its segment holds 61 rows, each a ninth of a decade below the last
    (100 kHz, 77.4 kHz, ... 21.5 mHz): the points per decade set the sweep, 8 decades × 9 + 1 = 73
    planned from 100 kHz to 1 mHz, and 30 counts nothing in it. inspect says so, and not a
    bare "30"."""
    import math

    assert (_setting("Number of Points"), _setting("Point Spacing"), _setting("Points Per Decade")) == ("30", "Logarithmic", "9")
    rows = _data_rows()
    frequency = [float(r[9]) for r in rows]
    assert len(rows) == 61 and [r[1] for r in rows] == [str(k) for k in range(61)]
    assert all(abs(math.log10(a / b) - 1 / 9) < 1e-5 for a, b in zip(frequency, frequency[1:]))
    assert round(math.log10(1e5 / 1e-3) * 9) + 1 == 73
    note = ix.load(PAR).attrs["point_count_note"]
    assert note == ("Point Spacing=Logarithmic, Points Per Decade=9: 73 points planned from 100 kHz to 1 mHz; the file holds 61 rows, 9 a decade "
                    "from 100 kHz to 21.5 mHz; its 'Number of Points=30' is not this sweep's count (the rows step by 1/9 decade, as Points Per Decade sets)"), note
    assert main(["inspect", str(PAR)]) == 0
    out = capsys.readouterr().out
    assert f"  point count note: {note}\n" in out and out.count("30") == 1


def _with_settings(tmp_path, **replaced) -> Path:
    text = PAR.read_text(encoding="utf-8")
    for key, value in replaced.items():
        text = text.replace(f"\n{key}={_setting(key)}\n", f"\n{key}={value}\n")
    path = tmp_path / "edited.par"
    path.write_text(text, encoding="utf-8")
    return path


def test_a_count_that_matches_the_rows_is_not_told(tmp_path):
    """SYNTHETIC: the REAL file with its plan ending where its rows end (21.544 mHz: 61 points at 9 a
    decade) and ``Number of Points=61``: nothing to tell."""
    path = _with_settings(tmp_path, **{"Number of Points": "61", "End Frequency (Hz)": "0.02154435"})
    attrs = ix.load(path).attrs
    assert "point_count_note" not in attrs and "frequency_plan_note" not in attrs


def test_linear_spacing_takes_the_count_from_number_of_points(tmp_path):
    """SYNTHETIC: the REAL file's header edited to ``Point Spacing=Linear``: its Number of Points is
    then the sweep's count, and 61 rows against 30 are told as another instrument's count."""
    path = _with_settings(tmp_path, **{"Point Spacing": "Linear"})
    assert ix.load(path).attrs["point_count_note"] == "header says 'Number of Points=30'; the file holds 61 rows"
