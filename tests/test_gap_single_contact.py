"""`impedax gap PAD` and `gap_analysis(total)`: a single contact (an electroadhesive gripper pad
on its target), whose measured impedance is the contact's own, R_EP ∥ CPE_EP ∥ C_gap, with no
skin or touchscreen to subtract. SYNTHETIC spectra from a numpy formula written here."""

import csv
import json

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from cli_run import run
from impedax.cli import main
from impedax.models.gap import gap_analysis
from impedax.models.sirin import gap_force_peak, gap_voltage, remaining_impedance
from impedax.data import format_frequency, format_quantity

EPS0 = 8.8541878128e-12
EPS_AIR = 1.00059
AREA = 4e-4  # a 2 cm × 2 cm pad [m²]
V0 = 200.0  # drive amplitude [V], below air's ~330 V breakdown: no spark warning
U_TRUE = 5e-6  # [m]
C_GAP = EPS0 * EPS_AIR * AREA / U_TRUE  # 708.8 pF
R_EP = 1e8  # [Ω]
ALPHA = 0.6  # well below 1: the CPE is no capacitor beside C_gap, so C_gap is determined
Q_EP = C_GAP * (2 * np.pi * 30.0) ** (1 - ALPHA)  # CPE admittance equals ωC_gap at 30 Hz (Sirin's EP corner)
FREQ = np.geomspace(1.0, 1e6, 41)  # the grid of tests/spectra.sirin_measurements: the pooled sampler compiled for it is reused


def _pad_impedance(c_gap=C_GAP, freq=FREQ):
    """Z of R_EP ∥ CPE_EP ∥ C_gap [Ω]: the admittances add, Y = 1/R + Q (jω)^α + jωC."""
    w = 2 * np.pi * freq
    return 1.0 / (1.0 / R_EP + Q_EP * (1j * w) ** ALPHA + 1j * w * c_gap)


def _pad_trials(seed, n_trials=5, noise=0.01, u_scatter=0.0):
    """``n_trials`` spectra of the pad with 1 % complex noise per point (Re and Im alike), each
    trial's gap u_t = U_TRUE·exp(u_scatter·N(0, 1)) (0: one gap for all)."""
    rng = np.random.default_rng(seed)
    gaps = U_TRUE * np.exp(u_scatter * rng.standard_normal(n_trials))
    z = np.stack([_pad_impedance(EPS0 * EPS_AIR * AREA / u) for u in gaps])
    z = z * (1 + noise * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape)))
    return ix.make_spectrum(FREQ, z, dims=("trial",))


def _peak_force(u):
    """Eq 1 with nothing in series: I = V0/Z_R, ΔV = V0 − 0·I − 0·I = V0, and C_gap lies parallel
    to the EP branch, so |ΔV_gap| = V0 and F = ½ ε0 ε_gap A V0²/u² at every frequency [N]."""
    return 0.5 * EPS0 * EPS_AIR * AREA * V0**2 / np.asarray(u) ** 2


def test_nothing_in_series_puts_the_whole_drive_across_the_gap():
    """`gap_voltage` and `gap_force_peak` with z_skin = z_ts = 0 against the closed form, for the
    true parameters and with C_gap alone."""
    params = {"R_EP": R_EP, "CPE_EP.Q": Q_EP, "CPE_EP.alpha": ALPHA, "C_gap": C_GAP}
    for remainder, p in (("R_EP || CPE_EP || C_gap", params), ("C_gap", {"C_gap": C_GAP})):
        volts = np.asarray(gap_voltage(p, FREQ, 0.0, 0.0, v0=V0, remainder=remainder))
        force = np.asarray(gap_force_peak(p, FREQ, 0.0, 0.0, area=AREA, v0=V0, remainder=remainder))
        np.testing.assert_allclose(volts, V0, rtol=1e-12)
        np.testing.assert_allclose(force, _peak_force(U_TRUE), rtol=1e-9)
    assert _peak_force(U_TRUE) == pytest.approx(2.8350, rel=1e-4)  # by hand: ½ · 8.8594e-12 · 4e-4 · 4e4 / 2.5e-11 = ½ · 5.670


def test_remainder_of_a_single_contact_is_the_total_s_trial_mean():
    total = _pad_trials(3)
    z = total["Z"].values
    remaining = remaining_impedance(total, None, None)
    np.testing.assert_allclose(remaining["Z"].values, z.mean(axis=0), rtol=1e-12)
    sem_re, sem_im = z.real.std(axis=0, ddof=1) / np.sqrt(5), z.imag.std(axis=0, ddof=1) / np.sqrt(5)
    np.testing.assert_allclose(remaining["sigma"].values, np.sqrt((sem_re**2 + sem_im**2) / 2), rtol=1e-12)
    assert remaining.attrs["single_contact"] == 1 and "n_trials_skin" not in remaining.attrs and "no skin or touchscreen" in remaining.attrs["quantity"]


def test_exactly_one_of_skin_and_screen_is_refused(tmp_path, capsys):
    pad = str(tmp_path / "pad.nc")
    ix.save(_pad_trials(1), pad)
    code, _, err = run(["gap", pad, pad, "--area", "4e-4", "--v0", "200"], capsys)
    assert code == 2
    assert "one spectrum file after DATA_TOTAL: give DATA_SKIN and DATA_TS both" in err and "or neither (a single contact" in err
    total = _pad_trials(1)
    with pytest.raises(ix.ParameterError, match="a skin spectrum without a touchscreen spectrum"):
        gap_analysis(total, total, None, area=AREA, method="pooled", progress=False)
    with pytest.raises(ix.ParameterError, match="a touchscreen spectrum without a skin spectrum"):
        gap_analysis(total, touchscreen=total, area=AREA, method="pooled", progress=False)


def test_single_contact_cli_reaches_the_sampler_with_the_total_itself(tmp_path, capsys, monkeypatch):
    """The fast default test of the mode (the sampling, ~17 s of compilation, is stood in for):
    ``impedax gap pad.nc --pooled`` hands the sampler the total's trial mean, nothing subtracted,
    and an EDL least-squares start whose C_gap is the SYNTHETIC truth (seed 7) within 1 %."""
    import impedax.fitting as fitting

    reached = {}

    def stand_in(circuit, data, **options):
        reached.update(data=data, init=options["init"])
        raise ix.DataError("stand-in: the sampler was reached")

    monkeypatch.setattr(fitting, "sample", stand_in)
    total = _pad_trials(7)
    pad = str(tmp_path / "pad.nc")
    ix.save(total, pad)
    code, _, err = run(["gap", pad, "--area", "4e-4", "--no-area-check", "--v0", "200", "--pooled", "--quiet"], capsys)
    assert code == 2 and "stand-in: the sampler was reached" in err
    data = reached["data"]
    np.testing.assert_allclose(data["Z"].values, total["Z"].values.mean(axis=0), rtol=1e-9)
    assert data.attrs["single_contact"] == 1 and "skin" not in data.attrs
    assert float(reached["init"].values["C_gap"]) == pytest.approx(C_GAP, rel=0.01)


def test_single_contact_pooled_recovers_the_gap_and_the_force():
    """`gap_analysis(total)` (pooled) on 5 SYNTHETIC trials of
    one gap, 1 % noise (seed 7): u's interval holds the truth, the gap voltage is V0 and the force
    band is eq 1 over u's band, with EP and without; the report names the mode."""
    result = gap_analysis(_pad_trials(7), area=AREA, v0=V0, method="pooled", steps=100, progress=False)
    g = result.gap
    assert g["q05"] <= U_TRUE <= g["q95"], g
    assert g["value"] == pytest.approx(U_TRUE, rel=0.01)
    assert result.gap_identified and result.single_contact
    out = result.summary()
    for key in ("gap_voltage_v", "gap_voltage_without_ep_v"):
        np.testing.assert_allclose(out[key]["median"], V0, rtol=1e-9)
    force = {k: np.asarray(out["force_n"][k]) for k in ("median", "q05", "q95")}
    assert np.ptp(force["median"]) <= 1e-9 * force["median"][0]  # one value over frequency
    # F falls as 1/u²: its median lies within eq 1 over u's interval, and its band holds the true gap's force
    assert _peak_force(g["q95"]) <= force["median"][0] <= _peak_force(g["q05"])
    assert force["q05"][0] <= _peak_force(U_TRUE) <= force["q95"][0]
    np.testing.assert_allclose(out["force_without_ep_n"]["median"], force["median"], rtol=1e-9)
    assert out["single_contact"] is True and out["force_conditions"].startswith("A taken as exact; a single contact")
    report = result.report()
    assert "mode            single contact (no skin or touchscreen given)" in report and "the same at every frequency" in report
    # a flat force has no frequency of its maximum: its value at every frequency (it read "max … at 1 Hz")
    (line,) = [ln for ln in report.splitlines() if ln.startswith("force (peak")]
    flat = format_quantity(float(force["median"][0]), "N")
    f = result.force["frequency"].values
    assert line.endswith(f"with EP: {flat} at every frequency ({format_frequency(f.min())}–{format_frequency(f.max())}); without EP: {flat} at every frequency ({format_frequency(f.min())}–{format_frequency(f.max())})"), line
    assert "skin and screen as their trial means" not in report
    assert result.to_xarray().attrs["single_contact"] == 1


def test_single_contact_cli_recovers_the_gap_and_says_its_mode(tmp_path, capsys):
    """``impedax gap pad.nc --area 4e-4 --no-area-check --v0 200 --pooled`` (SYNTHETIC, seed 8):
    u's interval holds the truth, and the JSON, CSV, --remaining and --plot say single contact."""
    pad = str(tmp_path / "pad.nc")
    ix.save(_pad_trials(8), pad)
    files = {"csv": tmp_path / "gap.csv", "remaining": tmp_path / "rem.nc", "plot": tmp_path / "gap.png"}
    code, stdout, _ = run(["gap", pad, "--area", "4e-4", "--no-area-check", "--v0", "200", "--pooled", "--steps", "200", "--quiet", "--json",
                           "--out", files["csv"], "--remaining", files["remaining"], "--plot", files["plot"]], capsys)
    assert code == 0
    out = json.loads(stdout)
    g = out["gap_um"]
    assert g["q05"] <= U_TRUE * 1e6 <= g["q95"], g
    assert out["c_gap_f"]["q05"] <= C_GAP <= out["c_gap_f"]["q95"]
    assert out["gap_identified"] and out["single_contact"] is True and out["method"] == "pooled" and set(out["trials"]) == {"total"}
    assert set(out["provenance"]["source"]) == {"total"}
    assert "total − skin − touchscreen" not in json.dumps(out, ensure_ascii=False)
    rows = list(csv.DictReader(files["csv"].open()))
    assert rows[0]["method"] == "bayes" and rows[0]["single_contact"] == "true"
    with xr.open_dataset(files["remaining"]) as rem:
        assert rem.attrs["single_contact"] == 1 and "total" in rem.attrs and "skin" not in rem.attrs and "touchscreen" not in rem.attrs
        assert "no skin or touchscreen subtracted" in rem.attrs["quantity"]
    assert files["plot"].stat().st_size > 10_000


def test_single_contact_hierarchical_cli_recovers_the_population_gap(tmp_path, capsys):
    """The hierarchical path (default): 6 SYNTHETIC trials whose gaps scatter by 3 % (ln u);
    the population median's interval holds the generating U_TRUE."""
    pad = str(tmp_path / "pad.nc")
    ix.save(_pad_trials(21, n_trials=6, u_scatter=0.03), pad)
    code, out, _ = run(["gap", pad, "--area", "4e-4", "--no-area-check", "--v0", "200", "--steps", "150", "--quiet", "--json"], capsys)
    assert code == 0
    out = json.loads(out)
    g = out["gap_um_population"]
    assert out["method"] == "hierarchical" and out["single_contact"] is True
    assert g["q05"] <= U_TRUE * 1e6 <= g["q95"], g
    assert g["value"] == pytest.approx(U_TRUE * 1e6, rel=0.05)
    np.testing.assert_allclose(out["gap_voltage_v"]["median"], V0, rtol=1e-9)
