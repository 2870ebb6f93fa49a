"""Gamry, ZPlot and CH Instruments dates (docs/io.md, below "What the instrument's file says"): ISO 8601
when the file establishes the order of day and month, else as written with `date_note`, as an EC-Lab
.mpt's (tests/test_biologic_date.py). Until 2026-12-06 each was the text alone: the REAL ZPlot file's
'10-12-2018' is 12 October or 10 December, and nothing said so."""

from pathlib import Path

import pytest

import impedax as ix

REAL = Path(__file__).resolve().parent / "fixtures" / "real"


@pytest.mark.parametrize("name, written, iso", [
    ("exampleDataGamry.DTA", "4/23/2018 16:43:15", "2018-04-23T16:43:15"),  # (DATE 4/23/2018, TIME 16:43:15: 23 is the day)
    ("exampleDataCHInstruments.txt", "Feb. 20, 2020 15:55:08", "2020-02-20T15:55:08"),  # (the month by name)
])
def test_a_real_date_the_file_establishes_is_iso_8601(name, written, iso):
    attrs = ix.load(REAL / name).attrs
    assert (attrs["date"], attrs["date_as_written"]) == (iso, written) and "date_note" not in attrs


def test_the_real_zplot_date_is_said_to_be_ambiguous():
    text = (REAL / "exampleDataZPlot.z").read_text(encoding="latin-1")
    assert "Date:                       10-12-2018\n" in text and "Time:                       11:04:34\n" in text
    attrs = ix.load(REAL / "exampleDataZPlot.z").attrs
    assert attrs["date"] == "10-12-2018 11:04:34" and "date_as_written" not in attrs
    assert attrs["date_note"].startswith("'10-12-2018 11:04:34' is ambiguous: 2018-10-12T11:04:34 (month first, MM/DD/YYYY) "
                                         "or 2018-12-10T11:04:34 (day first, DD/MM/YYYY)")


@pytest.mark.parametrize("calibrated, date, note", [
    ("13/02/2018", "2018-04-02T16:43:15", None),  # (a calibration day above 12 first: the file writes day first)
    ("02/04/2018", "02/04/2018 16:43:15", "'02/04/2018 16:43:15' is ambiguous"),
])
def test_gamry_calibration_dates_tell_the_order(tmp_path, calibrated, date, note):
    # SYNTHETIC header: the REAL .DTA with DATE 02/04/2018 and both calibration dates changed
    text = (REAL / "exampleDataGamry.DTA").read_bytes()
    text = text.replace(b"DATE\tLABEL\t4/23/2018\tDate", b"DATE\tLABEL\t02/04/2018\tDate")
    for key in (b"DCCALDATE", b"ACCALDATE"):
        text = text.replace(key + b"\tLABEL\t4/23/2018", key + b"\tLABEL\t" + calibrated.encode())
    assert b"4/23/2018" not in text
    path = tmp_path / "dated.DTA"
    path.write_bytes(text)
    attrs = ix.load(path).attrs
    assert attrs["date"] == date
    assert (attrs.get("date_note") or "").startswith(note or "") and (note is None) == ("date_note" not in attrs)
