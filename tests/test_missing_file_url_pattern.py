"""A web address or an unexpanded pattern given as a file (docs/io.md, "How a file is recognised"):
until 2026-12-06 "https:/example.org/run.csv: file not found; there is no folder 'https:/example.org'"
and "data/*.csv: file not found; there is no folder 'data'" or "file not found" alone."""

import shutil
from pathlib import Path

import pytest

import impedax as ix

from cli_run import run

REAL = Path(__file__).resolve().parent / "fixtures" / "real"


@pytest.fixture
def folder(tmp_path, monkeypatch):
    # the REAL ZPlot and CH Instruments files, copied into an empty folder
    for name in ("exampleDataZPlot.z", "exampleDataCHInstruments.txt"):
        shutil.copy(REAL / name, tmp_path / name)
    monkeypatch.chdir(tmp_path)
    return tmp_path


@pytest.mark.parametrize("given, said", [
    ("https://example.org/run.csv", "https:/example.org/run.csv: file not found; it is a web address, and impedax reads files on this computer: "
                                    "download it first (curl -O URL), or pipe it in with '-' for the file (curl -s URL | impedax COMMAND -)"),
    ("example*", "example*: file not found; 'example*' is a pattern of file names that the shell did not expand (was it quoted?): it matches "
                 "2 files here (exampleDataCHInstruments.txt, exampleDataZPlot.z); leave out the quotes"),
    ("runs/*.csv", "runs/*.csv: file not found; '*.csv' is a pattern of file names, and no file matches it"),
])
def test_the_name_is_told_for_what_it_is(folder, capsys, given, said):
    with pytest.raises(ix.DataError) as err:
        ix.load(given)
    assert str(err.value) == said
    code, _, err_text = run(["kk", given], capsys)
    assert code == 2 and err_text.strip() == f"impedax kk: error: {said}"
