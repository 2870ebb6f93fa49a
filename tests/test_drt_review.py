"""The DRT's peaks, report and command line after a user tour (docs/drt.md, "Peaks" and
"Choosing λ"). Oracles: SYNTHETIC spectra written here as numpy formulas (R‖C arcs
R/(1 + jωτ), ZARCs R/(1 + (jωτ)^α), complex Gaussian noise of known level) with their
closed-form R and τ; the measured τ range 1/(2π f_max)..1/(2π f_min); max|Z| of the data.
"""

from __future__ import annotations

import json
import math
import re
import warnings

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.errors import ParameterError
from impedax.fitting.drt import drt

F = np.geomspace(0.01, 1e5, 71)  # 10 mHz – 100 kHz, as the user's `impedax simulate ... --points 71`
W = 2 * np.pi * F
# R0 + R1‖C1 + R2‖C2 with R1 = 100 Ω at τ = 100 µs (C1 = 1 µF) and R2 = 1 kΩ at τ = 1 s (C2 = 1 mF)
TWO_ARCS = 100.0 + 100.0 / (1 + 1j * W * 1e-4) + 1000.0 / (1 + 1j * W * 1.0)


def rc(r, tau):
    return r / (1 + 1j * W * tau)


def noisy(z, level, seed):
    """Z + level·|Z|·(n' + j n'')/√2: relative noise of σ = level/√2 on each component."""
    rng = np.random.default_rng(seed)
    return z + level * np.abs(z) * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size)) / math.sqrt(2)


def decades(a, b):
    return abs(math.log10(a / b))


@pytest.fixture(scope="module")
def two_arcs_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("drt") / "two.csv"
    ix.save(ix.make_spectrum(F, TWO_ARCS), path)
    return str(path)


def run(capsys, *argv):
    """``impedax drt ARGV``: (exit code, stdout, stderr); argparse's errors exit by SystemExit."""
    try:
        code = main(["drt", *argv])
    except SystemExit as exc:
        code = exc.code
    out, err = capsys.readouterr()
    return code, out, err


# ------------------------------------------------------------------ 1. each peak's own window

def test_a_clean_arc_four_decades_from_a_big_one_is_its_own_peak():
    """Before: 1 peak, τ = 1.04 s, R = 1.11 kΩ (the 100 Ω arc, 9 % of R_pol, was pruned and its
    area given to the peak 4 decades away)."""
    result = drt((F, TWO_ARCS))
    assert len(result.peaks) == 2, result.report()
    small, big = result.peaks
    assert decades(small.tau_s, 1e-4) < 0.05 and decades(big.tau_s, 1.0) < 0.05
    assert small.r_ohm == pytest.approx(100.0, rel=0.03) and big.r_ohm == pytest.approx(1000.0, rel=0.03)
    assert result.dropped_peaks == ()


def test_a_peak_below_the_cut_off_is_dropped_and_reported_not_given_away():
    result = drt((F, TWO_ARCS), min_peak_fraction=0.2)  # 10 % when resolved: the 100 Ω arc (9 %) is below
    (big,) = result.peaks
    assert decades(big.tau_s, 1.0) < 0.05 and big.r_ohm == pytest.approx(1000.0, rel=0.03)  # not 1.1 kΩ
    (dropped,) = result.dropped_peaks
    assert decades(dropped.tau_s, 1e-4) < 0.05 and dropped.r_ohm == pytest.approx(100.0, rel=0.03)
    text = result.report()
    assert "1 peak(s) below the cut-off (20 % of ∫|γ|, 10 % when resolved" in text
    assert "dropped, R = 100 Ω in all (at τ = 100 µs)" in text
    payload = result.summary()
    assert payload["dropped_r_ohm"] == pytest.approx(100.0, rel=0.03) and len(payload["dropped_peaks"]) == 1
    assert payload["min_peak_fraction"] == 0.2


@pytest.mark.parametrize("level", [0.003, 0.01, 0.03])
def test_a_resolved_seven_percent_arc_is_reported_and_a_three_percent_one_is_dropped(level):
    """The cut-off: 10 % of ∫|γ|, 5 % for a peak resolved by deep minima (docs/drt.md)."""
    r7 = 1000 * 0.07 / 0.93  # 7 % of R_pol, 2 decades from the 1 kΩ arc
    result = drt((F, noisy(100 + rc(r7, 1e-3) + rc(1000, 0.1), level, 5)))
    assert [round(math.log10(p.tau_s)) for p in result.peaks] == [-3, -1], result.report()
    assert result.peaks[0].r_ohm == pytest.approx(r7, rel=0.06) and result.peaks[1].r_ohm == pytest.approx(1000, rel=0.03)
    r3 = 1000 * 0.03 / 0.97  # 3 % of R_pol, 4 decades away: below the cut-off, not added to the 1 kΩ arc
    result = drt((F, noisy(100 + rc(r3, 1e-4) + rc(1000, 1.0), level, 6)))
    (big,) = result.peaks
    assert big.r_ohm == pytest.approx(1000, rel=0.04) and decades(big.tau_s, 1.0) < 0.05
    (small,) = result.dropped_peaks
    assert small.r_ohm == pytest.approx(r3, rel=0.05) and decades(small.tau_s, 1e-4) < 0.1


@pytest.mark.parametrize("level", [0.003, 0.01, 0.03])
def test_the_side_lobes_of_a_zarc_join_it(level):
    """A ZARC (α 0.9) regularised under γ ≥ 0 rings: resolved lobes of ≈ 3.5 % a decade either
    side. They stay below the cut-off and count in the ZARC's R (closed form: R = 1 kΩ)."""
    z = 10 + 1000 / (1 + (1j * W * 1e-2) ** 0.9)
    for seed in (1, 2):
        result = drt((F, noisy(z, level, seed)))
        (peak,) = result.peaks
        assert decades(peak.tau_s, 1e-2) < 0.05 and peak.r_ohm == pytest.approx(1000, rel=0.03)


# ------------------------------------------------------------------ 2. JSON has what the text shows

def test_json_has_what_the_text_shows_and_no_nan(two_arcs_file, capsys):
    code, out, _ = run(capsys, two_arcs_file, "--json")
    assert code == 0 and "NaN" not in out and "Infinity" not in out
    payload = json.loads(out)
    old = {"tau_s", "gamma_ohm", "gamma_q05", "gamma_q95", "r_inf_ohm", "l_h", "lambda", "lambda_method", "peaks", "rms_rel", "warnings"}
    new = {"c_f", "r_pol_ohm", "residual_sigma", "difference_noise", "converged", "band_lambda", "lambda_choice", "lambda_note", "lambda_floor",
           "lambda_scale", "z_ref_ohm", "min_peak_fraction", "dropped_peaks", "dropped_r_ohm", "window_tau_s"}
    assert old | new <= set(payload)
    assert payload["c_f"] is None  # no series capacitor: inf → null
    assert payload["r_pol_ohm"] == pytest.approx(1100.0, rel=0.02)
    assert payload["z_ref_ohm"] == pytest.approx(np.max(np.abs(TWO_ARCS)), rel=1e-9)
    assert payload["window_tau_s"] == pytest.approx([1 / W.max(), 1 / W.min()], rel=1e-9)
    assert payload["converged"] is True and payload["band_lambda"] > 0
    for p in payload["peaks"]:
        assert {"tau_s", "r_ohm", "width_decades", "r_ohm_sd", "log10_tau_sd", "inside_window", "frequency_hz"} <= set(p)
        assert p["inside_window"] is True and p["r_ohm_sd"] > 0 and p["log10_tau_sd"] >= 0
        assert p["frequency_hz"] == pytest.approx(1 / (2 * math.pi * p["tau_s"]))


def test_json_gives_a_series_capacitance_and_a_peak_outside_the_measured_range(tmp_path, capsys):
    blocking = 20 + rc(500, 1e-3) + 1 / (1j * W * 2e-3)  # a series C of 2 mF: phase → −90° at 10 mHz
    path = tmp_path / "c.csv"
    ix.save(ix.make_spectrum(F, blocking), path)
    assert json.loads(run(capsys, str(path), "--json")[1])["c_f"] == pytest.approx(2e-3, rel=0.1)
    beyond = 10 + rc(200, 1e-3) + rc(300, 50.0)  # τ = 50 s > 1/(2π·10 mHz) = 15.9 s
    path = tmp_path / "beyond.csv"
    ix.save(ix.make_spectrum(F, beyond), path)
    peaks = json.loads(run(capsys, str(path), "--json")[1])["peaks"]
    assert [p["inside_window"] for p in peaks] == [True, False] and peaks[1]["tau_s"] > 1 / W.min()
    assert "(outside the measured range)" in run(capsys, str(path))[1]


def test_the_batch_lines_keep_the_outside_marker_and_the_json_its_keys(tmp_path, capsys):
    spectra = np.stack([noisy(10 + rc(200, 1e-3) + rc(300, 50.0), 0.003, s) for s in range(2)])
    path = tmp_path / "cycles.nc"
    ix.save(ix.make_spectrum(F, spectra, dims=("cycle",), coords={"cycle": [1, 2]}), path)
    code, out, _ = run(capsys, str(path))
    lines = [ln for ln in out.splitlines() if ln.lstrip().startswith("cycle=")]
    assert code == 0 and len(lines) == 2 and all("outside the measured range" in ln for ln in lines), out
    payload = json.loads(run(capsys, str(path), "--json")[1])
    assert all({"r_pol_ohm", "lambda_note", "dropped_peaks"} <= set(s) and [p["inside_window"] for p in s["peaks"]] == [True, False] for s in payload["spectra"])


# ------------------------------------------------------------------ 3. a fixed λ too small

def test_a_fixed_lambda_too_small_is_an_error_naming_lam():
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # (a RuntimeWarning leaked from the figure before)
        with pytest.raises(ParameterError, match=r"^lam must be larger than 1e-20 .*not finite"):
            drt((F, TWO_ARCS), lam=1e-20)
    assert np.all(np.isfinite(drt((F, TWO_ARCS), lam=1e-8).gamma))  # a small λ that the solve takes


def test_the_command_refuses_a_lambda_too_small_and_writes_no_figure(two_arcs_file, tmp_path, capsys):
    figure = tmp_path / "d.png"
    code, out, err = run(capsys, two_arcs_file, "--lam", "1e-20", "--plot", str(figure))
    assert code == 2 and out == "" and "Traceback" not in err
    # (a progress line, "[  2.1 s] …", comes first when the run takes 2 s on a loaded machine: once flaky under -n 2)
    said = [line for line in err.splitlines() if not re.match(r"\[\s*\d+\.\d s\]", line)]
    assert len(said) == 1 and said[0].startswith("impedax drt: error: --lam must be larger than 1e-20")
    assert not figure.exists()


# ------------------------------------------------------------------ 4. how λ was chosen, and its scale

def test_lambda_raised_to_the_floor_is_said():
    """Exact data: GCV's optimum is at the bottom of the grid (no noise to smooth)."""
    result = drt((F, TWO_ARCS))
    assert result.lam == pytest.approx(1e-4) and result.lambda_choice < 1e-4
    assert result.lambda_note.startswith("raised to the floor 0.0001")
    first, second = result.report().splitlines()[:2]
    assert first.endswith("λ = 0.0001 by gcv, " + result.lambda_note)
    assert second.startswith("λ is relative to max|Z|² = (1.2 kΩ)²")  # max|Z| = 1200 Ω at 10 mHz
    assert result.summary()["lambda_note"] == result.lambda_note and result.summary()["lambda_floor"] == 1e-4


def test_lambda_at_the_top_of_its_grid_is_said():
    """A resistor and 1 % noise: nothing to resolve, GCV asks for all the smoothing it can get."""
    result = drt((F, noisy(100.0 + 0 * F, 0.01, 3)))
    assert result.lam == pytest.approx(100.0) and result.lambda_note.startswith("at the top of its grid (100")
    assert "λ = 100 by gcv, at the top of its grid" in result.report()


def test_a_fixed_lambda_has_no_note():
    result = drt((F, noisy(TWO_ARCS, 0.01, 1)), lam=0.01)
    assert result.lambda_note == "" and math.isnan(result.lambda_choice)
    assert result.summary()["lambda_note"] is None and "λ = 0.01 as given" in result.report()


# ------------------------------------------------------------------ 5. residual σ and the noise

@pytest.mark.parametrize("level", [0.003, 0.01, 0.03])
def test_first_difference_noise_follows_the_noise_and_residual_sigma_the_misfit(level):
    sigma = level / math.sqrt(2)  # per component, relative
    result = drt((F, noisy(100 + rc(1000, 1e-2), level, 4)))
    assert sigma / 1.5 < result.difference_noise < 1.5 * sigma
    text = result.report()
    assert f"residual σ {result.noise_estimate * 100:.3g} %" in text and "noise estimate" not in text
    assert f"first-difference noise {result.difference_noise * 100:.2g} %" in text


def test_a_smooth_misfit_raises_the_residual_sigma_not_the_difference_noise():
    """Exact data at λ's floor: the R‖C deltas are smoothed, a systematic misfit of ≈ 1 %."""
    result = drt((F, TWO_ARCS))
    assert result.rms_rel > 0.005 and result.noise_estimate > 0.005
    assert result.difference_noise < 0.2 * result.noise_estimate


# ------------------------------------------------------------------ 6. --fmin/--fmax, --min-peak-fraction

def test_fmax_leaves_the_top_points_out_as_the_api_on_the_cut_spectrum(two_arcs_file, capsys):
    code, out, _ = run(capsys, two_arcs_file, "--fmin", "20m", "--fmax", "1k", "--json")
    payload = json.loads(out)
    keep = (F >= 0.02) & (F <= 1e3)
    assert code == 0 and payload["window_tau_s"] == pytest.approx([1 / W[keep].max(), 1 / W[keep].min()], rel=1e-9)
    cut = drt((F[keep], TWO_ARCS[keep]))
    assert payload["r_inf_ohm"] == pytest.approx(cut.r_inf_ohm, rel=1e-6)
    assert [p["tau_s"] for p in payload["peaks"]] == pytest.approx([p.tau_s for p in cut.peaks], rel=1e-6)


def test_the_r_inf_advice_can_be_followed_on_a_real_file(capsys):
    """REAL: PowerSuite's example file gives R_inf < 0 ("leave the top points out"); without
    the points above 10 kHz the warning goes."""
    path = "tests/fixtures/real/exampleDataPowersuite.txt"
    assert "leave the top points out (--fmax)" in run(capsys, path)[1]  # (Python: `data.where(data.frequency <= f, drop=True)`)
    code, out, _ = run(capsys, path, "--fmax", "10k")
    assert code == 0 and "R_inf = " in out and "warning: R_inf" not in out


def test_min_peak_fraction_says_one_range_in_python():
    """5 was "at most 1" and 1.0 "in [0, 1)" (2026-12-03 walkthrough): one range, as the CLI's."""
    for value in (5, 1.0):
        with pytest.raises(ix.ParameterError, match=r"min_peak_fraction must be at least 0 and below 1 \(a share of the DRT's area, e.g. 0.05\), got "):
            drt((F, TWO_ARCS), min_peak_fraction=value)
    with pytest.raises(ix.ParameterError, match="min_peak_fraction must be at least 0, got -0.1"):
        drt((F, TWO_ARCS), min_peak_fraction=-0.1)


def test_min_peak_fraction_from_the_command_line(two_arcs_file, capsys):
    payload = json.loads(run(capsys, two_arcs_file, "--min-peak-fraction", "0.2", "--json")[1])
    assert len(payload["peaks"]) == 1 and [round(math.log10(p["tau_s"])) for p in payload["dropped_peaks"]] == [-4]


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--fmin", "0"], "--fmin must be positive, got 0"),
        (["--fmax", "-5"], "--fmax must be positive, got -5"),
        (["--fmin", "10", "--fmax", "1"], "--fmax (1 Hz) is below --fmin (10 Hz)"),
        (["--fmin", "1M"], "no frequencies at or above --fmin = 1 MHz"),
        (["--fmax", "lots"], "argument --fmax: 'lots' is not a number"),
        (["--min-peak-fraction", "1.5"], "argument --min-peak-fraction: '1.5' must be at least 0 and below 1"),
        (["--min-peak-fraction", "some"], "argument --min-peak-fraction: 'some' is not a number"),
    ],
)
def test_bad_band_and_cut_off_options_exit_2_naming_the_option(two_arcs_file, capsys, argv, message):
    code, out, err = run(capsys, two_arcs_file, *argv)
    assert code == 2 and out == "" and "Traceback" not in err and message in err, err


@pytest.mark.parametrize("f_max, open_arc", [(159.0, True), (60.0, True), (1e5, False)])
def test_a_negative_l_of_a_band_cut_through_an_arc_names_the_arc(f_max, open_arc):
    """SYNTHETIC 10 Ω + 100 Ω (τ 1 ms) + 200 Ω (τ 1 s), exact, measured from 0.1 Hz to f_max:
    cut through the fast arc (−Z''/|Z| = 64 % and 33 % at the top, from the closed form), the
    DRT's L is negative and the warning blamed only a stray capacitance or a cable; it now
    says that the data end inside an arc, with that share. To 100 kHz: no negative-L warning."""
    f = np.geomspace(0.1, f_max, 41)
    omega = 2 * np.pi * f
    z = 10 + 100 / (1 + 1j * omega * 1e-3) + 200 / (1 + 1j * omega * 1.0)
    result = drt((f, z))
    negative_l = [w for w in result.warnings if w.startswith("L = ")]
    if not open_arc:
        assert not negative_l and result.l_h > -1e-6
        return
    share = -z[-1].imag / abs(z[-1])
    (warning,) = negative_l
    assert f"the data end inside an arc (−Z'' is still {share * 100:.0f} % of |Z| at the top frequency)" in warning
    assert "read R_inf as an upper bound of the series resistance" in warning and result.r_inf_ohm > 10
