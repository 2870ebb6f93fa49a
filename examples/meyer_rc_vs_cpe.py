"""Meyer (2012 thesis) Fig 5.3 and the force over Fig 5.1b's band: RC versus fractional (CPE) stratum corneum.

Reproduces: thesis Fig 5.3 (finger impedance |Z| and phase, subject data against the RC model),
with the model comparison the thesis could only suggest, and the force the two fitted models
PREDICT over frequency. (Thesis Fig 5.1b is measured data: the electrostatic force inferred from
friction for seven subjects at 100 Hz–10 kHz, against the RC model's prediction. No measured
force is reproduced here; the second figure shows model predictions only.)
Data: SYNTHETIC. One "measured" finger spectrum in the Fig 5.2 set-up (finger on a copper
plate: R_f + stratum corneum), 10 Hz–100 kHz, drawn with numpy from a fractional stratum
corneum R_f + R_sc ∥ CPE_sc with the thesis values (R_f = 500 Ω, R_sc = 130 kΩ, α = 0.8,
Q such that the CPE equals C_sc = 2.2 nF at 1 kHz), plus 2 % complex Gaussian noise (seed 53).
Both models are fitted with impedax.fit (sigma weighting) and compared with impedax.compare.
The force curves combine each fitted finger with the screen's C_i = 1.7 nF and C_s = 140 pF
(thesis eq 3.13; fixed, because from impedance alone only the series combination of C_s and
C_i is determined — the script shows impedax's warning when both are left free).
What to look for: the RC model misses the shallow |Z| slope and the flat phase (systematic
residuals, much higher AIC/BIC); the fractional model fits to the noise level and predicts a
force that rises gently over 100 Hz–10 kHz (the band of Fig 5.1b) instead of the RC model's
sharp knee. The "generating finger" curve uses the same force formula as the fits, so it checks
the fits, not the formula; the independent check is the charge bound |Q_i|²/(4ε0A) (Q_i the
charge on C_i, from the circuit current written out with numpy), which the generating finger's
force may not exceed. The bound belongs to one circuit: the fitted RC finger is another circuit,
with its own, higher bound (drawn too), so its force may rise above the generating finger's bound
(at 10 kHz 157.5 mN against that bound's 156.7 mN; ≈ 12 % above it near 0.16 MHz) while staying
under its own.

Run: python examples/meyer_rc_vs_cpe.py [OUT_DIR] [--fast]
"""

from __future__ import annotations

import numpy as np

import _example
import impedax
from impedax.data import format_frequency, format_percent, format_quantity
from impedax.models import meyer
from impedax.plotting import frequency_axis, labelled_log_ticks, legends_off_data, magnitude_axis

TRUE_FINGER = {"R_f": 500.0, "R_sc": 130e3, "CPE_sc.alpha": 0.8, "CPE_sc.Q": 2.2e-9 * (2 * np.pi * 1e3) ** 0.2}
"""Synthetic finger: thesis R_f, R_sc; CPE equal to C_sc = 2.2 nF at 1 kHz, α = 0.8."""
SCREEN = {"C_i": meyer.THESIS_PARAMS["C_i"], "C_s": meyer.THESIS_PARAMS["C_s"]}
NOISE_REL = 0.02
EPSILON_0 = 8.8541878128e-12  # F/m
SEED = 53
MODELS = {"rc": "R_f + R_sc || C_sc", "cpe": "R_f + R_sc || CPE_sc"}


def finger_impedance(freq, p):
    """Z = R_f + R_sc/(1 + R_sc Q (jω)^α) [Ω] — written with numpy, independent of impedax."""
    jw = 1j * 2.0 * np.pi * freq
    return p["R_f"] + p["R_sc"] / (1.0 + p["R_sc"] * p["CPE_sc.Q"] * jw ** p["CPE_sc.alpha"])


def synthetic_finger(freq, rng):
    z = finger_impedance(freq, TRUE_FINGER)
    noise = (rng.normal(size=freq.size) + 1j * rng.normal(size=freq.size)) / np.sqrt(2.0)
    return impedax.make_spectrum(freq, z * (1.0 + NOISE_REL * noise), sigma=NOISE_REL * np.abs(z) / np.sqrt(2.0), attrs={"synthetic": "yes"}, source="synthetic finger (Meyer Fig 5.3 style)")


def with_evidence(fits, data, fast):
    """EVIDENCE COLUMN. When impedax.fitting provides Bayesian sampling (`sample`, giving
    posteriors with `log_evidence`), sample each model from its least-squares fit so that
    impedax.compare adds the `log_evidence` and `waic` columns; otherwise return the fits."""
    sample = getattr(impedax.fitting, "sample", None)
    if sample is None:
        return fits
    steps = 300 if fast else 2000
    return [sample(f.circuit, data, init=f, noise="sigma", steps=steps, seed=SEED, progress=False) for f in fits]


def charge_bound(freq, p, area, v_a=meyer.THESIS_DRIVE_V):
    """Time-averaged charge bound |Q_i|²/(4ε0A) [N] with Q_i = I/(jω), I = V_A/Z_total of the whole
    chain C_s + C_i + R_sc ∥ CPE_sc + R_f — numpy, independent of impedax (eq 3.6's high-frequency limit).
    An RC finger (``C_sc`` in ``p``) is the CPE with α = 1 and Q = C_sc."""
    if "C_sc" in p:
        p = {**p, "CPE_sc.Q": p["C_sc"], "CPE_sc.alpha": 1.0}
    jw = 1j * 2.0 * np.pi * freq
    z_total = 1 / (jw * p["C_s"]) + 1 / (jw * p["C_i"]) + finger_impedance(freq, p)
    q_i = v_a / z_total / jw
    return np.abs(q_i) ** 2 / (4.0 * EPSILON_0 * area)


def force_curves(fits, freq):
    """At ``freq`` [Hz], 140 V: each fitted model's time-averaged force ({"rc", "cpe"}), the
    generating finger's, its charge bound and the fitted RC circuit's own charge bound [N]."""
    forces = {key: np.asarray(meyer.force_time_average({**f.values, **SCREEN}, freq, variant=key)) for key, f in zip(MODELS, fits)}
    truth = np.asarray(meyer.force_time_average({**TRUE_FINGER, **SCREEN}, freq, variant="cpe"))
    bound = charge_bound(freq, {**TRUE_FINGER, **SCREEN}, meyer.THESIS_PHYSICAL.area)
    rc_bound = charge_bound(freq, {**fits[0].values, **SCREEN}, meyer.THESIS_PHYSICAL.area)
    return forces, truth, bound, rc_bound


def screen_chain_identifiability(freq, rng):
    """Fit the whole chain C_s + C_i + R_sc || C_sc + R_f with C_s and C_i both free: only their
    series combination reaches Z, and impedax.fit says so."""
    p = {**meyer.THESIS_PARAMS}
    jw = 1j * 2.0 * np.pi * freq
    z = 1 / (jw * p["C_s"]) + 1 / (jw * p["C_i"]) + p["R_sc"] / (1 + jw * p["R_sc"] * p["C_sc"]) + p["R_f"]
    z = z * (1.0 + 0.01 * (rng.normal(size=freq.size) + 1j * rng.normal(size=freq.size)) / np.sqrt(2.0))
    result = impedax.fit(meyer.meyer_circuit("rc"), impedax.make_spectrum(freq, z), n_starts=4)
    return [w for w in result.warnings if "C_s" in w and "C_i" in w]


# the least width of a column of the comparison table [em of its font]: "k" (one digit) was
# squeezed to its digit's width by `auto_set_column_width` (which pads by 10 % of the text)
TABLE_LEAST_COLUMN_EM = 2.5


def least_column_width(table, ax, columns) -> None:
    """Set the cells of ``columns`` of ``table`` (in ``ax``, laid out) to `TABLE_LEAST_COLUMN_EM`
    of its font, in axes fraction."""
    fig = ax.get_figure()
    fig.draw_without_rendering()
    cells = table.get_celld()
    size_pt = next(iter(cells.values())).get_text().get_fontsize()
    width = TABLE_LEAST_COLUMN_EM * size_pt / (ax.get_position().width * fig.get_figwidth() * 72.0)
    for (_, column), cell in cells.items():
        if column in columns:
            cell.set_width(width)


def main(argv=None):
    args = _example.parse_args(__doc__, argv)
    import matplotlib.pyplot as plt

    rng = np.random.default_rng(SEED)
    freq = impedax.log_frequencies(10.0, 1e5, 31 if args.fast else 41)
    data = synthetic_finger(freq, rng)
    n_starts = 4 if args.fast else 16
    fits = [impedax.fit(text, data, weighting="sigma", n_starts=n_starts, seed=SEED) for text in MODELS.values()]
    comparison = impedax.compare(with_evidence(fits, data, args.fast))
    print("Meyer Fig 5.3 — SYNTHETIC finger spectrum (fractional stratum corneum, α = 0.8, 2 % noise)")
    for key, f in zip(MODELS, fits):
        units = {name: spec.unit for name, spec in f.circuit.parameter_specs().items()}
        values = ", ".join(f"{k} = {format_quantity(v, units[k], 4)}" for k, v in f.values.items())
        print(f"  {key:>3}: rms_rel {format_percent(f.rms_rel)}  chi2_red {f.chi2_red:.3g}  {values}")
    print("model comparison (impedax.compare):")
    print("  " + comparison.table().replace("\n", "\n  "))
    print(f"best model: {comparison.best}")
    if not args.fast:
        for warning in screen_chain_identifiability(impedax.log_frequencies(10.0, 1e6, 41), rng):
            print(f"screen chain with C_s and C_i both free — impedax.fit warns: {warning}")

    fine = np.logspace(1.0, 5.0, 300)
    colors = {"rc": "C0", "cpe": "C3"}
    fig, axes = plt.subplots(2, 2, figsize=(12, 8.5), layout="constrained")
    ax_mod, ax_ph, ax_res, ax_tab = axes.flat
    ax_mod.loglog(freq, np.abs(data["Z"].values), "o", mfc="none", color="k", label="synthetic finger data")
    ax_ph.semilogx(freq, np.degrees(np.angle(data["Z"].values)), "o", mfc="none", color="k", label="synthetic finger data")
    for key, f in zip(MODELS, fits):
        z = np.asarray(f.predict(fine))
        label = f"{'RC' if key == 'rc' else 'fractional (CPE)'}: {f.model}"
        ax_mod.loglog(fine, np.abs(z), color=colors[key], label=label)
        ax_ph.semilogx(fine, np.degrees(np.angle(z)), color=colors[key], label=label)
        ax_res.semilogx(freq, np.abs(f.residuals) * 100, ".-", color=colors[key], label=f"{label} (rms_rel {f.rms_rel * 100:.3g} %)")
    ax_res.axhline(NOISE_REL * 100, color="0.4", ls="--", lw=1, label="noise level (2 %)")
    ax_mod.set(xlabel="frequency [Hz]", ylabel="|Z| [Ω]", title="Fig 5.3 (top): finger impedance magnitude")
    magnitude_axis(ax_mod.yaxis)  # (impedax's |Z| rule: plain labels at or beyond both ends of the data, not 10⁴ and 10⁵ alone)
    ax_ph.set(xlabel="frequency [Hz]", ylabel="phase [deg]", title="Fig 5.3 (bottom): finger impedance phase")
    ax_res.set(xlabel="frequency [Hz]", ylabel="|relative residual| [%]", title="fit residuals", yscale="log")
    labelled_log_ticks(ax_res.yaxis)  # (the rule of impedax's comparison figure: 0.2, 0.5, 1, 2, 5, 10, 20, not 10⁻¹, 10⁰, 10¹)
    for ax in (ax_mod, ax_ph, ax_res):
        frequency_axis(ax.xaxis)  # (10, 100, 1000, 10k, 100k, as every impedax figure's frequency axis)
    for ax in (ax_mod, ax_ph):
        ax.legend(fontsize=8)
    ax_res.legend(fontsize=8)
    for ax in (ax_mod, ax_ph, ax_res):
        _example.decade_grid(ax)
    ax_tab.axis("off")
    ax_tab.set_title("impedax.compare (lower AIC/BIC is better)")
    rows = comparison.rows
    # (heading, key in the comparison's rows, format): each column as wide as its widest text
    shown = [("k", "n_params", "d"), ("rms_rel [%]", "rms_rel", ".3g"), ("χ²_red", "chi2_red", ".3g"), ("AIC", "aic", ".1f"), ("BIC", "bic", ".1f"), ("ΔAIC", "delta_aic", ".1f"), ("ln Z (Laplace)", "log_evidence", ".1f"), ("WAIC", "waic", ".1f")]
    shown = [column for column in shown if column[1] in rows[0]]
    cells = [[format(r[key] * (100 if key == "rms_rel" else 1), fmt) for _, key, fmt in shown] for r in rows]
    table = ax_tab.table(cellText=cells, rowLabels=[r["model"] for r in rows], colLabels=[heading for heading, _, _ in shown], loc="center", cellLoc="center")
    table.auto_set_font_size(False)
    table.set_fontsize(8)
    # (each column as wide as its widest text, with 10 % of it as padding; "k", one digit wide,
    # was squeezed to its digit: it gets TABLE_LEAST_COLUMN_EM, set once the layout is final)
    table.auto_set_column_width([c for c in range(-1, len(shown)) if shown[c][0] != "k"] if shown and shown[0][0] == "k" else list(range(-1, len(shown))))
    table.scale(1.0, 1.6)
    fig.suptitle("Meyer (2012) Fig 5.3 — RC vs fractional stratum corneum on a SYNTHETIC finger spectrum")
    legends_off_data(fig)  # (a legend over the points goes above or below its panel)
    least_column_width(table, ax_tab, [c for c, (heading, _, _) in enumerate(shown) if heading == "k"])
    _example.save(fig, args, "meyer_fig5_3_rc_vs_cpe_impedance.png")

    force_freq = np.logspace(1.0, 6.0, 200 if args.fast else 600)
    forces, truth, bound, rc_bound = force_curves(fits, force_freq)
    print("time-averaged force at 140 V (fitted finger + thesis C_i, C_s), model predictions:")
    table_freq = np.array([100.0, 1e3, 1e4, 1e5])  # (evaluated at these frequencies, not at the grid's nearest points)
    at, at_truth, at_bound, at_rc_bound = force_curves(fits, table_freq)
    for i, f_hz in enumerate(table_freq):
        print(f"  {format_frequency(f_hz):>7}   RC {at['rc'][i] * 1e3:7.2f} mN   CPE {at['cpe'][i] * 1e3:7.2f} mN   (generating finger {at_truth[i] * 1e3:7.2f} mN, its charge bound {at_bound[i] * 1e3:7.2f} mN; RC fit's own bound {at_rc_bound[i] * 1e3:7.2f} mN)")
    print(f"max force / charge bound (generating finger, 10 Hz–1 MHz): {np.max(truth / bound):.3f}")
    print(f"max force / charge bound (fitted RC finger, its own circuit, 10 Hz–1 MHz): {np.max(forces['rc'] / rc_bound):.3f}"
          f"  (the RC curve may exceed the generating finger's bound: up to {np.max(forces['rc'] / bound):.3f} of it)")

    fig, ax = plt.subplots(figsize=(8, 5), layout="constrained")
    ax.axvspan(100.0, 1e4, color="0.9", label="Fig 5.1b frequencies (100 Hz–10 kHz)")
    ax.semilogx(force_freq, bound * 1e3, ":", color="0.3", label="charge bound |Q_i|²/(4ε0A) of the generating finger only (numpy)")
    ax.semilogx(force_freq, rc_bound * 1e3, ":", color=colors["rc"], label="charge bound of the fitted RC circuit (its own; numpy)")
    ax.semilogx(force_freq, truth * 1e3, color="k", lw=3, alpha=0.3, label="generating (synthetic) fractional finger, same formula")
    ax.semilogx(force_freq, forces["rc"] * 1e3, color=colors["rc"], label="RC model fitted to the finger")
    ax.semilogx(force_freq, forces["cpe"] * 1e3, "--", color=colors["cpe"], label="fractional (CPE) model fitted to the finger")
    ax.set(xlabel="frequency [Hz]", ylabel="time-averaged force [mN]", title="Predicted force, 140 V sine: RC vs fractional model fitted to a SYNTHETIC finger\n(model predictions only — thesis Fig 5.1b is measured force, not shown)", ylim=(0, 1.08e3 * max(forces["rc"].max(), forces["cpe"].max(), bound.max(), rc_bound.max())))
    frequency_axis(ax.xaxis)
    ax.legend(fontsize=8, loc="lower right")
    _example.decade_grid(ax)
    legends_off_data(fig)
    _example.save(fig, args, "meyer_fig5_1b_force_rc_vs_cpe.png")


if __name__ == "__main__":
    main()
