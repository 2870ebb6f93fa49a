"""Outputs that no permission bit forbids but that cannot be written all the same, and a failure
while staging or moving an output into place; and the title of ``impedax inspect --plot``.

Root passes every `os.access` check (containers, NFS root-squash), so a folder like ``/sys``
or ``/proc`` looked writable and the command ran its whole fit before dying with a traceback
while staging the output. Now `check_writable` creates and removes a temporary file beside
the target (named as the staging is) before any work: exit 2, one line naming the path and
the system's reason, nothing run and nothing left behind. ``/sys`` and ``/proc`` refuse new
files to root too, so these tests mean the same for any user (a user other than root is
refused by the permission check already: "is not writable").
"""

from __future__ import annotations

import errno
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.errors import DataError
from impedax.io.atomic import OutputTransaction, atomic_path, check_writable, live_temporaries

PROGRESS_LINE = re.compile(r"^\[\s*\d+\.\d s\] ")  # `cli.common.progress_printer`'s lines

ROOT = Path(__file__).resolve().parents[1]
BIOLOGIC = ROOT / "tests" / "fixtures" / "real" / "exampleDataBioLogic.mpt"
CYCLES_NC = ROOT / "examples" / "data" / "autoeis_battery_cycles.nc"
IMPEDAX = Path(sys.executable).with_name("impedax")

# folders in which no one, root included, can create a file
UNWRITABLE = [d for d in ("/sys", "/proc") if os.path.isdir(d)]

# (id, argv with {path} (the output) and {data} (a good spectrum), extension)
COMMANDS = [
    ("fit-out", ["fit", "{data}", "--model", "R0 + R1 || C1", "--out", "{path}"], ".csv"),
    ("fit-plot", ["fit", "{data}", "--model", "R0 + R1 || C1", "--plot", "{path}"], ".png"),
    ("compare-out", ["compare", "{data}", "--model", "R0 + C1", "--model", "R0 + R1 || C1", "--out", "{path}"], ".json"),
    ("refine-out", ["refine", "{data}", "--model", "R0 + R1 || C1", "--out", "{path}"], ".json"),
    ("inspect-plot", ["inspect", "{data}", "--plot", "{path}"], ".png"),
    ("inspect-out", ["inspect", "{data}", "--out", "{path}"], ".csv"),
]


def _good_csv(path: Path) -> Path:
    f = np.geomspace(1.0, 1e5, 25)
    z = 100.0 + 1000.0 / (1 + 1j * 2 * np.pi * f * 1e-3)
    path.write_text("frequency_hz,z_real_ohm,z_imag_ohm\n" + "".join(f"{a!r},{b.real!r},{b.imag!r}\n" for a, b in zip(f.tolist(), z.tolist())))
    return path


def _staged_beside(path: Path) -> list[str]:
    """Files beside ``path`` named as its staged copies or probes are."""
    try:
        return [n for n in os.listdir(path.parent) if n.startswith(f".{path.name}.")]
    except OSError:
        return []


def _one_line_refusal(code: int, out: str, err: str, path: str) -> str:
    assert code == 2, (code, err)
    assert "Traceback" not in out + err
    lines = [line for line in err.strip().splitlines() if not PROGRESS_LINE.match(line)]  # (a run past 2 s says what it does)
    assert len(lines) == 1, err
    assert lines[0].startswith("impedax ") and "error:" in lines[0], err
    assert path in lines[0], err
    return lines[0]


@pytest.fixture
def no_work(monkeypatch):
    """Reading the data or fitting fails the test: a refusal must come before any work."""
    import impedax.cli.common as common

    def forbidden(*args, **kwargs):
        raise AssertionError("the command did work before refusing its output")

    monkeypatch.setattr(common, "load_selected", forbidden)
    monkeypatch.setattr(ix, "fit", forbidden)
    monkeypatch.setattr(ix, "compare", forbidden)
    import impedax.fitting as fitting

    monkeypatch.setattr(fitting, "refine", forbidden)


@pytest.mark.skipif(not UNWRITABLE, reason="no /sys or /proc here")
@pytest.mark.parametrize("folder", UNWRITABLE)
@pytest.mark.parametrize("case", COMMANDS, ids=[c[0] for c in COMMANDS])
def test_an_output_in_a_folder_that_refuses_files_is_refused_before_any_work(case, folder, no_work, capsys):
    _, template, ext = case
    path = f"{folder}/impedax-out{ext}"
    argv = [a.format(path=path, data=BIOLOGIC) for a in template]
    code = main(argv)
    out, err = capsys.readouterr()
    line = _one_line_refusal(code, out, err, path)
    # the reason is the operating system's (root) or the permission check's (other users)
    assert "cannot create a file in directory" in line or "is not writable" in line, line
    assert not _staged_beside(Path(path)) and not live_temporaries()


@pytest.mark.skipif(not os.path.isdir("/sys") or not IMPEDAX.exists(), reason="no /sys or no impedax program")
def test_the_program_refuses_at_once_with_exit_2_and_no_traceback(tmp_path):
    """The installed program, as the bug was met: exit 2 (it was 1, with a traceback, after the
    whole fit)."""
    proc = subprocess.run([str(IMPEDAX), "refine", str(BIOLOGIC), "--out", "/sys/x.csv"], capture_output=True, text=True, timeout=120, cwd=tmp_path)
    line = _one_line_refusal(proc.returncode, proc.stdout, proc.stderr, "/sys/x.csv")
    assert "/sys" in line and not proc.stdout


def test_check_writable_probes_and_leaves_nothing(tmp_path):
    target = tmp_path / "result.csv"
    assert check_writable(target) == target
    assert list(tmp_path.iterdir()) == [] and not live_temporaries()
    if os.path.isdir("/proc"):
        with pytest.raises(DataError, match=r"^/proc/x\.csv: ") as info:
            check_writable("/proc/x.csv")
        assert info.value.path == "/proc/x.csv"


def test_check_writable_does_not_trust_os_access(tmp_path, monkeypatch):
    """`os.access` answers yes (as it does for root), creating the file fails: refused, with
    the system's reason."""
    import tempfile

    monkeypatch.setattr(os, "access", lambda *a, **k: True)

    def refuse(*args, **kwargs):
        raise PermissionError(errno.EACCES, "Permission denied")

    monkeypatch.setattr(tempfile, "mkstemp", refuse)
    with pytest.raises(DataError) as info:
        check_writable(tmp_path / "x.png")
    assert str(info.value) == f"{tmp_path / 'x.png'}: cannot create a file in directory {tmp_path}: Permission denied"
    assert list(tmp_path.iterdir()) == []


def test_a_name_too_long_is_an_error_naming_it(tmp_path):
    with pytest.raises(DataError, match="File name too long"):
        check_writable(tmp_path / ("a" * 300 + ".csv"))


def test_staging_that_fails_after_the_check_is_an_error_naming_the_target(tmp_path, monkeypatch):
    """The folder stopped taking files between the check and the write: `DataError` naming the
    target, the earlier staged file removed, the existing targets unchanged."""
    import tempfile

    first, second = tmp_path / "a.csv", tmp_path / "b.png"
    first.write_text("old a")
    second.write_text("old b")
    real_mkstemp = tempfile.mkstemp

    def mkstemp(*args, prefix="", **kwargs):
        if prefix.startswith(".b.png."):
            raise OSError(errno.EROFS, "Read-only file system")
        return real_mkstemp(*args, prefix=prefix, **kwargs)

    monkeypatch.setattr(tempfile, "mkstemp", mkstemp)
    with pytest.raises(DataError) as info:
        with OutputTransaction() as transaction:
            transaction.write(first, lambda p: p.write_text("new a"))
            transaction.write(second, lambda p: p.write_text("new b"))
    assert str(info.value).startswith(f"{second}: ") and "Read-only file system" in str(info.value)
    assert first.read_text() == "old a" and second.read_text() == "old b"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv", "b.png"] and not live_temporaries()


def _replace_failing_for(monkeypatch, target: Path):
    """`os.replace` onto ``target`` fails (EXDEV, as a bind mount gives); any other works."""
    real_replace = os.replace

    def replace(src, dst, *args, **kwargs):
        if os.path.abspath(dst) == os.path.abspath(target):
            raise OSError(errno.EXDEV, "Invalid cross-device link")
        return real_replace(src, dst, *args, **kwargs)

    monkeypatch.setattr(os, "replace", replace)


def test_a_failed_commit_keeps_the_existing_target(tmp_path, monkeypatch):
    target = tmp_path / "a.json"
    target.write_text("the result of an earlier run")
    _replace_failing_for(monkeypatch, target)
    with pytest.raises(DataError) as info:
        with OutputTransaction() as transaction:
            transaction.write(target, lambda p: p.write_text("new"))
    assert str(info.value) == f"{target}: cannot write: Invalid cross-device link"
    assert target.read_text() == "the result of an earlier run"
    assert [p.name for p in tmp_path.iterdir()] == ["a.json"] and not live_temporaries()


def test_a_failed_rename_of_atomic_path_keeps_the_existing_target(tmp_path, monkeypatch):
    target = tmp_path / "table.csv"
    target.write_text("old")
    _replace_failing_for(monkeypatch, target)
    with pytest.raises(DataError, match="cannot write: Invalid cross-device link"):
        with atomic_path(target) as tmp:
            tmp.write_text("new")
    assert target.read_text() == "old" and [p.name for p in tmp_path.iterdir()] == ["table.csv"]


def test_the_cli_turns_a_failed_commit_into_exit_2(tmp_path, monkeypatch, capsys):
    data = _good_csv(tmp_path / "good.csv")
    target = tmp_path / "fit.json"
    target.write_text("the result of an earlier run")
    _replace_failing_for(monkeypatch, target)
    code = main(["fit", str(data), "--model", "R0 + R1 || C1", "--out", str(target)])
    out, err = capsys.readouterr()
    line = _one_line_refusal(code, out, err, str(target))
    assert "Invalid cross-device link" in line
    assert target.read_text() == "the result of an earlier run"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fit.json", "good.csv"] and not live_temporaries()


def test_write_result_refuses_before_converting_the_result(tmp_path):
    """The Python API: `DataError` naming the path, before ``summary()`` is asked for."""

    class Result:
        def summary(self):
            raise AssertionError("converted before the path was checked")

        def to_xarray(self):
            raise AssertionError("converted before the path was checked")

    for path in [p for p in ("/sys/x.json", "/proc/x.nc") if os.path.isdir(os.path.dirname(p))]:
        with pytest.raises(DataError) as info:
            ix.write_result(Result(), path)
        assert str(info.value).startswith(f"{path}: ")


# --- inspect --plot: the title names the file ------------------------------------------------

@pytest.fixture
def figures(monkeypatch):
    """The figures `impedax.plotting.save_figure` is given (still written)."""
    import impedax.plotting as plotting

    seen = []
    real_save = plotting.save_figure

    def save(fig, path, *args, **kwargs):
        seen.append(fig)
        return real_save(fig, path, *args, **kwargs)

    monkeypatch.setattr(plotting, "save_figure", save)
    return seen


def _title(fig) -> str:
    return fig._suptitle.get_text() if fig._suptitle is not None else ""


@pytest.mark.parametrize("source", ["netcdf", "csv", "relative-csv"])
def test_inspect_preview_is_titled_with_the_file_given(source, tmp_path, monkeypatch, figures, capsys):
    """The netCDF reader records no path: the title was ``: impedax netCDF — cycle=0…``. The
    title names the file by its name (a long folder was clipped at the figure's edges), and a
    file of several spectra shows them (it showed the first only)."""
    monkeypatch.chdir(tmp_path)
    if source == "netcdf":
        given = str(CYCLES_NC)
    else:
        _good_csv(tmp_path / "good.csv")
        given = "good.csv" if source == "relative-csv" else str(tmp_path / "good.csv")
    plot = tmp_path / "preview.png"
    assert main(["inspect", given, "--plot", str(plot)]) == 0, capsys.readouterr().err
    assert plot.read_bytes()[:4] == b"\x89PNG"
    assert len(figures) == 1
    title = _title(figures[0])
    assert title.startswith(f"{Path(given).name}: "), title
    if source == "netcdf":
        assert "spectra" in title and "the first of" not in title


def test_inspect_preview_of_standard_input_is_titled_stdin(tmp_path, monkeypatch, figures, capsys):
    import io

    from impedax.io.loader import STDIN_NAME

    data = _good_csv(tmp_path / "good.csv").read_bytes()
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(data)))
    plot = tmp_path / "preview.png"
    assert main(["inspect", "-", "--plot", str(plot)]) == 0, capsys.readouterr().err
    assert _title(figures[0]).startswith(f"{STDIN_NAME}: ")


@pytest.mark.parametrize("folder", ["/sys/impedax-demo", "/proc/impedax/demo"])
def test_demo_refuses_a_folder_nothing_can_be_made_in(folder, capsys):
    # root passes os.access there; the demo then died with a PermissionError traceback, exit 1
    code = main(["demo", "--out", folder, "--fast"])
    out, err = capsys.readouterr()
    line = _one_line_refusal(code, out, err, folder)
    assert "cannot create the folder in /" in line and not os.path.exists(folder)


def test_a_probe_that_cannot_be_removed_is_named(tmp_path, monkeypatch):
    """The probe is made but its removal fails (a folder whose files cannot be deleted): the
    error names the leftover, so that the user can remove it, not "cannot create"."""
    _refuse_removing(monkeypatch, "unlink", ".x.csv.staged.")
    with pytest.raises(DataError, match=r"made the test entry .*\.x\.csv\.staged\..* but cannot remove it \(Operation not permitted\)") as info:
        check_writable(tmp_path / "x.csv")
    assert info.value.path == str(tmp_path / "x.csv") and not live_temporaries()


def test_another_users_file_in_a_sticky_folder_is_refused(tmp_path, monkeypatch):
    """In a sticky folder (``/tmp``) only the owner of a file, or of the folder, may replace it;
    write permission on the folder does not tell. Here we pose as a user other than root who
    owns neither (the rename would fail after the work: EPERM)."""
    target = tmp_path / "theirs.csv"
    target.write_text("kept\n")
    tmp_path.chmod(0o1777)
    owner = target.stat().st_uid
    monkeypatch.setattr(os, "geteuid", lambda: owner + 4242)
    with pytest.raises(DataError, match=r"belongs to another user in .*sticky bit"):
        check_writable(target)
    assert target.read_text() == "kept\n" and sorted(p.name for p in tmp_path.iterdir()) == ["theirs.csv"]
    # the same file in a folder without the sticky bit, or when we own it: accepted
    tmp_path.chmod(0o777)
    assert check_writable(target) == target
    tmp_path.chmod(0o1777)
    monkeypatch.setattr(os, "geteuid", lambda: owner)
    assert check_writable(target) == target
    # outputs are written through a symlink: a link to that file is refused as the file is,
    # a dangling one is accepted (a new file is made where it points; the link is not replaced)
    monkeypatch.setattr(os, "geteuid", lambda: owner + 4242)
    link = tmp_path / "link.csv"
    link.symlink_to(target)
    with pytest.raises(DataError, match=r"belongs to another user"):
        check_writable(link)
    dangling = tmp_path / "dangling.csv"
    dangling.symlink_to(tmp_path / "nowhere.csv")
    assert check_writable(dangling) == dangling


def test_folder_probe_names_the_folder_and_leaves_nothing(tmp_path, monkeypatch):
    from impedax.io.atomic import probe_folder

    probe_folder(tmp_path, path=tmp_path / "out", text="--out: cannot create the folder")
    assert list(tmp_path.iterdir()) == []
    _refuse_removing(monkeypatch, "rmdir", ".impedax-probe-")
    with pytest.raises(DataError, match=r"made the test entry .*\.impedax-probe-.* but cannot remove it") as info:
        probe_folder(tmp_path, path=tmp_path / "out", text="--out: cannot create the folder")
    assert info.value.path == str(tmp_path / "out")


def _refuse_removing(monkeypatch, remover: str, marked: str) -> None:
    """``os.<remover>`` (unlink, rmdir) fails with EPERM for paths containing ``marked``."""
    real = getattr(os, remover)

    def refuse(path, *args, **kwargs):
        if marked in str(path):
            raise PermissionError(errno.EPERM, "Operation not permitted")
        return real(path, *args, **kwargs)

    monkeypatch.setattr(os, remover, refuse)
