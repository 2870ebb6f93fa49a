"""SIGINT and SIGTERM end any command with one line ("interrupted; nothing written") and exit
code 130 / 143: no traceback (not from emcee either), no temporary file left, no partial or
replaced output.

Each case runs ``impedax`` in a subprocess. To hit the exact moment under test without
depending on timing, a small driver patches that spot (halfway through a writer, inside emcee's
call of the log-probability, in a task of a dask computation the main thread waits for) to send
the signal to its own process; the real handlers of `impedax.cli.main` then do the rest. One
case interrupts a real run from outside.
"""

from __future__ import annotations

import importlib.util
import os
import re
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

from impedax.cli import main

ROOT = Path(__file__).resolve().parents[1]
EXIT = {signal.SIGINT: 130, signal.SIGTERM: 143}

# the driver: apply ``PATCH`` (Python source that may use ``kill()``), then run the program
DRIVER = """
import os, signal, sys, time
sys.argv = ["impedax", *{argv!r}]

def kill():
    os.kill(os.getpid(), {signum})
    time.sleep(60)  # the handler ends the process before this returns

{patch}
from impedax.cli import main
raise SystemExit(main())
"""

# (id, where the signal arrives: the patch, the command, the output files it would write)
PARTIAL_WRITE = """
import xarray
def to_netcdf(self, path, *args, **kwargs):
    with open(path, "wb") as fh:
        fh.write(b"CDF\\x02 half a file")
    kill()
xarray.Dataset.to_netcdf = to_netcdf
"""
PARTIAL_FIGURE = """
import matplotlib.figure
def savefig(self, fname, *args, **kwargs):
    with open(fname, "wb") as fh:
        fh.write(b"\\x89PNG half a figure")
    kill()
matplotlib.figure.Figure.savefig = savefig
"""
INSIDE_EMCEE = """
import emcee.ensemble
calls = [0]
original = emcee.ensemble._FunctionWrapper.__init__
def wrapped(self, f, args, kwargs):  # the signal arrives inside emcee's try/except around the log-probability
    def counted(x, *a, **k):
        calls[0] += 1
        if calls[0] == 25:
            kill()
        return f(x, *a, **k)
    original(self, counted, args, kwargs)
emcee.ensemble._FunctionWrapper.__init__ = wrapped
"""
IN_STAGING = """
import impedax.io.loader
def save(ds, path):
    with open(path, "wb") as fh:
        fh.write(b"CDF\\x02 half")
    kill()
import impedax
impedax.save = save
"""
INSIDE_DASK = """
import dask
import impedax.io
def save(ds, path, **options):  # the write waits on a dask computation whose task is interrupted
    def task(x):
        kill()
        return x
    dask.delayed(task)(1).compute(scheduler="threads")
impedax.io.save = save
"""

CASES = [
    ("simulate-netcdf", PARTIAL_WRITE, ["simulate", "R1 + C1", "--param", "R1=100", "--param", "C1=1e-6", "--out", "{tmp}/spectrum.nc"], ["spectrum.nc"]),
    ("simulate-figure-after-csv", PARTIAL_FIGURE, ["simulate", "R1 + C1", "--param", "R1=100", "--param", "C1=1e-6", "--out", "{tmp}/s.csv", "--plot", "{tmp}/s.png"], ["s.csv", "s.png"]),
    ("inspect-netcdf", PARTIAL_WRITE, ["inspect", "{tmp}/good.csv", "--out", "{tmp}/converted.nc"], ["converted.nc"]),
    pytest.param("fit-figure-after-result", PARTIAL_FIGURE, ["fit", "{tmp}/good.csv", "--model", "R0 + R1 || C1", "--out", "{tmp}/fit.json", "--plot", "{tmp}/fit.png"], ["fit.json", "fit.png"], marks=pytest.mark.slow, id="fit-figure-after-result"),
    ("sample-inside-emcee", INSIDE_EMCEE, ["sample", "{tmp}/good.csv", "--model", "R0 + R1 || C1", "--steps", "500", "--quiet", "--out", "{tmp}/post.nc", "--plot", "{tmp}/post.png"], ["post.nc", "post.png"]),
    pytest.param("inspect-inside-dask", INSIDE_DASK, ["inspect", "{tmp}/good.csv", "--out", "{tmp}/converted.nc"], ["converted.nc"],
                 marks=pytest.mark.skipif(importlib.util.find_spec("dask") is None, reason="dask is not installed"), id="inspect-inside-dask"),
    ("demo-staging-folder", IN_STAGING, ["demo", "--out", "{tmp}/demo", "--fast"], []),
]


def _good_csv(path: Path) -> None:
    f = np.geomspace(1.0, 1e5, 25)
    z = 100.0 + 1000.0 / (1 + 1j * 2 * np.pi * f * 1e-3)
    path.write_text("frequency_hz,z_real_ohm,z_imag_ohm\n" + "".join(f"{a!r},{b.real!r},{b.imag!r}\n" for a, b in zip(f.tolist(), z.tolist())))


def _environment() -> dict:
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    env.pop("IMPEDAX_MEMORY_LIMIT", None)
    return env


def _listing(folder: Path) -> dict:
    return {str(p.relative_to(folder)): (p.is_dir() or p.read_bytes()) for p in sorted(folder.rglob("*"))}


def _check_interrupted(code: int, err: str, signum: int, command: str, folder: Path, before: dict) -> None:
    assert code == EXIT[signum], (code, err)
    assert "Traceback" not in err and "emcee:" not in err, err
    # progress lines ("[  1.9 s] ...") show when the work outlasts their delay, as on a loaded machine: not the message
    lines = [line for line in err.strip().splitlines() if line.strip() and not re.match(r"\[\s*[\d.]+ s\] ", line)]
    assert lines == [f"impedax {command}: interrupted; nothing written"], err
    after = _listing(folder)
    created = set(after) - set(before)
    assert all(after[name] is True for name in created), created  # at most an empty output folder (demo)
    assert not [name for name in created if Path(name).name.startswith(".")], created
    assert {k: v for k, v in after.items() if k in before} == before  # nothing replaced


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
@pytest.mark.parametrize("case_id, patch, template, outputs", [c if hasattr(c, "marks") else pytest.param(*c, id=c[0]) for c in CASES])
def test_interrupt_at_the_worst_moment(case_id, patch, template, outputs, signum, tmp_path):
    _good_csv(tmp_path / "good.csv")
    for name in outputs[:1]:  # an earlier result that must survive
        (tmp_path / name).write_bytes(b"an earlier result")
    argv = [a.format(tmp=tmp_path) for a in template]
    before = _listing(tmp_path)
    source = DRIVER.format(argv=argv, signum=int(signum), patch=textwrap.dedent(patch))
    done = subprocess.run([sys.executable, "-c", source], capture_output=True, text=True, timeout=600, env=_environment(), cwd=tmp_path)
    _check_interrupted(done.returncode, done.stderr, signum, template[0], tmp_path, before)
    if template[0] != "demo":  # (the demo tells its story on stdout as it goes)
        assert done.stdout == ""


def test_interrupt_while_waiting_for_standard_input(tmp_path):
    """Blocked reading ``-`` from a pipe that never ends: Ctrl-C ends it cleanly."""
    process = subprocess.Popen(
        [sys.executable, "-m", "impedax", "fit", "-", "--model", "R1 + C1", "--out", str(tmp_path / "fit.json")],
        stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=_environment(), cwd=tmp_path,
    )
    time.sleep(3)  # well past the start of main (the handlers are set before anything heavy is imported)
    process.send_signal(signal.SIGINT)
    out, err = process.communicate(timeout=120)
    process.stdin.close()
    _check_interrupted(process.returncode, err, signal.SIGINT, "fit", tmp_path, {})
    assert out == ""


@pytest.mark.slow
@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_interrupt_a_real_sampling_run(signum, tmp_path):
    """A real ``sample`` run, interrupted from outside once its progress line shows emcee is running."""
    _good_csv(tmp_path / "good.csv")
    before = _listing(tmp_path)
    process = subprocess.Popen(
        [sys.executable, "-m", "impedax", "sample", "good.csv", "--model", "R0 + R1 || C1", "--steps", "200000", "--out", "post.nc"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=_environment(), cwd=tmp_path,
    )
    seen = b""
    while b"step " not in seen:  # the progress line appears once emcee has run for a second
        chunk = process.stderr.read1(4096)
        assert chunk, seen
        seen += chunk
    process.send_signal(signum)
    rest = process.stderr.read().decode()
    process.wait(timeout=120)
    text = seen.decode() + rest
    last = text.replace("\r", "\n").strip().splitlines()[-1]
    assert process.returncode == EXIT[signum], text
    assert last == "impedax sample: interrupted; nothing written" and "Traceback" not in text
    assert _listing(tmp_path) == before


def test_interrupt_when_called_from_python(tmp_path, capsys, monkeypatch):
    """Called as a function (argv given), `main` returns 130 and cleans up instead of ending the process."""
    import matplotlib.figure

    _good_csv(tmp_path / "good.csv")

    def savefig(self, fname, *args, **kwargs):
        Path(fname).write_bytes(b"half")
        os.kill(os.getpid(), signal.SIGINT)

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", savefig)
    before = _listing(tmp_path)
    handler = signal.getsignal(signal.SIGINT)
    code = main(["simulate", "R1 + C1", "--param", "R1=100", "--param", "C1=1e-6", "--out", str(tmp_path / "s.csv"), "--plot", str(tmp_path / "s.png")])
    out, err = capsys.readouterr()
    assert code == 130
    assert err.strip().splitlines() == ["impedax simulate: interrupted; nothing written"]
    assert _listing(tmp_path) == before
    assert signal.getsignal(signal.SIGINT) is handler  # the caller's handler is back
