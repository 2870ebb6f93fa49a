"""A spectrum whose imaginary part is stored with the opposite sign: `fit`'s note that the data
limit the fit and `diagnose`'s data_invalid verdict give the KK test's sign hint
(`io.sign_check.sign_hint`) instead of sending the user to measure again; correctly signed data
get none. Spectra are SYNTHETIC numpy formulas written here; the oracle of the flip is np.conj."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.cli import main
from impedax.fitting.comparison import _sign_hint_of
from impedax.fitting.least_squares.result import DATA_LIMIT_NOTE, SIGN_HINT_LEAD, misfit_notes

FREQ = np.geomspace(0.1, 1e5, 60)  # (60 points: the frequency bucket of test_diagnose.py's diagnoses, whose compiled solver the CLI check reuses)
OMEGA = 2 * np.pi * FREQ
# SYNTHETIC R0 + R1 ∥ C1: 20 Ω + 1 kΩ ∥ 10 µF, 0.5 % complex noise per point
TRUTH = 20 + 1000 / (1 + 1j * OMEGA * 1000 * 1e-5)
_RNG = np.random.default_rng(3)
Z = TRUTH * (1 + 0.005 * (_RNG.standard_normal(FREQ.size) + 1j * _RNG.standard_normal(FREQ.size)) / math.sqrt(2))
FLIPPED = np.conj(Z)  # −Z'' stored as Z''
MODEL = "R0 + R1 || C1"


@pytest.fixture(scope="module")
def flipped_fit():
    return ix.fit(MODEL, ix.make_spectrum(FREQ, FLIPPED))


def test_fit_of_flipped_data_says_the_sign_may_be_flipped(flipped_fit):
    (note,) = [w for w in flipped_fit.warnings if DATA_LIMIT_NOTE in w]
    assert f"; {SIGN_HINT_LEAD}the imaginary part may be stored with the opposite sign (−Z'')" in note
    assert "passes on conj(Z)" in note and "data.assign(Z=data['Z'].conj())" in note
    # the hint is the KK test's own, word for word
    assert note.endswith(ix.kk_test((FREQ, FLIPPED)).sign_hint)


def test_the_sign_hint_leads_the_warnings_of_single_and_batch_fits(flipped_fit):
    """The flipped sign is the cause: its note comes before the warnings that follow from it (a
    parameter at its bound, uneven residuals), in a single fit and in each fit of a batch."""
    assert flipped_fit.warnings[0].endswith(ix.kk_test((FREQ, FLIPPED)).sign_hint)
    assert len(flipped_fit.warnings) > 1  # (there are others to come after it)
    stacked = xr.concat([ix.make_spectrum(FREQ, FLIPPED), ix.make_spectrum(FREQ, np.conj(TRUTH))], dim="cell")
    batch = ix.fit(MODEL, stacked)
    assert len(batch.warnings) == 2
    for warnings, z in zip(batch.warnings.values(), (FLIPPED, np.conj(TRUTH))):
        assert SIGN_HINT_LEAD in warnings[0] and warnings[0].endswith(ix.kk_test((FREQ, z)).sign_hint), warnings


def test_correctly_signed_data_limited_by_noise_get_no_sign_hint():
    # 3 % noise on the formula itself as the model: the data, not the model, limit the fit
    rng = np.random.default_rng(11)
    noisy = TRUTH * (1 + 0.03 * (rng.standard_normal(FREQ.size) + 1j * rng.standard_normal(FREQ.size)) / math.sqrt(2))
    (notes,) = misfit_notes(FREQ, noisy[None], TRUTH[None])
    assert len(notes) == 1 and DATA_LIMIT_NOTE in notes[0] and SIGN_HINT_LEAD not in notes[0]
    assert ix.kk_test((FREQ, noisy)).sign_hint is None


def test_diagnose_blames_the_sign_not_the_measurement(flipped_fit):
    d = ix.diagnose(flipped_fit)
    assert d.verdict == "data_invalid"
    hint = ix.kk_test((FREQ, FLIPPED)).sign_hint
    assert hint and d.sign_hint == hint and hint in d.reason
    assert "Repeat" not in d.reason and "drift" not in d.reason
    summary = json.loads(json.dumps(d.summary()))  # (the --json contract: plain JSON)
    assert summary["sign_hint"] == hint and summary["kk"]["sign_hint"] == hint and summary["verdict"] == "data_invalid"


def test_cli_diagnose_names_the_column_to_rename(tmp_path, capsys):
    path = tmp_path / "flipped.csv"
    path.write_text("f,Z',Z''\n" + "".join(f"{f!r},{z.real!r},{z.imag!r}\n" for f, z in zip(FREQ.tolist(), FLIPPED.tolist())))
    assert main(["diagnose", str(path), "--model", MODEL]) == 0
    out = capsys.readouterr().out
    (verdict,) = [line for line in out.splitlines() if line.startswith("verdict:")]
    assert "DATA_INVALID" in verdict and "opposite sign (−Z'')" in verdict
    assert """rename the column "Z''" to "-Z''" in the header""" in verdict and "Repeat" not in verdict


def test_compare_keeps_the_sign_hint_when_it_replaces_the_note():
    note = f"the data are 77 % from ...: {DATA_LIMIT_NOTE}; {SIGN_HINT_LEAD}the imaginary part may be stored with the opposite sign"
    assert _sign_hint_of(note) == f"; {SIGN_HINT_LEAD}the imaginary part may be stored with the opposite sign"
    assert _sign_hint_of(f"the data are 1 % from ...: {DATA_LIMIT_NOTE}") == ""
