"""An option that takes one file, given twice: argparse kept the last, so ``impedax fit DATA
--out a.csv --out a.json`` wrote a.json alone and said nothing of a.csv (a walkthrough,
2026-12-06). Now exit 2, one message naming each value, nothing written."""

from __future__ import annotations

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

F = np.geomspace(1.0, 1e5, 30)


@pytest.fixture()
def spectrum(tmp_path):
    w = 2 * np.pi * F
    path = tmp_path / "rc.csv"
    ix.save(ix.make_spectrum(F, 10 + 100 / (1 + 1j * w * 1e-4)), path)  # R0 + R1 ∥ C1
    return path


@pytest.mark.parametrize("argv, flag", [
    (["fit", "{data}", "--model", "R0 + R1 || C1", "--out", "{tmp}/a.csv", "--out={tmp}/a.json"], "--out"),
    (["kk", "{data}", "--plot", "{tmp}/a.png", "--plot", "{tmp}/b.png"], "--plot"),
    (["draw", "R0 + R1 || C1", "-o", "{tmp}/a.png", "--out", "{tmp}/b.png"], "--out"),
])
def test_a_file_option_given_twice_is_refused_naming_both(argv, flag, spectrum, tmp_path, capsys):
    argv = [a.format(data=spectrum, tmp=tmp_path) for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"error: {flag} given 2 times" in err[0] and "it takes one file" in err[0]
    for name in ("a.csv", "a.json", "a.png", "b.png"):
        assert not (tmp_path / name).exists()


def test_once_is_as_before(spectrum, tmp_path, capsys):
    assert main(["fit", str(spectrum), "--model", "R0 + R1 || C1", "--out", str(tmp_path / "a.json"), "--quiet"]) == 0
    assert (tmp_path / "a.json").exists()
