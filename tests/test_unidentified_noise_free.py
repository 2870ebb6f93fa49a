"""Parameters of a near-null direction read undetermined also on noise-free data, where
χ²_red ≈ 1e-32 used to shrink their regularised variance to a ± of 0.01 % (the Meyer
finger's C_s and C_i; 1e11 % with 0.1 % noise)."""

import json
import math

import numpy as np

import impedax as ix
from impedax.cli import main

FINGER = "C_s + C_i + R_sc || C_sc + R_f"
TRUTH = {"C_s": 140e-12, "C_i": 1.7e-9, "R_sc": 130e3, "C_sc": 2.2e-9, "R_f": 500.0}  # Meyer eq 3.13
F = np.geomspace(1.0, 1e6, 61)


def _finger(params) -> np.ndarray:
    """SYNTHETIC, noise-free: C_s and C_i in series with R_sc ∥ C_sc and R_f, written out."""
    s = 2j * np.pi * F
    return 1 / (s * params["C_s"]) + 1 / (s * params["C_i"]) + params["R_sc"] / (1 + s * params["R_sc"] * params["C_sc"]) + params["R_f"]


def _check(groups, stderr, values):
    assert groups == (("C_s", "C_i"),)
    for name in ("C_s", "C_i"):  # undetermined: no finite ±, whatever chi2_red scales it by
        assert not math.isfinite(stderr[name]), (name, stderr[name])
    # the determined keep theirs: finite and tiny (the data are exact to ~1e-15)
    for name in ("R_sc", "C_sc", "R_f"):
        assert math.isfinite(stderr[name]) and 0 < stderr[name] / values[name] < 1e-9, (name, stderr[name])
        assert abs(values[name] / TRUTH[name] - 1) < 1e-8
    # only the series combination of C_s and C_i is determined (1/C = 1/C_s + 1/C_i)
    series = 1 / (1 / values["C_s"] + 1 / values["C_i"])
    assert abs(series / (1 / (1 / TRUTH["C_s"] + 1 / TRUTH["C_i"])) - 1) < 1e-8


def test_single_fit_noise_free_unidentified_are_undetermined():
    result = ix.fit(FINGER, ix.make_spectrum(F, _finger(TRUTH)))
    assert result.chi2_red < 1e-25  # noise-free: the scaling that made the ± look small
    _check(result.unidentified_groups, result.stderr, result.values)
    rows = {row["name"]: row for row in result.to_table()}
    assert rows["C_s"]["undetermined"] and rows["C_i"]["undetermined"] and rows["C_s"]["stderr"] is None
    assert not rows["R_sc"]["undetermined"] and rows["R_sc"]["stderr"] > 0


def test_batch_noise_free_unidentified_are_undetermined():
    other = {**TRUTH, "R_sc": 90e3}
    data = ix.make_spectrum(F, np.array([_finger(TRUTH), _finger(other)]), dims=("cycle",)).assign_coords(cycle=[1, 2])
    batch = ix.fit(FINGER, data)
    for cycle in (1, 2):
        ds = batch.dataset.sel(cycle=cycle)
        names = [str(n) for n in ds["param"].values]
        assert batch.unidentified_groups_of(cycle=cycle) == (("C_s", "C_i"),)
        assert bool(batch.undetermined("C_s").sel(cycle=cycle)) and bool(batch.undetermined("C_i").sel(cycle=cycle))
        assert not bool(batch.undetermined("R_f").sel(cycle=cycle))
        stderr = dict(zip(names, ds["stderr"].values.tolist()))
        assert not math.isfinite(stderr["C_s"]) and not math.isfinite(stderr["C_i"])
        assert math.isfinite(stderr["R_f"]) and stderr["R_f"] / float(ds["value"].sel(param="R_f")) < 1e-9


def test_cli_fit_noise_free_json_has_no_stderr_for_unidentified(tmp_path, capsys):
    csv = tmp_path / "finger.csv"
    z = _finger(TRUTH)
    np.savetxt(csv, np.column_stack([F, z.real, z.imag]), delimiter=",", header="frequency_hz,z_real_ohm,z_imag_ohm", comments="")
    out = tmp_path / "fit.json"
    assert main(["fit", str(csv), "--model", FINGER, "--out", str(out)]) == 0
    text = capsys.readouterr().out
    rows = {line.split()[0]: line for line in text.splitlines() if line.startswith(("C_s ", "C_i ", "R_f "))}
    assert "%" not in rows["C_s"] and "%" not in rows["C_i"] and "%" in rows["R_f"]  # no relative error shown for the undetermined
    params = json.loads(out.read_text())["params"]
    assert params["C_s"]["stderr"] is None and params["C_i"]["stderr"] is None
    assert params["R_f"]["stderr"] is not None and params["R_f"]["stderr"] > 0


def test_two_near_null_directions_over_the_same_parameters_give_one_group():
    """An SVD written here: two near-null right singular vectors, both over all four parameters
    (components ±0.5), are one group and one warning, as are those of a Havriliak–Negami element
    on REAL CHInstruments data (the group and its warning were listed twice until 2026-12-03)."""
    from pathlib import Path

    from impedax.fitting.statistics import null_sets

    s = np.array([1.0, 0.5, 1e-14, 1e-15])
    vt = np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0.5, 0.5, 0.5, 0.5], [0.5, -0.5, 0.5, -0.5]], float)
    groups, ratio = null_sets(s, vt, ["A", "B", "C", "D"])
    assert groups == [["A", "B", "C", "D"]] and ratio == 1e-15
    groups, _ = null_sets(s, np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0.7, 0.7, 0.1, 0.1], [0.1, 0.1, 0.7, 0.7]], float), ["A", "B", "C", "D"])
    assert groups == [["A", "B"], ["C", "D"]]  # (different parameters: two groups, as before)
    real = Path(__file__).parent / "fixtures" / "real" / "exampleDataCHInstruments.txt"
    fit = ix.fit("R0 + HN1 + L1", real)
    assert len(fit.unidentified_groups) == len({tuple(g) for g in fit.unidentified_groups}) >= 1
    assert len(fit.warnings) == len(set(fit.warnings))
