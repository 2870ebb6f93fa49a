"""Every command writes a percentage as the number, a space, % ("rms_rel 1.91 %", "± 2.8 %",
"(10 %)"), as diagnose's and the gap report's text do. Each command's stdout and stderr, on a
REAL file (impedance.py's example, exampleData.csv) and a SYNTHETIC one (R0 + R1 || CPE1 with 1 %
noise), is searched for a digit directly followed by % (a percentage the user types, as
``--noise 5%``, is input and appears in no output here)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

REAL = Path(__file__).parent / "fixtures" / "real" / "exampleData.csv"
REAL_MODEL = "R0 + L0 + R1 || CPE1"
SYNTHETIC_MODEL = "R0 + R1 || CPE1"
_GLUED = re.compile(r"\d%")


def _glued(text: str) -> list[str]:
    return [text[max(0, m.start() - 40): m.end() + 10] for m in _GLUED.finditer(text)]


@pytest.fixture(scope="module")
def synthetic(tmp_path_factory) -> Path:
    f = np.logspace(-1, 5, 31)
    z = 20 + 1e3 / (1 + 1e3 * 2e-5 * (2j * np.pi * f) ** 0.8)
    noise = 0.01 * np.random.default_rng(7).standard_normal((2, 31))
    path = tmp_path_factory.mktemp("pct") / "synthetic_rc.csv"
    ix.save(ix.make_spectrum(f, z.real * (1 + noise[0]) + 1j * z.imag * (1 + noise[1])), path)
    return path


def _commands(path: Path, model: str, real: bool) -> list[list[str]]:
    p = str(path)
    refine = ["refine", p, "--model", model] + (["--max-effects", "1", "--effects", "extra_relaxation"] if real else [])
    runs = [
        ["fit", p, "--model", model + " + R2 || CPE2" if real else model],
        ["fit", p, "--model", model, "--quiet"] if not real else ["fit", p, "--model", model],
        ["compare", p, "--model", model, "--model", model + " + R2 || CPE2"],
        ["kk", p],
        ["drt", p],
        ["diagnose", p, "--model", model],
        refine,
        ["inspect", p],
    ]
    if not real:
        runs.append(["sample", p, "--model", model, "--steps", "20"])
    return runs


@pytest.mark.parametrize("kind", ["real", "synthetic"])
def test_no_command_glues_a_digit_to_percent(kind, synthetic, capsys):
    real = kind == "real"
    path, model = (REAL, REAL_MODEL) if real else (synthetic, SYNTHETIC_MODEL)
    seen = {}
    for argv in _commands(path, model, real):
        code = main(argv)
        out = capsys.readouterr()
        assert code == 0, (argv, out.err)
        seen[argv[0]] = seen.get(argv[0], "") + out.out + out.err
        assert not _glued(out.out + out.err), (argv, _glued(out.out + out.err))
    # the texts searched hold percentages (the search is not vacuous): the fit's error column,
    # the refine step table, the compare and KK tables
    assert re.search(r"\d %", seen["fit"]) and re.search(r"\d %", seen["refine"]) and re.search(r"\d %", seen["compare"]), seen
    assert re.search(r"\d %", seen["kk"]), seen["kk"]
