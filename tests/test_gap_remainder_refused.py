"""A remainder Z_total − Z_skin − Z_TS given to `gap` as a single contact's total is refused:
its gap would take the whole drive V0 where it takes V0·Z_R/Z_total, and the force came out
17 % high at its peak and 2.6× at 2.5 kHz, flat over frequency, with no warning (a walkthrough
ran `impedax gap` on the demo's remaining_impedance.nc, 2026-12-04). A single contact's own
trial mean (`gap --remaining` of a total alone, attr single_contact) is still read."""

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.models import gap_analysis
from impedax.models.gap_inputs import is_remainder_file
from impedax.models.synthetic import example_spectra


@pytest.fixture(scope="module")
def spectra():
    s = example_spectra()
    return {k: s[k].isel(trial=slice(0, 4)) for k in ("total_sliding", "skin", "touchscreen")}


def test_the_cli_refuses_a_remainder_alone_and_names_the_three_files(tmp_path, capsys, spectra):
    paths = {k: str(tmp_path / f"{k}.nc") for k in spectra}
    for k, ds in spectra.items():
        ix.save(ds, paths[k])
    remainder = str(tmp_path / "remainder.nc")
    assert main(["remaining", paths["total_sliding"], paths["skin"], paths["touchscreen"], "--out", remainder]) == 0
    assert is_remainder_file(ix.load(remainder).attrs)
    capsys.readouterr()
    assert main(["gap", remainder, "--area", "130e-6", "--pooled", "--steps", "20", "--out", str(tmp_path / "gap.json")]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"impedax gap: error: {remainder}: this is a remainder Z_total − Z_skin − Z_TS (made from total ")
    assert "the gap voltage is V0·Z_R/Z_total" in err and "impedax gap TOTAL SKIN TOUCHSCREEN" in err and "Traceback" not in err
    assert not (tmp_path / "gap.json").exists()  # (nothing written)


def test_the_demos_remainder_is_one_too_and_python_refuses_it(spectra):
    from impedax.models.sirin import remaining_impedance

    remainder = remaining_impedance(spectra["total_sliding"], spectra["skin"], spectra["touchscreen"])  # (the demo's, no paths)
    assert is_remainder_file(remainder.attrs)
    with pytest.raises(ix.DataError, match="this is a remainder"):
        gap_analysis(remainder, area=130e-6, method="pooled", steps=20, progress=False)


def test_a_total_and_a_single_contacts_trial_mean_are_no_remainder(spectra):
    assert not is_remainder_file(spectra["total_sliding"].attrs)
    assert not is_remainder_file({"single_contact": 1, "n_trials_total": "4", "n_trials_skin": "4", "n_trials_touchscreen": "4"})
    mean = spectra["total_sliding"].mean("trial").assign_attrs(single_contact=1, n_trials_total="4")
    assert not is_remainder_file(mean.attrs) and np.isfinite(mean["Z"].values).all()


def test_remaining_refuses_a_remainder_as_a_total_and_writes_nothing(tmp_path, capsys, spectra):
    """`impedax remaining REMAINDER` read a remainder as a single contact's total, wrote it with
    ``single_contact=1`` (its sigma and skin/screen counts dropped), and `gap` then accepted that
    file: the flat force the refusal above exists to prevent (walkthrough 2026-12-06)."""
    paths = {k: str(tmp_path / f"{k}.nc") for k in spectra}
    for k, ds in spectra.items():
        ix.save(ds, paths[k])
    remainder = str(tmp_path / "remainder.nc")
    assert main(["remaining", paths["total_sliding"], paths["skin"], paths["touchscreen"], "--out", remainder]) == 0
    capsys.readouterr()
    again = tmp_path / "again.nc"
    assert main(["remaining", remainder, "--out", str(again)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"impedax remaining: error: {remainder}: this is a remainder Z_total − Z_skin − Z_TS (made from total ") and "Traceback" not in err
    assert not again.exists()
    # (a single contact's own total still goes through: nothing subtracted, its trial mean written)
    assert main(["remaining", paths["total_sliding"], "--out", str(tmp_path / "pad.nc")]) == 0
    assert ix.load(tmp_path / "pad.nc").attrs["single_contact"] in (1, "1", True)


@pytest.mark.parametrize("suffix", [".csv", ".tsv"])
def test_a_csv_remainder_is_refused_too_by_its_provenance_columns(tmp_path, capsys, spectra, suffix):
    """A CSV keeps no attrs: `impedax gap rem.csv` of `impedax remaining --out rem.csv` was analysed
    as a single contact, the overstated force above, where rem.nc was refused (SYNTHETIC example,
    2026-12-06). Its provenance columns say the command and the three files; a single contact's
    trial mean written as CSV (source: the total alone) is still read."""
    paths = {k: str(tmp_path / f"{k}.nc") for k in spectra}
    for k, ds in spectra.items():
        ix.save(ds, paths[k])
    remainder, pad = str(tmp_path / f"rem{suffix}"), str(tmp_path / f"pad{suffix}")
    assert main(["remaining", paths["total_sliding"], paths["skin"], paths["touchscreen"], "--out", remainder]) == 0
    assert main(["remaining", paths["total_sliding"], "--out", pad]) == 0
    capsys.readouterr()
    assert main(["gap", remainder, "--area", "130e-6", "--pooled"]) == 2
    err = capsys.readouterr().err
    assert "this is a remainder Z_total − Z_skin − Z_TS (its provenance columns say so)" in err and "Traceback" not in err
    assert not is_remainder_file(ix.load(pad).attrs) and is_remainder_file(ix.load(remainder).attrs)
