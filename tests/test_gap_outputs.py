"""What `impedax gap`'s output files hold (walkthrough 78b, 2026-12-02): the CSV's peak force and
verdicts, the JSON's sampling flag, alarms and keys with their unit, the .nc variables' units and
names, the `--out` help, and the reader's message for a frequency dimension named otherwise.
Results are hand-built stubs (no fit, no sampling): every number is SYNTHETIC, from numpy here."""

from __future__ import annotations

import csv
import json
from types import SimpleNamespace

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from cli_run import run
from impedax.cli.gap import GAP_OUT_HELP
from impedax.errors import DataError
from impedax.io import write_result
from impedax.models.gap import GAP_TABLE_COLUMNS, GapAnalysis
from impedax.models.sirin import paper_gap_estimate, remaining_impedance

EPS0 = 8.8541878128e-12  # vacuum permittivity [F/m], CODATA 2018
EPS_AIR = 1.00059  # air's relative permittivity (Sirin et al.)
AREA = 2e-4  # the walkthrough's gripper contact [m²]
GAP = 5e-6  # its gap thickness [m]
V0 = 500.0  # its drive amplitude [V]
FREQ = np.geomspace(1.0, 1e5, 21)
WARNINGS = ("the air gap carries 340 V at the force's peak; air breaks down near 330 V", "dimension 'repeat' averaged as replicates; check, a; b")


def _force_bands():
    """SYNTHETIC force and gap-voltage bands over FREQ: eq 1, F = ½ ε0 ε A V²/u², with a gap
    voltage that peaks at 1 kHz (V0 · a bell in log f), so the force maximum lies inside the grid."""
    volts = V0 * np.exp(-0.5 * (np.log10(FREQ) - 3.0) ** 2)
    force = 0.5 * EPS0 * EPS_AIR * AREA * volts**2 / GAP**2
    data = {}
    for k, s in (("median", 1.0), ("q05", 0.93), ("q95", 1.08)):
        data[k] = (("branch", "frequency"), np.stack([force * s, 0.8 * force * s]))
        data[f"gap_voltage_{k}"] = (("branch", "frequency"), np.stack([volts * np.sqrt(s), 0.9 * volts * np.sqrt(s)]))
    ds = xr.Dataset(data, coords={"branch": ["with_ep", "without_ep"], "frequency": FREQ})
    ds["median"].attrs["units"] = "N"  # (as gap_analysis makes it: only the median had a unit)
    return ds


POOLED_CHAIN = dict(mean_acceptance=0.41, autocorr={"u": 50.0, "R_EP": 40.0}, ess={"u": 3840.0, "R_EP": 4800.0}, n_walkers=64,
                    settings={"steps": 4000, "burn": 1000, "thin": 1, "stopped": "converged"}, chain_converged=True)
"""What the report's sampling line reads of a pooled (emcee) posterior: SYNTHETIC figures of a chain 60 τ long."""


def _stub(*, rhat_max=1.062, hierarchical=True, warnings=WARNINGS):
    """A `GapAnalysis` built by hand: SYNTHETIC remainder R_EP ∥ C_gap of 3 repeats, a fit stub
    and a hierarchical (or pooled) posterior stub with the diagnostics given."""
    c_gap = EPS0 * EPS_AIR * AREA / GAP
    z = 1.0 / (1.0 / 5e7 + 2j * np.pi * FREQ * c_gap)
    rng = np.random.default_rng(78)
    spectra = [ix.make_spectrum(FREQ, np.stack([zz * (1 + 0.015 * rng.standard_normal()) for _ in range(3)]), dims=("repeat",))
               for zz in (z + 2e3, np.full(FREQ.size, 1e3 + 0j), np.full(FREQ.size, 1e3 + 0j))]
    fit = SimpleNamespace(frequency=FREQ, z_model=z, rms_rel=0.015, chi2_red=0.1, weighting="sigma", model="R_EP || C_gap", values={"R_EP": 5e7, "C_gap": c_gap},
                          stderr={"R_EP": 1e6, "C_gap": 1e-12}, to_table=lambda: [{"name": "R_EP", "unit": "Ohm"}, {"name": "C_gap", "unit": "F"}])
    u = GAP * np.exp(0.02 * rng.standard_normal(400))
    draws = {"u": u, "C_gap": EPS0 * EPS_AIR * AREA / u, "R_EP": 5e7 * np.exp(0.05 * rng.standard_normal(400))}
    quantiles = {"value": 0.03, "q05": 0.01, "q95": 0.06}
    post = SimpleNamespace(
        population_parameters=lambda: draws, rhat=lambda: {"u": rhat_max, "R_EP": 1.001}, ess=lambda: {"u": 33.0, "R_EP": 400.0}, mixing=lambda: ({"u": rhat_max, "R_EP": 1.001}, {"u": 33.0, "R_EP": 400.0}),
        divergences=0, n_draws=400, mean_acceptance=0.85, summary=lambda: {"discrepancy": quantiles}, spread_between_trials=lambda name: quantiles,
        new_trial=lambda name: {"value": GAP, "q05": 0.9 * GAP, "q95": 1.1 * GAP},
    )
    pooled = SimpleNamespace(parameter_draws=lambda: draws, **POOLED_CHAIN)
    return GapAnalysis(remaining_impedance(*spectra), paper_gap_estimate(*spectra, area=AREA), fit, fit, None if hierarchical else pooled,
                       _force_bands(), AREA, V0, "CPE", warnings=warnings, method="hierarchical" if hierarchical else "pooled",
                       hierarchical=post if hierarchical else None)


def test_gap_csv_gives_the_peak_force_and_the_verdicts(tmp_path):
    """The walkthrough's CSV had the frequency of the force maximum but not the force, and no
    warning or sampling flag: now the bayes row has both, equal to the JSON's numbers."""
    result = _stub()
    write_result(result, tmp_path / "gap.csv")
    write_result(result, tmp_path / "gap.json")
    with open(tmp_path / "gap.csv", newline="", encoding="utf-8") as handle:
        rows = list(csv.DictReader(handle))
    summary = json.loads((tmp_path / "gap.json").read_text(encoding="utf-8"))
    bayes, paper = rows[:2]
    assert list(bayes)[: len(GAP_TABLE_COLUMNS)] == list(GAP_TABLE_COLUMNS)

    # the oracle: the band's largest median with EP, and the band there (numpy, not the result)
    bands = _force_bands().sel(branch="with_ep")
    i = int(np.argmax(bands["median"].values))
    assert 0 < i < FREQ.size - 1  # (the case: a maximum inside the grid)
    expected = {"force_max_frequency_hz": FREQ[i], "force_max_n": bands["median"].values[i], "force_max_low_n": bands["q05"].values[i], "force_max_high_n": bands["q95"].values[i]}
    for column, value in expected.items():
        assert float(bayes[column]) == pytest.approx(value, rel=1e-12), column
    # eq 1 at the peak: ½ ε0 ε A V0²/u² (the bell's top is 1 kHz, a grid point: V = V0)
    assert float(bayes["force_max_n"]) == pytest.approx(0.5 * EPS0 * EPS_AIR * AREA * V0**2 / GAP**2, rel=1e-9)
    json_force = summary["force_max_n"]
    assert (json_force["value"], json_force["q05"], json_force["q95"], json_force["frequency_hz"]) == (
        float(bayes["force_max_n"]), float(bayes["force_max_low_n"]), float(bayes["force_max_high_n"]), float(bayes["force_max_frequency_hz"]))
    assert summary["force_max_n"]["value"] == pytest.approx(max(summary["force_n"]["median"]), rel=1e-12)

    # the drive the forces are for: a result built without its origin had V0 given
    assert (float(bayes["v0_v"]), bayes["v0_from"]) == (V0, "given") == (summary["v0"], summary["v0_from"])
    # verdicts: R-hat 1.062 ≥ 1.05 is "SAMPLING UNRELIABLE"
    assert bayes["sampling_unreliable"] == "true" and summary["sampling_unreliable"] is True
    assert bayes["n_warnings"] == "2" and bayes["warnings"].split("\n") == list(WARNINGS) == summary["warnings"]
    assert bayes["alarms"].startswith("SAMPLING UNRELIABLE: 0 divergent transitions of 400 draws, R-hat up to 1.062") and bayes["alarms"].split("\n") == summary["alarms"]
    assert paper["method"] == "paper" and paper["force_max_n"] == paper["sampling_unreliable"] == paper["warnings"] == ""
    assert {r["method"] for r in rows[2:]} == {"bayes_parameter"}  # (the layout readers rely on: parameters after the two rows)


def test_gap_json_flags_and_keys_with_their_unit(tmp_path):
    """JSON: `sampling_unreliable` (false when clean or pooled), `alarms`, and beside the keys
    without a unit the same value under a key with it (c_gap_f, v0_v, paper_method.c_gap_f)."""
    clean = _stub(rhat_max=1.01, warnings=()).summary()
    assert clean["sampling_unreliable"] is False and clean["alarms"] == [] and clean["warnings"] == []
    pooled = _stub(hierarchical=False).summary()
    assert pooled["sampling"] is None and pooled["sampling_unreliable"] is False
    write_result(_stub(), tmp_path / "gap.json")
    s = json.loads((tmp_path / "gap.json").read_text(encoding="utf-8"))
    assert s["c_gap_f"] == s["c_gap"] and s["paper_method"]["c_gap_f"] == s["paper_method"]["c_gap"] and s["v0_v"] == s["v0"] == V0
    assert s["c_gap"]["value"] == pytest.approx(EPS0 * EPS_AIR * AREA / GAP, rel=0.01)  # F, not pF: ≈ 354 pF
    assert s["force_max_without_ep_n"]["value"] == pytest.approx(0.8 * s["force_max_n"]["value"], rel=1e-12)


def test_gap_netcdf_labels_every_variable(tmp_path):
    """The .nc's force variables were `median`/`q05`/`q95` with a unit on `median` only: every
    variable now has a long_name, and units where it has one; the names stay (files are read back)."""
    result = _stub()
    write_result(result, tmp_path / "gap.nc")
    with xr.open_dataset(tmp_path / "gap.nc", engine="scipy") as raw:
        names = set(raw.variables)
        attrs = {name: dict(raw[name].attrs) for name in names}
        file_attrs = dict(raw.attrs)
    units = {"frequency": "Hz", "median": "N", "q05": "N", "q95": "N", "gap_voltage_median": "V", "gap_voltage_q05": "V", "gap_voltage_q95": "V", "u_draws": "m"}
    assert set(units) <= names and {"parameter_value", "parameter_unit", "branch"} <= names
    for name in names:
        assert attrs[name].get("long_name"), name
        assert attrs[name].get("units") == units.get(name), name
    assert "force" in attrs["q05"]["long_name"] and "5 %" in attrs["q05"]["long_name"]
    assert file_attrs["sampling_unreliable"] == 1 and file_attrs["alarms"].startswith("SAMPLING UNRELIABLE")
    assert (file_attrs["v0"], file_attrs["v0_from"]) == (V0, "given")  # (added 2026-12-02)
    # (the result in memory is not changed by writing it)
    assert "units" not in result.force["q05"].attrs and result.force["median"].attrs == {"units": "N"} and result.force["frequency"].attrs == {}
    back = ix.io.read_netcdf(tmp_path / "gap.nc")
    assert back["q95"].attrs["units"] == "N" and back["frequency"].attrs["units"] == "Hz"


def test_gap_out_help_puts_the_parameter_rows_under_csv():
    """The `--out` help had "then a bayes_parameter row" after ".json the --json summary"."""
    csv_part, rest = GAP_OUT_HELP.split(".json the --json summary")
    assert "bayes_parameter row" in csv_part and "bayes_parameter" not in rest
    assert "force_max_n" in csv_part and "sampling_unreliable" in csv_part


FREQ_MESSAGE = ("'Z' has no 'frequency' dimension (its dimensions: 'repeat', 'freq'): name the frequency dimension 'frequency', "
                "with a coordinate in Hz, e.g. ds = ds.rename(freq=\"frequency\")")


def _raw_file(path, dim):
    """A netCDF written by plain xarray in impedax's layout (Z__real, Z__imag) over ``dim``;
    SYNTHETIC Z of R ∥ C, 3 repeats."""
    z = 1.0 / (1.0 / 1e5 + 2j * np.pi * FREQ * 1e-9) * (1 + 0.01 * np.random.default_rng(5).standard_normal((3, 1)))
    xr.Dataset({"Z__real": (("repeat", dim), z.real), "Z__imag": (("repeat", dim), z.imag)}, coords={dim: FREQ, "repeat": [0, 1, 2]}).to_netcdf(path, engine="scipy")
    return z


def test_reader_names_a_misnamed_frequency_dimension(tmp_path, capsys):
    """A file over `freq` said "dataset has no variable 'Z'"; now the reader and `ix.save` (the
    same mistake in memory) say what is wrong and how to rename, in the same words; the command
    exits 2 with it."""
    path = tmp_path / "wrongdim.nc"
    z = _raw_file(path, "freq")
    with pytest.raises(DataError) as read:
        ix.load(path)
    assert str(read.value) == f"{path}: {FREQ_MESSAGE}"
    in_memory = xr.Dataset({"Z": (("repeat", "freq"), z)}, coords={"freq": FREQ})
    with pytest.raises(DataError) as saved:
        ix.save(in_memory, tmp_path / "x.nc")
    assert str(saved.value).endswith(FREQ_MESSAGE)
    fixed = ix.io.read_netcdf(path).rename(freq="frequency")  # (the advice works)
    np.testing.assert_allclose(ix.validate_spectrum(fixed)["Z"].values, z)
    code, out, err = run(["gap", path, path, path, "--area", AREA, "--pooled"], capsys)
    assert code == 2 and FREQ_MESSAGE in err and "Traceback" not in err


def test_plain_xarray_file_in_impedax_layout_loads(tmp_path):
    """Z__real/Z__imag over `frequency` written without impedax's marks are joined as impedax's
    own are (they had been refused as having no 'Z')."""
    path = tmp_path / "plain.nc"
    z = _raw_file(path, "frequency")
    ds = ix.load(path)
    np.testing.assert_array_equal(ds["Z"].values, z)
    assert "Z__real" not in ds.variables


def test_gap_json_says_what_its_interval_covers_and_the_edl_fits_chi2():
    """`interval_covers`: the pooled interval is of these trials' mean u only, the hierarchical one
    of the population's median with the spread between trials; `edl_chi2_red` beside rms_rel, and
    the report's fits line says why it lies below 1 (the stub's σ is the SEM of 3 repeats)."""
    pooled, hierarchical = _stub(hierarchical=False), _stub()
    assert "not for the population's" in pooled.summary()["interval_covers"]
    assert "spread between trials" in hierarchical.summary()["interval_covers"] and "not for" not in hierarchical.summary()["interval_covers"]
    assert pooled.summary()["edl_chi2_red"] == 0.1
    fits = next(line for line in pooled.report().splitlines() if line.startswith("fits"))
    assert "χ²_red 0.1 against the trial means' SEM, below 1 as expected" in fits
