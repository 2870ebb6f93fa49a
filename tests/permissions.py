"""A read-only folder for the tests of unwritable outputs."""

import contextlib
import os
from pathlib import Path


@contextlib.contextmanager
def read_only_folder(folder: Path, monkeypatch):
    """``folder`` created read-only (0o555) for the block, writable again after it; for root,
    whom permissions do not stop, ``os.access`` answers for paths under it as for a user."""
    folder.mkdir()
    folder.chmod(0o555)
    if os.geteuid() == 0:
        real_access = os.access

        def access(path, mode, *args, **kwargs):
            if os.path.abspath(path).startswith(str(folder)) and mode & os.W_OK:
                return False
            return real_access(path, mode, *args, **kwargs)

        monkeypatch.setattr(os, "access", access)
    try:
        yield folder
    finally:
        folder.chmod(0o755)
