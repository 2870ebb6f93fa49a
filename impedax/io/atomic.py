"""Atomic file output: write to a temporary file beside the target, then rename; several files
at once as one `OutputTransaction` (all appear together, or none).

Every temporary file or folder impedax creates for output is recorded while it exists, so that
an interrupted process (SIGINT, SIGTERM: `impedax.cli.main`) can remove them all with
`remove_temporaries` before it exits, even when no ``finally`` block gets to run.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import signal
import stat
import tempfile
import threading
from pathlib import Path
from typing import Callable

from ..errors import DataError

__all__ = [
    "atomic_path", "check_writable", "check_file_name", "write_target", "probe_folder", "OutputTransaction", "staging_directory", "temporary_folder", "remove_temporary",
    "remove_temporaries", "live_temporaries",
    "written_outputs",
]

# temporaries that exist right now (files and folders); a set guarded by a lock, because a
# signal handler may read it while the main thread adds to it
_live: set[Path] = set()
_live_lock = threading.RLock()
# every target an `OutputTransaction` moved into place in this process, in order (so that an
# interrupt can say what was already written)
_written: list[str] = []


def _remember(path: Path) -> None:
    with _live_lock:
        _live.add(path)


def _forget(path: Path) -> None:
    with _live_lock:
        _live.discard(path)


def written_outputs() -> tuple[str, ...]:
    """Every file an `OutputTransaction` of this process has moved into place, in order."""
    with _live_lock:
        return tuple(_written)


def live_temporaries() -> tuple[Path, ...]:
    """The temporary files and folders impedax's writers hold right now."""
    with _live_lock:
        return tuple(_live)


def remove_temporaries() -> int:
    """Remove every temporary file and folder impedax's writers hold (on an interrupt); returns
    how many were removed. Targets are never touched: they are replaced only by a rename."""
    removed = 0
    for path in live_temporaries():
        try:
            if path.is_dir() and not path.is_symlink():
                shutil.rmtree(path, ignore_errors=True)
            else:
                path.unlink()
            removed += 1
        except FileNotFoundError:
            pass
        except OSError:
            continue
        _forget(path)
    return removed


def check_file_name(path: str | os.PathLike, example: str = "result.json", flag: str = "") -> None:
    """Refuse an output name that names a folder: one ending in ``/`` (``--plot figs/``), which
    `pathlib.Path` would turn into a file named ``figs`` (an existing ``figs`` file replaced by
    it), and an empty name. ``example`` is the file name the message suggests inside that
    folder; ``flag`` the option that named it (``--plot``), said first."""
    text = os.fspath(path)
    if isinstance(text, str) and not text.strip():  # (Path("") is "." and Path("").suffix "": neither says what is wrong)
        raise DataError(f"{flag + ': ' if flag else ''}empty file name: no output file was named (an unset shell variable, \"$OUT\" with nothing in it?)")
    if isinstance(text, str) and text.rstrip().endswith(tuple(s for s in (os.sep, os.altsep) if s)) and text.strip() not in (os.sep, os.altsep):
        folder = text.rstrip()
        said = f"{flag}: " if flag else ""
        raise DataError(f"{said}ends with {folder[-1]!r}, so it names a folder, not a file; give a file name in it, e.g. {folder}{example}", path=text)


def check_writable(path: str | os.PathLike, *, probe: bool = True) -> Path:
    """Raise `DataError` now (before any work) if ``path`` cannot be written.

    ``probe``: also create and remove a temporary file beside ``path``, named as the staging
    of an output is (`_temporary_beside`). Permission bits (`os.access`) do not answer for root
    (containers, NFS root-squash), nor for folders no one can create files in (``/sys``,
    ``/proc``, a read-only mount): only trying does. Any `OSError` on the way (a name too
    long, ...) is a `DataError` naming ``path`` too. A symbolic link is checked as the file
    it points to (`write_target`); a read-only file (no owner-write bit) is refused, and so is a
    name that ends with ``/`` (`check_file_name`)."""
    check_file_name(path)
    path = Path(path)
    try:
        return _check_writable(path, probe)
    except OSError as exc:
        raise DataError(f"cannot be written: {_reason(exc)}", path=path) from None


def write_target(path: str | os.PathLike) -> Path:
    """The file an output to ``path`` replaces: ``path`` itself, or the file a symbolic link
    there points to (written through, so that the link stays a link)."""
    path = Path(path)
    return Path(os.path.realpath(path)) if path.is_symlink() else path


def _check_writable(path: Path, probe: bool) -> Path:
    named = path
    path = write_target(path)
    parent = path.parent if str(path.parent) else Path(".")
    if path.is_symlink():  # (still a link after resolving: a loop)
        raise DataError("is a symbolic link loop; choose another name", path=named)
    if path.is_dir():
        raise DataError("is a directory, not a file", path=named)
    if not parent.is_dir():
        blocker = next((p for p in (parent, *parent.parents) if p.exists() or p.is_symlink()), None)
        if blocker is not None and not blocker.is_dir():
            raise DataError(f"{blocker.name} is a file, so the directory does not exist", path=named)
        raise DataError(f"directory {parent} does not exist", path=named)
    if not os.access(parent, os.W_OK | os.X_OK):
        raise DataError(f"directory {parent} is not writable", path=named)
    if path.exists() and not path.is_file():
        raise DataError("exists and is not a regular file (a device, pipe or socket); choose a file name", path=named)
    if path.exists() and not path.stat().st_mode & stat.S_IWUSR:  # (the bits, not os.access: root may write anything)
        mode = stat.S_IMODE(path.stat().st_mode)
        through = f" (the file {path} it links to)" if path != named else ""
        raise DataError(f"is read-only{through}, mode {mode:o}: impedax does not replace it; make it writable (chmod u+w) or choose another name", path=named)
    if path.exists() and _owned_by_another_in_sticky(path, parent):
        raise DataError(f"belongs to another user in {parent}, whose sticky bit lets only the owner replace it; choose another name", path=named)
    if probe:
        try:
            tmp = _temporary_beside(path, "staged.")
        except OSError as exc:
            raise DataError(_cannot_create(parent, exc), path=named) from None
        _remove_probe(tmp, os.unlink, named)
    return named


def _owned_by_another_in_sticky(path: Path, parent: Path) -> bool:
    """Renaming onto ``path`` fails in a sticky folder (``/tmp``) unless we own the file or the
    folder, or are root; write permission on the folder does not say so."""
    uid = os.geteuid() if hasattr(os, "geteuid") else None
    if uid is None or uid == 0 or not parent.stat().st_mode & stat.S_ISVTX:
        return False
    return uid not in (path.lstat().st_uid, parent.stat().st_uid)


def probe_folder(where: str | os.PathLike, *, path: str | os.PathLike, text: str) -> None:
    """Raise `DataError` (``text``, naming ``path``) unless a folder can be made and removed in
    ``where``: what `check_writable` does for a file, for an output folder. Permission bits do
    not answer for root under ``/sys`` or on a read-only mount; only trying does."""
    try:
        made = Path(tempfile.mkdtemp(prefix=".impedax-probe-", dir=where))
    except OSError as exc:
        raise DataError(f"{text}: {_reason(exc)}", path=Path(path)) from None
    _remove_probe(made, os.rmdir, Path(path))


def _remove_probe(made: Path, remove: Callable[[Path], None], path: Path) -> None:
    """Remove a probe just made; one that cannot be removed is named, so that the user can."""
    try:
        remove(made)
    except FileNotFoundError:
        pass
    except OSError as exc:
        raise DataError(f"made the test entry {made} but cannot remove it ({_reason(exc)}); remove it and check the folder", path=path) from None
    finally:
        _forget(made)


def _reason(exc: OSError) -> str:
    """The operating system's words for ``exc`` (``Permission denied``), without the path."""
    return exc.strerror or str(exc) or type(exc).__name__


def _cannot_create(parent: Path, exc: OSError) -> str:
    return f"cannot create a file in directory {parent}: {_reason(exc)}"


def _temporary_beside(path: Path, tag: str, suffix: str = "") -> Path:
    """A new temporary file beside ``path`` with its extension (``suffix`` where it has none:
    writers choose the format by the extension). Raises `OSError` when it cannot be made,
    leaving nothing behind."""
    parent = path.parent if str(path.parent) else Path(".")
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.{tag}", suffix=path.suffix or suffix or ".tmp", dir=parent)
    tmp = Path(tmp)
    _remember(tmp)
    try:
        os.close(fd)
        os.chmod(tmp, _output_mode(path))
    except BaseException:
        _discard(tmp)
        raise
    return tmp


def _output_mode(path: Path) -> int:
    """The permission bits of a new output at ``path``: those of the file it replaces (a
    private 0600 file stays private), else the usual 0666 less the umask (mkstemp makes 0600)."""
    try:
        return stat.S_IMODE(os.stat(path).st_mode) & 0o777
    except OSError:
        umask = os.umask(0)
        os.umask(umask)
        return 0o666 & ~umask


def _discard(tmp: Path) -> None:
    with contextlib.suppress(FileNotFoundError):
        os.unlink(tmp)
    _forget(tmp)


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike):
    """Yield a temporary path in the target's directory; on success rename it onto ``path``.

    On any error (an interrupt included) the temporary file is removed and ``path`` is left as
    it was. An `OSError` while making the temporary file or renaming it onto ``path`` becomes a
    `DataError` naming ``path`` (errors of the writing itself are the writer's).
    """
    path = check_writable(path, probe=False)  # (making the temporary file is the probe)
    target = write_target(path)
    try:
        tmp = _temporary_beside(target, "")
    except OSError as exc:
        raise DataError(_cannot_create(target.parent if str(target.parent) else Path("."), exc), path=path) from None
    try:
        yield tmp
    except BaseException:
        _discard(tmp)
        raise
    try:
        os.replace(tmp, target)
    except BaseException as exc:
        _discard(tmp)
        if isinstance(exc, OSError):
            raise DataError(f"cannot write: {_reason(exc)}", path=path) from None
        raise
    _forget(tmp)


def temporary_folder(parent: str | os.PathLike, prefix: str = ".staging-") -> Path:
    """A new temporary folder inside ``parent``, recorded for `remove_temporaries` until
    `remove_temporary` removes it."""
    folder = Path(tempfile.mkdtemp(prefix=prefix, dir=parent))
    _remember(folder)
    return folder


def remove_temporary(folder: str | os.PathLike) -> None:
    """Remove a folder made by `temporary_folder` (whatever it still holds)."""
    folder = Path(folder)
    shutil.rmtree(folder, ignore_errors=True)
    _forget(folder)


@contextlib.contextmanager
def staging_directory(parent: str | os.PathLike, prefix: str = ".staging-"):
    """A `temporary_folder` inside ``parent``, removed at the end."""
    folder = temporary_folder(parent, prefix)
    try:
        yield folder
    finally:
        remove_temporary(folder)


@contextlib.contextmanager
def _signals_held():
    """Hold SIGINT and SIGTERM back (delivered afterwards) while the renames of a commit run."""
    held = {signal.SIGINT, signal.SIGTERM}
    can_hold = hasattr(signal, "pthread_sigmask") and threading.current_thread() is threading.main_thread()
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, held) if can_hold else None
    try:
        yield
    finally:
        if previous is not None:
            signal.pthread_sigmask(signal.SIG_SETMASK, previous)


class OutputTransaction:
    """Several output files written as one: each is written to a temporary file beside its
    target (`write`), and `commit` moves them all into place together; `abort` (or an error,
    or an interrupt) removes the temporaries and leaves every target as it was.

    ``to_stdout`` is called with the bytes of an output whose path is ``-`` at commit time.
    """

    def __init__(self, *, to_stdout: Callable[[bytes], None] | None = None):
        self._staged: list[tuple[Path, str]] = []
        self._to_stdout = to_stdout
        self.committed: tuple[str, ...] = ()

    def write(self, path: str | os.PathLike, writer: Callable[[Path], None], *, suffix: str = "") -> None:
        """Stage an output: ``writer(tmp)`` writes the file to ``tmp`` (same extension as
        ``path``, or ``suffix`` where it has none and for ``-``). An `OSError` becomes a
        `DataError` naming ``path``."""
        target = str(path)
        try:
            if target == "-":
                fd, name = tempfile.mkstemp(prefix=".impedax-stdout.", suffix=suffix or ".txt")
                tmp = Path(name)
                _remember(tmp)
                os.close(fd)
            else:
                tmp = _temporary_beside(write_target(check_writable(target, probe=False)), "staged.", suffix)
        except OSError as exc:
            self.abort()
            where = f"in {tempfile.gettempdir()} for standard output" if target == "-" else f"in directory {Path(target).parent}"
            raise DataError(f"cannot create a file {where}: {_reason(exc)}", path=target) from None
        except BaseException:
            self.abort()
            raise
        self._staged.append((tmp, target))
        try:
            writer(tmp)
        except OSError as exc:
            self.abort()
            raise DataError(f"cannot write: {_reason(exc)}", path=target) from None
        except BaseException:
            self.abort()
            raise

    def commit(self) -> None:
        """Move every staged file into place (signals are held back during the renames)."""
        done = []
        try:
            with _signals_held():
                for tmp, target in self._staged:
                    if target == "-":
                        continue
                    os.replace(tmp, write_target(target))
                    _forget(tmp)
                    done.append(target)
                    with _live_lock:
                        _written.append(target)
        except OSError as exc:
            self.abort()
            raise DataError(f"cannot write: {_reason(exc)}" + (f" ({', '.join(done)} already written)" if done else ""), path=target) from None
        for tmp, target in self._staged:
            if target == "-":
                data = tmp.read_bytes()
                _discard(tmp)
                if self._to_stdout is not None:
                    self._to_stdout(data)
                done.append(target)
        self._staged = []
        self.committed = tuple(done)

    def abort(self) -> None:
        """Remove every staged temporary; no target is touched."""
        for tmp, _ in self._staged:
            _discard(tmp)
        self._staged = []

    def __enter__(self) -> "OutputTransaction":
        return self

    def __exit__(self, kind, exc, tb) -> None:
        if kind is None:
            self.commit()
        else:
            self.abort()
