"""The main job (`make demo`, `impedax demo`): the whole impedax story on the embedded SYNTHETIC
data in the style of Sirin et al. — from three impedance measurements of a finger on a
touchscreen to the air-gap thickness and the electrostatic force, by way of a model that fails,
a diagnosis that names the missing physics, and a refit whose error falls.

Everything is written to a staging folder first and moved into the output folder only when
the run has finished, all files together as every output of impedax is written
(`impedax.io.atomic.OutputTransaction`), so the output folder never holds a half-written result.
"""

from __future__ import annotations

import functools
import html
import os
import shutil
import sys
import time
from pathlib import Path
from typing import Sequence

import numpy as np

from .constants import EPSILON_AIR
from .data import format_frequency, format_percent_column
from .io.atomic import OutputTransaction, check_writable, remove_temporary, temporary_folder

__all__ = ["run_demo"]

AREA = 130e-6  # m², Sirin et al.
V0 = 75.0  # V drive amplitude, Sirin et al.
#: The files the demo writes into its output folder; each is checked before the run as any
#: output is (`impedax.io.atomic.check_writable`: a read-only file is refused, a link is
#: written through), so a run is not lost at its end.
OUTPUT_NAMES = (
    "total_sliding.nc", "skin.nc", "touchscreen.nc", "remaining_impedance.nc", "step2_naive_fit.png", "step3_refinement.png", "refined_circuit.png",
    "step4_gap_and_force.png", "force_bands.nc", "step5_force.png", "report.html",
)


def timings_line(steps: Sequence[tuple[str, float]]) -> str:
    """The demo's closing line from (step name, seconds) pairs: ``Timings: 1. Load the
    measurements: 3.2 s, 2. …`` (a bare step number did not say which step took the time)."""
    return "Timings: " + ", ".join(f"{name}: {seconds:.1f} s" for name, seconds in steps)


class _Story:
    """Prints the narrative with step headers and timings; collects the report (each step's
    text under its title, the header printed on the terminal only). ``timings``: (title,
    seconds) per step, the report's table; ``short_timings``: (short name, seconds), the closing
    line's (`timings_line`)."""

    def __init__(self, stream):
        self.stream = stream
        self.timings: list[tuple[str, float]] = []
        self.short_timings: list[tuple[str, float]] = []
        self.sections: list[tuple[str, list[str], list[str]]] = []
        self._t = None
        self._title = None
        self._short = None

    def step(self, number: int, title: str, *, short: str | None = None):
        """Start step ``number``, headed ``title``; ``short`` names it in the closing timings line
        (default the title itself; the demo's headings run past 100 characters, too long for six
        on one line)."""
        self._close()
        self._title = f"{number}. {title}"
        self._short = f"{number}. {short if short is not None else title}"
        self._t = time.perf_counter()
        self.sections.append((self._title, [], []))
        self.say(f"\n[{number}/6] {title}", report=False)  # (the report's <h2> is the heading: not again in its text)

    def say(self, text: str = "", *, report: bool = True):
        print(text, file=self.stream, flush=True)
        if report and self.sections and text:
            self.sections[-1][1].append(text.strip())

    def figure(self, name: str):
        self.sections[-1][2].append(name)

    def _close(self):
        if self._t is not None:
            dt = time.perf_counter() - self._t
            self.timings.append((self._title, dt))
            self.short_timings.append((self._short, dt))
            print(f"      ({dt:.1f} s)", file=self.stream, flush=True)
            self._t = None

    def finish(self):
        self._close()


SYNTHETIC_FOOTER = "data: SYNTHETIC (impedax's embedded set, made in the style of Sirin et al., not measured)"
"""The line under a demo figure that does not yet say its data are synthetic (`synthetic_footer`)."""


def synthetic_footer(fig) -> None:
    """Put `SYNTHETIC_FOOTER` under ``fig`` (small, grey, as a caption: the figure's own heading,
    an alarm's red included, keeps its words and style) unless a text of it already says
    "SYNTHETIC". A demo figure copied into a talk or a paper keeps saying that its data were
    made, not measured."""
    from .plotting import font_size

    texts = [text.get_text() for text in fig.texts] + [ax.get_title(loc) for ax in fig.axes for loc in ("left", "center", "right")]
    if not any("SYNTHETIC" in text for text in texts):
        fig.supxlabel(SYNTHETIC_FOOTER, fontsize=font_size("legend", 8), color="0.35")


def _save(fig, folder: Path, name: str) -> str:
    import matplotlib.pyplot as plt

    synthetic_footer(fig)
    fig.savefig(folder / name, dpi=110)
    plt.close(fig)
    return name


def _write_report(folder: Path, story: _Story, facts: dict) -> None:
    parts = [
        "<!doctype html><html><head><meta charset='utf-8'><title>impedax demo report</title>",
        "<style>body{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;line-height:1.45}"
        "img{max-width:100%;border:1px solid #ddd;margin:.5em 0}pre{background:#f6f6f6;padding:.6em;overflow:auto}"
        "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:.2em .6em;text-align:right}</style></head><body>",
        "<h1>impedax: a finger on a touchscreen, from impedance to air gap and force</h1>",
        "<p><b>Data: SYNTHETIC</b> measurements in the style of Sirin et al. (impedax.models.synthetic, fixed seed): "
        "30 trials each of the total impedance of a finger sliding on a touchscreen, of the skin and of the touchscreen, "
        "1 Hz–1 MHz. The contact varies from trial to trial: u is log-normal about 2.79 µm (C_gap = 413 pF for A = 130 mm²) with a 7 % spread.</p>",
        "<h2>Key numbers</h2><table>",
    ]
    for key, value in facts.items():
        parts.append(f"<tr><th style='text-align:left'>{html.escape(key)}</th><td>{html.escape(value)}</td></tr>")
    parts.append("</table>")
    for title, lines, figures in story.sections:
        if not lines and not figures:  # (the "Report" step itself: nothing to show but its timing)
            continue
        parts.append(f"<h2>{html.escape(title)}</h2><pre>{html.escape(chr(10).join(lines))}</pre>")
        for name in figures:
            parts.append(f"<img src='{html.escape(name)}' alt='{html.escape(name)}'>")
    parts.append("<h2>Timings</h2><table>")
    for title, dt in story.timings:
        parts.append(f"<tr><th style='text-align:left'>{html.escape(title)}</th><td>{dt:.1f} s</td></tr>")
    parts.append("</table></body></html>")
    (folder / "report.html").write_text("\n".join(parts), encoding="utf-8")


def _publish(staging: Path, out: Path) -> None:
    """Move every file of ``staging`` into ``out`` under its name, all together or none
    (`impedax.io.atomic.OutputTransaction`), as every output of impedax is written: through a
    symbolic link (the link stays a link), with the permission bits of the file it replaces,
    a read-only file refused (`DataError`) with nothing replaced."""
    with OutputTransaction() as outputs:
        for item in sorted(staging.iterdir()):
            outputs.write(out / item.name, functools.partial(shutil.copyfile, item))


def _band_text(band, prefix: str, i: int, scale: float, digits: int = 3) -> str:
    """``287 [275, 301]``: the median of ``band``'s ``{prefix}median`` at index ``i`` and its 90 %
    interval (``q05``, ``q95``), times ``scale``, to ``digits`` significant digits."""
    median, q05, q95 = (band[f"{prefix}{k}"][i].item() * scale for k in ("median", "q05", "q95"))
    return f"{median:8.{digits}g} [{q05:.{digits}g}, {q95:.{digits}g}]"


def run_demo(out: str | os.PathLike = "out", *, fast: bool = False, stream=None, quiet: bool = False) -> Path:
    """Run the demonstration; returns the path of ``report.html``. ``fast`` uses short MCMC
    chains (for tests and CI); ``quiet`` (``impedax demo --quiet``) leaves out the sampler's
    progress lines."""
    import impedax as ix
    from impedax.models import example_spectra, remaining_impedance
    from impedax.models.gap import force_maximum_text, gap_analysis
    from impedax.plotting import plot_spectrum
    from impedax.plotting.models import plot_force_bands

    stream = stream or sys.stdout
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    for name in OUTPUT_NAMES:  # before the run, not after it
        check_writable(out / name, probe=False)  # (making the staging folder below is the probe)
    staging = temporary_folder(out, prefix=".demo-")  # removed on an interrupt too (impedax.cli.main)
    story = _Story(stream)
    t_start = time.perf_counter()
    facts: dict[str, str] = {}
    try:
        story.say("impedax demo — what impedance spectra tell about a finger on a touchscreen", report=False)
        story.say("Data: SYNTHETIC measurements in the style of Sirin et al., embedded in impedax (not measured).", report=False)

        story.step(1, "Load the measurements and isolate the air gap", short="Load the measurements")
        spectra = example_spectra()
        total, skin, screen = spectra["total_sliding"], spectra["skin"], spectra["touchscreen"]
        n_trials = int(np.prod([total.sizes[d] for d in total["Z"].dims if d != "frequency"]))
        f = total["frequency"].values
        story.say(f"  {n_trials} trials each of the finger sliding on the screen (total), the skin alone and the screen alone, {format_frequency(f.min())} – {format_frequency(f.max())}.")
        story.say("  Electroadhesion: a voltage on the screen pulls the finger through the thin air gap between skin and glass.")
        story.say("  The gap acts as a capacitor; its thickness u sets the force. Subtracting skin and screen from the total")
        story.say("  leaves the impedance of the gap region: Z_R = Z_total − Z_skin − Z_TS (mean of the trials ± standard error).")
        remaining = remaining_impedance(total, skin, screen)
        for name, spectrum in (("total_sliding", total), ("skin", skin), ("touchscreen", screen)):
            ix.save(spectrum, staging / f"{name}.nc")
        ix.save(remaining, staging / "remaining_impedance.nc")
        story.say("  The remaining impedance goes to remaining_impedance.nc, and the three measurements to total_sliding.nc, skin.nc and")
        story.say("  touchscreen.nc (written with the other outputs at the end): impedax gap total_sliding.nc skin.nc touchscreen.nc --area 130e-6")
        story.say("  runs the gap and force analysis of steps 4–5 on them from the command line.")

        story.step(2, "Fit the naive model: the air gap as a pure capacitor", short="Fit the naive model")
        naive = ix.fit("C_gap", remaining, weighting="sigma")
        first = ix.diagnose(naive, data=remaining)
        story.say(f"  Model C_gap: rms_rel = {naive.rms_rel * 100:.3g} % (relative misfit), C_gap = {naive.values['C_gap'] * 1e12:.0f} pF.")
        for band in first.failing_bands:
            story.say(f"  Fails {format_frequency(band.f_min)} – {format_frequency(band.f_max)}: {band.pattern}")
        fig = plot_spectrum((naive.frequency, naive.z_data), (naive.frequency, naive.z_model), title=f"naive model C_gap: rms_rel = {naive.rms_rel * 100:.3g} % (failing bands shaded)", bands=[(b.f_min, b.f_max) for b in first.failing_bands], model_label="C_gap fit")
        story.figure(_save(fig, staging, "step2_naive_fit.png"))
        facts["naive model rms_rel"] = f"{naive.rms_rel * 100:.3g} %"

        story.step(3, "Diagnose: which physical effect is missing? Add it, refit, watch the error fall", short="Diagnose and refine")
        kk = first.kk
        story.say(f"  Kramers–Kronig test of the data: {'valid' if kk.valid else 'NOT valid'} (rms_rel {kk.rms_rel * 100:.3g} %) — " + ("the misfit is the model's, not the data's." if kk.valid else "parts of the data are not causal/stationary."))
        story.say(f"  Verdict on C_gap: {first.verdict}.")
        shown = first.suggestions[:3]
        for s, percent in zip(shown, format_percent_column([s.rms_rel for s in shown])):  # (3 significant digits, the decimal points lined up)
            story.say(f"    {s.effect:<24} ΔAIC {s.delta_aic:8.1f}   rms_rel {percent:>6} %   {s.model}")
        if first.best is not None:
            story.say(f"  Best: {first.best.explanation}")
        refinement = ix.refine(remaining, "C_gap", weighting="sigma", max_effects=3)
        story.say("  Refinement (diagnose → add the best effect → refit):")
        for line in refinement.table().splitlines():
            story.say("    " + line)
        story.say(f"  Final model: {refinement.final_model}   verdict: {refinement.verdict}")
        story.figure(_save(refinement.plot(), staging, "step3_refinement.png"))
        try:
            ix.save_circuit_diagram(refinement.final.circuit, staging / "refined_circuit.png", values=refinement.final.values)
            story.figure("refined_circuit.png")
            story.say("  Circuit diagram of the refined model with its fitted values: refined_circuit.png")
        except ix.ImpedaxError as exc:  # schemdraw is an optional extra (impedax[draw])
            story.say(f"  (no circuit diagram: {exc})")
        final = refinement.final
        facts["refined model"] = refinement.final_model
        facts["refined rms_rel"] = f"{final.rms_rel * 100:.3g} %"

        story.step(4, "Hierarchical Bayesian fit of the refined model: the gap thickness, its spread between trials, a new trial", short="Hierarchical Bayesian fit")
        if "C_gap" not in final.circuit.element_names:
            raise RuntimeError(f"the refined model {final.model} lost C_gap")
        # (600 draws per chain: at 400 the chains' R-hat reached 1.052 on one 2-core machine, over the 1.05 of
        # SAMPLING_RHAT_MAX, and the main job opened step 4 with SAMPLING UNRELIABLE; 600 gave 'no alarm' there)
        gap = gap_analysis(total, skin, screen, area=AREA, v0=V0, remainder=final.circuit, edl_fit=final, steps=150 if fast else 600, warmup=150 if fast else 400, progress=not quiet)
        g, p, spread, new = gap.gap, gap.paper, gap.gap_spread, gap.gap_new_trial
        post = gap.hierarchical
        for alarm in gap.alarms:  # (the report's and the figure's opening verdicts: the numbers below may be wrong)
            story.say(f"  {alarm}")
        if not gap.alarms:
            story.say("  no alarm: the sampling passed its checks (divergences, R-hat) and the model fits")
        story.say(f"  Every one of the {n_trials} total trials gets its own u, R_EP and CPE_EP.Q, drawn from a log-normal population;")
        story.say("  the noise per frequency comes from the trial scatter, plus a sampled discrepancy floor for misfit the model lacks.")
        story.say(f"  u = {g['value'] * 1e6:.3f} µm, 90 % credible interval {g['q05'] * 1e6:.3f}–{g['q95'] * 1e6:.3f} µm (population median; NUTS, {post.mu.shape[0]} chains × {post.mu.shape[1]} draws)")
        c = gap.c_gap  # (the draws' C_gap = ε0 ε_gap A/u, so its median is that of u's median)
        story.say(f"  C_gap = {c['value'] * 1e12:.1f} pF, 90 % credible interval {c['q05'] * 1e12:.1f}–{c['q95'] * 1e12:.1f} pF (u = ε0 ε_gap A/C_gap, ε_gap = {EPSILON_AIR:g}, A = {AREA * 1e6:g} mm²)")
        story.say(f"  spread between trials: {spread['relative']['value'] * 100:.1f} % (sd of ln u, 90 %: {spread['relative']['q05'] * 100:.1f}–{spread['relative']['q95'] * 100:.1f} %), ≈ {spread['sd_m'] * 1e6:.3f} µm")
        story.say(f"  a new trial: u in {new['q05'] * 1e6:.3f}–{new['q95'] * 1e6:.3f} µm (90 % predictive interval)")
        delta = post.summary()["discrepancy"]
        story.say(f"  discrepancy floor δ = {delta['value'] * 100:.2f} % (90 %: {delta['q05'] * 100:.2f}–{delta['q95'] * 100:.2f} %) on top of the trial-scatter noise (median {np.median(post.nu) * 100:.2f} %)")
        story.say(f"  paper's method: u = {p.gap * 1e6:.3f} µm, bounds {p.gap_lower * 1e6:.3f}–{p.gap_upper * 1e6:.3f} µm from the lowest/highest impedances")
        story.say(f"  naive C_gap-only fit would say u = {ix.models.gap_thickness(naive.values['C_gap']) * 1e6:.3f} µm (the missing effect biases it)")
        true_gap = ix.models.gap_thickness(413e-12, area=AREA)  # the generator's population median
        story.say(f"  (the synthetic data were made with a population median u = {true_gap * 1e6:.3f} µm, trials varying by 7 %; `impedax gap --pooled` gives the analysis of the trial means)")
        story.figure(_save(gap.plot(true_gap=true_gap), staging, "step4_gap_and_force.png"))
        if gap.alarms:
            facts["ALARM (step 4's numbers may be wrong)"] = "; ".join(gap.alarms)
        facts["gap thickness (hierarchical Bayesian, population median)"] = f"{g['value'] * 1e6:.3f} µm [{g['q05'] * 1e6:.3f}, {g['q95'] * 1e6:.3f}] (90 %)"
        facts["air-gap capacitance C_gap (hierarchical Bayesian, population median)"] = f"{c['value'] * 1e12:.1f} pF [{c['q05'] * 1e12:.1f}, {c['q95'] * 1e12:.1f}] (90 %)"
        facts["spread of u between trials"] = f"{spread['relative']['value'] * 100:.1f} % (≈ {spread['sd_m'] * 1e6:.3f} µm); a new trial: [{new['q05'] * 1e6:.3f}, {new['q95'] * 1e6:.3f}] µm (90 %)"
        facts["gap thickness (paper method)"] = f"{p.gap * 1e6:.3f} µm, bounds [{p.gap_lower * 1e6:.3f}, {p.gap_upper * 1e6:.3f}]"
        facts["naive-model gap thickness"] = f"{ix.models.gap_thickness(naive.values['C_gap']) * 1e6:.3f} µm"

        story.step(5, "Gap voltage and electrostatic force over frequency, with and without electrode polarization", short="Gap voltage and force")
        force = gap.force
        ff = force["frequency"].values
        with_ep, without = force.sel(branch="with_ep"), force.sel(branch="without_ep")
        for target in (1.0, 10.0, 250.0, 1e5):
            i = int(np.argmin(np.abs(np.log(ff / target))))
            story.say(
                f"  {format_frequency(ff[i]):>9}: force {_band_text(with_ep, '', i, 1e3)} mN with EP   vs {_band_text(without, '', i, 1e3)} mN without EP;"
                f"   gap voltage {_band_text(with_ep, 'gap_voltage_', i, 1.0, 4)} V vs {_band_text(without, 'gap_voltage_', i, 1.0, 4)} V"  # (4 digits: its interval is ±0.3 %)
            )
        story.say(f"  Peak force (Sirin eq 1, peak convention, V0 = {V0:g} V) and the amplitude |ΔV_gap| of the gap voltage, medians with their 90 % intervals.")
        story.say("  Below ~30 Hz the EP branch leaks the charge: the gap voltage and the force drop.")
        ix.io.write_netcdf(gap.to_xarray(), staging / "force_bands.nc")
        fig = plot_force_bands(gap)
        story.figure(_save(fig, staging, "step5_force.png"))
        # (as `impedax gap`'s report words it, its plateau included)
        facts["peak force with EP"] = f"{force_maximum_text(with_ep['median'])} (V0 = {V0:g} V, peak convention)"

        story.step(6, "Report")
        story.finish()
        facts["total run time"] = f"{time.perf_counter() - t_start:.0f} s"
        _write_report(staging, story, facts)
        _publish(staging, out)
    finally:
        story.finish()
        remove_temporary(staging)
    print("\n" + timings_line(story.short_timings), file=stream)
    report = out / "report.html"
    print(f"Report: {report.resolve()}", file=stream)
    return report
