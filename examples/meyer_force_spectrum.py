"""Meyer (2012 thesis) Fig 3.4: predicted electrostatic force on a fingertip over frequency.

Reproduces: thesis Fig 3.4, "Predicted Force over Frequency" — the time-averaged force of
eq 3.6/A.3 for a 140 V sinusoidal drive, 10 Hz–1 GHz.
Data: none measured. The model is the thesis circuit C_s + C_i + R_sc || C_sc + R_f with the
thesis's rounded parameters (eq 3.13: C_s = 140 pF, C_i = 1.7 nF, R_sc = 130 kΩ,
C_sc = 2.2 nF, R_f = 500 Ω, A = π(4 mm)²); the curve with the unrounded physical values
(ρ_sc = 33 kΩ·m, ε_sc = 1000, d_sc = 200 µm, ε_i = 3.9, d_i = 1 µm) is drawn for comparison.
What to look for: no force at DC (charge leaks through R_sc and cancels the field), a broad
plateau, peak ≈ 164 mN near 37 kHz, half of the peak at ≈ 0.53 kHz and ≈ 2.6 MHz (marked;
computed reference values of docs/physics.md, not printed in the thesis, whose
Fig 3.4 is a curve only),
and the fall at high frequency where R_f starves the capacitors. Also drawn: the finger
voltage |V_F| and the leaked-charge term |Q_f|/C_i whose difference makes the force.

Run: python examples/meyer_force_spectrum.py [OUT_DIR] [--fast]
"""

from __future__ import annotations

import numpy as np

import _example
from impedax.models import force_maximum, meyer
from impedax.plotting import frequency_axis, plain_log_ticks


def half_peak_frequencies(freq, force, peak_force):
    """Frequencies [Hz] below and above the grid's largest force where the force crosses half of
    ``peak_force`` (the refined maximum, `force_maximum`; linear interpolation in log frequency)."""
    i_peak = int(np.argmax(force))
    half = peak_force / 2.0
    log_f = np.log10(freq)
    low = np.interp(half, force[: i_peak + 1], log_f[: i_peak + 1])  # rising side
    high = np.interp(half, force[i_peak:][::-1], log_f[i_peak:][::-1])  # falling side, reversed to rise
    return 10.0**low, 10.0**high


def main(argv=None):
    args = _example.parse_args(__doc__, argv)
    import matplotlib.pyplot as plt

    points = 400 if args.fast else 3001
    freq = np.logspace(1.0, 9.0, points)
    model = meyer.meyer_model("rc")
    physical = meyer.meyer_model("rc", physical=meyer.THESIS_PHYSICAL)
    force = np.asarray(model.force(freq))
    force_physical = np.asarray(physical.force(freq))

    # the peaks refined between grid points (`force_maximum`), so they do not depend on the grid
    peak = force_maximum(lambda f: float(np.asarray(model.force(np.array([f])))[0]), freq, force)
    peak_physical = force_maximum(lambda f: float(np.asarray(physical.force(np.array([f])))[0]), freq, force_physical)
    f_low, f_high = half_peak_frequencies(freq, force, peak.force_n)
    force_10hz = float(np.asarray(model.force(np.array([10.0])))[0])
    print("Meyer Fig 3.4 — time-averaged force, 140 V sine, thesis parameters (eq 3.13, rounded)")
    print(f"  peak force        {peak.force_n * 1e3:.1f} mN at {peak.frequency_hz / 1e3:.1f} kHz   (computed reference, docs/physics.md: ≈ 164 mN near 37 kHz; the thesis's Fig 3.4 is a curve, no values printed)")
    print(f"  half-peak         {f_low / 1e3:.2f} kHz and {f_high / 1e6:.2f} MHz   (computed reference, docs/physics.md: ≈ 0.53 kHz and ≈ 2.6 MHz)")
    print(f"  force at 10 Hz    {force_10hz * 1e3:.3f} mN")
    print(f"  unrounded values  peak {peak_physical.force_n * 1e3:.1f} mN at {peak_physical.frequency_hz / 1e3:.1f} kHz")

    v_f = np.abs(np.asarray(meyer.finger_voltage(model.params, freq))) * meyer.THESIS_DRIVE_V
    q_over_ci = np.abs(np.asarray(meyer.leaked_charge(model.params, freq))) * meyer.THESIS_DRIVE_V / model.params["C_i"]

    fig, (ax, ax_v) = plt.subplots(2, 1, figsize=(8, 7.5), sharex=True, height_ratios=(3, 2), layout="constrained")
    ax.semilogx(freq, force * 1e3, lw=2, label="thesis parameters (rounded, eq 3.13)")
    ax.semilogx(freq, force_physical * 1e3, "--", lw=1.2, label="unrounded physical values")
    ax.plot(peak.frequency_hz, peak.force_n * 1e3, "o", color="C3", label=f"peak {peak.force_n * 1e3:.0f} mN at {peak.frequency_hz / 1e3:.0f} kHz")
    for f_half, text in ((f_low, f"{f_low / 1e3:.2f} kHz"), (f_high, f"{f_high / 1e6:.1f} MHz")):
        ax.axvline(f_half, color="0.5", ls=":", lw=1)
        ax.annotate(f"half peak\n{text}", (f_half, peak.force_n * 1e3 / 2), xytext=(6, -30), textcoords="offset points", fontsize=9)
    ax.axhline(peak.force_n * 1e3 / 2, color="0.5", ls=":", lw=1)
    ax.set(ylabel="time-averaged force [mN]", title="Meyer (2012) Fig 3.4 — predicted force over frequency (140 V sine)")
    ax.set_ylim(bottom=0)
    ax.legend(fontsize=9, loc="lower center")
    _example.decade_grid(ax)

    ax_v.loglog(freq, v_f, label="|V_F| finger voltage")
    ax_v.loglog(freq, q_over_ci, label="|Q_f|/C_i leaked-charge term")
    ax_v.set(xlabel="frequency [Hz]", ylabel="amplitude [V]", title="force ∝ |V_F|² − |Q_f|²/C_i²: the leaked charge cancels V_F at low frequency")
    ax_v.set_ylim(1e-1, 3e2)
    ax_v.legend(fontsize=9)
    plain_log_ticks(ax_v.yaxis)  # (0.1, 1, 10, 100 V beside the frequencies' plain numbers)
    for panel in (ax, ax_v):
        frequency_axis(panel.xaxis)  # (10, 100, 1000, 10k … 1G, as every impedax figure's frequency axis)
    _example.decade_grid(ax_v)
    _example.save(fig, args, "meyer_fig3_4_force_spectrum.png")


if __name__ == "__main__":
    main()
