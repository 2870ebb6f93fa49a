"""Every CLI output on hostile paths, plus limits, damaged files and standard input/output.

One row = one bad input. Each row asserts: exit code 2, exactly one message line on stderr
(under 300 characters) that names the file or the option, no traceback, and no file created or
changed (the folder is snapshotted before and after: names, sizes, contents, times).

The tables grow like those of tests/test_robustness.py: a command that writes a file is one
line in OUTPUT_FLAGS and meets every class of BAD_PATHS; a command with an input and an output
of a kind that can be named like the input is one line in OUT_IS_INPUT; a command with two
outputs is one line in FAILED_WRITES. docs/robustness.md ("Outputs, signals, standard
input/output and limits") lists the classes and what impedax does with each.
"""

from __future__ import annotations

import errno
import hashlib
import io
import os
import re
import sys

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from permissions import read_only_folder

# --- the commands that write files ---------------------------------------------------------

# (id, argv template with {output}, a valid extension, kind); {good}: a valid spectrum, {tmp}: the folder
OUTPUT_FLAGS = [
    ("simulate-out", ["simulate", "R1 + C1", "--out", "{output}"], ".csv", "spectrum"),
    ("simulate-plot", ["simulate", "R1 + C1", "--plot", "{output}"], ".png", "figure"),
    ("force-plot", ["force", "meyer", "--plot", "{output}"], ".png", "figure"),
    ("force-out", ["force", "meyer", "--out", "{output}"], ".csv", "result"),
    ("fit-out", ["fit", "{good}", "--model", "R1 + C1", "--out", "{output}"], ".json", "result"),
    ("fit-plot", ["fit", "{good}", "--model", "R1 + C1", "--plot", "{output}"], ".png", "figure"),
    ("compare-plot", ["compare", "{good}", "--model", "R1", "--model", "R1 + C1", "--plot", "{output}"], ".png", "figure"),
    ("compare-out", ["compare", "{good}", "--model", "R1", "--model", "R1 + C1", "--out", "{output}"], ".csv", "result"),
    ("sample-out", ["sample", "{good}", "--model", "R1 + C1", "--steps", "20", "--out", "{output}"], ".nc", "result"),
    ("sample-corner", ["sample", "{good}", "--model", "R1 + C1", "--steps", "20", "--corner", "{output}"], ".png", "figure"),
    ("sample-plot", ["sample", "{good}", "--model", "R1 + C1", "--steps", "20", "--plot", "{output}"], ".png", "figure"),
    ("kk-plot", ["kk", "{good}", "--plot", "{output}"], ".png", "figure"),
    ("kk-out", ["kk", "{good}", "--out", "{output}"], ".json", "result"),  # (added 2026-12-01)
    ("drt-out", ["drt", "{good}", "--out", "{output}"], ".csv", "drt"),
    ("drt-plot", ["drt", "{good}", "--plot", "{output}"], ".png", "figure"),
    ("diagnose-out", ["diagnose", "{good}", "--model", "R1 + C1", "--out", "{output}"], ".csv", "result"),
    ("diagnose-plot", ["diagnose", "{good}", "--model", "R1 + C1", "--plot", "{output}"], ".png", "figure"),
    ("refine-out", ["refine", "{good}", "--model", "R1 + C1", "--out", "{output}"], ".json", "result"),
    ("refine-plot", ["refine", "{good}", "--model", "R1 + C1", "--plot", "{output}"], ".png", "figure"),
    ("gap-out", ["gap", "{good}", "{good}", "{good}", "--area", "130e-6", "--out", "{output}"], ".nc", "result"),
    ("gap-plot", ["gap", "{good}", "{good}", "{good}", "--area", "130e-6", "--plot", "{output}"], ".png", "figure"),
    ("draw", ["draw", "R1 + C1", "-o", "{output}"], ".svg", "diagram"),
    ("inspect-out", ["inspect", "{good}", "--out", "{output}"], ".nc", "spectrum"),
    ("inspect-plot", ["inspect", "{good}", "--plot", "{output}"], ".png", "figure"),
]

# (id, output path template (``{ext}``: the flag's valid extension), message fragment, kinds it applies to)
ALL_KINDS = ("spectrum", "figure", "result", "drt", "diagram")
BAD_PATHS = [
    ("unknown-extension", "{tmp}/out.foo", "extension '.foo'", ALL_KINDS),
    ("extension-of-another-kind", "{tmp}/out.xlsx", "extension '.xlsx'", ALL_KINDS),
    ("under-a-file", "{tmp}/good.csv/out{ext}", "good.csv is a file", ALL_KINDS),
    ("read-only-folder", "{tmp}/ro/out{ext}", "is not writable", ALL_KINDS),
    ("read-only-file", "{tmp}/read-only{ext}", "is read-only", ALL_KINDS),  # (made 0444 by the test)
    ("empty-name", "", "empty file name", ALL_KINDS),
    # (until 2026-12-08 a name ending in '/' was written as a file without it: --plot figs/ made a
    # file figs, and old.png/ replaced old.png)
    ("names-a-folder", "{tmp}/figs/", "ends with '/', so it names a folder, not a file; give a file name in it, e.g. ", ALL_KINDS),
    ("existing-file-as-a-folder", "{tmp}/old.png/", "ends with '/', so it names a folder", ALL_KINDS),
    ("binary-to-stdout", "-", "cannot go to standard output", ("figure", "diagram")),
]

# (id, argv template whose output is the input {good}; ``{same}`` is replaced by the spelling under test)
OUT_IS_INPUT = [
    ("fit", ["fit", "{good}", "--model", "R1 + C1", "--out", "{same}"]),
    ("sample", ["sample", "{good}", "--model", "R1 + C1", "--steps", "20", "--out", "{same}"]),
    ("diagnose", ["diagnose", "{good}", "--model", "R1 + C1", "--out", "{same}"]),
    ("refine", ["refine", "{good}", "--model", "R1 + C1", "--out", "{same}"]),
    ("gap", ["gap", "{good}", "{other}", "{other}", "--area", "130e-6", "--out", "{same}"]),
    ("inspect", ["inspect", "{good}", "--out", "{same}"]),
    ("drt", ["drt", "{good}", "--out", "{same}"]),
    ("kk", ["kk", "{good}", "--out", "{same}"]),
]
SAME_FILE_SPELLINGS = [  # (id, how the input is named as the output)
    ("same-path", "{tmp}/good.csv"),
    ("dot-segment", "{tmp}/./good.csv"),
    ("symlink-to-input", "{tmp}/link.csv"),
]

PROGRESS_LINE = re.compile(r"^\[\s*\d+\.\d s\] ")  # `cli.common.progress_printer`'s lines

TWO_OUTPUTS_ONE_PATH = [  # (id, argv, message fragment)
    ("corner-and-plot", ["sample", "{good}", "--model", "R1 + C1", "--corner", "{tmp}/x.png", "--plot", "{tmp}/x.png"], "name the same file"),
    ("corner-and-plot-dot-segment", ["sample", "{good}", "--model", "R1 + C1", "--corner", "{tmp}/x.png", "--plot", "{tmp}/./x.png"], "name the same file"),
    ("corner-and-plot-symlink", ["sample", "{good}", "--model", "R1 + C1", "--corner", "{tmp}/old.png", "--plot", "{tmp}/link.png"], "name the same file"),
    ("out-and-plot-one-name", ["fit", "{good}", "--model", "R1 + C1", "--out", "{tmp}/x.png", "--plot", "{tmp}/x.png"], "extension '.png'"),
    ("fit-stdout-twice", ["fit", "{good}", "--model", "R1 + C1", "--out", "-", "--json"], "both write to standard output"),
    ("sample-stdout-twice", ["sample", "{good}", "--model", "R1 + C1", "--out", "-", "--json"], "both write to standard output"),
    ("diagnose-stdout-twice", ["diagnose", "{good}", "--model", "R1 + C1", "--out", "-", "--json"], "both write to standard output"),
    ("refine-stdout-twice", ["refine", "{good}", "--model", "R1 + C1", "--out", "-", "--json"], "both write to standard output"),
    ("gap-stdout-twice", ["gap", "{good}", "{good}", "{good}", "--area", "1e-4", "--out", "-", "--json"], "both write to standard output"),
    ("inspect-stdout-twice", ["inspect", "{good}", "--out", "-", "--json"], "both write to standard output"),
    ("drt-stdout-twice", ["drt", "{good}", "--out", "-", "--json"], "both write to standard output"),
    ("kk-stdout-twice", ["kk", "{good}", "--out", "-", "--json"], "both write to standard output"),
    ("stdin-read-twice", ["gap", "-", "-", "{good}", "--area", "1e-4"], "read only once"),
]

# commands with two outputs where the second (the figure) fails after the first was written:
# (id, argv with {out} and {plot}, extension of {out}); `slow` ones do a full diagnosis or MCMC
FAILED_WRITES = [
    pytest.param(["simulate", "R1 + C1", "--param", "R1=100", "--param", "C1=1e-6", "--out", "{out}", "--plot", "{plot}"], ".csv", id="simulate"),
    pytest.param(["fit", "{good}", "--model", "R0 + R1 || C1", "--out", "{out}", "--plot", "{plot}"], ".json", id="fit"),
    pytest.param(["inspect", "{good}", "--out", "{out}", "--plot", "{plot}"], ".nc", id="inspect"),
    pytest.param(["force", "meyer", "--points", "9", "--out", "{out}", "--plot", "{plot}"], ".json", id="force"),
    pytest.param(["drt", "{good}", "--out", "{out}", "--plot", "{plot}"], ".csv", id="drt"),
    pytest.param(["kk", "{good}", "--out", "{out}", "--plot", "{plot}"], ".csv", id="kk"),
    pytest.param(["sample", "{good}", "--model", "R0 + R1 || C1", "--steps", "30", "--quiet", "--out", "{out}", "--plot", "{plot}"], ".nc", id="sample"),
    pytest.param(["diagnose", "{good}", "--model", "R0 + R1 || C1", "--out", "{out}", "--plot", "{plot}"], ".json", id="diagnose", marks=pytest.mark.slow),
    pytest.param(["refine", "{good}", "--model", "R0 + R1 || C1", "--max-effects", "1", "--out", "{out}", "--plot", "{plot}"], ".json", id="refine", marks=pytest.mark.slow),
]

DEMO_FOLDERS = [  # (id, --out template, message fragment)
    ("out-is-a-file", "{tmp}/good.csv", "is not a folder"),
    ("out-under-a-file", "{tmp}/good.csv/demo", "is a file, so no folder can be made under it"),
    ("out-deep-under-a-file", "{tmp}/good.csv/a/b/c", "is a file, so no folder can be made under it"),
    ("read-only-folder", "{tmp}/ro", "is not writable"),
    ("new-folder-in-read-only-folder", "{tmp}/ro/demo", "is not writable"),
    ("empty-name", "", "empty folder name"),
]

SIZE_LIMITS = [  # (id, argv, environment, message fragment)
    ("simulate-points", ["simulate", "R1 + C1", "--points", "2000000000"], {}, "IMPEDAX_MEMORY_LIMIT"),
    ("force-points", ["force", "meyer", "--points", "2000000000"], {}, "IMPEDAX_MEMORY_LIMIT"),
    ("sample-steps", ["sample", "{good}", "--model", "R1 + C1", "--steps", "1000000000"], {}, "IMPEDAX_MEMORY_LIMIT"),
    ("sample-walkers", ["sample", "{good}", "--model", "R1 + C1", "--walkers", "100000000", "--steps", "100"], {}, "IMPEDAX_MEMORY_LIMIT"),
    ("gap-steps", ["gap", "{good}", "{good}", "{good}", "--area", "1e-4", "--steps", "1000000000"], {}, "IMPEDAX_MEMORY_LIMIT"),
    ("lowered-limit", ["simulate", "R1 + C1", "--points", "61"], {"IMPEDAX_MEMORY_LIMIT": "1k"}, "IMPEDAX_MEMORY_LIMIT=1k"),
    ("limit-not-a-size", ["simulate", "R1 + C1"], {"IMPEDAX_MEMORY_LIMIT": "lots"}, "expected a size"),
    ("limit-negative", ["simulate", "R1 + C1"], {"IMPEDAX_MEMORY_LIMIT": "-5G"}, "expected a size"),
    ("file-limit-not-a-size", ["inspect", "{good}"], {"IMPEDAX_MAX_FILE_BYTES": "big"}, "IMPEDAX_MAX_FILE_BYTES"),
    ("file-over-lowered-limit", ["inspect", "{good}"], {"IMPEDAX_MAX_FILE_BYTES": "10"}, "IMPEDAX_MAX_FILE_BYTES=SIZE"),
]


def _netcdf_files(folder):
    """Crafted and truncated netCDF files: name → message fragment."""
    import xarray as xr

    from impedax.io.netcdf import encode_dataset

    spectrum = ix.make_spectrum([1.0, 10.0, 100.0], np.array([100 - 50j, 100 - 5j, 100 - 1j]))
    ix.save(spectrum, folder / "whole.nc")
    raw = (folder / "whole.nc").read_bytes()
    (folder / "whole.nc").unlink()
    encoded = encode_dataset(spectrum)
    (folder / "signature-only.nc").write_bytes(b"CDF\x01")
    (folder / "truncated.nc").write_bytes(raw[: len(raw) // 2])
    encoded.drop_vars("Z__imag").to_netcdf(folder / "no-imaginary.nc", engine="scipy")
    deep = encoded.copy()
    deep.attrs["notes"] = "json:" + "[" * 100_000 + "]" * 100_000
    deep.to_netcdf(folder / "deep-json.nc", engine="scipy")
    broken = encoded.copy()
    broken.attrs["notes"] = "json:{nope"
    broken.to_netcdf(folder / "bad-json.nc", engine="scipy")
    empty = xr.Dataset(
        {"Z__real": (("trial", "frequency"), np.zeros((0, 3)), {"impedax_part": "real"}),
         "Z__imag": (("trial", "frequency"), np.zeros((0, 3)), {"impedax_part": "imag"})},
        coords={"frequency": [1.0, 10.0, 100.0], "trial": np.arange(0)},
    )
    empty.to_netcdf(folder / "zero-trials.nc", engine="scipy")
    with open(folder / "ten-gigabytes.csv", "wb") as fh:  # sparse: no disk used
        fh.truncate(10 * 2**30)
    os.symlink("loop-b.csv", folder / "loop-a.csv")
    os.symlink("loop-a.csv", folder / "loop-b.csv")
    os.symlink("nowhere.csv", folder / "dangling.csv")


BAD_FILES = [  # (file name, message fragment)
    ("signature-only.nc", "truncated netCDF file"),
    ("truncated.nc", "damaged or truncated"),
    ("no-imaginary.nc", "has no Z__imag partner"),
    ("deep-json.nc", "nested too deeply"),
    ("bad-json.nc", "is not valid JSON"),
    ("zero-trials.nc", "has length 0"),
    ("ten-gigabytes.csv", "IMPEDAX_MAX_FILE_BYTES"),
    ("loop-a.csv", "symlink loop"),
    ("dangling.csv", "broken symbolic link"),
]
FILE_READERS = [  # (id, argv template with {input})
    ("inspect", ["inspect", "{input}"]),
    ("fit", ["fit", "{input}", "--model", "R1 + C1", "--out", "{tmp}/fit.json"]),
    ("kk", ["kk", "{input}", "--plot", "{tmp}/kk.png"]),
]


# --- the harness ----------------------------------------------------------------------------

GOOD_SPECTRUM_POINTS = 25


def _good_csv() -> str:
    """R0 + R1 || C1 (100 Ω, 1 kΩ, 1 µF), 25 points over 1 Hz–100 kHz, no noise."""
    f = np.geomspace(1.0, 1e5, GOOD_SPECTRUM_POINTS)
    z = 100.0 + 1000.0 / (1 + 1j * 2 * np.pi * f * 1000.0 * 1e-6)
    return "frequency_hz,z_real_ohm,z_imag_ohm\n" + "".join(f"{a!r},{b.real!r},{b.imag!r}\n" for a, b in zip(f.tolist(), z.tolist()))


def _snapshot(folder) -> dict:
    """Every path under ``folder`` with its kind, size, content hash and modification time."""
    out = {}
    for root, dirs, files in os.walk(folder):
        for name in dirs + files:
            path = os.path.join(root, name)
            info = os.lstat(path)
            digest = ""
            if os.path.isfile(path) and not os.path.islink(path) and info.st_size < 2**20:
                with open(path, "rb") as fh:
                    digest = hashlib.sha256(fh.read()).hexdigest()
            out[os.path.relpath(path, folder)] = (info.st_mode, info.st_size, info.st_mtime_ns, digest)
    return out


def _fill(template, **values):
    return [a.format(**values) if "{" in a else a for a in template]


def _check_refused(code, out, err, fragment, names, folder, before):
    """Exit 2, one message line (< 300 characters) holding ``fragment`` and one of ``names``,
    no traceback, nothing created or changed under ``folder``."""
    assert code == 2, (code, err)
    lines = [line for line in err.strip().splitlines() if not PROGRESS_LINE.match(line)]  # (a run past 2 s says what it does)
    assert len(lines) == 1, err
    assert len(lines[0]) < 300, lines[0]
    assert lines[0].startswith("impedax ") and "error:" in lines[0], err
    assert fragment in lines[0], err
    assert any(n in lines[0] for n in names if n), (names, err)
    assert "Traceback" not in err + out
    assert _snapshot(folder) == before


@pytest.fixture
def workdir(tmp_path, monkeypatch):
    (tmp_path / "good.csv").write_text(_good_csv())
    (tmp_path / "other.csv").write_text(_good_csv())
    (tmp_path / "old.png").write_bytes(b"an earlier figure")
    os.symlink("good.csv", tmp_path / "link.csv")
    os.symlink("old.png", tmp_path / "link.png")
    with read_only_folder(tmp_path / "ro", monkeypatch):
        monkeypatch.chdir(tmp_path)
        yield tmp_path


def _run(argv, capsys):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def _bad_path_rows():
    rows = []
    for flag_id, template, ext, kind in OUTPUT_FLAGS:
        for case_id, path, fragment, kinds in BAD_PATHS:
            if kind in kinds:
                rows.append(pytest.param(template, ext, path, fragment, id=f"{case_id}-{flag_id}"))
    return rows


@pytest.mark.parametrize("template, ext, path, fragment", _bad_path_rows())
def test_bad_output_path(template, ext, path, fragment, workdir, capsys):
    output = path.format(tmp=workdir, ext=ext)
    argv = _fill(template, output=output, good=str(workdir / "good.csv"), tmp=str(workdir))
    flag = template[template.index("{output}") - 1]
    if "/read-only" in path:  # an earlier output its owner made read-only: kept as it is
        with open(output, "wb") as fh:
            fh.write(b"kept")
        os.chmod(output, 0o444)
    before = _snapshot(workdir)
    code, out, err = _run(argv, capsys)
    _check_refused(code, out, err, fragment, [output, flag], workdir, before)


@pytest.mark.parametrize("spelling", SAME_FILE_SPELLINGS, ids=[s[0] for s in SAME_FILE_SPELLINGS])
@pytest.mark.parametrize("command", OUT_IS_INPUT, ids=[c[0] for c in OUT_IS_INPUT])
def test_output_is_the_input(command, spelling, workdir, capsys):
    same = spelling[1].format(tmp=workdir)
    argv = _fill(command[1], good=str(workdir / "good.csv"), other=str(workdir / "other.csv"), same=same)
    before = _snapshot(workdir)
    code, out, err = _run(argv, capsys)
    _check_refused(code, out, err, "is the input file", [same, "--out"], workdir, before)


@pytest.mark.parametrize("case", TWO_OUTPUTS_ONE_PATH, ids=[c[0] for c in TWO_OUTPUTS_ONE_PATH])
def test_two_outputs_at_one_path(case, workdir, capsys):
    _, template, fragment = case
    argv = _fill(template, good=str(workdir / "good.csv"), tmp=str(workdir))
    before = _snapshot(workdir)
    code, out, err = _run(argv, capsys)
    _check_refused(code, out, err, fragment, ["--out", "--plot", "--corner", "standard input", str(workdir)], workdir, before)


@pytest.mark.parametrize("template, ext", FAILED_WRITES)
def test_a_failed_figure_leaves_every_output_as_it_was(template, ext, workdir, capsys, monkeypatch):
    """The disk fills up while the figure is written, after the result file was written: the
    result file already there keeps its old content, no temporary is left, exit 2."""
    import matplotlib.figure

    out = workdir / f"result{ext}"
    out.write_bytes(b"the result of an earlier run")
    plot = workdir / "figure.png"

    def disk_full(self, fname, *args, **kwargs):
        with open(fname, "wb") as fh:  # a partial file, as a full disk leaves it
            fh.write(b"\x89PNG partial")
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", disk_full)
    argv = _fill(template, good=str(workdir / "good.csv"), out=str(out), plot=str(plot))
    before = _snapshot(workdir)
    code, stdout, err = _run(argv, capsys)
    _check_refused(code, stdout, err, "No space left on device", [str(plot)], workdir, before)
    assert out.read_bytes() == b"the result of an earlier run"


@pytest.mark.parametrize("case", DEMO_FOLDERS, ids=[c[0] for c in DEMO_FOLDERS])
def test_demo_output_folder(case, workdir, capsys):
    _, template, fragment = case
    folder = template.format(tmp=workdir)
    before = _snapshot(workdir)
    code, out, err = _run(["demo", "--out", folder, "--fast"], capsys)
    _check_refused(code, out, err, fragment, [folder, "--out"], workdir, before)


@pytest.mark.parametrize("case", SIZE_LIMITS, ids=[c[0] for c in SIZE_LIMITS])
def test_sizes_are_checked_before_allocation(case, workdir, capsys, monkeypatch):
    _, template, environment, fragment = case
    for name, value in environment.items():
        monkeypatch.setenv(name, value)
    argv = _fill(template, good=str(workdir / "good.csv"))
    before = _snapshot(workdir)
    code, out, err = _run(argv, capsys)
    flags = [a for a in argv if a.startswith("--")] + list(environment)
    _check_refused(code, out, err, fragment, flags + [str(workdir / "good.csv")], workdir, before)


@pytest.mark.parametrize("case", BAD_FILES, ids=[c[0] for c in BAD_FILES])
@pytest.mark.parametrize("command", FILE_READERS, ids=[c[0] for c in FILE_READERS])
def test_damaged_and_odd_files(command, case, workdir, capsys):
    name, fragment = case
    _netcdf_files(workdir)
    path = workdir / name
    argv = _fill(command[1], input=str(path), tmp=str(workdir))
    before = _snapshot(workdir)
    code, out, err = _run(argv, capsys)
    _check_refused(code, out, err, fragment, [str(path)], workdir, before)


@pytest.mark.parametrize("case", BAD_FILES, ids=[c[0] for c in BAD_FILES])
# no warning from a file left open, e.g. "Cannot close a netcdf_file opened with mmap=True"
# from the file's finaliser (impedax reads netCDF files into memory instead of mapping them)
@pytest.mark.filterwarnings("error::RuntimeWarning", "error::pytest.PytestUnraisableExceptionWarning")
def test_damaged_files_in_the_python_api(case, workdir):
    name, fragment = case
    _netcdf_files(workdir)
    with pytest.raises(ix.DataError) as caught:
        ix.load(workdir / name)
    assert fragment in str(caught.value) and str(workdir / name) in str(caught.value)
    assert len(str(caught.value)) < 300 and "\n" not in str(caught.value)


# --- what works: standard input and output, UTF-16, transactions --------------------------


def _stdin(monkeypatch, data: bytes) -> None:
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(data)))


def test_spectrum_from_standard_input_is_sniffed(workdir, capsys, monkeypatch):
    text = _good_csv().encode()
    _stdin(monkeypatch, text)
    code, out, err = _run(["inspect", "-", "--json"], capsys)
    assert code == 0, err
    import json

    summary = json.loads(out)
    assert summary["points"] == GOOD_SPECTRUM_POINTS and summary["format"] == "delimited text"
    ix.save(ix.load(workdir / "good.csv"), workdir / "good.nc")
    _stdin(monkeypatch, (workdir / "good.nc").read_bytes())
    data = ix.load("-")
    assert data.attrs["path"] == "<stdin>"
    np.testing.assert_array_equal(data["Z"].values, ix.load(workdir / "good.csv")["Z"].values)


def test_bad_standard_input_is_named_stdin(workdir, capsys, monkeypatch):
    _stdin(monkeypatch, b"frequency_hz,z_real_ohm,z_imag_ohm\n1,2,3\n1,2,3\n")
    before = _snapshot(workdir)
    code, out, err = _run(["kk", "-"], capsys)
    _check_refused(code, out, err, "duplicate frequency", ["<stdin>"], workdir, before)


def test_json_and_csv_to_standard_output(workdir, capsys):
    import json

    code, out, err = _run(["fit", str(workdir / "good.csv"), "--model", "R0 + R1 || C1", "--out", "-"], capsys)
    assert code == 0, err
    summary = json.loads(out)  # stdout holds the JSON and nothing else
    assert summary["params"]["R1"]["value"] == pytest.approx(1000.0, rel=1e-6)
    code, out, err = _run(["simulate", "R1 + C1", "--param", "R1=100", "--param", "C1=1e-6", "--points", "5", "--out", "-"], capsys)
    assert code == 0 and out.splitlines()[0] == "frequency_hz,z_real_ohm,z_imag_ohm" and len(out.splitlines()) == 6
    code, out, err = _run(["drt", str(workdir / "good.csv"), "--out", "-"], capsys)
    assert code == 0 and out.splitlines()[0].startswith("tau_s,gamma_ohm")
    assert not [p for p in workdir.iterdir() if p.name.startswith(".")]


def test_utf16_without_byte_order_mark_is_read(workdir):
    path = workdir / "utf16.csv"
    path.write_bytes(_good_csv().encode("utf-16-le"))
    data = ix.load(path)
    assert data.sizes["frequency"] == GOOD_SPECTRUM_POINTS
    path.write_bytes(_good_csv().encode("utf-16-be"))
    assert ix.load(path).sizes["frequency"] == GOOD_SPECTRUM_POINTS


def test_file_limit_can_be_raised(workdir, monkeypatch):
    monkeypatch.setenv("IMPEDAX_MAX_FILE_BYTES", "100")
    with pytest.raises(ix.DataError, match="IMPEDAX_MAX_FILE_BYTES"):
        ix.load(workdir / "good.csv")
    monkeypatch.setenv("IMPEDAX_MAX_FILE_BYTES", "1M")
    assert ix.load(workdir / "good.csv").sizes["frequency"] == GOOD_SPECTRUM_POINTS


def test_all_outputs_appear_together(workdir, capsys):
    out, plot = workdir / "fit.json", workdir / "fit.png"
    code, _, err = _run(["fit", str(workdir / "good.csv"), "--model", "R0 + R1 || C1", "--out", str(out), "--plot", str(plot)], capsys)
    assert code == 0, err
    assert out.read_text().startswith("{") and plot.read_bytes()[:4] == b"\x89PNG"
    assert not [p for p in workdir.iterdir() if p.name.startswith(".")]


def test_transaction_aborts_on_error_and_keeps_targets(tmp_path):
    from impedax.io.atomic import OutputTransaction, live_temporaries

    first, second = tmp_path / "a.txt", tmp_path / "b.txt"
    first.write_text("old a")
    with pytest.raises(RuntimeError):
        with OutputTransaction() as transaction:
            transaction.write(first, lambda p: p.write_text("new a"))
            transaction.write(second, lambda p: p.write_text("new b"))
            raise RuntimeError("a bug after the writes")
    assert first.read_text() == "old a" and not second.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt"] and not live_temporaries()
    with OutputTransaction() as transaction:
        transaction.write(first, lambda p: p.write_text("new a"))
        transaction.write(second, lambda p: p.write_text("new b"))
    assert first.read_text() == "new a" and second.read_text() == "new b"
    assert transaction.committed == (str(first), str(second))


def test_canonical_csv_is_read_as_arrays_with_the_same_result(workdir):
    """impedax's own CSV is parsed straight into arrays (memory: benchmarks/README.md, "Scale");
    the result is what the general reader gives for the same rows (a comment line sends the file
    down the general path)."""
    text = _good_csv()
    path = workdir / "canonical.csv"
    path.write_text(text)
    fast = ix.load(path)
    path.write_text("# the same rows\n" + text)
    general = ix.load(path)
    np.testing.assert_array_equal(fast["Z"].values, general["Z"].values)
    np.testing.assert_array_equal(fast["frequency"].values, general["frequency"].values)
    assert fast.attrs == general.attrs
    path.write_text(text + "1.0,5,5\n")  # a repeated frequency: the general reader's message, with both lines
    with pytest.raises(ix.DataError, match=r"line 27: duplicate frequency 1 Hz \(also on line 2\)"):
        ix.load(path)



def test_every_out_that_can_go_to_standard_output_says_so_in_its_help():
    """`--out -` works for these commands (`OUTPUT_KINDS` with a ``stdout_suffix``); their help
    names '-' and what it prints (drt's and inspect's said nothing of it until 2026-12-05,
    and drt's prints CSV where kk's prints JSON)."""
    import argparse

    from impedax.cli import build_parser

    subparsers = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    helps = {name: next((a.help for a in sub._actions if "--out" in a.option_strings), None) for name, sub in subparsers.choices.items()}
    to_stdout = {"simulate", "fit", "compare", "sample", "kk", "drt", "diagnose", "refine", "force", "gap", "remaining", "inspect"}
    for name in to_stdout:
        assert "'-'" in helps[name], (name, helps[name])
    assert "'-' the CSV to standard output" in helps["drt"] and "'-' the CSV to standard output" in helps["inspect"]
    assert "'-' the JSON to standard output" in helps["kk"]
    assert {n for n, h in helps.items() if h and "'-'" not in h} == {"draw", "stack", "demo"}  # (binary or folder outputs)
