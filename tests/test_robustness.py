"""Every CLI command on hostile input: exit code 2, one clear message, no traceback, no output.

The tables are built to grow: add a command to FILE_COMMANDS (reads a spectrum file),
MODEL_COMMANDS (takes a circuit) or OUTPUT_COMMANDS (writes a file) and it meets every bad
input of the matching table. Placeholders: ``{input}`` the bad file, ``{good}`` a valid
spectrum file, ``{model}`` the bad model, ``{output}`` the bad output path, ``{tmp}`` the
test's folder. docs/robustness.md lists these rows and what impedax does with each.
"""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

# --- commands -------------------------------------------------------------------------------

FILE_COMMANDS = [  # (id, argv template with {input})
    ("inspect", ["inspect", "{input}"]),
    ("inspect-json", ["inspect", "{input}", "--json", "--out", "{tmp}/converted.nc"]),
    ("fit", ["fit", "{input}", "--model", "R1 + C1", "--json", "--out", "{tmp}/fit.nc"]),
    ("compare", ["compare", "{input}", "--model", "R1", "--model", "R1 + C1"]),
    ("sample", ["sample", "{input}", "--model", "R1 + C1", "--steps", "20", "--json", "--out", "{tmp}/post.nc"]),
    ("gap", ["gap", "{input}", "{tmp}/good.csv", "{tmp}/good.csv", "--area", "130e-6", "--json", "--out", "{tmp}/gap.nc"]),
    ("diagnose", ["diagnose", "{input}", "--model", "R1 + C1", "--json"]),
    ("refine", ["refine", "{input}", "--model", "R1 + C1", "--max-steps", "1", "--json"]),
]
MODEL_COMMANDS = [  # (id, argv template with {model})
    ("info", ["info", "{model}"]),
    ("simulate", ["simulate", "{model}", "--out", "{tmp}/out.csv"]),
    ("draw", ["draw", "{model}", "-o", "{tmp}/out.svg"]),
    ("fit", ["fit", "{tmp}/good.csv", "--model", "{model}"]),
    ("compare", ["compare", "{tmp}/good.csv", "--model", "R1", "--model", "{model}"]),
    ("sample", ["sample", "{tmp}/good.csv", "--model", "{model}", "--steps", "20"]),
    ("diagnose", ["diagnose", "{tmp}/good.csv", "--model", "{model}"]),
    ("refine", ["refine", "{tmp}/good.csv", "--model", "{model}"]),
]
PARAM_COMMANDS = [  # (id, argv template with {model} and {param})
    ("simulate", ["simulate", "{model}", "--param", "{param}", "--out", "{tmp}/out.csv"]),
    ("draw", ["draw", "{model}", "--param", "{param}", "-o", "{tmp}/out.png"]),
    ("fit-fix", ["fit", "{tmp}/good.csv", "--model", "{model}", "--fix", "{param}"]),
    ("fit-init", ["fit", "{tmp}/good.csv", "--model", "{model}", "--init", "{param}"]),
]
PRIOR_COMMANDS = [  # (id, argv template with {prior})
    ("sample", ["sample", "{tmp}/good.csv", "--model", "R1 + CPE1", "--steps", "20", "--prior", "{prior}", "--out", "{tmp}/post.nc"]),
]
OUTPUT_COMMANDS = [  # (id, argv template with {output}, output extension)
    ("simulate", ["simulate", "R1 + C1", "--out", "{output}"], ".csv"),
    ("simulate-plot", ["simulate", "R1 + C1", "--plot", "{output}"], ".png"),
    ("draw", ["draw", "R1 + C1", "-o", "{output}"], ".svg"),
    ("inspect", ["inspect", "{good}", "--out", "{output}"], ".nc"),
    ("fit-out", ["fit", "{good}", "--model", "R1 + C1", "--out", "{output}"], ".nc"),
    ("fit-plot", ["fit", "{good}", "--model", "R1 + C1", "--plot", "{output}"], ".png"),
    ("compare-plot", ["compare", "{good}", "--model", "R1", "--model", "R1 + C1", "--plot", "{output}"], ".png"),
    ("sample-out", ["sample", "{good}", "--model", "R1 + C1", "--steps", "20", "--out", "{output}"], ".nc"),
    ("sample-corner", ["sample", "{good}", "--model", "R1 + C1", "--steps", "20", "--corner", "{output}"], ".png"),
    ("sample-plot", ["sample", "{good}", "--model", "R1 + C1", "--steps", "20", "--plot", "{output}"], ".png"),
    ("diagnose-plot", ["diagnose", "{good}", "--model", "R1 + C1", "--plot", "{output}"], ".png"),
    ("refine-plot", ["refine", "{good}", "--model", "R1 + C1", "--plot", "{output}"], ".png"),
]

# --- bad inputs -----------------------------------------------------------------------------

GOOD_CSV = "frequency_hz,z_real_ohm,z_imag_ohm\n1,100,-50\n10,100,-5\n"
HEADER = "frequency_hz,z_real_ohm,z_imag_ohm\n"

BAD_FILES = [  # (id, file name, content or None for a missing file, message fragment)
    ("missing-file", "nope.csv", None, "file not found"),
    ("empty-file", "empty.csv", b"", "file is empty"),
    ("blank-lines-only", "blank.csv", b"\n\n  \n", "file is empty"),
    ("binary-garbage", "garbage.csv", bytes(range(256)) * 8, "binary file"),
    ("binary-with-txt-extension", "garbage.txt", b"\x7fELF\x02\x01\x01\x00" + bytes(500), "binary file"),
    ("wrong-columns", "wrong.csv", b"voltage,current\n1,2\n", "not a recognised spectrum file"),
    ("header-only", "header.csv", HEADER.encode(), "no data rows"),
    ("numbers-without-header", "nohead.csv", b"1,2,3,4\n4,5,6,7\n", "not a header"),  # 3 columns are read as f, Z', Z''
    ("short-row", "short.csv", (HEADER + "1,2,3\n2,2\n").encode(), "2 fields"),
    ("text-in-number-column", "text.csv", (HEADER + "1,2,3\n2,abc,3\n").encode(), "'abc' is not a number"),
    ("nan-value", "nan.csv", (HEADER + "1,2,3\n2,nan,3\n").encode(), "NaN/Inf"),
    ("inf-frequency", "inf.csv", (HEADER + "inf,2,3\n").encode(), "NaN/Inf"),
    ("overflowing-1e400", "overflow.csv", (HEADER + "1,1e400,3\n").encode(), "NaN/Inf"),
    ("zero-frequency-only", "zero.csv", (HEADER + "0,2,3\n").encode(), "no data rows (skipped: line 2: f = 0"),  # DC rows are skipped and reported
    ("negative-frequency", "neg.csv", (HEADER + "1,2,3\n-5,2,3\n").encode(), "frequency must be positive"),
    ("duplicate-frequency", "dup.csv", (HEADER + "1,2,3\n1,2,3\n").encode(), "duplicate frequency 1 Hz"),
    ("netcdf-extension-not-netcdf", "x.nc", b"hello", "not a readable netCDF"),
    ("gamry-without-zcurve", "x.DTA", b"EXPLAIN\r\nTAG\tEISPOT\r\n", "no ZCURVE table"),
    ("gamry-empty-zcurve", "y.DTA", b"EXPLAIN\nZCURVE\tTABLE\n\tPt\tTime\tFreq\tZreal\tZimag\n\t#\ts\tHz\tohm\tohm\n", "no data rows"),
    ("biologic-bad-header-count", "x.mpt", b"EC-Lab ASCII FILE\r\nNb header lines : 400\r\n", "does not fit"),
    ("biologic-nan", "y.mpt", b"EC-Lab ASCII FILE\nNb header lines : 3\nfreq/Hz\tRe(Z)/Ohm\t-Im(Z)/Ohm\n1\tNaN\t3\n", "NaN/Inf"),
    ("zplot-negative-frequency", "x.z", b"ZPLOT2 ASCII\nEnd Comments\n-1, 0, 0, 0, 10, -5, 0, 0, 3\n", "frequency must be positive"),
    ("labone-different-grids", "dev1_imps.csv", b"chunk;timestamp;size;fieldname\n0;1;2;frequency;1;2\n0;1;2;realz;1;1\n0;1;2;imagz;-1;-1\n1;1;2;frequency;1;3\n1;1;2;realz;1;1\n1;1;2;imagz;-1;-1\n", "different frequency grid"),
    ("autolab-duplicate-frequency", "nova.txt", "Frequency (Hz);Z' (Ω);-Z'' (Ω)\n10;1;1\n10;1;1\n".encode(), "duplicate frequency 10 Hz"),
]
if importlib.util.find_spec("h5py") is None:
    BAD_FILES.append(("hdf5-without-h5py", "sweep.h5", b"\x89HDF\r\n\x1a\n" + bytes(100), "pip install h5py"))

BAD_MODELS = [  # (id, model, message fragment)
    ("unknown-element", "X1 + R1", "unknown element symbol 'X'"),
    ("typo-with-hint", "R1 + Csc", "did you mean C_sc?"),
    ("empty-model", "", "empty circuit"),
    ("unbalanced-parenthesis", "(R1 + C1", "is not closed"),
    ("duplicate-name", "R1 + R1", "duplicate element name"),
    ("random-unicode", "R1 + ☃", "unexpected character '☃'"),
    ("control-character", "R1 +\x07C1", "unexpected character"),
    ("too-many-elements", " + ".join(f"R{k}" for k in range(300)), "more than 256 elements"),
    ("deep-nesting", "(" * 500 + "R1" + ")" * 500, "nested deeper than 64"),
    ("very-long-garbage", "R1 + " + "%" * 200_000, "unexpected character '%'"),
]

BAD_PARAMS = [  # (id, model, --param value, message fragment)
    ("unknown-parameter", "R1 + C1", "R2=3", "unknown parameter 'R2'"),
    ("not-a-number", "R1 + C1", "R1=abc", "is not a number"),
    ("nan-parameter", "R1 + C1", "R1=nan", "must be finite"),
    ("overflowing-parameter-1e400", "R1 + C1", "R1=1e400", "must be finite"),
    ("negative-resistance", "R1 + C1", "R1=-5", "outside its bounds"),
    ("alpha-above-one", "R1 + CPE1", "CPE1.alpha=1.5", "outside its bounds"),
    ("missing-equals", "R1 + C1", "R1", "expected NAME=VALUE"),
]

BAD_PRIORS = [  # (id, --prior value, message fragment)
    ("unknown-parameter", "R2=uniform:1,2", "unknown parameter 'R2'"),
    ("unknown-kind", "R1=beta:1,2", "unknown prior kind 'beta'"),
    ("one-number", "R1=uniform:1", "takes two numbers"),
    ("not-numbers", "R1=normal:a,b", "are not two numbers"),
    ("reversed-bounds", "R1=uniform:5,1", "must be below"),
    ("loguniform-from-zero", "R1=loguniform:0,10", "positive lower end"),
    ("negative-sd", "R1=normal:1,-2", "standard deviation must be positive"),
    ("infinite", "R1=uniform:1,inf", "must be finite"),
    ("outside-bounds", "CPE1.alpha=uniform:0.5,2", "reaches outside"),
    ("missing-equals", "R1", "expected NAME=KIND:ARGS"),
]

BAD_OUTPUTS = [  # (id, output template without extension, message fragment)
    ("missing-directory", "{tmp}/missing/dir/out", "does not exist"),
    ("output-is-a-directory", "{tmp}/adir", "is a directory"),
    ("parent-is-a-file", "{tmp}/good.csv/out", "does not exist"),
]


# --- the harness ----------------------------------------------------------------------------


def _fill(template: list[str], **values: str) -> list[str]:
    return [arg.format(**values) if "{" in arg and len(arg) < 200 else arg for arg in template]


def _run(argv: list[str], capsys) -> tuple[int, str, str]:
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def _check_failure(code, out, err, fragment, tmp_path, before):
    assert code == 2, (code, err)
    assert fragment in err, err
    assert "Traceback" not in err and "Traceback" not in out
    lines = err.strip().splitlines()
    assert len(lines) <= 2 and lines[-1].startswith("impedax ") and sum("error:" in ln for ln in lines) == 1, err  # one message (after at most one notice)
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # nothing written, no temp files


@pytest.fixture
def workdir(tmp_path):
    (tmp_path / "good.csv").write_text(GOOD_CSV)
    (tmp_path / "adir.csv").mkdir()
    (tmp_path / "adir.svg").mkdir()
    (tmp_path / "adir.png").mkdir()
    (tmp_path / "adir.nc").mkdir()
    return tmp_path


@pytest.mark.parametrize("command", FILE_COMMANDS, ids=[c[0] for c in FILE_COMMANDS])
@pytest.mark.parametrize("case", BAD_FILES, ids=[c[0] for c in BAD_FILES])
def test_bad_input_file(command, case, workdir, capsys):
    _, template = command
    _, name, content, fragment = case
    path = workdir / name
    if content is not None:
        path.write_bytes(content)
    before = sorted(p.name for p in workdir.iterdir())
    code, out, err = _run(_fill(template, input=str(path), tmp=str(workdir)), capsys)
    _check_failure(code, out, err, fragment, workdir, before)
    assert str(path) in err  # the message names the file


def test_input_path_is_a_directory(workdir, capsys):
    code, out, err = _run(["inspect", str(workdir / "adir.csv")], capsys)
    _check_failure(code, out, err, "is a directory", workdir, sorted(p.name for p in workdir.iterdir()))


@pytest.mark.parametrize("command", MODEL_COMMANDS, ids=[c[0] for c in MODEL_COMMANDS])
@pytest.mark.parametrize("case", BAD_MODELS, ids=[c[0] for c in BAD_MODELS])
def test_bad_model(command, case, workdir, capsys):
    _, template = command
    _, model, fragment = case
    before = sorted(p.name for p in workdir.iterdir())
    argv = [model if a == "{model}" else a.format(tmp=str(workdir)) for a in template]
    code, out, err = _run(argv, capsys)
    assert code == 2 and fragment in err and "Traceback" not in err
    assert len(err) < 2000 or model in err  # long input is echoed once, not repeated
    assert sorted(p.name for p in workdir.iterdir()) == before


@pytest.mark.parametrize("command", PARAM_COMMANDS, ids=[c[0] for c in PARAM_COMMANDS])
@pytest.mark.parametrize("case", BAD_PARAMS, ids=[c[0] for c in BAD_PARAMS])
def test_bad_parameter(command, case, workdir, capsys):
    _, template = command
    _, model, param, fragment = case
    before = sorted(p.name for p in workdir.iterdir())
    argv = [model if a == "{model}" else param if a == "{param}" else a.format(tmp=str(workdir)) for a in template]
    code, out, err = _run(argv, capsys)
    _check_failure(code, out, err, fragment, workdir, before)


@pytest.mark.parametrize("command", PRIOR_COMMANDS, ids=[c[0] for c in PRIOR_COMMANDS])
@pytest.mark.parametrize("case", BAD_PRIORS, ids=[c[0] for c in BAD_PRIORS])
def test_bad_prior(command, case, workdir, capsys):
    _, template = command
    _, prior, fragment = case
    before = sorted(p.name for p in workdir.iterdir())
    argv = [prior if a == "{prior}" else a.format(tmp=str(workdir)) for a in template]
    code, out, err = _run(argv, capsys)
    _check_failure(code, out, err, fragment, workdir, before)


@pytest.mark.parametrize("command", OUTPUT_COMMANDS, ids=[c[0] for c in OUTPUT_COMMANDS])
@pytest.mark.parametrize("case", BAD_OUTPUTS, ids=[c[0] for c in BAD_OUTPUTS])
def test_unwritable_output(command, case, workdir, capsys):
    _, template, ext = command
    _, output, fragment = case
    before = sorted(p.name for p in workdir.iterdir())
    argv = _fill(template, output=output.format(tmp=str(workdir)) + ext, good=str(workdir / "good.csv"), tmp=str(workdir))
    code, out, err = _run(argv, capsys)
    _check_failure(code, out, err, fragment, workdir, before)


def test_model_overflow_is_reported_not_written(workdir, capsys):
    before = sorted(p.name for p in workdir.iterdir())
    code, out, err = _run(["simulate", "R1 + L1", "--param", "L1=1e308", "--out", str(workdir / "o.csv")], capsys)
    _check_failure(code, out, err, "not finite (overflow)", workdir, before)


def test_huge_but_finite_values_are_read_exactly(workdir, capsys):
    """1e300 Ω is absurd but finite: impedax reads it unchanged rather than guessing."""
    path = workdir / "huge.csv"
    path.write_text(HEADER + "1,1e300,-1e300\n1e300,1,-1\n")
    ds = ix.load(path)
    np.testing.assert_array_equal(ds["Z"].values, [1e300 - 1e300j, 1 - 1j])
    code, out, err = _run(["inspect", str(path)], capsys)
    assert code == 0 and "Traceback" not in err
