"""What a user review of compare / diagnose / refine on the real spectra found in their figures
and text (2026-11-28), each with a stand-in of the result (duck-typed, no fit: fast):

- the shading of the failing (or not KK-consistent) bands was never named: the |Z| legend was
  drawn before the bands were shaded, so their label was lost (every spectrum figure);
- a diagnosis figure drew the best suggestion on |Z| without a legend entry, and its residual
  legend did not say the Re/Im residuals are the baseline's;
- log axes within a decade or two (refine's rms_rel per step and compare's residuals in %, |Z|
  of a battery in Ω) were labelled 4×10⁰, 6×10⁻¹ instead of 4, 0.6; refine's step 0 title read "step 0: (start)  (rms_rel …)";
- two models of one curve in compare (a CPE at α = 1 and a capacitor) were drawn in one line
  style, the second hiding the first;
- refine said nothing for the first several seconds (its first diagnosis' line came before the
  2 s delay and was dropped);
- refine's text said "(pass init=)", the Python keyword, with no command to do so.
"""

from __future__ import annotations

import io
import re
import time
from types import SimpleNamespace

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest

from impedax.cli.common import command_line_words
from impedax.cli.common import progress_printer
from impedax.cli.refine import reproduce_line
from impedax.plotting import plot_spectrum
from impedax.plotting.comparison import plot_comparison
from impedax.plotting.diagnosis import NOISE_LEVEL_LABEL, plot_diagnosis, plot_refinement

F = np.geomspace(1e-2, 1e4, 31)


def rc(r1: float, c1: float = 1e-3, r0: float = 0.1) -> np.ndarray:
    return r0 + r1 / (1 + 1j * 2 * np.pi * F * r1 * c1)


def fit(model: str, z_model: np.ndarray, z_data: np.ndarray, **extra) -> SimpleNamespace:
    residuals = (z_model - z_data) / np.abs(z_data)
    rms = float(np.sqrt(np.mean(np.abs(residuals) ** 2 / 2)))
    return SimpleNamespace(model=model, frequency=F, z_data=z_data, z_model=z_model, residuals=residuals, rms_rel=rms, **extra)


def legend_texts(ax) -> list[str]:
    legend = ax.get_legend()
    return [t.get_text() for t in legend.get_texts()] if legend is not None else []


def tick_texts(axis) -> list[str]:
    axis.axes.figure.canvas.draw()
    return [t.get_text() for t in axis.get_ticklabels(which="both") if t.get_text()]


def test_spectrum_figure_names_the_shaded_bands():
    fig = plot_spectrum((F, rc(1.0)), (F, rc(1.1)), bands=[(0.1, 1.0)])
    assert "model fails" in legend_texts(fig.axes[1])  # |Z| panel
    labels = tick_texts(fig.axes[1].yaxis)  # |Z| from 0.1 to 1.1 Ω: 0.2, 0.3, ..., not 2×10⁻¹
    assert labels and not any("10^" in t or "times" in t for t in labels), labels
    plt.close(fig)


def diagnosis_stand_in() -> SimpleNamespace:
    data = rc(1.0) + rc(0.5, 1e-1, 0.0)
    baseline = fit("R0 + R1 || C1", rc(1.4), data)
    best = SimpleNamespace(effect="extra_relaxation+diffusion", fit=fit("R0 + R1 || C1 + R2 || C2", data * 1.001, data))
    band = SimpleNamespace(f_min=0.05, f_max=5.0)
    return SimpleNamespace(baseline=baseline, failing_bands=[band], verdict="missing_effect", best=best, noise_level=1e-3)


def test_diagnosis_figure_legends_say_what_is_drawn():
    fig = plot_diagnosis(diagnosis_stand_in())
    nyquist, modulus, _, residual = fig.axes[:4]
    assert "+ extra_relaxation+diffusion" in legend_texts(nyquist)
    assert {"baseline", "+ extra_relaxation+diffusion", "model fails"} <= set(legend_texts(modulus))
    assert {"Re (baseline)", "Im (baseline)", "|res| with extra_relaxation+diffusion"} <= set(legend_texts(residual))
    # the suggestion's curve is drawn without setting the scale again, which brought back 10^0
    labels = tick_texts(modulus.yaxis)
    assert labels and not any("10^" in t for t in labels), labels
    plt.close(fig)


def test_diagnosis_figure_shades_a_band_the_kk_test_flags_apart_from_the_models():
    """A band marked ``data_problem`` (the KK test flags the data behind its misfit) is shaded in
    its own colour and legend entry on the |Z|, phase and residual panels; the model's band stays
    "model fails" (REAL BioLogic's spike band at 56.2 Hz was shaded "model fails", 2026-12-06)."""
    from matplotlib.colors import to_rgba

    from impedax.plotting.diagnosis import DATA_PROBLEM_BANDS, DATA_PROBLEM_COLOR

    d = diagnosis_stand_in()
    d.failing_bands = [SimpleNamespace(f_min=0.05, f_max=5.0, data_problem=False), SimpleNamespace(f_min=50.0, f_max=80.0, data_problem=True)]
    fig = plot_diagnosis(d)
    for ax in fig.axes[1:4]:
        spans = {(round(p.get_x(), 6), round(p.get_x() + p.get_width(), 6)): p.get_facecolor()[:3] for p in ax.patches}
        assert spans[(0.05, 5.0)] == to_rgba("tab:red")[:3] and spans[(50.0, 80.0)] == to_rgba(DATA_PROBLEM_COLOR)[:3], spans
    assert {"model fails", DATA_PROBLEM_BANDS} <= set(legend_texts(fig.axes[1]))
    plt.close(fig)


def refinement_stand_in() -> SimpleNamespace:
    data = rc(1.0) + rc(0.5, 1e-1, 0.0)
    d = diagnosis_stand_in()
    final = fit("R0 + R1 || C1 + R2 || C2", data * 1.002, data)
    steps = [
        SimpleNamespace(fit=fit("R0 + R1 || C1", rc(1.4), data), effect=None, removed=(), change="(start)", model="R0 + R1 || C1", diagnosis=d),
        SimpleNamespace(fit=final, effect="extra_relaxation", removed=(), change="+ R2 || C2 [extra_relaxation]", model="R0 + R1 || C1 + R2 || C2",
                        diagnosis=SimpleNamespace(failing_bands=[], noise_level=1e-3, baseline=final, noise_ratio=0.5)),
    ]
    return SimpleNamespace(steps=steps, final_model=steps[-1].model, verdict="adequate", masked_points=())


def test_refinement_figure_plain_percent_ticks_named_shading_and_start():
    fig = plot_refinement(refinement_stand_in())
    labels = tick_texts(fig.axes[0].yaxis)
    assert labels and not any("10^" in t or "times" in t or "e-0" in t for t in labels), labels
    first = fig.axes[1]
    assert "model fails" in legend_texts(first)
    assert "(start)" not in first.get_title() and first.get_title().startswith("step 0: start")
    # the noise mark sits where the step's noise ratio is 1: its rms_rel / its ratio (0.5), twice
    # the last step's 0.141 %; the start's stand-in diagnosis has no ratio, so no mark
    (noise,) = [line for line in fig.axes[0].get_lines() if line.get_label() == NOISE_LEVEL_LABEL]
    assert list(noise.get_xdata()) == [1] and noise.get_ydata()[0] == pytest.approx(2 * 0.2 / np.sqrt(2), rel=1e-3)
    plt.close(fig)


def test_refinement_figure_draws_each_point_on_the_side_of_its_noise_mark_its_verdict_says():
    """Each step is judged against its own noise level: rms_rel / noise ratio (the ratio weighs σ
    by where the residuals lie). One line from the last step's ratio (here 0.01: at 14.1 %) put
    the start (11.7 %, judged 1.26× the noise) below it, as on BioLogic (start 2.07 % judged
    1.26×, line at 2.24 %). Read back from the figure: a step judged above 1× lies above its
    mark, one judged below lies below."""
    refinement = refinement_stand_in()
    refinement.steps[0].diagnosis.noise_ratio = 1.26
    refinement.steps[1].diagnosis.noise_ratio = 0.01
    fig = plot_refinement(refinement)
    error = fig.axes[0]
    (points,) = [line for line in error.get_lines() if line.get_marker() == "o"]
    (noise,) = [line for line in error.get_lines() if line.get_label() == NOISE_LEVEL_LABEL]
    assert NOISE_LEVEL_LABEL in legend_texts(error)
    rms = np.array([s.fit.rms_rel * 100 for s in refinement.steps])  # (11.7 %, 0.141 %)
    np.testing.assert_allclose(points.get_ydata(), rms)
    assert list(noise.get_xdata()) == [0, 1]
    np.testing.assert_allclose(noise.get_ydata(), rms / np.array([1.26, 0.01]))
    above = np.asarray(points.get_ydata()) > np.asarray(noise.get_ydata())
    assert list(above) == [True, False]  # (1.26× above its mark, 0.01× below it)
    plt.close(fig)


def test_refinement_figure_writes_no_step_label_across_its_noise_mark():
    """A step's upright label starts right of its point and must clear the short noise mark at
    the same step, which reaches ms/2 points either side (the demo's "electrode_polarization" ran
    up through its mark, 2026-12-06). Here step 1 lies at 0.141 % with its mark at 0.283 %, in
    the label's way; the mark's box is computed from the point, the marker size and the dpi."""
    fig = plot_refinement(refinement_stand_in())
    error = fig.axes[0]
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    (noise,) = [line for line in error.get_lines() if line.get_label() == NOISE_LEVEL_LABEL]
    (label,) = [t for t in error.texts if t.get_text() == "extra_relaxation"]
    x, y = error.transData.transform((noise.get_xdata()[0], noise.get_ydata()[0]))
    half_width, half_height = (noise.get_markersize() / 2, noise.get_markeredgewidth() / 2)
    half_width, half_height = (v * fig.dpi / 72 for v in (half_width, half_height))
    box = label.get_window_extent(renderer)
    assert box.y0 < y < box.y1  # (the label does reach the mark's height: the case is one that can fail)
    assert box.x0 > x + half_width or box.x1 < x - half_width, (box, x, half_width)
    plt.close(fig)


def test_refinement_figure_shows_the_data_with_the_first_and_last_model():
    refinement = refinement_stand_in()
    fig = plot_refinement(refinement)
    nyquist = fig.axes[-1]
    assert nyquist.get_xlabel() == "Z' [Ω]"
    lines = {line.get_label(): line for line in nyquist.get_lines()}
    # (the stand-in's rms_rel: |1.002 − 1|/√2 = 0.141 % for the last step)
    assert set(lines) == {"data", "start: R0 + R1 || C1 (11.7 %)", "final: R0 + R1 || C1 + R2 || C2 (0.141 %)"}, set(lines)
    data = refinement.steps[0].fit.z_data
    np.testing.assert_allclose(lines["data"].get_ydata(), -data.imag)
    np.testing.assert_allclose(lines["final: R0 + R1 || C1 + R2 || C2 (0.141 %)"].get_xdata(), (data * 1.002).real)
    # the two arcs are flat (height/width < 0.6): the panel runs across the figure's top (its
    # grid slot spans both columns; its box narrows to the data's shape since 2026-12-06)
    fig.canvas.draw()
    box, error_box = nyquist.get_position(), fig.axes[0].get_position()
    assert nyquist.get_subplotspec().colspan == range(0, 2) and box.width > 0.6 and box.y0 > error_box.y1
    plt.close(fig)


def test_refinement_figure_marks_the_points_every_step_left_out():
    refinement = refinement_stand_in()
    masked_z = (-0.2 - 0.1j, 1.3 - 0.4j)  # (a non-passive point and an outlier, beyond the data's range)
    refinement.steps[0].diagnosis.masked_points = (1e3, 2e3)
    refinement.steps[0].diagnosis.masked_impedance = masked_z
    fig = plot_refinement(refinement)
    nyquist = fig.axes[-1]
    (cross,) = [line for line in nyquist.get_lines() if line.get_marker() == "x"]
    np.testing.assert_allclose(cross.get_xydata(), [[-0.2, 0.1], [1.3, 0.4]])
    assert "masked (2: left out of every fit)" in legend_texts(nyquist)
    # the panel is scaled to show them too
    lo, hi = nyquist.get_xlim()
    assert lo < -0.2 and hi > 1.3
    plt.close(fig)


def test_refinement_figure_of_a_steep_spectrum_puts_its_nyquist_panel_above_the_error():
    z = 0.1 + 1.0 / (1j * 2 * np.pi * F * 1e-3) ** 0.9  # a blocking electrode: a near-vertical line
    steps = [SimpleNamespace(fit=fit("R0 + C1", z * 1.05, z), effect=None, removed=(), change="(start)", model="R0 + C1", diagnosis=None)]
    fig = plot_refinement(SimpleNamespace(steps=steps, final_model="R0 + C1", verdict="missing_effect", masked_points=()))
    nyquist, error = fig.axes[-1], fig.axes[0]
    assert [line.get_label() for line in nyquist.get_lines()] == ["data", "start: R0 + C1 (3.54 %)"]  # 5 %/√2
    fig.canvas.draw()
    box, error_box = nyquist.get_position(), error.get_position()
    # above the error panel, within its column (the box narrowed to the line's shape since
    # 2026-12-06, `nyquist_view`: it no longer spans the column from its left edge)
    assert box.y0 > error_box.y1 and box.x0 > error_box.x0 - 0.05 and box.x1 < error_box.x1 + 0.05 and box.width < 0.5
    plt.close(fig)


def test_comparison_overlapping_models_in_their_own_line_styles_and_plain_ticks():
    data = rc(1.0) * (1 + 0.05 * np.sin(np.log(F)))
    same = rc(1.0)
    comparison = SimpleNamespace(fits=[fit("R0 + R1 || C1", same, data, weighting="modulus"), fit("R0 + R1 || CPE1", same, data, weighting="modulus")], best="R0 + R1 || C1")  # (every fit has a weighting: the title names it)
    fig = plot_comparison(comparison)
    styles = {line.get_linestyle() for line in fig.axes[1].get_lines() if not line.get_label().startswith("data")}
    assert len(styles) == 2
    labels = tick_texts(fig.axes[3].yaxis)
    assert labels and not any("10^" in t or "times" in t for t in labels), labels
    plt.close(fig)


def test_refine_progress_prints_the_line_said_before_the_delay():
    out = io.StringIO()
    say = progress_printer(0.05, stream=out)
    say("step 0: diagnosing R0 + R1 || C1")
    deadline = time.monotonic() + 5.0
    while "step 0" not in out.getvalue() and time.monotonic() < deadline:
        time.sleep(0.01)
    say("step 1: diagnosing R0 + R1 || C1 + W")
    say.close()
    lines = out.getvalue().splitlines()
    assert len(lines) == 2 and "step 0: diagnosing" in lines[0] and "step 1" in lines[1]


def test_refine_progress_prints_every_line_said_before_the_delay_in_order():
    # (refine of a real battery cycle said "step 0" and "fitting the baseline" in its first 2 s,
    # and began its progress at the third line)
    out = io.StringIO()
    say = progress_printer(0.05, stream=out)
    first = ["step 0: diagnosing R0 + R1 || CPE1", "  fitting the baseline R0 + R1 || CPE1", "  the DRT of the data and of the baseline"]
    for text in first:
        say(text)
    deadline = time.monotonic() + 5.0
    while time.monotonic() < deadline and "the DRT" not in out.getvalue():
        time.sleep(0.01)
    say("  fitting 12 candidate circuits of 4 effects")
    say.close()
    said = [re.sub(r"^\[\s*\d+\.\d s\] ", "", line) for line in out.getvalue().splitlines()]
    assert said == [*first, "  fitting 12 candidate circuits of 4 effects"]


def test_refine_progress_quiet_when_the_run_is_short():
    out = io.StringIO()
    say = progress_printer(0.05, stream=out)
    say("step 0: diagnosing R0 + R1 || C1")
    say.close()
    time.sleep(0.15)
    assert out.getvalue() == ""


def test_refine_text_gives_the_command_for_init():
    note = "fit of R0 + R1 || CPE1 from scratch reaches rms_rel 0.3 %; started from the refinement's values it reaches 0.2 % (pass init=)"
    assert "pass init=" not in command_line_words(note) and "--init" in command_line_words(note)
    final = SimpleNamespace(
        model="R0 + R1 || CPE1", values={"R0": 0.1, "R1": 1.5, "CPE1.Q": 0.05, "CPE1.alpha": 0.5}, fixed=dict.fromkeys(["R0", "R1", "CPE1.Q", "CPE1.alpha"], False), bounds={},
        frequency=np.array([1.0, 2.0, 10.0, 20.0, 100.0]),
    )
    args = SimpleNamespace(select=["cycle=0"], weighting=None, fmin=None, fmax=1000.0)
    line = reproduce_line(SimpleNamespace(notes=(note,), final=final, masked_points=(), final_from_values=True), args)
    assert "impedax fit DATA --select cycle=0 --fmax 1000.0 --model 'R0 + R1 || CPE1' --init R0=0.1 --init R1=1.5" in line
    assert reproduce_line(SimpleNamespace(notes=("another note",), final=final, masked_points=(), final_from_values=False), args) is None
    # another path's note of its own model does not make the final fit need its values (the line had claimed so)
    assert reproduce_line(SimpleNamespace(notes=(note,), final=final, masked_points=(), final_from_values=False), args) is None
    masked = reproduce_line(SimpleNamespace(notes=(note,), final=final, masked_points=(5.0, 50.0), final_from_values=True), args)
    assert "without the 2 masked points" in masked and "--fmax 1000.0 --exclude 5,50 --model" in masked


@pytest.mark.parametrize("scratch_aic,says", [(-1000.0 + 0.15, "which the data do not tell apart"), (-1000.0 + 25.0, "; started from the refinement's values it reaches")])
def test_a_fit_from_scratch_at_an_optimum_as_good_is_not_said_to_stop_short(monkeypatch, scratch_aic, says):
    """A 13-parameter battery model reached two optima at ΔAIC 0.15 and the note had said a fit
    from scratch "stops short": within ΔAIC 10 the note says the data do not tell them apart
    (stand-in fits: χ² and AIC only)."""
    from impedax.fitting.diagnosis import refinement as rf

    last = SimpleNamespace(model="R0 + R1 || CPE1", values={"R0": 1.0}, fixed={"R0": False}, bounds={}, circuit=None, weighting="modulus", registry=None, chi2=1.0, aic=-1000.0, rms_rel=0.010)
    scratch = SimpleNamespace(chi2=1.001, aic=scratch_aic, rms_rel=0.0101)
    warm = SimpleNamespace(chi2=1.0, aic=-1000.0, rms_rel=0.010)
    monkeypatch.setattr(rf, "fit", lambda *a, init=None, **k: warm if init is not None else scratch)
    monkeypatch.setattr(rf, "undetermined_parameters", lambda f: set())
    kept, note = rf._reproduced(None, last, n_starts=1, seed=0)
    assert kept is warm and says in note and "(pass init=)" in note


@pytest.mark.parametrize("label", ["not KK-consistent"])
def test_kk_style_shading_after_legend_is_named(label):
    from impedax.plotting import plot_bode, shade_bands

    fig, (a, b) = plt.subplots(2)
    plot_bode(a, b, (F, rc(1.0)), (F, rc(1.1)))
    shade_bands([a, b], [(0.1, 1.0)], label=label)
    assert label in legend_texts(a)
    plt.close(fig)


# --- text of the fitting results (the review's findings 1, 9 and 10) --------------------------------


def test_a_batch_names_its_dimensions_in_words():
    """Before: "3 spectra over {'cycle': 3}" (a Python dict)."""
    from pathlib import Path

    import impedax as ix

    result = ix.fit("R0 + R1 || CPE1", ix.load(Path(__file__).resolve().parent.parent / "examples" / "data" / "autoeis_battery_cycles.nc"))
    assert result.report().splitlines()[0] == "model R0 + R1 || CPE1: 3 spectra over cycle (3)"
    assert "over cycle (3): converged" in result._repr_html_()


def test_compound_units_are_written_with_omega():
    from impedax.data import format_quantity

    assert format_quantity(3050.0, "Ohm s^-1/2") == "3.05 kΩ s^-1/2"  # before: "Ohm s^-1/2", then "3.05e+03 Ω s^-1/2"
    assert format_quantity(2200.0, "Ohm") == "2.2 kΩ"


@pytest.mark.parametrize(
    "value, unit, text",
    [
        (0.00287, "Ohm s^-1/2", "2.87 mΩ s^-1/2"),  # a Warburg σ: was "0.00287 Ω s^-1/2"
        (4.09e-07, "F s^(alpha-1)", "409 nF s^(α-1)"),  # REAL test_data.txt's CPE_relax3.Q beside "C1 = 1.5 nF": was "4.09e-07 F s^(α-1)"
        (0.000182, "F s^(alpha-1)", "182 µF s^(α-1)"),  # REAL Gamry's CPE_relax.Q: was "0.000182 F s^(α-1)"
        (540.0, "F s^(alpha-1)", "540 F s^(α-1)"),
        (6.61e7, "Ohm s^-1/2", "66.1 MΩ s^-1/2"),
        (2.0, "m^2", "2 m^2"),  # (a unit led by a power: no prefix, which would read as (mm)^2)
    ],
)
def test_compound_units_take_the_prefix_of_their_leading_unit(value, unit, text):
    """`format_quantity` writes a compound unit with the SI prefix of its leading unit, as it
    writes Ω, F, H alone and as the figures' axes count them ("CPE1.Q [nF s^(α-1)]"): the
    refine report's final fit line read "CPE_relax3.Q = 4.09e-07 F s^(α-1)" beside "C1 = 1.5 nF"
    (REAL test_data.txt). Oracle: the value over the prefix's power of ten, by hand."""
    from impedax.data import format_quantity

    assert format_quantity(value, unit) == text


@pytest.mark.slow  # (the suite's 15-minute budget, 2026-12-01: make test-all runs it)
def test_the_apply_line_says_when_the_diagnosis_left_points_out():
    """A diagnosis that masks points the KK test blames says so on its apply line: `impedax fit`
    of the suggestion on every point reached 2.8 % where the suggestion had 1.69 %, and nothing
    said why (BioLogic's file, 2026-11; since 2026-12-02 its 4 flagged points are kept, and
    PowerSuite's file, whose diagnosis masks 2, carries the check). On BioLogic's the rule that
    ranks the simpler candidate first is said where it applies, not as 60 words on every run."""
    from pathlib import Path

    import impedax as ix

    real = Path(__file__).resolve().parent / "fixtures" / "real"
    d = ix.diagnose(ix.load(real / "exampleDataPowersuite.txt"), "R0 + R1 || C1")
    assert d.masked_points and d.best is not None
    report = d.report()
    assert f"this diagnosis left out {len(d.masked_points)} point{'' if len(d.masked_points) == 1 else 's'}" in report and "a fit of every point reaches other values" in report
    d = ix.diagnose(ix.load(real / "exampleDataBioLogic.mpt"), "R0 + R1 || C1")
    report = d.report()
    assert not d.masked_points and "this diagnosis left out" not in report
    assert re.search(r"ranked before 2\. \(ΔAIC -\d+\.\d\): within ΔAIC 10 of each other the data barely tell them apart, and the simpler goes first \(4 free parameters against 5\)", report), report
    assert "one that keeps every element of yours, then the simpler" not in report


def test_compare_s_best_mark_says_when_the_best_fit_has_warnings():
    """CH Instruments' spectrum: the lowest AIC goes to R0 + R1 || CPE1, whose R1 is undetermined
    (relative error 1e14 %); the table marked it "← best" with nothing on the row."""
    from pathlib import Path

    import impedax as ix

    data = ix.load(Path(__file__).resolve().parent / "fixtures" / "real" / "exampleDataCHInstruments.txt")
    c = ix.compare([ix.fit(m, data) for m in ("R0 + R1 || C1", "R0 + R1 || CPE1")])
    best = next(f for f in c.fits if f.model == c.best)
    row = next(line for line in c.report().splitlines() if "← best" in line)
    assert best.warnings and row.endswith(f"← best by AIC, with {len(best.warnings)} warning(s) below")
    # the table alone prints no warnings: its mark points to report() instead of "below"
    row = next(line for line in c.table().splitlines() if "← best" in line)
    assert row.endswith(f"← best by AIC, with {len(best.warnings)} warning(s) (report() lists them)")
    assert not any(w in c.table() for w in best.warnings) and all(w in c.report() for w in best.warnings)
    # ... and the table names the best model whose every parameter the data determine
    assert not best.stderr["R1"] / best.values["R1"] < 1
    assert c.best_determined == "R0 + R1 || C1" == c.summary()["best_determined"]
    # ... far behind (46.7 % against 12.9 %), so the table points to the reduced model instead
    assert ("R0 + R1 || CPE1 leaves R1 undetermined: the data hold R0 + CPE1, the model without it, which fits the same (its warnings say so); "
            "the best model with every parameter determined, R0 + R1 || C1, fits far worse (ΔAIC ") in c.table()
    assert "so compare the reduced model, not that one" in c.table()
    # rows are told apart by position, not by model text: the same circuit with R1 fixed
    fixed = ix.fit("R0 + R1 || CPE1", data, fixed={"R1": 1e4})
    twice = ix.compare([best, fixed])
    assert twice.table().count("← best") == 1 and "the best model with every parameter determined, R0 + R1 || CPE1 [R1=10000], fits far worse" in twice.table()
    from impedax.cli.compare import warning_lines

    assert twice.best_index == 0 and twice.best_determined_index == 1
    assert sum("(best by AIC)" in line for line in warning_lines(twice)) == 1  # (both rows had it)
    assert "R0 + R1 || CPE1 leaves R1 undetermined: the data hold R0 + CPE1, the model without it, which fits the same (its warnings say so); there is no other model" in ix.compare([best]).table()


def test_bound_notes_write_compound_units_with_omega():
    from impedax.fitting.least_squares.result import bound_note

    note = bound_note("W1.sigma", 0.0, "lower", value=6.61e7, stderr=2.3e27, unit="Ohm s^-1/2")
    assert note == "W1.sigma = 66.1 MΩ s^-1/2 cannot be told from its lower bound 0 (linearised standard error 2.3e+27 Ω s^-1/2, bounds ignored)"


def test_an_explanation_names_a_band_the_suggestion_lowers_but_does_not_clear():
    # "removes the misfit at ..." named only the bands a suggestion cleared: one that fell from
    # 4 % to 1 % but stayed a failing band went unmentioned. Stand-in fits, residuals by hand:
    # 20 points, band A (1–3 Hz, 3 points) cleared, band B (100–300 Hz, 3 points) lowered ×4,
    # band C (10–30 kHz) untouched, band D (most points) lowered but left to the overall rms_rel
    from impedax.fitting.diagnosis.bands import FailingBand
    from impedax.fitting.diagnosis.diagnosis import _lowered_bands

    f = np.geomspace(1.0, 1e5, 20)
    before = np.full(f.size, 0.001 + 0j)
    after = before.copy()
    band = {name: (f >= lo) & (f <= hi) for name, (lo, hi) in {"A": (1, 3), "B": (100, 300), "C": (1e4, 3e4), "D": (1, 1e5)}.items()}
    before[band["B"]], after[band["B"]] = 0.04 * (1 + 1j), 0.01 * (1 + 1j)
    before[band["C"]] = after[band["C"]] = 0.03 * (1 + 1j)
    base, cand = SimpleNamespace(frequency=f, residuals=before), SimpleNamespace(frequency=f, residuals=after)
    bands = [FailingBand(lo, hi, "", ("real",), 1.0) for lo, hi in ((1, 3), (100, 300), (1e4, 3e4), (1, 1e5))]
    lowered = _lowered_bands(base, cand, bands, fixed=((1, 3),))
    assert [b for b, _, _ in lowered] == [(100, 300)]
    (_, rms_before, rms_after), = lowered
    assert rms_before == pytest.approx(0.04 * np.sqrt(2)) and rms_after == pytest.approx(0.01 * np.sqrt(2))  # √mean|r|², as rms_rel


@pytest.mark.parametrize("shape", ["flat", "steep"])
def test_a_nyquist_panel_keeps_equal_scales_and_no_empty_half_plane(shape):
    # equal scales widened the limits about the middle: a flat battery-like spectrum (one arc
    # and a Warburg tail, 4:1, written here) sat in the middle of its panel with half the
    # plane at −Z'' < 0 where no point is (Gamry's real file: −Z'' from −8,000 to 15,000 Ω).
    # The widening now lies beyond the data's far side, and a flat spectrum gets a panel
    # across the figure's top shaped like it, so that there is little to widen; the scales stay
    # equal (to matplotlib's own tolerance, 0.5 %)
    from impedax.plotting import plot_spectrum

    f = np.geomspace(1e-2, 1e5, 60)
    jw = 2j * np.pi * f
    z = 0.02 + 0.05 / (1 + jw * 0.05 * 1e-2) + 0.004 * (1 - 1j) / np.sqrt(2 * np.pi * f) * 0.3
    if shape == "steep":  # a blocking electrode: a near-vertical capacitive line
        z = 10.0 + 1 / (1e-5 * jw**0.95)
    fig = plot_spectrum((f, z), (f, z * 1.01))
    ax = fig.axes[0]
    fig.canvas.draw()
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    box = ax.get_window_extent()
    assert abs((x1 - x0) / box.width - (y1 - y0) / box.height) < 0.006 * (x1 - x0) / box.width  # equal scales
    data_x, data_y = (z.real.min(), z.real.max()), ((-z.imag).min(), (-z.imag).max())
    assert x0 < data_x[0] and x1 > data_x[1] and y0 < data_y[0] and y1 > data_y[1]  # every point inside
    # (across: its grid slot spans both columns; its box narrows to the data's shape)
    across = ax.get_subplotspec().colspan == range(0, 2)
    if shape == "flat":  # across the top, as high as the spectrum: little empty plane, none below it
        assert across and data_y[0] - y0 < 0.1 * (y1 - y0) and (y1 - y0) < 1.5 * (data_y[1] - data_y[0])
    else:  # down the left, its box narrowed to the line (2026-12-06, `nyquist_view`): before, the
        # range widened to the right of it, more than twice the data's Z' span, the rest empty plane
        assert not across and data_x[0] - x0 < 0.1 * (x1 - x0) and (x1 - x0) < 1.25 * (data_x[1] - data_x[0])
    plt.close(fig)


@pytest.mark.parametrize("shape", ["flat", "arc", "steep"])
@pytest.mark.parametrize("size", [(8, 6.5), (6, 4), (14, 6.5)])
def test_a_nyquist_panel_keeps_every_point_when_the_figure_is_resized(shape, size):
    # the shift of the widened range was set once, at the figure's own size: resized before
    # saving, a steep spectrum's panel (11 × 6.5 → 8 × 6.5 inches) showed none of its points.
    # Now it is redone at every draw
    from impedax.plotting import plot_spectrum

    f = np.geomspace(1e-2, 1e5, 60)
    jw = 2j * np.pi * f
    z = {"flat": 0.02 + 0.05 / (1 + jw * 0.05 * 1e-2) + 0.0012 * (1 - 1j) / np.sqrt(2 * np.pi * f),
         "arc": 10 + 100 / (1 + jw * 100 * 1e-5), "steep": 10.0 + 1 / (1e-5 * jw**0.95)}[shape]
    fig = plot_spectrum((f, z), (f, z * 1.01))
    fig.set_size_inches(*size)
    fig.canvas.draw()
    ax = fig.axes[0]
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    box = ax.get_window_extent()
    assert abs((x1 - x0) / box.width - (y1 - y0) / box.height) < 0.006 * (x1 - x0) / box.width  # equal scales
    points = np.concatenate([z, z * 1.01])
    assert np.all((points.real > x0) & (points.real < x1) & (-points.imag > y0) & (-points.imag < y1))
    assert y0 > (-points.imag).min() - 0.1 * (y1 - y0) and x0 > points.real.min() - 0.1 * (x1 - x0)  # no empty plane below or left
    zoom_x, zoom_y = (x0 + 0.4 * (x1 - x0), x0 + 0.5 * (x1 - x0)), (y0 + 0.4 * (y1 - y0), y0 + 0.5 * (y1 - y0))
    ax.set_xlim(*zoom_x)  # a zoom by hand (both axes, as the toolbar sets them) is not undone
    ax.set_ylim(*zoom_y)
    fig.canvas.draw()
    assert zoom_x[0] < np.mean(ax.get_xlim()) < zoom_x[1] and zoom_y[0] < np.mean(ax.get_ylim()) < zoom_y[1]
    plt.close(fig)


def test_compare_lists_a_warning_every_model_has_once():
    # Autolab's real spectrum (impedance.py's example): common circuits all stop near 12 %, and
    # each carried the same misfit note (it quotes the data's KK misfit, 0.33 %) under its name,
    # the same paragraph once per model (two here: a third, R0 + R1 || CPE1 + R2 || CPE2, cost the
    # fast suite 2 s and showed nothing two do not)
    from pathlib import Path

    import impedax as ix
    from impedax.cli.compare import warning_lines

    data = ix.load(Path(__file__).resolve().parent / "fixtures" / "real" / "exampleDataAutolab.txt")
    c = ix.compare([ix.fit(m, data) for m in ("R0 + R1 || CPE1", "R0 + R1 || CPE1 + W1")])
    note = next(w for w in c.fits[0].warnings if w.startswith("the model misses structure"))
    assert all(note in f.warnings for f in c.fits)
    lines = warning_lines(c)
    assert sum(note in line for line in lines) == 1
    every = next(i for i, line in enumerate(lines) if line.startswith("  every model: "))
    assert any(note in line for line in lines[every + 1 :]) and lines[every + 1].startswith("    - ")
    for f in c.fits:  # each model's own warnings are still listed under its name
        own = [w for w in f.warnings if not all(w in g.warnings for g in c.fits)]
        for w in own:
            assert any(w in line for line in lines), (w, lines)


def nyquist_of(z: np.ndarray):
    fig, ax = plt.subplots(figsize=(6, 3))
    from impedax.plotting import plot_nyquist

    plot_nyquist(ax, (F, z))
    fig.canvas.draw()
    return fig, ax


def tick_values(axis) -> tuple[np.ndarray, np.ndarray]:
    """(tick positions in view, their labels read as numbers)."""
    lo, hi = sorted(axis.get_view_interval())
    pairs = [(t.get_loc(), t.label1.get_text()) for t in axis.get_major_ticks() if lo <= t.get_loc() <= hi]
    return np.array([p for p, _ in pairs]), np.array([float(text.replace("\N{MINUS SIGN}", "-")) for _, text in pairs])


@pytest.mark.parametrize(("r1", "prefix", "scale"), [(2.0e6, "M", 1e6), (1.5e3, "k", 1e3), (60.0, "", 1.0), (0.04, "m", 1e-3)])
def test_nyquist_axes_count_in_the_prefix_of_the_data(r1, prefix, scale):
    # an arc of r1 [Ω]: a megohm skin arc read "1e6" apart from its ticks, a battery's mΩ "0.02"
    fig, ax = nyquist_of(rc(r1, 1e-3 / r1, 0.0))
    assert ax.get_xlabel() == f"Z' [{prefix}Ω]" and ax.get_ylabel() == f"−Z'' [{prefix}Ω]"
    for axis in (ax.xaxis, ax.yaxis):
        locs, values = tick_values(axis)
        assert locs.size >= 3
        np.testing.assert_allclose(values * scale, locs, atol=1e-9 * r1)  # each label is its tick / scale
        assert not axis.get_offset_text().get_text()  # no detached "1e6"
    plt.close(fig)


def test_nyquist_axes_share_one_prefix_and_a_zoom_relabels_them():
    z = 200.0 + rc(1.2e3, 1e-6, 0.0)  # Z' up to 1.4 kΩ, −Z'' up to 0.6 kΩ: both axes in kΩ
    fig, ax = nyquist_of(z)
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("Z' [kΩ]", "−Z'' [kΩ]")
    ax.set_xlim(150, 450)
    ax.set_ylim(0, 300)
    fig.canvas.draw()
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("Z' [Ω]", "−Z'' [Ω]")
    locs, values = tick_values(ax.xaxis)
    np.testing.assert_allclose(values, locs)
    plt.close(fig)


def test_log_modulus_ticks_read_as_numbers_with_prefixes():
    from impedax.plotting import _plain_number

    assert [_plain_number(x) for x in (1e6, 1e5, 2e4, 1e3, 40.0, 0.5, 1e-3, 5e-4, 2e-9)] == ["1M", "100k", "20k", "1000", "40", "0.5", "0.001", "500µ", "2n"]
    z = 100.0 + rc(1e6, 1e-6, 0.0)  # |Z| from 100 Ω to 1 MΩ
    fig = plot_spectrum((F, z), (F, z * 1.01))
    labels = tick_texts(fig.axes[1].yaxis)
    # (since 2026-12-06 in the Nyquist panel's prefix, MΩ, with no prefix of its own on a tick:
    # "1M, 100k, 1000" under [Ω] stood beside a Nyquist panel in MΩ)
    assert fig.axes[1].get_ylabel() == "|Z| [MΩ]" and fig.axes[0].get_xlabel() == "Z' [MΩ]"
    assert {"1", "0.1", "0.001"} <= set(labels) and not any("e+" in t or t[-1] in "kMmµn" for t in labels), labels
    plt.close(fig)


def test_drt_peak_labels_and_gamma_axis_in_prefixes():
    from impedax.plotting.drt import plot_gamma

    tau = np.geomspace(1e-4, 1e3, 200)
    gamma = 3.8e6 * np.exp(-0.5 * (np.log10(tau / 8.2) / 0.2) ** 2)
    peak = SimpleNamespace(tau_s=404.0, gamma_max_ohm=3.8e6, r_ohm=5.853e6)
    result = SimpleNamespace(tau=tau, gamma=gamma, gamma_q05=0.9 * gamma, gamma_q95=1.1 * gamma, peaks=[peak], window=(1e-3, 1e2))
    fig, ax = plt.subplots()
    plot_gamma(ax, result)
    fig.canvas.draw()
    assert ax.get_ylabel() == "γ [MΩ]"
    assert [t.get_text() for t in ax.texts] == ["404 s\n5.85 MΩ"]  # was "4e+02 s\n5.85e+06 Ω"
    plt.close(fig)


def test_corner_in_the_parameters_units_with_median_and_interval_titles():
    from impedax.plotting.bayes import interval_text, plot_corner

    rng = np.random.default_rng(3)
    n = 20000
    r0 = rng.normal(63.5, 0.3, n)  # narrow: a linear axis in Ω (was log10 R0 from 1.7975 to 1.81)
    r1 = 10 ** rng.normal(6.0, 0.05, n)  # 1 MΩ within ±12 %: a linear axis counted in MΩ
    q = 10 ** rng.normal(-6.0, 1.0, n)  # over decades: a log axis
    alpha = rng.normal(0.9, 0.02, n)
    fig = plot_corner(np.stack([r0, r1, q, alpha], axis=-1), ["R0", "R1", "CPE1.Q", "CPE1.alpha"], [True, True, True, False], units=["Ohm", "Ohm", "F s^(alpha-1)", "1"])
    fig.canvas.draw()
    axes = np.array(fig.axes).reshape(4, 4)
    assert [axes[3, j].get_xlabel() for j in range(4)] == ["R0 [Ω]", "R1 [MΩ]", "CPE1.Q [F s^(α-1)]", "CPE1.alpha"]
    assert [axes[3, j].get_xscale() for j in range(4)] == ["linear", "linear", "log", "linear"]
    assert axes[2, 0].get_yscale() == "log" and axes[1, 0].get_ylabel() == "R1 [MΩ]"
    # diagonal titles: the median and 5–95 % interval of each; against the generating normals
    # (quantiles ±1.645 sd; 20,000 draws, 4,000 shown: sampling error ≲ 0.05 sd at the tails)
    title = axes[0, 0].get_title()
    median, low, high = map(float, title.removeprefix("R0 = ").removesuffix(" Ω").replace("[", "").replace("]", "").replace(",", "").split())
    assert abs(median - 63.5) < 0.03 and abs(low - (63.5 - 1.645 * 0.3)) < 0.05 and abs(high - (63.5 + 1.645 * 0.3)) < 0.05, title
    assert axes[1, 1].get_title().startswith("R1 = 1.00 [0.8") and axes[1, 1].get_title().endswith(" MΩ")
    plt.close(fig)
    assert interval_text(4.8e6, 4.7e6, 4.9e6, "Ω") == "4.80 [4.70, 4.90] MΩ"
    assert interval_text(1.2e3, 13.0, 9.51e4, "Ω", significant=True) == "1.2 [0.013, 95.1] kΩ"
    assert interval_text(0.916, 0.883, 0.948) == "0.916 [0.883, 0.948]"


def test_a_cpe_q_on_a_linear_axis_is_counted_in_a_prefix_of_its_compound_unit():
    """A narrow Q (1.20 ± 0.02 × 1e-8, a linear axis): matplotlib's offset "1e−8" had been glued
    to the label "CPE_sc.Q [F s^(α-1)]"; now the prefix goes into the unit, as for Ω, F, H."""
    from impedax.plotting.bayes import plot_corner

    rng = np.random.default_rng(4)
    q = rng.normal(1.2e-8, 0.02e-8, 5000)
    alpha = rng.normal(0.8, 0.01, 5000)
    fig = plot_corner(np.stack([q, alpha], axis=-1), ["CPE_sc.Q", "CPE_sc.alpha"], [False, False], units=["F s^(alpha-1)", "1"])
    fig.canvas.draw()
    axes = np.array(fig.axes).reshape(2, 2)
    assert axes[1, 0].get_xlabel() == "CPE_sc.Q [nF s^(α-1)]"
    assert axes[1, 0].xaxis.get_offset_text().get_text() == "" and axes[1, 0].xaxis.get_major_formatter().scale == 1e-9
    ticks = [float(t.get_text().replace("\N{MINUS SIGN}", "-")) for t in axes[1, 0].get_xticklabels() if t.get_text()]
    assert ticks and all(11.0 <= t <= 13.0 for t in ticks), ticks  # the values in nF s^(α-1)
    plt.close(fig)


def test_corner_titles_use_every_draw_not_the_scatters_subsample():
    """20,000 draws whose evenly spaced 4,000 (the scatter's) have another median: the title
    gives numpy's quantiles of every draw."""
    from impedax.plotting.bayes import plot_corner

    x = np.concatenate([np.full(10000, 1.0), np.full(10000, 3.0)])
    x[::5] = 2.0  # (the evenly spaced subsample would be mostly 2.0)
    fig = plot_corner(x[:, None], ["a"], [False], max_points=4000)
    fig.canvas.draw()
    q05, q50, q95 = np.quantile(x, [0.05, 0.5, 0.95])  # 1, 2, 3; of the 4,000 shown the median is 2.5
    assert fig.axes[0].get_title() == f"a = {q50:.1f} [{q05:.1f}, {q95:.1f}]"
    assert "20000 draws; 4000 in the scatter" in fig._suptitle.get_text()
    plt.close(fig)


def test_corner_titles_and_ticks_stay_within_the_figure():
    """Five parameters: a long diagonal title goes on two lines and every title ends inside the
    figure (sigma_rel's ran past its right edge); a linear axis has at most 5 ticks, so that
    five-digit labels do not run together."""
    from impedax.plotting.bayes import plot_corner

    rng = np.random.default_rng(0)
    d = np.stack([rng.normal(63.5, 0.3, 5000), rng.normal(48, 1, 5000), rng.normal(0.0093, 3e-4, 5000), rng.normal(0.915, 0.02, 5000), rng.normal(0.0204, 0.0015, 5000)], -1)
    fig = plot_corner(d, ["R0", "R1", "CPE1.Q", "CPE1.alpha", "sigma_rel"], [True, True, True, False, True], units=["Ohm", "Ohm", "F s^(alpha-1)", "1", "1"])
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    diagonal = [ax for ax in fig.axes if ax.get_title()]
    assert len(diagonal) == 5 and diagonal[0].get_title() == "R0 = 63.49 [63.01, 63.99] Ω"
    assert diagonal[-1].get_title().startswith("sigma_rel =\n0.0204 [")
    for ax in diagonal:
        box = ax.title.get_window_extent(renderer)
        assert box.x1 <= fig.bbox.x1 + 0.5 and box.x0 >= -0.5, ax.get_title()
    last = fig.axes[-1]
    assert len([t for t in last.get_xticks() if last.get_xlim()[0] <= t <= last.get_xlim()[1]]) <= 5
    plt.close(fig)


def test_relative_errors_in_the_fit_table_read_as_percentages():
    from impedax.data import format_relative_error

    assert [format_relative_error(x) for x in (0.038, 0.0052, 0.126, 1.26, -2.56, 1.2e10)] == ["3.8 %", "0.52 %", "13 %", "126 %", "256 %", "1.2e+12 %"]


def test_batch_panels_count_their_values_in_an_si_prefix():
    import impedax as ix

    f = np.geomspace(1, 1e5, 30)
    c = 1e-6 * (1 + 0.2 * np.arange(4))  # 1.0–1.6 µF: the panel read 1e-6 apart from its ticks
    z = np.stack([100.0 + 1e3 / (1 + 2j * np.pi * f * 1e3 * ck) for ck in c])
    batch = ix.fit("R0 + R1 || C1", ix.make_spectrum(f, z, dims=("trial",)), fixed={"R1": 1e3})
    fig = batch.plot()
    fig.canvas.draw()
    (panel,) = [ax for ax in fig.axes if ax.get_title().startswith("C1")]
    assert panel.get_title() == "C1 [µF]" and not panel.yaxis.get_offset_text().get_text()
    locs, values = tick_values(panel.yaxis)
    np.testing.assert_allclose(values * 1e-6, locs, atol=1e-12)
    (r0,) = [ax for ax in fig.axes if ax.get_title().startswith("R0")]
    assert r0.get_title() == "R0 [Ω]"
    plt.close(fig)


def test_refinement_nyquist_is_scaled_to_the_data_and_the_last_model_not_a_start_far_off():
    # the demo's start: a pure capacitor, a vertical line far above an arc; it had made the
    # panel steep and shrunk the data into its corner
    arc = rc(50.0, 1e-3, 0.0)
    capacitor = 1 / (2j * np.pi * F * 1e-5)
    steps = [
        SimpleNamespace(fit=fit("C1", capacitor, arc), effect=None, removed=(), change="(start)", model="C1", diagnosis=None),
        SimpleNamespace(fit=fit("R1 || C1", arc * 1.001, arc), effect="parallel_resistance", removed=(), change="+ R1", model="R1 || C1", diagnosis=None),
    ]
    fig = plot_refinement(SimpleNamespace(steps=steps, final_model="R1 || C1", verdict="adequate", masked_points=()))
    nyquist = fig.axes[-1]
    fig.canvas.draw()
    x0, x1 = nyquist.get_xlim()
    y0, y1 = nyquist.get_ylim()
    assert x1 < 1.6 * 50 and -0.1 * 50 < x0 < 5  # the arc spans 0–50 Ω (with 5 % margins): it fills the width
    assert y1 < 0.1 * float(np.max(-capacitor.imag))  # the capacitor's line runs off the top
    assert nyquist.get_subplotspec().colspan == range(0, 2)  # a flat arc: the panel across the figure
    plt.close(fig)


@pytest.mark.parametrize("shared", [None, ["R0"]], ids=["batch", "shared"])
def test_batch_error_bars_stop_at_a_user_bound_the_value_sits_on(shared):
    import impedax as ix

    # R0 is 100 Ω in every spectrum; bounds hold it at or above 150 Ω, where it sits (in a
    # batch of independent fits, and in a global fit that shares R0)
    f = np.geomspace(1, 1e5, 30)
    z = np.stack([100.0 + 1e3 * (1 + 0.1 * k) / (1 + 2j * np.pi * f * 1e-3 * (1 + 0.1 * k)) for k in range(3)])
    rng = np.random.default_rng(2)
    z = z * (1 + 0.01 * (rng.normal(size=z.shape) + 1j * rng.normal(size=z.shape)))
    batch = ix.fit("R0 + R1 || C1", ix.make_spectrum(f, z, dims=("trial",)), bounds={"R0": (150.0, 1e4)}, **({"shared": shared} if shared else {}))
    ds = batch.dataset
    assert float(ds["lower"].sel(param="R0")) == 150.0 and float(ds["upper"].sel(param="R1")) == np.inf
    assert ds["at_bound"].sel(param="R0").values.all(), batch.report()
    fig = batch.plot()
    (panel,) = [ax for ax in fig.axes if ax.get_title().startswith("R0")]
    # no bar reaches below the bound (it was drawn down to 150 Ω − stderr): a value at its
    # bound has none (text and JSON give it no standard error), only the "at bound" marker
    segments = [s for c in panel.collections if hasattr(c, "get_segments") for s in c.get_segments()]
    assert all(np.min(np.asarray(s)[:, 1]) >= 150.0 - 1e-6 for s in segments)
    (marked,) = [line for line in panel.get_lines() if line.get_label() == "at bound (no stderr)"]
    assert np.all(marked.get_ydata() >= 150.0 - 1e-6) and len(marked.get_xdata()) == 3
    plt.close(fig)


def test_review_edge_cases_of_the_prefixes():
    from impedax.data import format_quantity, format_relative_error
    from impedax.plotting import equal_aspect
    from impedax.plotting.bayes import interval_text

    # the prefix of a value as printed, and of an interval by its largest member
    assert format_quantity(999.6, "Ω") == "1 kΩ" and format_quantity(0.9996, "Ω") == "1 Ω"
    assert interval_text(999.0, 984.0, 1017.0, "Ω") == "0.999 [0.984, 1.017] kΩ"
    # a compound unit led by F counts in a prefix, as its axis does (was "×10⁻⁵ F s^(α-1)" beside an axis in µF s^(α-1))
    assert interval_text(1.0e-5, 0.968e-5, 1.034e-5, "F s^(α-1)") == "10.00 [9.68, 10.34] µF s^(α-1)"
    # metres too, since 2026-12-03 (an air gap read "2.8055 [2.8030, 2.8078] ×10⁻⁶ m"); another unit far from 1 keeps its power of ten
    assert interval_text(1.0e-5, 0.968e-5, 1.034e-5, "m") == "10.00 [9.68, 10.34] µm"
    assert interval_text(1.0e-5, 0.968e-5, 1.034e-5, "V") == "1.000 [0.968, 1.034] ×10⁻⁵ V"
    assert format_relative_error(float("nan")) == "—" and format_relative_error(99.996) == "1e+04 %"
    # a label the user wrote with a prefix (values already in kΩ) is left as it is
    fig, ax = plt.subplots()
    ax.plot([0.0, 50.0], [0.0, 20.0], "o")
    ax.set_xlabel("Z' [kΩ]")
    ax.set_ylabel("−Z'' [kΩ]")
    equal_aspect(ax)
    fig.canvas.draw()
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("Z' [kΩ]", "−Z'' [kΩ]")
    locs, values = tick_values(ax.xaxis)
    np.testing.assert_allclose(values, locs)
    plt.close(fig)
    # panels that share an axis are relabelled together (matplotlib gives them one formatter)
    fig, (left, right) = plt.subplots(1, 2, sharey=True)
    from impedax.plotting import plot_nyquist

    plot_nyquist(left, (F, rc(2e3, 1e-6, 0.0)))
    plot_nyquist(right, (F, rc(2e6, 1e-9, 0.0)))
    fig.canvas.draw()
    assert left.get_ylabel() == right.get_ylabel() == "−Z'' [MΩ]"
    plt.close(fig)


def test_a_fit_s_model_is_drawn_as_a_curve_and_its_residuals_are_at_the_data():
    # SYNTHETIC R0 + R1 ∥ C1 at 2 points a decade: the model was drawn as chords through the
    # data's frequencies. Now it is a curve on the arc of the fitted values (centre R0 + R1/2,
    # radius R1/2: the closed form), over the data's band only, and the residual panel still
    # holds the residuals at the data's frequencies, not ones interpolated from the curve
    import impedax as ix

    f = np.geomspace(1.0, 1e5, 11)
    z = 10.0 + 100.0 / (1 + 1j * 2 * np.pi * f * 100.0 * 1e-6)
    rng = np.random.default_rng(3)
    data = ix.make_spectrum(f, z * (1 + 0.003 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size))))
    r = ix.fit("R0 + R1 || C1", data)
    fig = r.plot()
    nyquist, modulus, _, residual_axis = fig.axes[:4]
    (line,) = [ln for ln in nyquist.get_lines() if ln.get_label() == "fit"]
    x, y = line.get_data()
    assert x.size >= 200
    r0, r1 = r.values["R0"], r.values["R1"]
    assert np.allclose(np.hypot(x - (r0 + r1 / 2), y), r1 / 2, rtol=1e-9)
    (bode,) = [ln for ln in modulus.get_lines() if ln.get_label() == "fit"]
    assert bode.get_xdata().min() == pytest.approx(1.0) and bode.get_xdata().max() == pytest.approx(1e5)
    z_fit = r0 + r1 / (1 + 1j * 2 * np.pi * f * r1 * r.values["C1"])
    expected = (z_fit - data["Z"].values) / np.abs(data["Z"].values) * 100
    re_line = [ln for ln in residual_axis.get_lines() if ln.get_label() == "Re"][0]
    assert np.allclose(re_line.get_ydata(), expected.real, atol=1e-9)
    plt.close(fig)
    # the comparison figure draws each model the same way
    fig = ix.compare([r, ix.fit("R0 + R1 || CPE1", data)]).plot()
    drawn = [ln for ln in fig.axes[0].get_lines() if ln.get_label().startswith("R0 + R1 || C1 ")]
    assert len(drawn) == 1 and drawn[0].get_xydata().shape[0] >= 200
    plt.close(fig)


def test_a_batch_figure_draws_each_fit_as_a_curve_on_its_own_arc():
    # SYNTHETIC: two R0 + R1 ∥ C1 spectra of 11 points; each drawn fit lies on the arc of its
    # own fitted values (the closed form) and has the dense grid's points
    import impedax as ix
    import xarray as xr

    f = np.geomspace(1.0, 1e5, 11)
    rng = np.random.default_rng(4)
    stack = []
    for r1 in (100.0, 250.0):
        z = 10.0 + r1 / (1 + 1j * 2 * np.pi * f * r1 * 1e-6)
        stack.append(ix.make_spectrum(f, z * (1 + 0.003 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)))))
    batch = ix.fit("R0 + R1 || C1", xr.concat(stack, dim="trial"))
    fig = batch.plot()
    nyquist = fig.axes[-1]
    curves = [ln for ln in nyquist.get_lines() if ln.get_linestyle() == "-"]
    assert len(curves) == 2
    for i, line in enumerate(curves):
        x, y = line.get_data()
        r0, r1 = (float(batch.values(n).isel(trial=i)) for n in ("R0", "R1"))
        assert x.size >= 200 and np.allclose(np.hypot(x - (r0 + r1 / 2), y), r1 / 2, rtol=1e-9)
    plt.close(fig)


def test_a_lone_prefixed_tick_is_written_as_its_value():
    # one tick on a prefixed axis read "20.0" (one decimal whatever the value); as written now
    from impedax.plotting import prefixed_axis

    fig, ax = plt.subplots()
    ax.plot([0, 1], [19990, 20020])
    ax.set_ylabel("R [Ω]")
    prefixed_axis(ax.yaxis)
    for ticks, expected in (([20000], ["20"]), ([20500], ["20.5"]), ([20000, 20010], ["20.00", "20.01"])):
        ax.set_yticks(ticks)
        assert tick_texts(ax.yaxis) == expected and ax.get_ylabel() == "R [kΩ]"
    # the cursor's readout counts in the ticks' prefix too (it read 20004.6 under [kΩ])
    assert ax.yaxis.get_major_formatter().format_data_short(20004.6) == "20.005"
    assert ax.yaxis.get_major_formatter().format_data_short(20046.0) == "20.046"
    plt.close(fig)


@pytest.mark.slow  # (an end-to-end run of ~10 s: make test-all; the fast suite's 15-minute budget)
def test_diagnose_says_each_stage_as_it_begins():
    """`diagnose(progress=)` is called as each stage begins, in order (the CLI prints the lines
    once a run has taken 2 s): SYNTHETIC R0 + R1 ∥ C1 + a second arc, fitted with one arc."""
    import impedax as ix

    f = np.geomspace(1, 1e5, 40)
    jw = 2j * np.pi * f
    data = ix.make_spectrum(f, 10 + 100 / (1 + jw * 100 * 1e-6) + 300 / (1 + jw * 300 * 1e-3))
    said = []
    d = ix.diagnose(data, "R0 + R1 || C1", progress=said.append)
    # (nothing masked: nothing is marked as masked in the figure)
    assert d.masked_points == () and d.masked_impedance == ()
    assert not [line for ax in d.plot().axes for line in ax.get_lines() if line.get_marker() == "x"]
    assert said[0] == "fitting the baseline R0 + R1 || C1" and said[1] == "the Kramers–Kronig test of the data"
    assert any(re.fullmatch(r"fitting \d+ candidate circuits of \d+ effects", s) for s in said), said



def _points_under_legend(ax) -> int:
    """How many of the points ``ax``'s lines draw (their data through transData) lie inside its
    frame and under its legend: the oracle, apart from `drawn_points`."""
    box, frame = ax.get_legend().get_window_extent(), ax.get_window_extent()
    count = 0
    for line in ax.get_lines():
        if line.get_transform() != ax.transData:  # (axhline and the like)
            continue
        xy = ax.transData.transform(np.column_stack([line.get_xdata(), line.get_ydata()]).astype(float))
        inside = (xy[:, 0] >= frame.x0) & (xy[:, 0] <= frame.x1) & (xy[:, 1] >= frame.y0) & (xy[:, 1] <= frame.y1)
        under = (xy[:, 0] >= box.x0) & (xy[:, 0] <= box.x1) & (xy[:, 1] >= box.y0) & (xy[:, 1] <= box.y1)
        count += int(np.sum(inside & under))
    return count


def test_a_legend_that_would_cover_data_is_moved_out_of_the_panel():
    """A panel filled with points (a 15 × 15 grid: every spot "best" tries covers some) has its
    legend moved out of the frame, over none of them; a legend with room inside stays there."""
    from impedax.plotting import legends_off_data

    fig, (full, room) = plt.subplots(1, 2, figsize=(8, 3.5), layout="constrained")
    gx, gy = np.meshgrid(np.linspace(0, 1, 15), np.linspace(0, 1, 15))
    full.plot(gx.ravel(), gy.ravel(), "o", ms=3, label="data everywhere")
    full.legend()
    room.plot([0.0, 0.1, 0.2], [0.0, 0.1, 0.05], "o", label="data in a corner")
    room.set_xlim(0, 1)
    room.set_ylim(0, 1)
    room.legend(loc="upper right")
    fig.draw_without_rendering()
    assert _points_under_legend(full) > 0  # (the oracle sees the overlap before)
    legends_off_data(fig)
    fig.draw_without_rendering()
    assert _points_under_legend(full) == 0 and _points_under_legend(room) == 0
    box, frame = full.get_legend().get_window_extent(), full.get_window_extent()
    assert box.y0 >= frame.y1 - 1  # above the frame (the panel has no title)
    kept, frame = room.get_legend().get_window_extent(), room.get_window_extent()
    assert frame.contains(*kept.p0) and frame.contains(*kept.p1)  # (room inside: left where it was)
    plt.close(fig)


def test_refinement_and_diagnosis_figures_put_no_legend_over_their_data():
    """Every legend of the refine and diagnose figures (stand-ins: a two-arc spectrum whose
    Nyquist panel the legend of long model names would cover) lies over none of the points
    its panel draws (read back from the figure after layout)."""
    for fig in (plot_refinement(refinement_stand_in()), plot_diagnosis(diagnosis_stand_in())):
        fig.draw_without_rendering()
        for ax in fig.axes:
            if ax.get_legend() is not None:
                assert _points_under_legend(ax) == 0, [t.get_text() for t in ax.get_legend().get_texts()]
        plt.close(fig)


def test_corner_title_and_axis_of_a_small_q_use_one_prefix():
    """A CPE's Q of 8.6e-5 F s^(α-1) (SYNTHETIC draws, normal, sd 4 %): the diagonal title read
    ×10⁻⁵ while its axis counted in µ; now both count in the prefix of the axis. And where the
    draws' tail reaches past 1e-3 though q95 stays below it, the title follows the axis (m)."""
    from impedax.plotting.bayes import plot_corner

    rng = np.random.default_rng(7)
    for center, sd, prefix, scale in ((8.6e-5, 0.04 * 8.6e-5, "µ", 1e-6), (0.9e-3, 0.04e-3, "m", 1e-3)):
        q = rng.normal(center, sd, 20000)
        alpha = rng.normal(0.8, 0.01, 20000)
        fig = plot_corner(np.stack([q, alpha], axis=-1), ["CPE1.Q", "CPE1.alpha"], [True, False], units=["F s^(alpha-1)", "1"])
        fig.canvas.draw()
        axes = np.array(fig.axes).reshape(2, 2)
        assert axes[1, 0].get_xlabel() == f"CPE1.Q [{prefix}F s^(α-1)]" and axes[1, 0].xaxis.get_major_formatter().scale == scale
        title = axes[0, 0].get_title().replace("\n", " ")
        assert title.endswith(f" {prefix}F s^(α-1)") and "×10" not in title, title
        median = float(title.removeprefix("CPE1.Q = ").split(" ")[0])
        low, high = map(float, title.split("[")[1].split("]")[0].split(", "))
        np.testing.assert_allclose([median, low, high], np.quantile(q, [0.5, 0.05, 0.95]) / scale, rtol=2e-3)
        plt.close(fig)


def test_a_step_title_keeps_rms_rel_and_its_value_on_one_line():
    """A residual panel's title wraps to its width but never inside "(rms_rel 1.72 %)" (REAL
    VersaStudio's step 2 read "(rms_rel" / "1.72 %)"): the change text is lengthened word by
    word, so the wrap falls at every place near the end once."""
    refinement = refinement_stand_in()
    for extra in range(0, 60, 3):
        refinement.steps[1].change = "+ R2 || C2 [extra_relaxation]" + " word" * (extra // 3) + "x" * (extra % 3)
        fig = plot_refinement(refinement)
        titles = [ax.get_title() for ax in fig.axes[1:] if "rms_rel" in ax.get_title()]
        plt.close(fig)
        lines = [line for t in titles for line in t.split("\n") if "rms_rel" in line]
        assert lines and all(line.rstrip().endswith("%)") for line in lines), lines
