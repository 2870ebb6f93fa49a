"""Meyer (2012 thesis) Fig 5.1a: inferred electrostatic force versus drive voltage (square law).

Reproduces: thesis Fig 5.1a — log-log plot of the electrostatic normal force inferred from
friction against the actuation voltage (10 kHz square wave, 60–140 V) for seven subjects, each
with its fitted exponent (thesis: mean exponent 1.92; dashed line: exponent 2).
Data: SYNTHETIC. Seven subjects (seed 1912), each with its own friction coefficient µ
(0.35–0.75) and force scale (30–250 mN at 140 V, log-uniform), with a true force ∝ V².
For each subject the friction experiment of thesis §4.3–4.4 is simulated with numpy: at five
normal forces (0.2–1.0 N) × four swipes, friction is measured with the voltage off
(µ F_n + noise) and on (µ (F_n + F_e) + noise), noise sd 6 mN. impedax then does the thesis
analysis: µ from the no-voltage friction line (`friction_coefficient`, Fig 4.8), the
electrostatic force F_e = ΔF/µ (eq 4.1, `force_from_friction`) with its standard error, and a
least-squares line of log F_e on log V gives each subject's exponent.
What to look for: straight lines on log-log axes, exponents scattered around 2 (measurement
noise only, so the scatter is smaller than the thesis's), the spread of force levels between
subjects (the thesis saw an order of magnitude), and the mean exponent printed.

Run: python examples/meyer_square_law.py [OUT_DIR] [--fast]
"""

from __future__ import annotations

import numpy as np

import _example
from impedax.models import meyer

SEED = 1912
SUBJECTS = 7
VOLTAGES = np.array([60.0, 80.0, 100.0, 120.0, 140.0])  # V, 10 kHz square wave
NORMAL_FORCES = np.array([0.2, 0.4, 0.6, 0.8, 1.0])  # N
SWIPES = 4
FRICTION_NOISE = 6e-3  # N, sd of one half-swipe friction reading


def simulate_subject(rng):
    """One synthetic subject: µ, force at 140 V, and friction readings off/on per voltage."""
    mu = rng.uniform(0.35, 0.75)
    force_140 = np.exp(rng.uniform(np.log(0.03), np.log(0.25)))
    true_force = force_140 * (VOLTAGES / 140.0) ** 2
    normal = np.repeat(NORMAL_FORCES, SWIPES)
    off = mu * normal[None, :] + rng.normal(0.0, FRICTION_NOISE, (VOLTAGES.size, normal.size))
    on = mu * (normal[None, :] + true_force[:, None]) + rng.normal(0.0, FRICTION_NOISE, (VOLTAGES.size, normal.size))
    return {"mu": mu, "true_force": true_force, "normal": normal, "off": off, "on": on}


def infer_forces(subject):
    """Thesis §4.4: µ from all no-voltage readings, then F_e = ΔF/µ per voltage with its SE."""
    line = meyer.friction_coefficient(np.tile(subject["normal"], VOLTAGES.size), subject["off"].ravel())
    delta = subject["on"] - subject["off"]  # same normal force, voltage on minus off
    delta_mean = delta.mean(axis=1)
    delta_se = delta.std(axis=1, ddof=1) / np.sqrt(delta.shape[1])
    force = meyer.force_from_friction(delta_mean, line)
    force_se = np.abs(force) * np.hypot(delta_se / np.abs(delta_mean), line.mu_stderr / line.mu)
    return line, force, force_se


def power_law(voltage, force):
    """Exponent and prefactor of force = a·V^n by least squares in log-log."""
    n, log_a = np.polyfit(np.log(voltage), np.log(force), 1)
    return float(n), float(np.exp(log_a))


def main(argv=None):
    args = _example.parse_args(__doc__, argv)
    import matplotlib.pyplot as plt

    rng = np.random.default_rng(SEED)
    fig, ax = plt.subplots(figsize=(7.5, 6), layout="constrained")
    exponents = []
    print(f"Meyer Fig 5.1a — SYNTHETIC subjects (seed {SEED}), 10 kHz square wave, force inferred from friction")
    print("  subject   mu (fit)   F_e at 140 V   exponent")
    for k in range(SUBJECTS):
        subject = simulate_subject(rng)
        line, force, force_se = infer_forces(subject)
        n, a = power_law(VOLTAGES, force)
        exponents.append(n)
        print(f"  {k + 1:>7}   {line.mu:.3f}      {force[-1] * 1e3:7.1f} mN     {n:.2f}")
        color = f"C{k}"
        ax.errorbar(VOLTAGES, force, yerr=force_se, fmt="o", color=color, ms=5, capsize=2, label=f"subject {k + 1}: n = {n:.2f}")
        v_line = np.linspace(VOLTAGES[0], VOLTAGES[-1], 50)
        ax.plot(v_line, a * v_line**n, "-", color=color, lw=1)
    mean_exponent = float(np.mean(exponents))
    print(f"mean exponent {mean_exponent:.2f} (sd {np.std(exponents, ddof=1):.2f}; thesis: mean 1.92, square law = 2)")

    v_ref = np.array([55.0, 150.0])
    ax.plot(v_ref, 0.2 * (v_ref / 140.0) ** 2, "k--", lw=1.5, label="F ∝ V² (exponent 2)")
    ax.set(xscale="log", yscale="log", xlabel="actuation voltage V_A [V]", ylabel="inferred electrostatic force F_e [N]")
    ax.set_title(f"Meyer (2012) Fig 5.1a — force vs voltage, SYNTHETIC subjects\nmean fitted exponent {mean_exponent:.2f}", fontsize=11)
    ax.set_xticks([60, 80, 100, 120, 140], labels=["60", "80", "100", "120", "140"])
    ax.minorticks_off()
    ax.legend(fontsize=8, loc="upper left", ncols=2)
    _example.decade_grid(ax)
    _example.save(fig, args, "meyer_fig5_1a_square_law.png")


if __name__ == "__main__":
    main()
