"""Hypothesis fuzz of every reader: random bytes, and real files mutated (bytes flipped, lines
dropped, repeated, swapped or truncated, numbers negated or blanked), read by `load` and by each
reader directly. Only impedax's own errors may come out, and every call must end: a guard
alarm turns a hang (the old Gamry reader looped forever on a negative NOTES count) into a
failure. Counts announced in headers are checked before anything is allocated for them.
"""

import contextlib
import os
import signal
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

import impedax as ix
from impedax.errors import ImpedaxError
from impedax.io import READERS, read_csv

FIXTURES = Path(__file__).parent / "fixtures"
REAL_FILES = sorted(p for p in (FIXTURES / "real").iterdir() if p.suffix not in (".npz", ".py", ".md") and not p.name.startswith("LICENSE"))
FILES = REAL_FILES + sorted(p for p in FIXTURES.iterdir() if p.is_file())
# IMPEDAX_FUZZ_EXAMPLES=2000 for a long, randomised search; the default suite replays a fixed 40
_EXAMPLES = int(os.environ.get("IMPEDAX_FUZZ_EXAMPLES", "40"))
SETTINGS = settings(max_examples=_EXAMPLES, deadline=None, derandomize=_EXAMPLES <= 40, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
GUARD_SECONDS = 60  # a bound on termination, not a speed requirement: a read here takes milliseconds


@contextlib.contextmanager
def must_finish():
    def hang(signum, frame):
        raise AssertionError(f"a reader did not finish within {GUARD_SECONDS} s (endless loop?)")

    previous = signal.signal(signal.SIGALRM, hang)
    signal.alarm(GUARD_SECONDS)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def read_all_ways(data: bytes, suffix: str) -> None:
    """`load` and every reader on ``data``: a Dataset or an ImpedaxError, nothing else."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"fuzz{suffix}"
        path.write_bytes(data)
        with must_finish():
            for read in [ix.load, read_csv, *(r.read for r in READERS)]:
                try:
                    ds = read(path)
                except ImpedaxError:
                    continue
                z = ds["Z"].values
                assert np.all(np.isfinite(z)) and np.all(ds["frequency"].values > 0)


def _lines(data: bytes) -> list[bytes]:
    return data.split(b"\n")


def mutate(data: bytes, draw) -> bytes:
    kind = draw(st.sampled_from(["flip", "drop", "repeat", "swap", "truncate", "negate", "blank", "huge"]))
    lines = _lines(data)
    k = draw(st.integers(0, max(len(lines) - 1, 0)))
    if kind == "flip":
        buf = bytearray(data)
        for _ in range(draw(st.integers(1, 8))):
            if buf:
                buf[draw(st.integers(0, len(buf) - 1))] = draw(st.integers(0, 255))
        return bytes(buf)
    if kind == "drop":
        return b"\n".join(lines[:k] + lines[k + 1 :])
    if kind == "repeat":
        return b"\n".join(lines[: k + 1] + lines[k:])
    if kind == "swap":
        j = draw(st.integers(0, max(len(lines) - 1, 0)))
        lines[k], lines[j] = lines[j], lines[k]
        return b"\n".join(lines)
    if kind == "truncate":
        return data[: draw(st.integers(0, len(data)))]
    if kind == "negate":  # counts and values turn negative (NOTES count -1 used to loop forever)
        return data.replace(b"\t2\t", b"\t-1\t", 1).replace(lines[k], lines[k].replace(b"1", b"-1"))
    if kind == "blank":
        return data.replace(lines[k], lines[k].replace(b"0", b""), 1)
    return data.replace(lines[k], lines[k].replace(b"1", b"999999999"), 1)


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
@SETTINGS
@given(data=st.data())
def test_mutated_real_files_raise_only_impedax_errors(path, data):
    mutated = mutate(path.read_bytes(), data.draw)
    read_all_ways(mutated, path.suffix)


@SETTINGS
@given(blob=st.binary(max_size=4096), suffix=st.sampled_from([".csv", ".txt", ".DTA", ".mpt", ".z", ".nc", ".h5", ".xlsx", ".ods", ".pssession", ".idf", ".dfr", ".par", ".mpr"]))
def test_random_bytes_raise_only_impedax_errors(blob, suffix):
    read_all_ways(blob, suffix)


SIGNATURES = [b"EXPLAIN\r\n", b"EC-Lab ASCII FILE\r\nNb header lines : 3\r\n", b"ZPLOT2 ASCII\n", b'"Z60W Data File: Version 1.1"\n', b"VERSION8.0\n 3\n 1\n",
              b"<Application>\nName=VersaStudio\n", b"\xff\xfe{\x00", b"CDF\x01", b"\x89HDF\r\n\x1a\n", b"PK\x03\x04", b"BIO-LOGIC MODULAR FILE",
              b"Solarcell=false\nTechnique=x\nprimary_data\n3\n", b"chunk;timestamp;size;fieldname\n", b"freq/Hz\tRe(Z)/Ohm\t-Im(Z)/Ohm\n"]


@SETTINGS
@given(signature=st.sampled_from(SIGNATURES), tail=st.binary(max_size=2048))
def test_each_signature_with_random_content(signature, tail):
    """Every sniff claims these; the reader behind it must still fail cleanly."""
    read_all_ways(signature + tail, ".dat")


@pytest.mark.parametrize(
    "content",
    [
        b"EXPLAIN\nNOTES\tNOTES\t-1\t&Notes...\nZCURVE\tTABLE\n",
        b"EXPLAIN\nNOTES\tNOTES\t999999999999\t&Notes...\n",
        b"VERSION8.0\n 999999999999\n 1\n 1.0\n",
        b"Solarcell=false\nTechnique=x\nprimary_data\n3\n999999999999\n1 2 3\n",
        b"\xff\xfe" + ("[" * 100000).encode("utf-16-le"),
    ],
    ids=["gamry-negative-notes", "gamry-huge-notes", "dfr-huge-count", "ivium-huge-count", "pssession-deep-json"],
)
def test_hostile_counts_are_refused(tmp_path, content):
    path = tmp_path / "hostile.dat"
    path.write_bytes(content)
    with must_finish(), pytest.raises(ImpedaxError):
        ix.load(path)
