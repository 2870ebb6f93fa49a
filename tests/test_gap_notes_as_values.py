"""`impedax gap` leaves out the EDL fit's note that its model misses structure where the alarm
MODEL DOES NOT FIT says it, and the fit's note that the data limit it where its note of a misfit
near the alarm's takes its place. It found both by their words (`MODEL_MISSES_STRUCTURE`,
`DATA_LIMIT_NOTE`): reworded, both were said twice. The fit carries them as values set where the
notes are made (`FitResult.misfit_note` with `model_misfit`, `FitResult.data_limit_note`); a fit
without them is read by the words.

Oracle: the fit's notes as written, and the same notes reworded. SYNTHETIC data: R0 + R1 ∥ C1
(20 Ω, 1 kΩ at τ 1 ms) plus a second arc (1 kΩ at τ 1 s), 0.5 % complex noise (seed 11), fitted
with one arc (as test_misfit_blame_value.py); the gap figures are test_gap_near_misfit_note.py's
stand-ins (a fit 25 % or 23.8 % from the data, a KK chain at 4.8 %)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.least_squares import result as result_module
from impedax.fitting.least_squares.notes import DATA_LIMIT, MISFIT, MODEL_MISFIT
from impedax.fitting.least_squares.result import DATA_LIMIT_NOTE, MODEL_MISSES_STRUCTURE, FitResult, fit_blaming_note
from impedax.io import read_netcdf
from impedax.models.gap import _edl_fit_warnings

F = np.geomspace(0.01, 1e5, 36)
W = 2 * np.pi * F
REWORDED = "the data hold structure this model lacks"
GAP_FREQ = np.geomspace(1.0, 1e5, 21)
GAP_Z = 4e3 - 1e3j * np.ones(GAP_FREQ.size)
REMAINDER = ix.make_spectrum(GAP_FREQ, GAP_Z, attrs={"single_contact": 1, "n_trials_total": 1})
BOUND = "R_EP is at its lower bound 0"


class _KK:
    """The remainder's KK chains, standing in: the misfit a KK-consistent model reaches, set here."""

    def __init__(self, rms_rel):
        self.rms_rel = rms_rel

    def misfits(self, freq, z, rows):
        return np.full(len(rows), self.rms_rel)


def _edl(rms_rel, warnings, **values):
    """An EDL fit rms_rel from the remainder at every point, with ``warnings`` and the tags a fit
    sets where it makes its notes (``warning_tags``; none given: a fit built by hand, read by the words)."""
    params = {"R_EP": 5e3, "CPE_EP.Q": 1e-4, "CPE_EP.alpha": 0.5, "C_gap": 4e-10}
    return SimpleNamespace(rms_rel=rms_rel, z_model=GAP_Z + rms_rel * np.abs(GAP_Z), weighting="modulus", free_names=list(params), model="R_EP || CPE_EP || C_gap",
                           values=params, stderr={k: 0.01 * v for k, v in params.items()}, at_bound=(), warnings=tuple(warnings), **values)


def _arcs(second: bool):
    z = 20.0 + 1e3 / (1 + 1j * W * 1e-3) + (1e3 / (1 + 1j * W * 1.0) if second else 0.0)
    rng = np.random.default_rng(11)
    return ix.make_spectrum(F, z * (1 + 0.005 * (rng.normal(size=F.size) + 1j * rng.normal(size=F.size)) / np.sqrt(2)))


@pytest.fixture(scope="module")
def reworded():
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(result_module, "MODEL_MISSES_STRUCTURE", REWORDED)
        return ix.fit("R0 + R1 || C1", _arcs(True))


def test_the_fit_sets_its_blaming_note_where_it_makes_it(reworded, tmp_path):
    (note,) = [w for w in reworded.warnings if w.startswith(REWORDED)]
    assert reworded.misfit_note == note and fit_blaming_note(reworded) == note
    assert fit_blaming_note(SimpleNamespace(warnings=reworded.warnings)) == ""  # (the old words find none)
    plain, good = ix.fit("R0 + R1 || C1", _arcs(True)), ix.fit("R0 + R1 || C1", _arcs(False))
    (by_words,) = [w for w in plain.warnings if MODEL_MISSES_STRUCTURE in w]
    assert fit_blaming_note(plain) == by_words == fit_blaming_note(SimpleNamespace(warnings=plain.warnings))  # (the normal path: the words' note)
    assert good.misfit_note == "" and fit_blaming_note(good) == ""
    path = tmp_path / "fit.nc"
    ix.write_result(reworded, path)
    assert fit_blaming_note(FitResult.from_xarray(read_netcdf(path))) == note
    ds = reworded.to_xarray()
    ds.attrs = {k: v for k, v in ds.attrs.items() if k not in ("warning_tags", "model_misfit", "data_limit_note", "data_limit_hint", "misfit_note", "uneven_noise", "sigma_residual_notes", "model_misfits")}  # (a file without them: the words)
    ix.io.write_netcdf(ds, path)
    old = FitResult.from_xarray(read_netcdf(path))
    assert old.misfit_note is None and fit_blaming_note(old) == ""


def test_a_reworded_misfit_note_gives_way_to_the_alarm(reworded):
    note = reworded.misfit_note
    by_words = _edl(0.25, (note, BOUND))  # (no values: the words, which miss the reworded note)
    assert _edl_fit_warnings(by_words, REMAINDER, _KK(0.048)) == [f"EDL fit: {note}", f"EDL fit: {BOUND}"]
    fitted = _edl(0.25, (note, BOUND), warning_tags=((MISFIT, MODEL_MISFIT), ()))
    assert _edl_fit_warnings(fitted, REMAINDER, _KK(0.048)) == [f"EDL fit: {BOUND}"]
    # without the alarm (2.3×) the notes stay
    assert _edl_fit_warnings(_edl(0.11, (note, BOUND), warning_tags=((MISFIT, MODEL_MISFIT), ())), REMAINDER, _KK(0.048)) == [f"EDL fit: {note}", f"EDL fit: {BOUND}"]


def test_a_reworded_data_limit_note_gives_way_to_the_near_misfit_note():
    reworded = "the data are 4.8 % (rms_rel) from any Kramers–Kronig-consistent model (…), within 5× of this fit's misfit: what limits this fit is the data's noise"
    plain = reworded.split(": what limits")[0] + f": {DATA_LIMIT_NOTE}"
    by_words = _edl_fit_warnings(_edl(0.238, (BOUND, reworded)), REMAINDER, _KK(0.048))
    assert f"EDL fit: {reworded}" in by_words  # (the old rule keeps it beside the near-misfit note)
    for note in (reworded, plain):
        out = _edl_fit_warnings(_edl(0.238, (BOUND, note), warning_tags=((), (MISFIT, DATA_LIMIT))), REMAINDER, _KK(0.048))
        assert out[0] == f"EDL fit: {BOUND}" and len(out) == 2 and out[1].startswith("R_EP || CPE_EP || C_gap misses the spectrum by 23.8 %")
    assert _edl_fit_warnings(_edl(0.238, (BOUND, plain)), REMAINDER, _KK(0.048)) == out  # (the normal path: the words decide the same)
