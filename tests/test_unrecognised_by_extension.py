"""A file no reader claims whose extension belongs to one reader alone (`Reader.extensions`)
is told first why that reader refused it (docs/io.md, "How a file is recognised")."""

from pathlib import Path

import pytest

import impedax as ix
from impedax.io import Reader, register_reader

REAL = Path(__file__).resolve().parent / "fixtures" / "real"


def test_a_real_mpt_without_its_first_line_names_the_biologic_reason(tmp_path):
    # REAL exampleDataBioLogic.mpt opens with "EC-Lab ASCII FILE", EC-Lab's signature line; without it
    # users were told only "as delimited text, no frequency column in header ['Nb', 'header', ...]"
    raw = (REAL / "exampleDataBioLogic.mpt").read_bytes()
    first, rest = raw.split(b"\n", 1)
    assert first.strip() == b"EC-Lab ASCII FILE"
    path = tmp_path / "cell.mpt"
    path.write_bytes(rest)
    with pytest.raises(ix.DataError) as caught:
        ix.load(path)
    assert str(caught.value).startswith(f"{path}, line 1: not a recognised spectrum file: named .mpt, the extension of reader "
                                        "'BioLogic EC-Lab mpt', which does not recognise it: first line is not 'EC-Lab ASCII FILE'; "
                                        "as delimited text, no frequency column")


def test_an_upper_case_extension_and_a_users_reader(tmp_path):
    path = tmp_path / "run.LAB"
    path.write_text("time;voltage\n1;2\n")
    mine = Reader("LAB", (".lab",), lambda p, h: None if h.startswith(b"LAB/1") else "no 'LAB/1' first line", lambda p: None)
    with pytest.raises(ix.DataError, match=r"not a recognised spectrum file: named \.LAB, the extension of reader 'LAB', which does not recognise it: "
                                           r"no 'LAB/1' first line; as delimited text"):
        ix.load(path, readers=register_reader(mine))


@pytest.mark.parametrize("name", ["notes.txt", "notes.csv", "notes"])
def test_an_extension_of_several_readers_or_none_keeps_the_message(tmp_path, name):
    # (.txt and .csv are listed by several readers: no one of them is the format the name promises)
    path = tmp_path / name
    path.write_text("voltage,current\n1,2\n")
    with pytest.raises(ix.DataError, match=r"line 1: not a recognised spectrum file: as delimited text, no frequency column"):
        ix.load(path)
