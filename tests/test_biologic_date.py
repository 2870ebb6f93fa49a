"""An EC-Lab .mpt's date (docs/io.md, "What the instrument's file says"): ISO 8601 when the file
establishes the order of day and month, else kept as written with `date_note` giving both readings.
Until 2026-12-06 `date` was the text alone: the REAL file's '02/04/2018' is 4 February or 2 April."""

from pathlib import Path

import pytest

import impedax as ix

REAL = Path(__file__).resolve().parent / "fixtures" / "real" / "exampleDataBioLogic.mpt"
WRITTEN = "02/04/2018 10:02:46"  # (lines 13 and 14 of the REAL file)


def test_the_real_files_date_is_said_to_be_ambiguous():
    lines = REAL.read_bytes().decode("latin-1").splitlines()
    assert lines[12] == f"Acquisition started on : {WRITTEN}" and lines[13] == f"Technique started on : {WRITTEN}"
    attrs = ix.load(REAL).attrs
    assert attrs["date"] == WRITTEN and "date_as_written" not in attrs
    # both readings, by hand: 2 April or 4 February 2018
    assert attrs["date_note"] == (f"'{WRITTEN}' is ambiguous: 2018-02-04T10:02:46 (month first, MM/DD/YYYY) or 2018-04-02T10:02:46 "
                                  f"(day first, DD/MM/YYYY); no day above 12 in the file's dates ('{WRITTEN}') tells which; kept as written")


@pytest.mark.parametrize("acquisition, technique, iso", [
    ("06/15/2023 16:30:52.260", "06/15/2023 16:30:52.260", "2023-06-15T16:30:52.260"),  # a day above 12 second: month first
    ("15/06/2023 9:30:52", "15/06/2023 9:31:00", "2023-06-15T09:30:52"),  # a day above 12 first: day first
    ("02/04/2018 10:02:46", "02/14/2018 11:00:00", "2018-02-04T10:02:46"),  # the technique's date tells the acquisition's order
    ("02.04.2018 10:02:46", "14.04.2018 10:02:46", "2018-04-02T10:02:46"),
    ("2018-04-02 10:02:46", "2018-04-02 10:02:46", "2018-04-02T10:02:46"),  # year first
])
def test_a_date_whose_order_the_file_establishes_is_iso_8601(tmp_path, acquisition, technique, iso):
    # SYNTHETIC headers: the REAL file with other dates written in
    text = REAL.read_bytes().replace(f"Acquisition started on : {WRITTEN}".encode(), f"Acquisition started on : {acquisition}".encode())
    text = text.replace(f"Technique started on : {WRITTEN}".encode(), f"Technique started on : {technique}".encode())
    path = tmp_path / "dated.mpt"
    path.write_bytes(text)
    attrs = ix.load(path).attrs
    assert (attrs["date"], attrs["date_as_written"]) == (iso, acquisition) and "date_note" not in attrs


@pytest.mark.parametrize("written, note", [
    ("13/13/2020 10:00:00", "'13/13/2020 10:00:00' is no date read month first (MM/DD/YYYY) nor day first (DD/MM/YYYY); kept as written"),
    ("Monday 10:00", "'Monday 10:00' is not read as a date (day, month and year with '/', '-' or '.', or a month by name); kept as written"),
])
def test_a_date_that_is_no_date_is_kept_and_said_so(tmp_path, written, note):
    path = tmp_path / "odd.mpt"
    path.write_bytes(REAL.read_bytes().replace(WRITTEN.encode(), written.encode()))
    attrs = ix.load(path).attrs
    assert (attrs["date"], attrs["date_note"]) == (written, note)
