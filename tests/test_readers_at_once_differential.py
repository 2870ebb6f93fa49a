"""The REAL text files of tests/fixtures/real/, mutated at random (a cell turned into text, a
comma, a space, an empty cell, a cell too many or too few, a line dropped or repeated, the file
cut), read with the table engine's fast paths (`impedax.io.table._columns_at_once`,
`_sweeps_at_once`, `RowBlock`, `impedax.io.csv._split_rows`) and without them (the row-by-row loop and a Dataset per sweep, as
before 2026-12-06): the same Dataset or the same message, every time. Seeded; set
IMPEDAX_AT_ONCE_EXAMPLES for a longer search (600 per file passed on 2026-12-06)."""

import os
import random
from pathlib import Path

import pytest

import impedax as ix
from impedax.io import csv as delimited
from impedax.io import table

REAL = Path(__file__).parent / "fixtures" / "real"
TEXT_FILES = sorted(p for p in REAL.iterdir() if p.suffix.lower() in (".csv", ".txt", ".mpt", ".dta", ".z", ".par"))
EXAMPLES = int(os.environ.get("IMPEDAX_AT_ONCE_EXAMPLES", "6"))
_CELLS = ["abc", "", "1,5", "1.5", " 7 ", "nan", "1e999", "-", "0", '"3"', "1_0", "+.5e-3"]


def _mutated(text: str, rng: random.Random) -> str:
    lines = text.split("\n")
    k = rng.randrange(len(lines))
    kind = rng.choice(["cell", "cell", "cell", "extra", "short", "drop", "repeat", "cut"])
    delimiter = next((d for d in ("\t", ";", ",") if d in lines[k]), " ")
    cells = lines[k].split(delimiter)
    if kind == "cell":
        cells[rng.randrange(len(cells))] = rng.choice(_CELLS)
    elif kind == "extra":
        cells.append(rng.choice(_CELLS))
    elif kind == "short" and len(cells) > 1:
        cells.pop(rng.randrange(len(cells)))
    elif kind == "drop":
        return "\n".join(lines[:k] + lines[k + 1:])
    elif kind == "repeat":
        return "\n".join(lines[: k + 1] + lines[k:])
    elif kind == "cut":
        return text[: rng.randrange(len(text) // 2, len(text))]
    lines[k] = delimiter.join(cells)
    return "\n".join(lines)


def _read(path: Path):
    try:
        return ix.load(path)
    except ix.DataError as exc:
        return str(exc)


@pytest.mark.parametrize("real", TEXT_FILES, ids=lambda p: p.name)
def test_mutated_real_files_read_the_same_at_once_and_row_by_row(tmp_path, monkeypatch, real):
    rng = random.Random(real.name)
    text = real.read_text(encoding="latin-1")
    path = tmp_path / real.name
    split = table.RowBlock.split
    for _ in range(EXAMPLES):
        path.write_text(_mutated(text, rng), encoding="latin-1")
        fast = _read(path)
        with monkeypatch.context() as m:
            m.setattr(table, "_columns_at_once", lambda *args: None)
            m.setattr(table, "_sweeps_at_once", lambda *args: None)
            m.setattr(table.RowBlock, "split", classmethod(lambda cls, numbered, delimiter: [(n, t.split(delimiter)) for n, t in numbered]))
            m.setattr(delimited, "_split_rows", lambda rows, delimiter: [(n, delimited.split_line(t, delimiter)) for n, t in rows])
            slow = _read(path)
        assert table.RowBlock.split == split
        if isinstance(slow, str) or isinstance(fast, str):
            assert fast == slow
        else:
            assert fast.identical(slow)
