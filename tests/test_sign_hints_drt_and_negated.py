"""The DRT of a spectrum stored with the opposite sign says so first and suggests no circuit
from it (`DRTResult.sign_hint`, `io.sign_check.values_sign_hint`), as the KK test and
`impedax inspect` do; correctly signed data get no hint. A wholly negated Z (−Z, leads swapped)
is named as such by all three, where it got the real-part hint, whose fix gave conj(Z). Spectra are SYNTHETIC numpy formulas
written here; the oracle of the flip is np.conj (and −Z for a negated real part)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.cli import main

FREQ = np.geomspace(0.1, 1e5, 41)
OMEGA = 2 * np.pi * FREQ
# SYNTHETIC R0 + R1 ∥ C1 + R2 ∥ C2: 10 Ω + 100 Ω (τ 1 ms) + 200 Ω (τ 1 s), 0.3 % complex noise
TRUTH = 10 + 100 / (1 + 1j * OMEGA * 1e-3) + 200 / (1 + 1j * OMEGA * 1.0)
_RNG = np.random.default_rng(5)
Z = TRUTH * (1 + 0.003 * (_RNG.standard_normal(FREQ.size) + 1j * _RNG.standard_normal(FREQ.size)) / math.sqrt(2))


def test_the_drt_of_conjugated_data_leads_with_the_sign_hint():
    result = ix.drt((FREQ, np.conj(Z)))
    assert result.sign_hint and result.sign_hint.startswith("the imaginary part may be stored with the opposite sign (−Z'')")
    assert result.warnings[0] == result.sign_hint  # (the cause first; the misfit warning follows)
    assert "Z'' > 0 at 40 of the 40 points not nearly resistive" in result.sign_hint  # (one point, 100 kHz, has |Z''| < 2 % of |Z|)
    assert result.summary()["sign_hint"] == result.sign_hint
    assert result.to_xarray().attrs["sign_hint"] == result.sign_hint
    assert result.suggested_circuit().reasons[0].startswith("read off data whose sign looks flipped")


@pytest.mark.parametrize("stored, hint, fix", [
    (lambda z: -z, "Z may be stored with the opposite sign (−Z: the current's sign or leads swapped): Z' < 0 at 41 of 41 points", lambda d: -d),
    (lambda z: -np.conj(z), "the real part may be stored with the opposite sign (−Z'): Z' < 0 at 41 of 41 points", lambda d: -np.conj(d)),
])
def test_a_negated_real_part_alone_or_with_z_is_told_apart(tmp_path, capsys, stored, hint, fix):
    """−Z and −conj(Z) both have Z' < 0 everywhere; the hint's fix must give Z back (the
    oracle: the fix each hint names, applied to the stored data). The DRT, the KK test and
    inspect say the same."""
    data = stored(Z)
    np.testing.assert_allclose(fix(data), Z)
    result = ix.drt((FREQ, data))
    assert result.sign_hint.startswith(hint)
    assert ix.kk_test((FREQ, data)).sign_hint.startswith(hint)
    path = tmp_path / "negated.csv"
    ix.save(ix.make_spectrum(FREQ, data), path)
    assert main(["inspect", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["sign_hint"].startswith(hint)


def test_correctly_signed_data_get_no_hint():
    result = ix.drt((FREQ, Z))
    assert result.sign_hint is None and result.summary()["sign_hint"] is None
    assert "sign_hint" not in result.to_xarray().attrs
    assert not any("opposite sign" in w for w in result.warnings)
    assert not result.suggested_circuit().reasons[0].startswith("read off")


def test_an_inductive_loop_is_no_flipped_sign():
    """Z'' > 0 at the top (a lead's 20 µH) while the arcs stay capacitive: no hint."""
    result = ix.drt((FREQ, Z + 1j * OMEGA * 20e-6))
    assert result.sign_hint is None


def test_cli_text_json_and_a_batch(tmp_path, capsys):
    flipped = tmp_path / "flipped.csv"
    ix.save(ix.make_spectrum(FREQ, np.conj(Z)), flipped)
    assert main(["drt", str(flipped)]) == 0
    out = capsys.readouterr().out
    warnings = [line for line in out.splitlines() if line.startswith("warning: ")]
    # the hint carries the fix for this file: the column as the CSV reader took it
    assert warnings[0].startswith("warning: the imaginary part may be stored with the opposite sign") and "rename the column 'z_imag_ohm' to '-z_imag_ohm'" in warnings[0]
    assert out.rstrip().endswith("starting circuit from the DRT: none while the sign looks flipped (the warning above); correct it, then run impedax drt again")
    assert main(["drt", str(flipped), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["warnings"][0] == summary["sign_hint"]
    # (the JSON says what the text's last line says: no circuit to start from, and why; 2026-12-06)
    assert summary["suggestion_withheld"] == "while the sign looks flipped (the warning above); correct it, then run impedax drt again"
    # two cells, the second stored flipped: the report names it, the circuit comes from the first
    stack = tmp_path / "cells.nc"
    ix.save(ix.make_spectrum(FREQ, np.stack([Z, np.conj(Z)]), dims=("cell",)), stack)
    assert main(["drt", str(stack)]) == 0
    out = capsys.readouterr().out
    assert "warning: in 1 of 2 spectra (cell=1): the imaginary part may be stored with the opposite sign" in out
    line = out.rstrip().splitlines()[-1]
    assert line.startswith("starting circuit from the DRT (the one 1 of 2 spectra suggest") and "R0 + R1 || C1 + R2 || C2" in line  # (two ideal R‖C: narrow peaks, suggest.NARROW_FACTOR)
    assert main(["drt", str(stack), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["suggestion_withheld"] is None  # (one cell reads right: a circuit is given)


REAL = sorted(p for p in (__import__("pathlib").Path(__file__).parent / "fixtures" / "real").iterdir()
              if p.suffix.lower() in (".dfr", ".idf", ".ids", ".pssession", ".csv", ".txt", ".mpt", ".dta", ".par", ".z", ".xlsx"))


def test_columns_swapped_are_told_from_a_negated_z_on_every_real_file():
    """Z' and Z'' stored in each other's columns read as Z'' + jZ': Z' < 0 and Z'' > 0, as −Z
    reads too, and such files got the real-part hint, whose fix (−conj) gives neither reading
    right. Bode's gain–phase relation tells the two apart: on each REAL file whose exchanged
    columns show that signature (12 of the 15: their first spectrum, the file's own numbers), the hint names the swap and its fix, which gives the
    file's Z back exactly; negated, it names −Z as before. The SYNTHETIC two-arc spectrum too."""
    from impedax.io.sign_check import values_sign_hint

    cases = [(path.name, ix.load(path)) for path in REAL] + [("SYNTHETIC", ix.make_spectrum(FREQ, Z))]
    assert len(cases) >= 15
    for name, data in cases:
        freq = data["frequency"].values
        z = data["Z"].values.reshape(-1, freq.size)[0]
        swapped = z.imag + 1j * z.real
        if np.count_nonzero(swapped.real < 0) < 0.9 * z.size or np.count_nonzero(swapped.imag > 0) < 0.9 * z.size:
            continue  # (inductive points at high frequency: neither hint's evidence)
        hint = values_sign_hint(freq, swapped)
        assert hint.startswith("Z' and Z'' may be stored in each other's columns"), (name, hint)
        fixed = ix.make_spectrum(freq, swapped).assign(Z=lambda d: d["Z"].imag + 1j * d["Z"].real)  # (the hint's own fix)
        np.testing.assert_array_equal(fixed["Z"].values, z)
        assert values_sign_hint(freq, -z).startswith("Z may be stored with the opposite sign (−Z"), name
        assert values_sign_hint(freq, z) is None, name


def test_inspect_names_the_swap(tmp_path, capsys):
    """The SYNTHETIC spectrum written with the columns exchanged under a canonical header."""
    path = tmp_path / "swapped.csv"
    path.write_text("frequency_hz,z_real_ohm,z_imag_ohm\n" + "".join(f"{f!r},{z.imag!r},{z.real!r}\n" for f, z in zip(FREQ.tolist(), Z.tolist())))
    assert main(["inspect", str(path), "--json"]) == 0
    hint = json.loads(capsys.readouterr().out)["sign_hint"]
    assert hint.startswith(f"Z' and Z'' may be stored in each other's columns: Z' < 0 at {FREQ.size} of {FREQ.size} points") and "data['Z'].imag + 1j * data['Z'].real" in hint
