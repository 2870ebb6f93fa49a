"""A global fit's spectra whose warnings blame the model (`BatchFitResult.misses_structure`,
per spectrum) were read from the misfit note's words (`MODEL_MISFIT_MARKS`): a reworded note
flipped them. A joint fit carries them as a batch does, a value set where the note is made
(`SharedFitResult.model_misfits`), stored in the .nc; a file without it is read by the words.

Oracle: the notes as the fit wrote them, and the same fit with the phrase reworded (the constant
`MODEL_MISSES_STRUCTURE` monkeypatched before the fit). SYNTHETIC data (as
test_misfit_blame_value.py): one arc, R0 + R1 ∥ C1 (20 Ω, 1 kΩ at τ 1 ms), and the same with a
second arc (1 kΩ at τ 1 s), 0.5 % complex noise (seed 11), two trials fitted with one arc and R0
shared: the second trial's model misses its second arc."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.fitting.least_squares import result as result_module
from impedax.fitting.least_squares.result import MODEL_MISSES_STRUCTURE, warnings_blame_model
from impedax.io import read_netcdf

F = np.geomspace(0.01, 1e5, 36)
W = 2 * np.pi * F
REWORDED = "the data hold structure this model lacks"


def _arcs(second: bool) -> np.ndarray:
    z = 20.0 + 1e3 / (1 + 1j * W * 1e-3) + (1e3 / (1 + 1j * W * 1.0) if second else 0.0)
    rng = np.random.default_rng(11)
    return z * (1 + 0.005 * (rng.normal(size=F.size) + 1j * rng.normal(size=F.size)) / np.sqrt(2))


def _joint(**words):
    stack = xr.concat([ix.make_spectrum(F, _arcs(False)), ix.make_spectrum(F, _arcs(True))], dim="trial").assign_coords(trial=["one", "two"])
    with pytest.MonkeyPatch.context() as mp:
        for name, text in words.items():
            mp.setattr(result_module, name, text)
        return ix.fit("R0 + R1 || C1", stack, shared=["R0"], over="trial")


def test_a_joint_fit_marks_its_reworded_spectra(tmp_path):
    plain, joint = _joint(), _joint(MODEL_MISSES_STRUCTURE=REWORDED)
    assert isinstance(joint, ix.SharedFitResult)
    assert any(w.startswith(REWORDED) for w in joint.warnings["trial=two"])
    assert [warnings_blame_model(joint.warnings.get(k, ())) for k in ("trial=one", "trial=two")] == [False, False]  # (the old rule flips)
    assert joint.model_misfits == plain.model_misfits == ("trial=two",)
    assert joint.misses_structure.values.tolist() == plain.misses_structure.values.tolist() == [False, True]
    # the normal path: the value is the words
    assert [warnings_blame_model(plain.warnings.get(k, ())) for k in ("trial=one", "trial=two")] == [False, True]
    assert any(MODEL_MISSES_STRUCTURE in w for w in plain.warnings["trial=two"])
    path = tmp_path / "joint.nc"
    ix.write_result(joint, path)
    back = ix.SharedFitResult.from_xarray(read_netcdf(path))
    assert back.model_misfits == ("trial=two",) and back.misses_structure.values.tolist() == [False, True]
    ds = plain.to_xarray()
    ds.attrs = {k: v for k, v in ds.attrs.items() if k not in ("warning_tags", "model_misfit", "data_limit_note", "data_limit_hint", "misfit_note", "uneven_noise", "sigma_residual_notes", "model_misfits")}  # (a file without it: the words)
    ix.io.write_netcdf(ds, path)
    old = ix.SharedFitResult.from_xarray(read_netcdf(path))
    assert old.model_misfits is None and old.misses_structure.values.tolist() == [False, True]
