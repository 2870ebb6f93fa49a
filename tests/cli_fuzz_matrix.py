"""A matrix of bad input for every ``impedax`` command, run in one process (not a test: a tool).

    PYTHONPATH=$PWD:$PWD/tests python tests/cli_fuzz_matrix.py [--only WORD] [--list]

Each case is a command line built from a command's good line and one bad value (or file, or
circuit). A case is flagged when its run raises out of `impedax.cli.main` (a traceback), when
stderr holds "Traceback", when its exit code is not 0 or 2, when it failed and changed the file
its --out names (each case's --out file exists beforehand with known bytes), or when it ran
longer than TIMEOUT seconds. Runs that exit 0 on a bad value are listed as "accepted" for a
reader to judge. The tables of tests/test_robustness*.py pin the messages; this matrix is wider
and asserts less (docs/robustness.md).
"""

from __future__ import annotations

import argparse
import contextlib
import io
import os
import signal
import sys
import tempfile
import time
import traceback
from pathlib import Path

import numpy as np

TIMEOUT = 240
SENTINEL = b"an existing output file: a failing run must leave these bytes\n"
HEADER = "frequency_hz,z_real_ohm,z_imag_ohm\n"


def _arc_rows(freqs) -> str:
    z = 10 + 100 / (1 + 2j * np.pi * np.asarray(freqs) * 100 * 1e-6)
    return "".join(f"{f:.8g},{v.real:.8g},{v.imag:.8g}\n" for f, v in zip(freqs, z))


def make_files(folder: Path) -> dict[str, str]:
    """The good and bad input files of the matrix, written into ``folder``: name → path."""
    import impedax as ix

    f = np.geomspace(1, 1e5, 21)
    files = {
        "good": HEADER + _arc_rows(f),
        "good2": HEADER + _arc_rows(f * 1.0),
        "empty": "",
        "header": HEADER,
        "one-point": HEADER + _arc_rows([100.0]),
        "two-points": HEADER + _arc_rows([10.0, 100.0]),
        "all-nan": HEADER + "".join(f"{x:g},nan,nan\n" for x in f),
        "nan-z-column": HEADER + "".join(f"{x:g},1,nan\n" for x in f),
        "duplicate-frequencies": HEADER + _arc_rows(f) + _arc_rows(f[:3]),
        "negative-frequencies": HEADER + _arc_rows(-f),
        "zero-z": HEADER + "".join(f"{x:g},0,0\n" for x in f),
        "truncated": (HEADER + _arc_rows(f))[:-17],
        "truncated-mid-number": (HEADER + _arc_rows(f)).rsplit(",", 1)[0] + ",1e",
        "constant-z": HEADER + "".join(f"{x:g},100,0\n" for x in f),
        "huge": HEADER + "".join(f"{x:g},1e305,-1e305\n" for x in f),
        "tiny": HEADER + "".join(f"{x:g},1e-305,-1e-305\n" for x in f),
        "decreasing": HEADER + _arc_rows(f[::-1]),
        "one-column": "frequency_hz\n" + "".join(f"{x:g}\n" for x in f),
        "semicolons-garbage": "a;b;c\n;;\n",
        "latin1": (HEADER.replace("ohm", "Ω") + _arc_rows(f)),
    }
    paths = {}
    for name, text in files.items():
        path = folder / f"{name}.csv"
        path.write_bytes(text.encode("latin-1" if name == "latin1" else "utf-8", errors="replace"))
        paths[name] = str(path)
    (folder / "binary.csv").write_bytes(bytes(range(256)) * 4)
    paths["binary"] = str(folder / "binary.csv")
    (folder / "a-directory").mkdir()
    paths["directory"] = str(folder / "a-directory")
    paths["missing"] = str(folder / "no-such-file.csv")
    # a series: two spectra along "day" (for --select, --over, --plot-x)
    z = ix.load(paths["good"]).Z.values
    series = ix.make_spectrum(f, np.stack([z, z * 1.01]), dims=("day",), coords={"day": [1, 2]})
    ix.save(series, str(folder / "series.nc"))
    paths["series"] = str(folder / "series.nc")
    # a netCDF truncated half-way
    data = (folder / "series.nc").read_bytes()
    (folder / "truncated.nc").write_bytes(data[: len(data) // 2])
    paths["truncated-nc"] = str(folder / "truncated.nc")
    # the three spectra of a gap analysis (SYNTHETIC, formulas of tests/spectra.py)
    sys.path.insert(0, str(Path(__file__).parent))
    from spectra import sirin_measurements

    fg, *spectra = sirin_measurements(np.random.default_rng(4), 3, noise=0.005, trial_scatter=0.0)
    for name, zz in zip(("total", "skin", "ts"), spectra):
        ix.save(ix.make_spectrum(fg, zz, dims=("trial",)), str(folder / f"{name}.nc"))
        paths[name] = str(folder / f"{name}.nc")
    plugin = folder / "bad_plugin.py"
    plugin.write_text("raise RuntimeError('boom')\n")
    paths["bad-plugin"] = str(plugin)
    (folder / "syntax_plugin.py").write_text("def (:\n")
    paths["syntax-plugin"] = str(folder / "syntax_plugin.py")
    (folder / "out.txt").write_bytes(SENTINEL)
    return paths


BAD_NUMBERS = ["-1", "0", "nan", "inf", "-inf", "1e400", "abc", "", "1.5", "1e-300", "-0", "0x10", "1,000", "½"]
BAD_CIRCUITS = ["(R1 + C1", "R1 + C1)", "R1 + X1", "R1 + R1", "", " ", "R1 ∥ C1", "R1 + C1 +", "R1 ||", "|| R1", "R1 + ()", "R1 C1",
                "R1 + CPE1.alpha", "R1 + C_", "R1 + L1 + 1", "R0-p(R1,C1", "p(R1)", "R1 + C1 # comment", "R1\nC1", "Rx", "R1 + W", "R1+R2+R3" * 200]
BAD_SELECT = ["day", "day=", "=1", "day=3", "nope=1", "day=1=2", "day=abc", "day=1:", "day=:", "day=2:1", "day=1,,2", "day=nan", "day=inf", "frequency=1",
              "day=1 day=2", "day==1", "day=[1", "day=1e400", "day=-1"]
BAD_ASSIGN = ["R1", "R1=", "=5", "R9=1", "R1=abc", "R1=nan", "R1=inf", "R1=-1", "R1=0", "R1=1e400", "R1=1:2", "R1.x=1", "R1==1", "C1=1u", "R1=5,R0=1",
              "r1=5", "R1=½"]
BAD_BOUNDS = ["R1", "R1=", "R1=5", "R1=5:1", "R1=abc:1", "R1=1:abc", "R1=nan:1", "R1=-inf:inf", "R1=1:1", "R1=-5:-1", "R1=1e400:1e401", "R9=1:2", "R1=::",
              "R1=1:2:3", "C1=1u:1m", "R1=0:0"]
BAD_PRIORS = ["R1", "R1=", "R1=uniform", "R1=uniform:", "R1=uniform:1", "R1=uniform:1,2,3", "R1=uniform:2,1", "R1=uniform:nan,1", "R1=normal:1,0",
              "R1=lognormal:1,-1", "R1=loguniform:-1,1", "R9=uniform:1,2", "R1=halfnormal:1", "R1=uniform:1e400,1e401", "R1=:1,2", "R1=uniform:a,b",
              "R1=fixed:1", "R1=uniform:1u,1m", "R1=normal:1,1e-320"]
BAD_EXCLUDE = ["", ",", "abc", "1,abc", "-1", "0", "nan", "inf", "1e400", "7", "1,1", "1;10"]
BAD_OUTPUT_EXT = ["out.xyz", "out", "out.", ".csv", "out.CSV", "out.json.gz", "out.txt"]


VALUES_OF = {"--param": BAD_ASSIGN, "--fix": BAD_ASSIGN, "--init": BAD_ASSIGN, "--bound": BAD_BOUNDS, "--prior": BAD_PRIORS, "--exclude": BAD_EXCLUDE}


class Timeout(BaseException):
    pass


def _alarm(signum, frame):
    raise Timeout()


def run_case(argv: list[str], out_path: str | None, stdin: bytes | None = None) -> dict:
    """One in-process run of ``impedax *argv``: exit code, stdout, stderr, seconds, and whether
    the --out file changed."""
    from impedax.cli import main

    if out_path:
        Path(out_path).write_bytes(SENTINEL)
    out, err = io.StringIO(), io.StringIO()
    signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(TIMEOUT)
    start = time.perf_counter()
    raised = None
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                code = main(argv)
            except SystemExit as exc:
                code = exc.code
    except Timeout:
        code, raised = "timeout", None
    except BaseException:  # noqa: BLE001 - the point of the matrix
        code, raised = "raised", traceback.format_exc()
    finally:
        signal.alarm(0)
    seconds = time.perf_counter() - start
    changed = None
    if out_path:
        p = Path(out_path)
        changed = (not p.is_file()) or p.read_bytes() != SENTINEL
    return {"code": code, "out": out.getvalue(), "err": err.getvalue() + (raised or ""), "seconds": seconds, "out_changed": changed}


def verdict(result: dict) -> str | None:
    code = result["code"]
    if code == "raised":
        return "TRACEBACK (raised out of main)"
    if code == "timeout":
        return f"TIMEOUT (> {TIMEOUT} s)"
    if "Traceback" in result["err"] or "Traceback" in result["out"]:
        return "TRACEBACK (printed)"
    if code not in (0, 2):
        return f"EXIT {code}"
    if code != 0 and result["out_changed"]:
        return "OUT CHANGED by a failing run"
    messages = [line for line in result["err"].splitlines() if line.startswith("impedax") and ": error: " in line]
    if code == 2 and len(messages) != 1:
        return f"{len(messages)} error messages"
    return None


# --- the cases ------------------------------------------------------------------------------


def good_lines(p: dict[str, str], tmp: Path) -> dict[str, tuple[list[str], str | None]]:
    """Each command's quick good line and its --out file (None: no --out)."""
    o = lambda ext: str(tmp / f"existing{ext}")  # noqa: E731
    rc = "R0 + R1 || C1"
    return {
        "simulate": (["simulate", rc, "--param", "R0=10", "R1=100", "C1=1u", "--points", "11", "--out", o(".csv")], o(".csv")),
        "info": (["info", rc], None),
        "fit": (["fit", p["good"], "--model", rc, "--out", o(".json")], o(".json")),
        "compare": (["compare", p["good"], "--model", "R0 + C1", "--model", rc, "--out", o(".csv")], o(".csv")),
        "sample": (["sample", p["good"], "--model", rc, "--walkers", "8", "--steps", "40", "--out", o(".nc")], o(".nc")),
        "kk": (["kk", p["good"], "--out", o(".json")], o(".json")),
        "drt": (["drt", p["good"], "--out", o(".json")], o(".json")),
        "diagnose": (["diagnose", p["good"], "--model", rc, "--out", o(".json")], o(".json")),
        "refine": (["refine", p["good"], "--model", rc, "--max-effects", "1", "--out", o(".json")], o(".json")),
        "force": (["force", "meyer", "--points", "5", "--out", o(".csv")], o(".csv")),
        "gap": (["gap", p["total"], p["skin"], p["ts"], "--area", "130e-6", "--pooled", "--steps", "20", "--out", o(".json")], o(".json")),
        "remaining": (["remaining", p["total"], p["skin"], p["ts"], "--out", o(".nc")], o(".nc")),
        "draw": (["draw", rc, "-o", o(".svg")], o(".svg")),
        "inspect": (["inspect", p["good"], "--out", o(".csv")], o(".csv")),
        "stack": (["stack", p["good"], p["good2"], "--out", o(".nc")], o(".nc")),
        "demo": (["demo", "--fast", "--out", str(tmp / "demo-out")], None),
    }


def _with(argv, option, value):
    """``argv`` with ``option value`` replacing the option's first value if present, else added."""
    argv = list(argv)
    if option in argv:
        k = argv.index(option)
        argv[k + 1] = value
        # (spread values after it, e.g. --param R0=10 R1=100: drop them)
        while k + 2 < len(argv) and "=" in argv[k + 2] and not argv[k + 2].startswith("-"):
            del argv[k + 2]
        return argv
    return argv + [option, value] if not value.startswith("-") else argv + [f"{option}={value}"]


def option_table(command: str):
    """(option, kind, choices) of every option of ``command`` that takes a value."""
    from impedax.cli import _subparser, build_parser

    sub = _subparser(build_parser(command), command)
    rows = []
    for action in sub._actions:
        if not action.option_strings or action.nargs == 0 or action.dest in ("help", "plugin"):
            continue
        rows.append((action.option_strings[-1], action.type, action.choices, action.metavar))
    return rows


FILE_OPTIONS = ("--plot", "--corner", "--trace", "--residual-map", "--out", "--frequencies", "--remaining")
TEXT_OPTIONS = ("--title",)


def cases(p: dict[str, str], tmp: Path) -> list[tuple[str, list[str], str | None]]:
    lines = good_lines(p, tmp)
    out = []

    def add(case_id, argv, out_path):
        out.append((case_id, argv, out_path))

    for command, (argv, out_path) in lines.items():
        if command == "demo":
            continue
        for option, kind, choices, metavar in option_table(command):
            if option in ("--model",) and command in ("simulate", "info", "draw"):
                continue
            if option == "--out" or option == "-o":
                for ext in BAD_OUTPUT_EXT:
                    add(f"{command} {option} {ext}", _with(argv, option, str(tmp / ext)), out_path)
                add(f"{command} {option} missing-dir", _with(argv, option, str(tmp / "missing" / "x.json")), out_path)
                add(f"{command} {option} is-a-dir", _with(argv, option, p["directory"]), out_path)
                add(f"{command} {option} /proc", _with(argv, option, "/proc/impedax-out.csv"), out_path)
                continue
            if option in FILE_OPTIONS:
                for value in ("missing/x.png", p["directory"], str(tmp / "x.xyz"), str(tmp / "x"), "", "/proc/x.png"):
                    add(f"{command} {option} {value!r}", _with(argv, option, value if not value.startswith("missing") else str(tmp / value)), out_path)
                continue
            if option == "--model":
                for model in BAD_CIRCUITS:
                    add(f"{command} --model {model[:30]!r}", _with(argv, option, model), out_path)
                continue
            if option == "--select":
                series_argv = [p["series"] if a == p["good"] else a for a in argv]
                for value in BAD_SELECT:
                    add(f"{command} --select {value!r}", _with(series_argv, option, value), out_path)
                continue
            if option in VALUES_OF:
                for value in VALUES_OF[option]:
                    add(f"{command} {option} {value!r}", _with(argv, option, value), out_path)
                continue
            if choices:
                for value in ("bogus", "", "UNIT"):
                    add(f"{command} {option} {value!r}", _with(argv, option, value), out_path)
                continue
            if option in TEXT_OPTIONS:
                for value in ("", "$\\frac{", "x" * 10000, "\x1b[2J", "$x"):
                    add(f"{command} {option} {value[:12]!r}", _with(argv, option, value), out_path)
                continue
            for value in BAD_NUMBERS + ["R1", "1,2", "auto"]:
                add(f"{command} {option} {value!r}", _with(argv, option, value), out_path)
        # bad files in every file position
        positions = [k for k, a in enumerate(argv) if a in (p["good"], p["good2"], p["total"], p["skin"], p["ts"])]
        for k in positions:
            for name in ("empty", "header", "one-point", "two-points", "all-nan", "nan-z-column", "duplicate-frequencies", "negative-frequencies",
                         "zero-z", "truncated", "truncated-mid-number", "constant-z", "huge", "tiny", "decreasing", "one-column",
                         "semicolons-garbage", "latin1", "binary", "directory", "missing", "truncated-nc", "series"):
                bad = list(argv)
                bad[k] = p[name]
                add(f"{command} file#{k} {name}", bad, out_path)
        # plugins
        add(f"{command} --plugin raising", ["--plugin", p["bad-plugin"], *argv], out_path)
        add(f"{command} --plugin syntax", ["--plugin", p["syntax-plugin"], *argv], out_path)
        add(f"{command} --plugin missing", ["--plugin", p["missing"], *argv], out_path)
        add(f"{command} --plugin directory", ["--plugin", p["directory"], *argv], out_path)

    # conflicting flags and extra combinations
    rc = "R0 + R1 || C1"
    g = p["good"]
    extra = [
        ("fit fix+init same", ["fit", g, "--model", rc, "--fix", "R0=10", "--init", "R0=5"]),
        ("fit fix+bound same", ["fit", g, "--model", rc, "--fix", "R0=10", "--bound", "R0=1:5"]),
        ("fit init outside bound", ["fit", g, "--model", rc, "--init", "R0=100", "--bound", "R0=1:5"]),
        ("fit fix twice", ["fit", g, "--model", rc, "--fix", "R0=10", "--fix", "R0=11"]),
        ("fit shared without over", ["fit", p["series"], "--model", rc, "--shared", "R0"]),
        ("fit over without shared", ["fit", p["series"], "--model", rc, "--over", "day"]),
        ("fit shared unknown", ["fit", p["series"], "--model", rc, "--shared", "R9", "--over", "day"]),
        ("fit over unknown", ["fit", p["series"], "--model", rc, "--shared", "R0", "--over", "nope"]),
        ("fit shared on one spectrum", ["fit", g, "--model", rc, "--shared", "R0", "--over", "day"]),
        ("fit shared all", ["fit", p["series"], "--model", rc, "--shared", "R0,R1,C1", "--over", "day"]),
        ("fit shared+fix", ["fit", p["series"], "--model", rc, "--shared", "R0", "--over", "day", "--fix", "R0=10"]),
        ("fit shared empty", ["fit", p["series"], "--model", rc, "--shared", "", "--over", "day"]),
        ("fit shared ,", ["fit", p["series"], "--model", rc, "--shared", ",", "--over", "day"]),
        ("fit plot-x on one", ["fit", g, "--model", rc, "--plot-x", "day", "--plot", str(tmp / "p.png")]),
        ("fit plot-x unknown", ["fit", p["series"], "--model", rc, "--plot-x", "nope", "--plot", str(tmp / "p.png")]),
        ("fit plot-x without plot", ["fit", p["series"], "--model", rc, "--plot-x", "day"]),
        ("fit plot-params unknown", ["fit", p["series"], "--model", rc, "--plot-params", "R9", "--plot", str(tmp / "p.png")]),
        ("fit plot-params on one", ["fit", g, "--model", rc, "--plot-params", "R0", "--plot", str(tmp / "p.png")]),
        ("fit residual-map on one", ["fit", g, "--model", rc, "--residual-map", str(tmp / "r.png")]),
        ("fit fmin=fmax", ["fit", g, "--model", rc, "--fmin", "10", "--fmax", "10"]),
        ("fit exclude all", ["fit", g, "--model", rc, "--exclude", ",".join(f"{x:.8g}" for x in np.geomspace(1, 1e5, 21))]),
        ("fit json and out -", ["fit", g, "--model", rc, "--json", "--out", "-"]),
        ("fit out - tex", ["fit", g, "--model", rc, "--out", str(tmp / "x.tex"), "--json"]),
        ("fit out same as input", ["fit", g, "--model", rc, "--out", g]),
        ("fit out same as plot", ["fit", g, "--model", rc, "--out", str(tmp / "same.png"), "--plot", str(tmp / "same.png")]),
        ("fit dpi without plot", ["fit", g, "--model", rc, "--dpi", "50"]),
        ("fit dpi huge", ["fit", g, "--model", rc, "--dpi", "100000", "--plot", str(tmp / "p.png")]),
        ("fit dpi 1", ["fit", g, "--model", rc, "--dpi", "1", "--plot", str(tmp / "p.png")]),
        ("compare same model twice", ["compare", g, "--model", rc, "--model", rc]),
        ("compare all fixed", ["compare", g, "--model", "R0", "--model", "R0 + C1", "--fix", "R0=1"]),
        ("sample burn=steps", ["sample", g, "--model", rc, "--walkers", "8", "--steps", "20", "--burn", "20"]),
        ("sample thin>steps", ["sample", g, "--model", rc, "--walkers", "8", "--steps", "20", "--thin", "50"]),
        ("sample odd walkers", ["sample", g, "--model", rc, "--walkers", "7", "--steps", "20"]),
        ("sample walkers < 2*params", ["sample", g, "--model", rc, "--walkers", "4", "--steps", "20"]),
        ("sample noise sigma no sigma", ["sample", g, "--model", rc, "--walkers", "8", "--steps", "20", "--noise", "sigma"]),
        ("sample prior+fix same", ["sample", g, "--model", rc, "--walkers", "8", "--steps", "20", "--fix", "R0=10", "--prior", "R0=uniform:1,20"]),
        ("sample prior outside bound", ["sample", g, "--model", rc, "--walkers", "8", "--steps", "20", "--bound", "R0=1:5", "--prior", "R0=uniform:10,20"]),
        ("sample corner-params unknown", ["sample", g, "--model", rc, "--walkers", "8", "--steps", "20", "--corner-params", "R9", "--corner", str(tmp / "c.png")]),
        ("sample corner-params empty", ["sample", g, "--model", rc, "--walkers", "8", "--steps", "20", "--corner-params", "", "--corner", str(tmp / "c.png")]),
        ("sample corner-params without corner", ["sample", g, "--model", rc, "--walkers", "8", "--steps", "20", "--corner-params", "R0"]),
        ("sample on series no select", ["sample", p["series"], "--model", rc, "--walkers", "8", "--steps", "20"]),
        ("sample shared no over", ["sample", p["series"], "--model", rc, "--walkers", "8", "--steps", "20", "--shared", "R0"]),
        ("kk no-inductance zhit", ["kk", g, "--method", "zhit", "--no-inductance"]),
        ("kk c with zhit", ["kk", g, "--method", "zhit", "--c", "0.5"]),
        ("kk max-rc 1e9", ["kk", g, "--max-rc", "1000000000"]),
        ("kk noise sigma no sigma", ["kk", g, "--noise", "sigma"]),
        ("drt lam 1e-300", ["drt", g, "--lam", "1e-300"]),
        ("drt lam 1e300", ["drt", g, "--lam", "1e300"]),
        ("drt min-peak-fraction 2", ["drt", g, "--min-peak-fraction", "2"]),
        ("drt lam-method with fixed lam", ["drt", g, "--lam", "0.01", "--lam-method", "lcurve"]),
        ("diagnose effects unknown", ["diagnose", g, "--model", rc, "--effects", "nope"]),
        ("diagnose keep-all-points + noise", ["diagnose", g, "--model", rc, "--keep-all-points", "--noise", "1%"]),
        ("diagnose noise 0%", ["diagnose", g, "--model", rc, "--noise", "0%"]),
        ("diagnose noise -5%", ["diagnose", g, "--model", rc, "--noise=-5%"]),
        ("diagnose noise abc%", ["diagnose", g, "--model", rc, "--noise", "abc%"]),
        ("diagnose noise %", ["diagnose", g, "--model", rc, "--noise", "%"]),
        ("diagnose no model", ["diagnose", g]),
        ("refine max-effects 0", ["refine", g, "--model", rc, "--max-effects", "0"]),
        ("refine fix unknown", ["refine", g, "--model", rc, "--fix", "R9=1"]),
        ("force vezzoli variant", ["force", "vezzoli", "--variant", "cpe"]),
        ("force no-param-check negative", ["force", "meyer", "--no-param-check", "--param", "area=-1"]),
        ("force no-param-check zero", ["force", "meyer", "--no-param-check", "--param", "area=0"]),
        ("force no-param-check nan", ["force", "meyer", "--no-param-check", "--param", "area=nan"]),
        ("force no-param-check huge", ["force", "meyer", "--no-param-check", "--param", "area=1e300"]),
        ("force points 1e9", ["force", "meyer", "--points", "1000000000"]),
        ("simulate points 1e9", ["simulate", rc, "--points", "1000000000"]),
        ("simulate frequencies + fmin", ["simulate", rc, "--frequencies", g, "--fmin", "10"]),
        ("simulate frequencies bad", ["simulate", rc, "--frequencies", p["all-nan"]]),
        ("simulate frequencies series", ["simulate", rc, "--frequencies", p["series"]]),
        ("simulate select without frequencies", ["simulate", rc, "--select", "day=1"]),
        ("simulate fmin=fmax points 5", ["simulate", rc, "--fmin", "10", "--fmax", "10", "--points", "5"]),
        ("simulate param missing", ["simulate", rc, "--param", "R0=10"]),
        ("simulate json out csv", ["simulate", rc, "--json"]),
        ("gap pooled + method pooled", ["gap", p["total"], p["skin"], p["ts"], "--area", "130e-6", "--pooled", "--method", "pooled", "--steps", "20"]),
        ("gap no-area-check negative", ["gap", p["total"], p["skin"], p["ts"], "--area", "-1", "--no-area-check"]),
        ("gap no-area-check zero", ["gap", p["total"], p["skin"], p["ts"], "--area", "0", "--no-area-check"]),
        ("gap remaining + three files", ["gap", p["total"], p["skin"], p["ts"], "--area", "130e-6", "--pooled", "--steps", "20", "--remaining", str(tmp / "rem.nc")]),
        ("gap one file", ["gap", p["total"], "--area", "130e-6", "--pooled", "--steps", "20"]),
        ("gap same file thrice", ["gap", p["total"], p["total"], p["total"], "--area", "130e-6", "--pooled", "--steps", "20"]),
        ("gap steps auto hierarchical", ["gap", p["total"], p["skin"], p["ts"], "--area", "130e-6", "--steps", "abc"]),
        ("remaining trials one file", ["remaining", p["total"], "--trials", "--out", str(tmp / "r.nc")]),
        ("remaining one file", ["remaining", p["total"], "--out", str(tmp / "r.nc")]),
        ("remaining same file", ["remaining", p["total"], p["total"], p["total"], "--out", str(tmp / "r.nc")]),
        ("remaining good csv three", ["remaining", g, g, g, "--out", str(tmp / "r.nc")]),
        ("stack one file", ["stack", g, "--out", str(tmp / "s.nc")]),
        ("stack series files", ["stack", p["series"], p["series"], "--out", str(tmp / "s.nc")]),
        ("stack dim frequency", ["stack", g, p["good2"], "--dim", "frequency", "--out", str(tmp / "s.nc")]),
        ("stack dim empty", ["stack", g, p["good2"], "--dim", "", "--out", str(tmp / "s.nc")]),
        ("stack dim 'a b'", ["stack", g, p["good2"], "--dim", "a b", "--out", str(tmp / "s.nc")]),
        ("stack coords dup", ["stack", g, p["good2"], "--coords", "1", "1", "--out", str(tmp / "s.nc")]),
        ("stack coords nan", ["stack", g, p["good2"], "--coords", "nan", "1", "--out", str(tmp / "s.nc")]),
        ("stack coords mixed", ["stack", g, p["good2"], "--coords", "1", "a", "--out", str(tmp / "s.nc")]),
        ("stack coords empty", ["stack", g, p["good2"], "--coords", "", "b", "--out", str(tmp / "s.nc")]),
        ("stack different grids", ["stack", g, p["two-points"], "--out", str(tmp / "s.nc")]),
        ("stack common-frequencies disjoint", ["stack", g, p["one-point"], "--common-frequencies", "--out", str(tmp / "s.nc")]),
        ("stack no out", ["stack", g, p["good2"]]),
        ("demo out is a file", ["demo", "--fast", "--out", str(tmp / "out.txt")]),
        ("demo out in /proc", ["demo", "--fast", "--out", "/proc/impedax-demo"]),
        ("demo out empty", ["demo", "--fast", "--out", ""]),
        ("info json unknown", ["info", "R1 + X1", "--json"]),
        ("draw param unknown", ["draw", rc, "--param", "R9=1", "-o", str(tmp / "d.svg")]),
        ("draw out png dpi", ["draw", rc, "-o", str(tmp / "d.xyz")]),
        ("inspect stdin empty", ["inspect", "-"]),
        ("fit stdin empty", ["fit", "-", "--model", rc]),
        ("impedax no command", []),
        ("impedax --plugin only", ["--plugin"]),
        ("version", ["--version"]),
    ]
    # figure options with a figure to draw: --dpi and --title only act then
    for command, (argv, out_path) in lines.items():
        flags = [o for o, *_ in option_table(command)] if command != "demo" else []
        for figure_flag in [f for f in ("--plot", "--corner", "--trace", "--residual-map") if f in flags]:
            drawn = _with(argv, figure_flag, str(tmp / "figure.png"))
            if command == "fit" and figure_flag == "--residual-map":
                drawn = [p["series"] if a == p["good"] else a for a in drawn]
            for value in ["1", "5", "19", "1e-300", "20", "1200", "1201"]:
                add(f"{command} {figure_flag} --dpi {value}", _with(drawn, "--dpi", value), out_path)
            for value in [r"$\undefined$", r"$\frac{1}$", "a $x^$ b", r"Z at $\omega$", r"costs \$5", "$", "\x1b[2J", "x" * 5000]:
                add(f"{command} {figure_flag} --title {value[:16]!r}", _with(drawn, "--title", value), out_path)
    # data whose labels and file names hold dollar signs, drawn
    import impedax as ix

    labelled = ix.load(p["series"]).assign_coords(day=[r"$\bad$", "price $5 and $6"])
    ix.save(labelled, str(tmp / "labelled.nc"))
    named = tmp / r"x$\bad$.csv"
    named.write_bytes(Path(p["good"]).read_bytes())
    for command in ("fit", "compare", "kk", "drt", "inspect"):
        argv, out_path = lines[command]
        for name, path in (("labels", str(tmp / "labelled.nc")), ("file name", str(named))):
            add(f"{command} --plot data with $ in its {name}", _with([path if a == p["good"] else a for a in argv], "--plot", str(tmp / "figure.png")), out_path)
    for case_id, argv in extra:
        out.append((case_id, argv, None))
    return out


def main_(argv=None) -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--only", help="run only the cases whose id contains this")
    parser.add_argument("--skip", action="append", default=[], help="leave out the cases whose id contains this")
    parser.add_argument("--list", action="store_true")
    parser.add_argument("--verbose", action="store_true", help="print every case's stderr")
    options = parser.parse_args(argv)
    os.environ.setdefault("IMPEDAX_PROGRESS", "0")
    with tempfile.TemporaryDirectory() as folder:
        tmp = Path(folder)
        os.chdir(tmp)
        files = make_files(tmp)
        table = cases(files, tmp)
        table = [c for c in table if (not options.only or options.only in c[0]) and not any(s in c[0] for s in options.skip)]
        if options.list:
            for case_id, argv, _ in table:
                print(case_id, argv[:8])
            print(len(table), "cases")
            return 0
        flagged, accepted = [], []
        for n, (case_id, argv, out_path) in enumerate(table, 1):
            stdin = sys.stdin
            sys.stdin = io.TextIOWrapper(io.BytesIO(b""))
            try:
                result = run_case(argv, out_path)
            finally:
                sys.stdin = stdin
            bad = verdict(result)
            last = result["err"].strip().splitlines()[-1:] or [""]
            line = f"[{n}/{len(table)}] {result['code']!s:>7} {result['seconds']:6.1f}s {case_id}"
            if bad:
                flagged.append((case_id, argv, bad, result))
                print(f"{line}  <<< {bad}\n    {result['err'][-1500:]}", flush=True)
            else:
                if result["code"] == 0:
                    accepted.append((case_id, argv))
                print(line + (f"\n    {last[0][:300]}" if options.verbose or result["code"] == 0 else ""), flush=True)
        print(f"\n{len(table)} cases, {len(flagged)} flagged, {len(accepted)} accepted (exit 0)")
        for case_id, argv, bad, _ in flagged:
            print(f"FLAGGED {bad}: {case_id}: {argv}")
        return 1 if flagged else 0


if __name__ == "__main__":
    sys.exit(main_())
