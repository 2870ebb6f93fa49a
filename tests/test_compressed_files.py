"""A compressed spectrum file or an archive (``run.csv.gz``, ``runs.zip``) is named as such, with
what to do: until 2026-12-06 "a binary file that no reader claims"."""

import bz2
import gzip
import io
import lzma
import re
import sys
import zipfile

import numpy as np
import pytest

import impedax as ix

from cli_run import run

# SYNTHETIC R0 + R1 || C1 (R0 = 10 Ω, R1 = 100 Ω, C1 = 1 µF) at 20 frequencies
F = np.logspace(5, -1, 20)
Z = 10 + 100 / (1 + 1j * 2 * np.pi * F * 1e-4)
TEXT = ("frequency,zreal,zimag\n" + "".join(f"{a!r},{b.real!r},{b.imag!r}\n" for a, b in zip(F.tolist(), Z.tolist()))).encode()


def _zip(data: bytes) -> bytes:
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w") as archive:
        archive.writestr("run.csv", data)
    return buffer.getvalue()


@pytest.mark.parametrize("name, pack, said", [
    ("run.csv.gz", gzip.compress, "a gzip-compressed file, which impedax does not open: decompress it first (gunzip -k FILE)"),
    ("run.csv.bz2", bz2.compress, "a bzip2-compressed file, which impedax does not open: decompress it first (bunzip2 -k FILE)"),
    ("run.csv.xz", lzma.compress, "an xz-compressed file, which impedax does not open: decompress it first (unxz -k FILE)"),
    ("runs.zip", _zip, "a zip archive (and no .xlsx or .ods workbook), which impedax does not open: extract the spectrum file from it first (unzip FILE)"),
])
def test_a_compressed_file_is_named_as_such(tmp_path, monkeypatch, capsys, name, pack, said):
    path = tmp_path / name
    path.write_bytes(pack(TEXT))
    with pytest.raises(ix.DataError, match="^" + re.escape(f"{path}: not a recognised spectrum file: {said}")):
        ix.load(path)
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(pack(TEXT))))
    code, _, err = run(["inspect", "-"], capsys)
    assert code == 2 and f"<stdin>: not a recognised spectrum file: {said}" in err


def test_the_decompressed_file_reads(monkeypatch):
    # (what the message says to do: the same bytes, decompressed, are the spectrum written)
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(gzip.decompress(gzip.compress(TEXT)))))
    np.testing.assert_array_equal(ix.load("-")["Z"].values, Z)


@pytest.mark.parametrize("name, opening, said", [
    # SYNTHETIC: each format's signature (its specification's first bytes), then binary content
    ("old.xls", b"\xd0\xcf\x11\xe0\xa1\xb1\x1a\xe1", "an Excel 97-2003 workbook (.xls) or another OLE2 file, which impedax does not open: "
                                                     "save the workbook as .xlsx (Excel: File > Save As) or each sheet as CSV"),
    ("report.pdf", b"%PDF-1.4\n%\xe2\xe3\xcf\xd3\n", "a PDF document, which impedax does not open: give the file of the spectrum's numbers"),
    ("nyquist.png", b"\x89PNG\r\n\x1a\n", "a PNG image, which impedax does not open: give the file of the spectrum's numbers"),
    ("nyquist.jpg", b"\xff\xd8\xff\xe0", "a JPEG image, which impedax does not open: give the file of the spectrum's numbers"),
])
def test_a_workbook_document_or_image_is_named(tmp_path, name, opening, said):
    # (an .xls, a PDF or a plot given for the data was "a binary file that no reader claims")
    path = tmp_path / name
    path.write_bytes(opening + bytes(range(256)) * 8)
    with pytest.raises(ix.DataError, match="^" + re.escape(f"{path}: not a recognised spectrum file: {said}")):
        ix.load(path)
