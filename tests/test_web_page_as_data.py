"""A web page saved in place of a spectrum file (the page that shows a CSV on a code host, downloaded
with its address) is named as such: until 2026-12-06 "as delimited text, no frequency column in
header ['<!DOCTYPE', 'html>']"."""

import pytest

import impedax as ix

from cli_run import run

SAID = ("not a recognised spectrum file: an HTML web page, not the data (a page that shows the file, saved in its place?): "
        "download the file itself (on GitHub, its Raw button)")


@pytest.mark.parametrize("opening", ["<!DOCTYPE html>\n<html lang=\"en\">\n", "\ufeff  <html>\n", "<HTML>\n"])
def test_a_web_page_is_named(tmp_path, capsys, opening):
    # SYNTHETIC page whose table shows the CSV's first line
    path = tmp_path / "data.csv"
    path.write_text(opening + "<head><title>data.csv</title></head><body><table><tr><td>frequency,zreal,zimag</td></tr>"
                    "<tr><td>1000,10,-5</td></tr></table></body></html>\n", encoding="utf-8")
    with pytest.raises(ix.DataError) as err:
        ix.load(path)
    assert str(err.value).startswith(f"{path}: {SAID}; ")
    code, _, text = run(["kk", path], capsys)
    assert code == 2 and f"{path}: {SAID}" in text


def test_a_plain_table_is_still_read_as_one(tmp_path):
    path = tmp_path / "run.csv"
    path.write_text("frequency,zreal,zimag\n1000,10,-5\n100,12,-8\n10,20,-9\n")
    assert ix.load(path)["Z"].values.tolist() == [10 - 5j, 12 - 8j, 20 - 9j]
