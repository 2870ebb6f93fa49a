"""The KK/Z-HIT review: a flipped sign gets a hint (kk and inspect), Z-HIT's band ends, the
linear-only options refused with Z-HIT, which rule flagged each band (text, JSON, plot), and
messages that name the file and the frequency. Spectra are numpy formulas or the real
VersaStudio file of tests/fixtures/real; the oracles are numpy (conj, |Z|, hypot)."""

from __future__ import annotations

import importlib
import json
import math
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.errors import DataError

ROOT = Path(__file__).resolve().parents[1]
VERSA = ROOT / "tests" / "fixtures" / "real" / "exampleDataVersaStudio.par"
BATTERY = ROOT / "benchmarks" / "data" / "autoeis_battery_130.nc"
zhit_module = importlib.import_module("impedax.fitting.zhit")  # (ix.fitting.zhit is the function)

F_TOUR = np.geomspace(0.02, 1e5, 61)


def tour_spectrum(f=F_TOUR):
    """55 Ω + 1.5 kΩ ‖ CPE (n = 0.9) + a 0.2 mH lead: the phase still bends at 100 kHz."""
    w = 2 * np.pi * f
    return 55 + 1500 / (1 + (1j * w * 0.02) ** 0.9) + 1j * w * 2e-4


def noisy(z, level, seed):
    rng = np.random.default_rng(seed)
    return z * (1 + level * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size)) / math.sqrt(2))


def write_csv(path, f, z, imag_header="Zimag", imag=None):
    rows = "".join(f"{a!r},{b!r},{c!r}\n" for a, b, c in zip(f.tolist(), z.real.tolist(), (z.imag if imag is None else imag).tolist()))
    path.write_text(f"frequency,Zreal,{imag_header}\n" + rows)
    return path


def json_out(args, capsys):
    assert main(args) == 0
    return json.loads(capsys.readouterr().out)


def one_error(args, capsys) -> str:
    assert main(args) == 2
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert len(err) == 1 and "Traceback" not in captured.err, captured.err
    return err[0]


# --- 1. a flipped sign convention -------------------------------------------------------------

@pytest.fixture
def versa():
    data = ix.load(VERSA)
    return data["frequency"].values, data["Z"].values


@pytest.fixture
def flipped_csv(tmp_path, versa):
    """The VersaStudio spectrum with −Z'' stored under a 'Zimag' header (the export mistake)."""
    f, z = versa
    return write_csv(tmp_path / "flipped.csv", f, z, imag=-z.imag)


def test_kk_and_inspect_say_the_sign_may_be_flipped(flipped_csv, capsys):
    assert main(["kk", str(flipped_csv)]) == 0
    out = capsys.readouterr().out
    assert "NOT valid" in out
    hints = [line for line in out.splitlines() if line.startswith("hint:")]
    assert len(hints) == 1 and "opposite sign (−Z'')" in hints[0] and "passes on conj(Z)" in hints[0]
    assert "rename the column 'Zimag' to '-Zimag'" in hints[0]
    assert json_out(["kk", str(flipped_csv), "--json"], capsys)["sign_hint"] == hints[0].removeprefix("hint: ")
    assert main(["inspect", str(flipped_csv)]) == 0
    out = capsys.readouterr().out
    assert out.count("opposite sign") == 1 and "Z'' > 0 at" in out and "'-Zimag'" in out
    assert "opposite sign" in json_out(["inspect", str(flipped_csv), "--json"], capsys)["sign_hint"]


def test_the_fix_the_hint_names_makes_the_data_valid(flipped_csv, tmp_path, versa, capsys):
    f, z = versa
    fixed = tmp_path / "fixed.csv"
    fixed.write_text(flipped_csv.read_text().replace("Zimag", "-Zimag", 1))
    out = json_out(["kk", str(fixed), "--json"], capsys)
    assert out["valid"] is True and out["sign_hint"] is None
    assert out["rms_rel"] == pytest.approx(ix.kk_test((f, z)).rms_rel, rel=1e-9)  # the file's own spectrum again
    # and the reverse mistake, a '-' header over Z'': the hint says to drop the '-'
    wrong = write_csv(tmp_path / "wrong.csv", f, z, imag_header="-Zimag")
    assert main(["kk", str(wrong)]) == 0
    assert "rename the column '-Zimag' to 'Zimag'" in capsys.readouterr().out


def test_an_untouched_file_and_an_inductive_spectrum_get_no_hint(versa, capsys):
    out = json_out(["kk", str(VERSA), "--json"], capsys)
    assert out["sign_hint"] is None and out["valid"] is True
    assert json_out(["inspect", str(VERSA), "--json"], capsys)["sign_hint"] is None
    assert main(["kk", str(VERSA), "--method", "zhit"]) == 0 and "hint" not in capsys.readouterr().out
    from impedax.io.sign_check import positive_imaginary_evidence

    f = np.geomspace(1, 1e6, 50)
    w = 2 * np.pi * f
    inductive = 1 + 1j * w * 1e-3 + 5 / (1 + 1j * w * 1e-5)  # Z'' > 0 everywhere, |Z| rising
    assert np.all(inductive.imag > 0) and positive_imaginary_evidence(f, inductive) is None
    capacitive = 55 + 1500 / (1 + (2j * np.pi * F_TOUR * 0.02) ** 0.9)
    assert positive_imaginary_evidence(F_TOUR, capacitive) is None and positive_imaginary_evidence(F_TOUR, np.conj(capacitive)) is not None


def test_a_flipped_arc_with_a_resistive_plateau_gets_the_hint_from_its_values():
    """SYNTHETIC 10 + 1000/(1 + (jω·1e-3)^0.9), 1 mHz–100 kHz, 0.5 % noise, stored conjugated: at
    the low-frequency plateau Z'' is within the noise of 0, so Z'' > 0 at fewer than 90 % of
    all points and `inspect` gave no hint (the KK retest did); counted over the points whose
    |Z''| is at least 2 % of |Z|, every one is positive. The unflipped copy gets none."""
    from impedax.io.sign_check import positive_imaginary_evidence

    rng = np.random.default_rng(1)  # (84 % of the points positive; seeds 0–9 give 84–93 %, each found)
    f = np.geomspace(1e-3, 1e5, 81)
    z = 10 + 1000 / (1 + (2j * np.pi * f * 1e-3) ** 0.9)
    z = z * (1 + 0.005 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)))
    flipped = np.conj(z)
    assert np.mean(flipped.imag > 0) < 0.9  # (the share that missed it)
    evidence = positive_imaginary_evidence(f, flipped)
    assert evidence is not None and "points not nearly resistive" in evidence
    assert positive_imaginary_evidence(f, z) is None


def test_header_less_and_phase_files_and_z_hit_get_the_hint(tmp_path, versa, capsys):
    f, z = versa
    bare = tmp_path / "bare.csv"
    bare.write_text("".join(f"{a!r},{b.real!r},{-b.imag!r}\n" for a, b in zip(f.tolist(), z.tolist())))
    assert main(["inspect", str(bare)]) == 0
    assert "add a header line that names it, e.g. frequency,Z',-Z''" in capsys.readouterr().out
    polar = tmp_path / "polar.csv"
    polar.write_text("frequency,|Z|,phase\n" + "".join(f"{a!r},{abs(b)!r},{-math.degrees(np.angle(b))!r}\n" for a, b in zip(f.tolist(), z.tolist())))
    assert main(["kk", str(polar), "--method", "zhit"]) == 0
    out = capsys.readouterr().out
    assert "Z-HIT fails at" in out and "rename the column 'phase' to '-phase'" in out


def test_a_stack_names_how_many_spectra_look_flipped(tmp_path, capsys):
    z = tour_spectrum()
    path = tmp_path / "two.nc"
    ix.save(ix.make_spectrum(F_TOUR, np.stack([z, np.conj(z)]), dims=("trial",)), path)
    out = json_out(["kk", str(path), "--json"], capsys)
    assert [s["sign_hint"] is None for s in out["spectra"]] == [True, False]
    assert main(["kk", str(path)]) == 0
    assert "hint: in 1 of 2 spectra (trial=1)" in capsys.readouterr().out


# --- 2. Z-HIT at the band's ends --------------------------------------------------------------

def _spline_slope_only(data):
    """`ix.zhit` with the end slope off (END_LAYER = 0): the smoothing spline's slope alone."""
    layer = zhit_module.END_LAYER
    try:
        zhit_module.END_LAYER = 0.0
        return ix.zhit(data)
    finally:
        zhit_module.END_LAYER = layer


def test_z_hit_passes_exact_data_whose_phase_bends_at_the_top():
    z = tour_spectrum()
    result = ix.zhit((F_TOUR, z))
    assert result.valid and result.conclusive
    # |Z| from the phase against the exact |Z|: 5.7 % at 100 kHz before the end slope, 1.7 % now
    assert np.max(np.abs(result.modulus / np.abs(z) - 1)) < 0.025
    assert result.end_slope_local[np.argmax(F_TOUR)]
    # the spline's slope alone (END_LAYER = 0) still flags the top: what was reported
    alone = _spline_slope_only((F_TOUR, z))
    assert not alone.valid and alone.bad_bands[-1][1] == pytest.approx(1e5)


def test_z_hit_passes_the_real_versastudio_file_as_the_linear_test_does(versa):
    result = ix.zhit(versa)
    assert result.valid and ix.kk_test(versa).valid
    assert np.max(np.abs(result.residuals)) < 0.025  # 6.8 % at 100 kHz before


def test_the_end_slope_clears_points_and_never_adds_one():
    for seed in range(6):
        z = noisy(tour_spectrum(), 0.01, seed)
        with_end = ix.zhit((F_TOUR, z))
        without = _spline_slope_only((F_TOUR, z))
        assert with_end.noise_estimate == without.noise_estimate and not np.any(with_end.flagged & ~without.flagged)
        assert np.all(np.abs(with_end.residuals) <= np.abs(without.residuals) + 1e-12)
    noisy_valid = [ix.zhit((F_TOUR, noisy(tour_spectrum(), 0.005, seed))).valid for seed in range(20)]
    assert all(noisy_valid)  # 0 of 20 before (the top point flagged)


def test_a_drift_and_a_wrong_point_near_the_top_are_still_flagged():
    z = tour_spectrum()
    top = F_TOUR > 1e4
    drift = z.copy()
    drift[top] *= 1 + 0.08 * np.log10(F_TOUR[top] / 1e4)  # |Z| drifts by 8 % over the top decade, the phase does not
    wrong = z.copy()
    third = np.argsort(F_TOUR)[-3]
    wrong[third] *= 1.10
    for seed in range(5):
        result = ix.zhit((F_TOUR, noisy(drift, 0.005, seed)))
        assert not result.valid and result.flagged[np.argmax(F_TOUR)] and result.bad_bands[-1][0] > 1e4
        result = ix.zhit((F_TOUR, noisy(wrong, 0.005, seed)))
        assert result.flagged[third] and not result.valid


def test_z_hit_says_when_there_are_too_few_frequencies():
    f = np.geomspace(0.01, 1e5, 9)  # 1.1 a decade
    w = 2 * np.pi * f
    result = ix.zhit((f, 10 + 1000 / (1 + 1j * w * 1e-2)))
    assert not result.conclusive and "inconclusive" in result.report()
    assert result.summary()["conclusive"] is False
    assert ix.zhit((F_TOUR, tour_spectrum())).summary()["conclusive"] is True


# --- 3. options of the linear test only -------------------------------------------------------

@pytest.mark.parametrize("option", [["--c", "0.9"], ["--max-rc", "5"], ["--no-inductance"], ["--no-capacitance"]])
def test_z_hit_refuses_the_options_of_the_linear_test(option, capsys):
    message = one_error(["kk", str(VERSA), "--method", "zhit", *option], capsys)
    assert message.startswith("impedax kk: error: " + option[0]) and "--method zhit has none" in message
    assert main(["kk", str(VERSA), *option]) == 0  # the linear test takes it


# --- 4. which rule flagged a band -------------------------------------------------------------

def rule_oracle(result):
    """Per band, with numpy: points above the point level, and the longest run above the run level."""
    order = np.argsort(result.frequency)
    f = result.frequency[order]
    m = np.hypot(result.residuals_real, result.residuals_imag)[order]
    s, t = result.threshold_scale, result.thresholds
    out = []
    for lo, hi in result.bad_bands:
        inside = (f >= lo * (1 - 1e-9)) & (f <= hi * (1 + 1e-9))
        above = m[inside] > t["run"] * s
        longest = max((len(run) for run in "".join("1" if a else "0" for a in above).split("0")), default=0)
        out.append((int(np.sum(m[inside] > t["point"] * s)), longest))
    return out


@pytest.mark.skipif(not BATTERY.exists(), reason="the battery benchmark file")
def test_the_text_names_the_run_rule_on_the_battery_cycle(capsys):
    data = ix.load(BATTERY).sel(cycle=15)
    result = ix.kk_test(data)
    assert result.bad_bands and result.band_rules == (("run",),)
    (points_above, longest), = rule_oracle(result)
    assert points_above == 0 and longest >= 3  # inside the point threshold, a run above 3 s
    assert main(["kk", str(BATTERY), "--select", "cycle=15"]) == 0
    out = capsys.readouterr().out
    run_level = 3 * result.threshold_scale * 100
    assert f"run of ≥ 3 with |Δ| > 3 s = {run_level:.3g} %" in out
    band_line = next(line for line in out.splitlines() if "bad band" in line)
    assert "(run rule)" in band_line and "point rule" not in band_line and f"> {run_level:.3g} %" in band_line


def test_a_single_wrong_point_is_named_by_the_point_rule(capsys):
    f = np.geomspace(0.1, 1e5, 61)
    w = 2 * np.pi * f
    z = noisy(10 + 1000 / (1 + 1j * w * 1e-3), 0.002, 4)
    z[30] *= 1.05
    result = ix.kk_test((f, z))
    assert len(result.bad_bands) == 1 and "point" in result.band_rules[0]
    assert rule_oracle(result)[0][0] >= 1
    summary = result.summary()
    assert summary["method"] == "linear" and summary["bad_band_rules"] == [list(r) for r in result.band_rules]
    assert summary["bad_bands_hz"] == summary["bad_bands"]
    s = result.threshold_scale
    assert summary["threshold_scale_rel"] == s and summary["point_threshold_rel"] == pytest.approx(5 * s) and summary["run_threshold_rel"] == pytest.approx(3 * s)
    assert summary["window_threshold_rel"] == pytest.approx(4.5 * s / 3) and summary["run_length"] == 3 and summary["window"] == 9
    assert summary["noise_estimate_rel"] == result.noise_estimate and summary["chain_error_rel"] == result.chain_error


def flags_by_loops(result):
    """The three rules of docs/kk.md written out point by point (frequency order): |Δ| above the
    point level at one point, above the run level at `run_length` consecutive points, or the mean
    of Δ' or Δ'' over any `window` consecutive points above the window level; then a single
    unflagged point between two flagged ones is flagged too."""
    order = np.argsort(result.frequency)
    re, im = result.residuals_real[order], result.residuals_imag[order]
    m = np.hypot(re, im)
    levels, t, n = result.rule_levels, result.thresholds, m.size
    ruled = [bool(m[i] > levels["point"]) for i in range(n)]
    length, width = int(t["run_length"]), int(t["window"])
    for i in range(n - length + 1):
        if all(m[j] > levels["run"] for j in range(i, i + length)):
            for j in range(i, i + length):
                ruled[j] = True
    for i in range(n - width + 1):
        if abs(sum(re[i:i + width]) / width) > levels["window"] or abs(sum(im[i:i + width]) / width) > levels["window"]:
            for j in range(i, i + width):
                ruled[j] = True
    return np.array([ruled[i] or (0 < i < n - 1 and ruled[i - 1] and ruled[i + 1]) for i in range(n)])


def test_every_flagged_point_has_a_rule_or_closes_a_gap():
    for seed in range(4):
        f = np.geomspace(0.1, 1e5, 61)
        w = 2 * np.pi * f
        r1 = 1000 * (1 + 0.1 * np.linspace(1, 0, f.size))  # drifts during a high→low sweep
        result = ix.kk_test((f, noisy(10 + r1 / (1 + 1j * w * 1e-3), 0.005, seed)))
        order = np.argsort(result.frequency)
        flag = np.asarray(result.flagged, bool)[order]
        assert np.array_equal(flag, flags_by_loops(result))
        assert result.bad_bands  # (the drift is flagged: the check below is not vacuous)
        assert all(rules for rules in result.band_rules) and len(result.band_rules) == len(result.bad_bands)


def test_the_plot_draws_abs_delta_and_both_levels():
    z = tour_spectrum(np.geomspace(0.1, 1e5, 61)).copy()
    f = np.geomspace(0.1, 1e5, 61)
    z[20] *= 1.05
    result = ix.kk_test((f, z))
    fig = result.plot()
    ax = next(a for a in fig.axes if a.get_ylabel() == "KK residual (Z − Z_kk)/|Z| [%]")
    lines = {line.get_label(): line for line in ax.get_lines()}
    magnitude = next(line for label, line in lines.items() if label.startswith("|Δ|"))
    order = np.argsort(f)
    assert np.allclose(magnitude.get_ydata(), np.hypot(result.residuals_real, result.residuals_imag)[order] * 100)
    levels = {label.split(":")[0]: line.get_ydata()[0] for label, line in lines.items() if "rule" in label}
    assert levels["point rule"] == pytest.approx(5 * result.threshold_scale * 100) and levels["run rule"] == pytest.approx(3 * result.threshold_scale * 100)
    assert any("point" in t.get_text() and "rule" in t.get_text() for t in ax.texts)
    zfig = ix.zhit((f, z)).plot()
    assert any(line.get_label().startswith("run rule") for line in zfig.axes[2].get_lines())


def test_the_rule_labels_stay_clear_of_the_residual_curves_and_the_legend():
    """(walkthrough 2026-12-03, the CHI file: |Δ| at 3.9 % between 1 and 2 Hz ran behind
    "point + run + window rule" on a range to 4.66 %, and looked cut off.) Every curve of the
    residual panel stays in the y range and below each band's label; the legend overlaps none."""
    result = ix.kk_test(ix.load(ROOT / "tests" / "fixtures" / "real" / "exampleDataCHInstruments.txt"))
    fig = result.plot()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = next(a for a in fig.axes if a.get_ylabel().startswith("KK residual"))
    labels = [t for t in ax.texts if t.get_text().endswith("rule")]
    assert labels  # (the case: bands named by their rules)
    low, high = ax.get_ylim()
    legend = ax.get_legend().get_window_extent(renderer)
    for line in ax.get_lines():
        y = np.asarray(line.get_ydata(), float)
        assert low <= y.min() and y.max() <= high, line.get_label()
        top = ax.transData.transform((1.0, y.max()))[1]  # (display y of the curve's highest point)
        for text in labels:
            assert top < text.get_window_extent(renderer).y0, (line.get_label(), text.get_text())
    for text in labels:
        assert not legend.overlaps(text.get_window_extent(renderer)), text.get_text()


# --- 5. messages ------------------------------------------------------------------------------

def test_messages_name_the_file_and_the_frequency(tmp_path, capsys):
    two = write_csv(tmp_path / "two.csv", np.array([1000.0, 100.0]), np.array([10 - 1j, 12 - 3j]))
    assert one_error(["kk", str(two)], capsys) == f"impedax kk: error: {two}: the KK test needs at least 4 frequencies, got 2"
    f = np.array([1000.0, 500.0, 100.0, 50.0, 20.0, 10.0])
    z = np.array([10 - 1j, 0j, 12 - 3j, 13 - 3j, 14 - 3j, 15 - 2j])
    zero = write_csv(tmp_path / "zero.csv", f, z)
    assert one_error(["kk", str(zero)], capsys).startswith(f"impedax kk: error: {zero}: Z is exactly zero at 500 Hz;")
    assert one_error(["kk", str(zero), "--method", "zhit"], capsys).startswith(f"impedax kk: error: {zero}: Z is exactly zero at 500 Hz;")
    with pytest.raises(DataError, match="Z is exactly zero at 500 Hz"):
        ix.kk_test((f, z))
    stack = ix.make_spectrum(f, np.stack([z + (z == 0), z]), dims=("trial",))
    with pytest.raises(DataError, match=r"Z is exactly zero at 500 Hz \(in 1 of 2 spectra\)"):
        ix.kk_test_batch(stack)



def test_a_kk_batch_result_has_the_report_the_command_line_prints(capsys, tmp_path):
    """`KKBatchResult.report()` (added 2026-12-02: a Python walkthrough found none) is the text
    `impedax kk` prints for a stack: its first line counts the spectra, one row each after."""
    import numpy as np

    import impedax as ix
    from impedax.cli import main

    f = np.logspace(-1, 5, 40)
    z = np.stack([10 + r / (1 + 2j * np.pi * f * r * 1e-5) for r in (100.0, 200.0, 300.0)])
    rng = np.random.default_rng(4)
    z = z * (1 + 0.005 * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape)))
    data = ix.make_spectrum(f, z, dims=("cell",), coords={"cell": ["a", "b", "c"]})
    text = ix.kk_test_batch(data).report()
    lines = text.splitlines()
    assert lines[0].startswith("linear KK test of 3 spectra over cell: ") and [line.split()[0] for line in lines[2:5]] == ["cell=a", "cell=b", "cell=c"]
    ix.save(data, tmp_path / "stack.nc")
    capsys.readouterr()
    assert main(["kk", str(tmp_path / "stack.nc")]) == 0
    assert capsys.readouterr().out.startswith(text + "\n")


def test_a_kk_batch_with_a_failing_spectrum_ends_with_a_next_line_that_runs(capsys, tmp_path):
    """SYNTHETIC: three R‖C arcs at 0.5 % noise, cell b with one point 20 % off. The stack's
    report says how to go on (it had no next: line, the single test has one): the command it
    names tests cell b alone and that run names the point to leave out."""
    f = np.logspace(-1, 5, 40)
    z = np.stack([10 + r / (1 + 2j * np.pi * f * r * 1e-5) for r in (100.0, 200.0, 300.0)])
    rng = np.random.default_rng(4)
    z = z * (1 + 0.005 * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape)))
    z[1, 20] *= 1.2
    data = ix.make_spectrum(f, z, dims=("cell",), coords={"cell": ["a", "b", "c"]})
    path = tmp_path / "stack.nc"
    ix.save(data, path)
    capsys.readouterr()
    assert main(["kk", str(path)]) == 0
    last = capsys.readouterr().out.strip().splitlines()[-1]
    assert last.startswith(f"next: impedax kk {path} --select cell=b tests cell=b alone (1 of 3 not valid) and names the points to leave out;") and "save the data" not in last
    assert main(last.removeprefix("next: impedax ").split(" tests ")[0].split()) == 0
    single = capsys.readouterr().out
    assert "next: leave them out and test again:" in single and "--exclude" in single
    assert "standard input is read once" in ix.kk_test_batch(data).report("-").splitlines()[-1]


def test_the_next_line_of_data_from_standard_input_says_to_save_them_first(capsys, monkeypatch):
    """SYNTHETIC R‖C at 0.5 % noise with one point 20 % off, given on standard input: the
    suggested ``impedax kk - --exclude …`` cannot be pasted as it is (the input is spent)."""
    import io

    f = np.logspace(-1, 5, 40)
    z = noisy(10 + 200 / (1 + 2j * np.pi * f * 200 * 1e-5), 0.005, 4)
    z[20] *= 1.2
    text = "frequency,Zreal,Zimag\n" + "".join(f"{a!r},{b!r},{c!r}\n" for a, b, c in zip(f.tolist(), z.real.tolist(), z.imag.tolist()))
    monkeypatch.setattr("sys.stdin", io.TextIOWrapper(io.BytesIO(text.encode())))
    assert main(["kk", "-"]) == 0
    next_line = next(line for line in capsys.readouterr().out.splitlines() if line.startswith("next:"))
    assert "impedax kk - --exclude" in next_line and "standard input is read once" in next_line


def test_a_kk_result_has_warnings_as_a_fit_has_and_a_batch_a_one_line_repr():
    """`KKResult.warnings` (the JSON's key had it; the object had none): the notes, then the sign
    hint of a flipped Im Z (numpy's conj of an R‖C). A stack's repr is one line of verdicts (it
    printed every spectrum's arrays)."""
    f = np.geomspace(0.1, 1e5, 41)
    z = 10 + 100 / (1 + 2j * np.pi * f * 1e-3)
    flipped = ix.kk_test((f, np.conj(z)))
    assert flipped.sign_hint and flipped.warnings[-1] == flipped.sign_hint
    assert list(flipped.warnings) == flipped.summary()["warnings"]
    sparse = ix.kk_test((f[::8], z[::8]))  # 6 points: inconclusive, a note
    assert sparse.warnings and sparse.warnings[0].startswith("inconclusive")
    batch = ix.kk_test_batch(ix.make_spectrum(f, np.stack([z, np.conj(z)]), dims=("cell",), coords={"cell": ["a", "b"]}))
    assert repr(batch) == "KKBatchResult(2 spectra over cell: 1 KK-consistent, 1 not)"


@pytest.mark.skipif(not BATTERY.exists(), reason="the battery benchmark file")
def test_the_docs_battery_examples_are_what_the_command_and_the_repr_give_now(capsys, monkeypatch):
    """docs/kk.md quoted "(3 of 130 not valid)" and "127 KK-consistent, 3 not" for the 130 REAL
    battery cycles, from KK rules since changed; the command gives 95 and 35 (2026-12-06). Oracle:
    the count of the verdicts the report's table prints, and the docs' text."""
    monkeypatch.chdir(ROOT)  # (the path as the docs write it)
    relative = "benchmarks/data/autoeis_battery_130.nc"
    assert main(["kk", relative]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    rows = [line for line in lines if line.startswith("cycle=")]
    failed = sum(" NOT valid " in line for line in rows)
    assert len(rows) == 130 and lines[0] == f"linear KK test of 130 spectra over cycle: {130 - failed} KK-consistent, {failed} not"
    docs = " ".join((ROOT / "docs" / "kk.md").read_text(encoding="utf-8").split())  # (lines joined as they wrap)
    assert lines[-1].split(" and names ")[0] + " and names" in docs
    assert f"KKBatchResult(130 spectra over cycle: {130 - failed} KK-consistent, {failed} not)" in docs
    assert repr(ix.kk_test_batch(ix.load(BATTERY))) == f"KKBatchResult(130 spectra over cycle: {130 - failed} KK-consistent, {failed} not)"
