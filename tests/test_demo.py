"""`make demo` in fast mode: every step runs, the files appear together, the story names the
missing effect and the error falls, and the gap thickness is near the synthetic truth. The
hierarchical `GapAnalysis` the demo samples also serves the gap's rendering tests (summary JSON,
CSV, report, `impedax gap --json`), so the fast suite runs that sampler once."""

import re

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from gap_files import saved_gap_files
from test_models_gap import _cli_gap_json, _measurements

U_TRUE_UM = 2.787  # C_gap = 413 pF, A = 130 mm² (docs/physics.md: ≈ 2.79 µm)


@pytest.fixture(scope="module")
def demo_run(tmp_path_factory):
    """`impedax demo --fast`, with the hierarchical `GapAnalysis` its step 4 made (recorded on its
    way out of `gap_analysis`): (exit code, terminal text, output folder, analysis)."""
    out = tmp_path_factory.mktemp("demo")
    import contextlib
    import io

    import impedax.models.gap as gap_module

    made = []
    analysed = gap_module.gap_analysis

    def recorded(*args, **options):
        made.append(analysed(*args, **options))
        return made[-1]

    buffer = io.StringIO()
    with pytest.MonkeyPatch.context() as patch, contextlib.redirect_stdout(buffer):
        patch.setattr(gap_module, "gap_analysis", recorded)
        code = main(["demo", "--out", str(out), "--fast"])
    assert len(made) == 1
    return code, buffer.getvalue(), out, made[0]


@pytest.fixture(scope="module")
def demo(demo_run):
    return demo_run[:3]


@pytest.fixture(scope="module")
def analysis(demo_run):
    """The demo's hierarchical gap analysis (30 SYNTHETIC trials, the refined remainder model):
    the sampled `GapAnalysis` the rendering tests below take, so that the fast suite compiles and
    runs the hierarchical sampler once (test_models_gap.py's own 8-trial analysis is slow)."""
    return demo_run[3]


def test_demo_writes_everything(demo):
    code, text, out = demo
    assert code == 0
    names = {p.name for p in out.iterdir()}
    inputs = {"total_sliding.nc", "skin.nc", "touchscreen.nc"}  # (the embedded SYNTHETIC spectra, for impedax gap on the command line)
    assert names == inputs | {"report.html", "remaining_impedance.nc", "force_bands.nc", "step2_naive_fit.png", "step3_refinement.png", "refined_circuit.png", "step4_gap_and_force.png", "step5_force.png"}
    report = (out / "report.html").read_text()
    for name in names - inputs - {"report.html", "remaining_impedance.nc", "force_bands.nc"}:
        assert name in report
    from impedax.models.synthetic import example_spectra

    for name, embedded in zip(sorted(inputs), (example_spectra()[k] for k in ("skin", "total_sliding", "touchscreen"))):
        written = ix.load(out / name)
        np.testing.assert_array_equal(written["Z"].values, embedded["Z"].values)
    assert "impedax gap total_sliding.nc skin.nc touchscreen.nc --area 130e-6" in text
    assert text.strip().splitlines()[-1] == f"Report: {(out / 'report.html').resolve()}"


def test_demo_story(demo):
    _, text, _ = demo
    for step in range(1, 7):
        assert f"[{step}/6]" in text
    assert "SYNTHETIC" in text
    assert "Verdict on C_gap: missing_effect" in text
    assert re.search(r"^\s+electrode_polarization\s+ΔAIC", text, flags=re.M)  # top suggestion
    assert "Final model: R_EP || CPE_EP || C_gap   verdict: adequate" in text
    naive = float(re.search(r"Model C_gap: rms_rel = ([\d.e-]+)", text).group(1))
    final = [float(x) for x in re.findall(r"^\s+\d+\s+([\d.]+) %", text, flags=re.M)]
    assert naive > 0.3 and final[-1] / 100 < naive / 20  # the error falls


def test_demo_gap_thickness(demo):
    _, text, _ = demo
    u, lo, hi = (float(x) for x in re.search(r"u = ([\d.]+) µm, 90 % credible interval ([\d.]+)–([\d.]+) µm", text).groups())
    assert lo <= u <= hi
    assert lo <= U_TRUE_UM <= hi  # the interval of the population median contains the generating u
    spread = float(re.search(r"spread between trials: ([\d.]+) %", text).group(1))
    assert 3.0 < spread < 14.0  # generated with 7 % between trials (and 1 % between sessions)
    new_lo, new_hi = (float(x) for x in re.search(r"a new trial: u in ([\d.]+)–([\d.]+) µm", text).groups())
    assert new_lo < lo and new_hi > hi
    assert u == pytest.approx(U_TRUE_UM, rel=0.03)
    paper = float(re.search(r"paper's method: u = ([\d.]+) µm", text).group(1))
    assert paper == pytest.approx(U_TRUE_UM, rel=0.05)


def test_report_gives_each_heading_once(tmp_path):
    """The report's sections held their step header again as their first line ("[1/6] Load …"
    under the heading "1. Load …"), and the empty "Report" step had a section of its own; now
    the header is on the terminal only and a step with nothing to show has only its timing."""
    import io

    from impedax.demo import _Story, _write_report

    terminal = io.StringIO()
    story = _Story(terminal)
    story.step(1, "Load the measurements")
    story.say("  30 trials each")
    story.step(6, "Report")
    story.finish()
    _write_report(tmp_path, story, {"key": "value"})
    report = (tmp_path / "report.html").read_text()
    assert "[1/6]" not in report and "[6/6]" not in report and "<pre></pre>" not in report
    assert report.count("<h2>1. Load the measurements</h2>") == 1 and report.count("Load the measurements") == 2  # heading, timing row
    assert "<h2>6. Report</h2>" not in report and report.count("6. Report") == 1  # its timing row only
    assert "<pre>30 trials each</pre>" in report
    assert "[1/6] Load the measurements" in terminal.getvalue() and "[6/6] Report" in terminal.getvalue()


def test_a_read_only_output_is_refused_before_the_run(tmp_path, capsys):
    """As every command's outputs (`impedax.io.atomic.check_writable`): the demo's report.html
    read-only in the output folder stops the demo before its first step, naming the file, and
    nothing is written. Before: the run went on and `os.replace` put a new file in its place."""
    report = tmp_path / "report.html"
    report.write_text("keep me")
    report.chmod(0o444)
    assert main(["demo", "--out", str(tmp_path), "--fast"]) == 2
    captured = capsys.readouterr()
    assert captured.err.count("error:") == 1 and str(report) in captured.err and "is read-only" in captured.err
    assert "[1/6]" not in captured.out
    assert [p.name for p in tmp_path.iterdir()] == ["report.html"] and report.read_text() == "keep me"


def test_the_demos_files_are_written_as_every_output(tmp_path):
    """Through a symbolic link (the link stays), keeping the permission bits of the file
    replaced, all files together; a read-only one refuses the lot, leaving every file as it was."""
    from impedax.demo import _publish
    from impedax.errors import DataError

    staging, out, elsewhere = (tmp_path / name for name in ("staging", "out", "elsewhere"))
    for folder in (staging, out, elsewhere):
        folder.mkdir()
    (staging / "report.html").write_text("new report")
    (staging / "step5_force.png").write_bytes(b"new figure")
    (elsewhere / "report.html").write_text("old report")
    (out / "report.html").symlink_to(elsewhere / "report.html")
    (out / "step5_force.png").write_bytes(b"old figure")
    (out / "step5_force.png").chmod(0o600)
    _publish(staging, out)
    assert (out / "report.html").is_symlink() and (elsewhere / "report.html").read_text() == "new report"
    assert (out / "step5_force.png").read_bytes() == b"new figure" and (out / "step5_force.png").stat().st_mode & 0o777 == 0o600
    assert sorted(p.name for p in out.iterdir()) == ["report.html", "step5_force.png"]  # no temporary left
    assert sorted(p.name for p in elsewhere.iterdir()) == ["report.html"]

    (staging / "report.html").write_text("newer report")
    (out / "step5_force.png").chmod(0o444)
    with pytest.raises(DataError, match="step5_force.png.*is read-only"):
        _publish(staging, out)
    assert (elsewhere / "report.html").read_text() == "new report" and (out / "step5_force.png").read_bytes() == b"new figure"
    assert sorted(p.name for p in out.iterdir()) == ["report.html", "step5_force.png"]
    assert sorted(p.name for p in elsewhere.iterdir()) == ["report.html"]


def test_timings_line_names_each_step():
    """The closing "Timings:" line names each step by its short name (it gave the step numbers
    only), and the report's table keeps the full headings; no demo run (`_Story` alone)."""
    import io

    from impedax.demo import _Story, timings_line

    assert timings_line([("1. Load the measurements", 3.24), ("6. Report", 0.06)]) == "Timings: 1. Load the measurements: 3.2 s, 6. Report: 0.1 s"
    story = _Story(io.StringIO())
    story.step(3, "Diagnose: which physical effect is missing? Add it, refit, watch the error fall", short="Diagnose and refine")
    story.step(6, "Report")
    story.finish()
    assert [name for name, _ in story.short_timings] == ["3. Diagnose and refine", "6. Report"]  # (no short name: the title)
    assert [title for title, _ in story.timings] == ["3. Diagnose: which physical effect is missing? Add it, refit, watch the error fall", "6. Report"]
    assert [s for _, s in story.short_timings] == [s for _, s in story.timings]
    assert re.fullmatch(r"Timings: 3\. Diagnose and refine: \d+\.\d s, 6\. Report: \d+\.\d s", timings_line(story.short_timings))


def test_demo_prints_c_gap_beside_u(demo):
    """Step 4 gives the posterior C_gap with its interval (2026-12-01: only u was printed, so
    u = ε0 ε_gap A/C_gap could not be checked from the story): the oracle is that formula with
    ε0, ε_gap = 1.00059 (air) and A = 130 mm² written here; u's interval maps onto C_gap's
    reversed (C_gap falls as u grows). The report's facts give it too."""
    _, text, out = demo
    u, u_lo, u_hi = (float(x) * 1e-6 for x in re.search(r"u = ([\d.]+) µm, 90 % credible interval ([\d.]+)–([\d.]+) µm", text).groups())
    c, c_lo, c_hi = (float(x) * 1e-12 for x in re.search(r"C_gap = ([\d.]+) pF, 90 % credible interval ([\d.]+)–([\d.]+) pF", text).groups())
    eps0, eps_air, area = 8.8541878128e-12, 1.00059, 130e-6
    assert c == pytest.approx(eps0 * eps_air * area / u, rel=5e-4)  # (u printed to 1 nm, C_gap to 0.1 pF)
    assert c_lo == pytest.approx(eps0 * eps_air * area / u_hi, rel=5e-4) and c_hi == pytest.approx(eps0 * eps_air * area / u_lo, rel=5e-4)
    assert 380e-12 < c < 450e-12  # near the generator's 413 pF
    assert f"{c * 1e12:.1f} pF [{c_lo * 1e12:.1f}, {c_hi * 1e12:.1f}] (90 %)" in (out / "report.html").read_text()


def test_demo_force_lines_give_both_intervals_and_the_gap_voltage(demo):
    """Step 5 gave the force without EP without its interval ("287 mN with EP [275, 301] vs
    393 mN without EP") and no gap voltage though titled so (2026-12-01): each line now gives
    median [q05, q95] for both branches, of the force and of |ΔV_gap|, read back here from
    force_bands.nc (the same bands); and a gap
    voltage is at most the drive V0 = 75 V (the remainder is one element of a passive divider)."""
    import numpy as np

    import impedax as ix

    _, text, out = demo
    bands = ix.io.read_netcdf(out / "force_bands.nc")
    number = r"\s*([\d.e+-]+) \[([\d.e+-]+), ([\d.e+-]+)\]"
    lines = re.findall(rf"^\s+(\S+ \S?Hz): force{number} mN with EP\s+vs{number} mN without EP;\s+gap voltage{number} V vs{number} V$", text, flags=re.M)
    assert len(lines) == 4, text
    ff = bands["frequency"].values
    for where, *values in lines:
        i = next(k for k, f in enumerate(ff) if ix.data.format_frequency(f) == where)
        printed = np.array(values, float).reshape(4, 3)  # (force with, force without [mN], voltage with, without [V])
        for row, (branch, prefix, scale) in zip(printed, [("with_ep", "", 1e3), ("without_ep", "", 1e3), ("with_ep", "gap_voltage_", 1.0), ("without_ep", "gap_voltage_", 1.0)]):
            expected = [bands[f"{prefix}{k}"].sel(branch=branch).values[i] * scale for k in ("median", "q05", "q95")]
            assert row == pytest.approx(expected, rel=5e-3) and row[1] <= row[0] <= row[2]
        assert printed[2:, 2].max() <= 75.0


def test_demo_says_the_alarms_its_figure_shows(demo_run):
    """The fast demo's sampling (4 chains × 150 draws) can miss R-hat < 1.05: its step-4 figure
    then opens with the red banner "SAMPLING UNRELIABLE: 0 divergent transitions of 600 draws,
    R-hat up to 1.115, ESS down to 54: the bands may be wrong", while its story and report.html
    gave u = 2.803 µm [2.737, 2.863] without a word of it (2026-12-06). Each alarm the analysis
    raises (`GapAnalysis.alarms`, the report's and the figure's opening verdicts; oracle: the
    R-hat and divergences of its own sampling summary) is now said in step 4 and in the report's
    key numbers; with none, the story says the sampling passed its checks."""
    _, text, out, analysis = demo_run
    sampling = analysis.summary()["sampling"]
    unreliable = sampling["divergences"] > 0.01 * sampling["draws"] or not sampling["rhat_max"] < 1.05
    assert any(a.startswith("SAMPLING UNRELIABLE") for a in analysis.alarms) == unreliable
    step4 = text.split("[4/6]")[1].split("[5/6]")[0]
    report = (out / "report.html").read_text()
    for alarm in analysis.alarms:
        assert alarm in step4 and alarm in report
    if not analysis.alarms:
        assert "no alarm" in step4


def test_demo_peak_force_is_the_gaps_own_maximum_with_its_frequency_as_impedax_writes_it(demo_run):
    """The report's "peak force with EP" wrote its frequency "1e+03 Hz" (`:.3g`) for a 1 kHz
    grid maximum (2026-12-06); it now gives the force maximum as `impedax gap`'s report does
    (oracle: that report's "force (peak …) with EP: …" text, and the grid's largest median of
    force_bands.nc read back), the frequency with its prefix and no exponent."""
    import html

    _, _, out, analysis = demo_run
    row = re.search(r"<th[^>]*>peak force with EP</th><td>([^<]*)</td>", (out / "report.html").read_text())
    fact = html.unescape(row.group(1))
    gap_line = next(line for line in analysis.report().splitlines() if line.startswith("force (peak"))
    with_ep = gap_line.split(" with EP: ")[1].split("; without EP: ")[0]
    assert fact.startswith(with_ep) and "e+" not in fact and "e-" not in fact, (fact, with_ep)
    bands = ix.io.read_netcdf(out / "force_bands.nc")
    median = bands["median"].sel(branch="with_ep").values
    newtons = float(median.max())
    assert re.search(r"([\d.]+) mN", fact) and float(re.search(r"([\d.]+) mN", fact).group(1)) == pytest.approx(newtons * 1e3, rel=5e-3)
    assert re.search(r" at [\d.]+ (k|M|m)?Hz", fact)


# --- the demo's hierarchical analysis, rendered as `impedax gap` renders it (JSON, CSV, report) --


def test_hierarchical_reports_spread_and_new_trial(analysis):
    """The default method: population median with its interval and a new trial's wider
    interval (the spread the demo's trials were made with is checked in test_demo_gap_thickness)."""
    assert analysis.method == "hierarchical"
    s = analysis.summary()
    pop, new = s["gap_um_population"], s["gap_um_new_trial"]
    assert pop == s["gap_um"] and new["q05"] <= pop["q05"] and new["q95"] >= pop["q95"]
    assert 0 < s["gap_um_spread"] < 0.15 * pop["value"]


def test_naive_model_fails_and_edl_model_fits(analysis):
    assert analysis.naive_fit.rms_rel > 5 * analysis.edl_fit.rms_rel


def test_force_with_ep_is_lower_than_without_below_30_hz(analysis):
    low = analysis.force["frequency"] < 30
    with_ep = analysis.force.sel(branch="with_ep")["median"][low]
    without = analysis.force.sel(branch="without_ep")["median"][low]
    assert bool((with_ep < without).all())
    # closed form of the no-EP force at the lowest frequency for the posterior median:
    # F = ½ ε0 A |V_gap|²/u², V_gap = V0·Z_gap/(Z_skin + Z_TS + Z_gap)
    s = analysis.summary()
    assert s["convention"] == "peak" and len(s["force_n"]["median"]) == analysis.force.sizes["frequency"]


def test_summary_json_contract(analysis):
    s = analysis.summary()
    for key in ("c_gap", "gap_um"):
        assert set(s[key]) >= {"value", "q05", "q95"}
    assert set(s["force_n"]) >= {"frequency_hz", "median", "q05", "q95"}
    assert set(s["force_without_ep_n"]) >= {"frequency_hz", "median", "q05", "q95"}
    np.testing.assert_array_equal(s["force_without_ep_n"]["frequency_hz"], s["force_n"]["frequency_hz"])
    # the gap voltage on the force's frequencies, from the hierarchical draws too (added 2026-12-01)
    for key in ("gap_voltage_v", "gap_voltage_without_ep_v"):
        band = s[key]
        np.testing.assert_array_equal(band["frequency_hz"], s["force_n"]["frequency_hz"])
        assert np.all(band["q05"] <= band["median"]) and np.all(band["median"] <= band["q95"]) and 0 < np.max(band["q95"]) <= analysis.v0 * 1.5
    assert isinstance(s["warnings"], list)
    assert s["gap_um"]["value"] == pytest.approx(analysis.gap["value"] * 1e6)


def test_cli_gap_json(tmp_path, capsys, monkeypatch, analysis):
    """`impedax gap --json` passes its options on and renders the hierarchical analysis. The
    analysis is the demo's (its sampling is tested above), so the CLI's own part runs without a
    second sampling; the whole run from the command line is test_models_gap.py's
    `test_cli_gap_json_end_to_end` (slow: ~2 min)."""
    import impedax.models.gap as gap_module

    asked = {}

    def analysed(total, skin, touchscreen, **options):
        asked.update(options)
        return analysis

    monkeypatch.setattr(gap_module, "gap_analysis", analysed)
    _cli_gap_json(tmp_path, capsys, np.random.default_rng(11))
    assert asked["area"] == pytest.approx(130e-6) and asked["steps"] == 200 and asked["method"] == "hierarchical"


def test_gap_csv_names_the_unit_of_every_column(tmp_path, analysis):
    """`gap --out FILE.csv`: one row per method, SI values with the unit in each column name
    (the JSON's gap_um are the same u in µm)."""
    import csv

    path = tmp_path / "gap.csv"
    ix.io.write_result(analysis, path)
    with open(path, newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert list(rows[0])[:10] == ["method", "c_gap_f", "c_gap_low_f", "c_gap_high_f", "u_m", "u_low_m", "u_high_m", "gap_identified", "u_lower_bound_m", "u_lower_bound_withheld"]
    bayes, paper = rows[:2]
    # then a row per EDL parameter, with its unit (added 2026-12-01)
    parameters = {r["parameter"]: r for r in rows[2:]}
    assert {r["method"] for r in rows[2:]} == {"bayes_parameter"} and parameters["u"]["unit"] == "m" and float(parameters["u"]["value"]) == float(bayes["u_m"])
    assert (bayes["method"], paper["method"]) == ("bayes", "paper")
    summary = analysis.summary()
    for column, key in (("u_m", "value"), ("u_low_m", "q05"), ("u_high_m", "q95")):
        assert float(bayes[column]) * 1e6 == pytest.approx(summary["gap_um"][key], rel=1e-12)
    assert float(bayes["c_gap_f"]) == pytest.approx(summary["c_gap"]["value"], rel=1e-12)
    assert float(paper["u_m"]) * 1e6 == pytest.approx(summary["paper_method"]["gap_um"], rel=1e-12)
    assert [float(paper["u_low_m"]) * 1e6, float(paper["u_high_m"]) * 1e6] == pytest.approx(summary["paper_method"]["gap_bounds_um"], rel=1e-12)
    assert paper["c_gap_low_f"] == "" and bayes["gap_identified"] == "true" and bayes["u_lower_bound_m"] == "" and bayes["u_lower_bound_withheld"] == ""
    assert 1e-6 < float(bayes["u_m"]) < 1e-5  # metres: u = 2.79 µm


def test_report_says_what_the_force_bands_condition_on(analysis):
    assert "A taken as exact; skin and screen as their trial means, without their errors" in analysis.report()
    # the area in mm² too, as the demo's C_gap line gives it ("A = 130 mm²"); it read "(A = 0.00013 m²)"
    assert "force bands     A taken as exact; skin and screen as their trial means, without their errors (A = 0.00013 m², i.e. 130 mm²)" in analysis.report()
    assert analysis.summary()["force_conditions"].startswith("A taken as exact")
    assert not any("piles up at the" in w for w in analysis.warnings)  # u = 2.79 µm is far from 1 nm and 1 mm


@pytest.mark.parametrize("flag, expected", [([], True), (["--no-area-check"], False)])
def test_cli_gap_passes_the_area_check_on(tmp_path, capsys, monkeypatch, analysis, flag, expected):
    import impedax.models.gap as gap_module

    asked = {}
    monkeypatch.setattr(gap_module, "gap_analysis", lambda total, skin, touchscreen, **options: asked.update(options) or analysis)
    paths = saved_gap_files(tmp_path, _measurements(np.random.default_rng(4), n_trials=3))
    assert main(["gap", *paths, "--area", "130e-6", "--steps", "20", "--json", *flag]) == 0
    assert asked["check_area"] is expected


def test_no_area_warning_for_a_fingertip_area(analysis):
    from impedax.models.gap import _fingertip_area_notes

    assert _fingertip_area_notes(130e-6) == [] and _fingertip_area_notes(1e-6) == [] and len(_fingertip_area_notes(2e-2)) == 1
    assert not any("fingertip" in w for w in analysis.warnings)


def test_the_u_histogram_gives_its_density_per_micrometre(analysis):
    """The u panel's y axis read "density" without its unit: a density of u over an axis in µm
    is per µm. Oracle: the bars' areas, height × width read off the axis in µm, sum to 1."""
    import matplotlib.pyplot as plt

    fig = analysis.plot()
    try:
        ax = fig.axes[1]
        assert ax.get_xlabel() == "gap thickness u [µm]" and ax.get_xscale() == "linear"
        assert ax.get_ylabel() == "probability density [1/µm]"
        (bars,) = ax.containers  # (the histogram's)
        area = sum(p.get_height() * p.get_width() for p in bars.patches)
        assert area == pytest.approx(1.0, rel=1e-6)
    finally:
        plt.close(fig)
