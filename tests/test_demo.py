"""`make demo` in fast mode: every step runs, the files appear together, the story names the
missing effect and the error falls, and the gap thickness is near the synthetic truth."""

import re

import pytest

from impedax.cli import main

U_TRUE_UM = 2.787  # C_gap = 413 pF, A = 130 mm² (docs/physics.md: ≈ 2.79 µm)


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    out = tmp_path_factory.mktemp("demo")
    import contextlib
    import io

    buffer = io.StringIO()
    with contextlib.redirect_stdout(buffer):
        code = main(["demo", "--out", str(out), "--fast"])
    return code, buffer.getvalue(), out


def test_demo_writes_everything(demo):
    code, text, out = demo
    assert code == 0
    names = {p.name for p in out.iterdir()}
    assert names == {"report.html", "remaining_impedance.nc", "force_bands.nc", "step2_naive_fit.png", "step3_refinement.png", "refined_circuit.png", "step4_gap_and_force.png", "step5_force.png"}
    report = (out / "report.html").read_text()
    for name in names - {"report.html", "remaining_impedance.nc", "force_bands.nc"}:
        assert name in report
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
    final = [float(x) for x in re.findall(r"^\s+\d+\s+([\d.]+)%", text, flags=re.M)]
    assert naive > 0.3 and final[-1] / 100 < naive / 20  # the error falls


def test_demo_gap_thickness(demo):
    _, text, _ = demo
    u, lo, hi = (float(x) for x in re.search(r"u = ([\d.]+) µm, 90% credible interval ([\d.]+)–([\d.]+) µm", text).groups())
    assert lo <= u <= hi
    assert lo <= U_TRUE_UM <= hi  # the interval of the population median contains the generating u
    spread = float(re.search(r"spread between trials: ([\d.]+)%", text).group(1))
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
    u, u_lo, u_hi = (float(x) * 1e-6 for x in re.search(r"u = ([\d.]+) µm, 90% credible interval ([\d.]+)–([\d.]+) µm", text).groups())
    c, c_lo, c_hi = (float(x) * 1e-12 for x in re.search(r"C_gap = ([\d.]+) pF, 90% credible interval ([\d.]+)–([\d.]+) pF", text).groups())
    eps0, eps_air, area = 8.8541878128e-12, 1.00059, 130e-6
    assert c == pytest.approx(eps0 * eps_air * area / u, rel=5e-4)  # (u printed to 1 nm, C_gap to 0.1 pF)
    assert c_lo == pytest.approx(eps0 * eps_air * area / u_hi, rel=5e-4) and c_hi == pytest.approx(eps0 * eps_air * area / u_lo, rel=5e-4)
    assert 380e-12 < c < 450e-12  # near the generator's 413 pF
    assert f"{c * 1e12:.1f} pF [{c_lo * 1e12:.1f}, {c_hi * 1e12:.1f}] (90%)" in (out / "report.html").read_text()


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
