"""Vezzoli et al.: the electrovibration force model — Table 2 value and Figs 8, 9, 10.

Reproduces: the force of eq 10 with the Table 2 parameters (h_i = 90 µm, h_s = 350 µm,
A = 1 cm², ε_i = 3.35, ε_s = 2340, ρ_s = 3.0e4 Ω·m, V_m = 2000 V, 440 Hz: 0.0556 N, paper
0.056 N); Fig 8, force over frequency for several stratum corneum thicknesses under Meyer's
conditions (140 V, 1 µm insulator, ε_i = 3.4; A, ε_s, ρ_s from Table 2, which the paper does not
restate for Fig 8); Fig 9, force over insulator thickness for ε_i from 1 to 36 (500 Hz, 140 V);
Fig 10, the voltage needed for 0.01 N against ε_i (1 µm insulator, 500 Hz).
Data: none measured — model curves with the paper's parameters. All forces are time averages.
What to look for: the high-pass (ωτ)²/(1 + (ωτ)²) of the stratum corneum (τ = ε0 ε_s ρ_s ≈ 0.6 ms,
corner ≈ 0.25 kHz) in Fig 8, a thinner stratum corneum giving more force; in Fig 9 the force
falling with insulator thickness, less steeply for a high-permittivity insulator; in Fig 10
the voltage for 0.01 N falling as ε_i rises.

Run: python examples/vezzoli_electrovibration.py [OUT_DIR] [--fast]
"""

from __future__ import annotations

import warnings

import numpy as np

import _example
from impedax.models import vezzoli

SC_THICKNESSES = np.array([100e-6, 200e-6, 350e-6, 500e-6])  # m, Fig 8
INSULATOR_PERMITTIVITIES = np.array([1.0, 3.4, 7.0, 12.0, 24.0, 36.0])  # Fig 9


def _paper_sweeps(n: int):
    """Figs 8–10's sweeps (``n`` points each), their values printed."""
    freq = np.logspace(2.0, 4.0, n)
    fig8 = vezzoli.stratum_corneum_sweep(freq, SC_THICKNESSES)
    h_i = np.logspace(-7.0, -4.0, n)
    fig9 = vezzoli.insulator_sweep(h_i, INSULATOR_PERMITTIVITIES)
    eps_i = np.linspace(1.0, 36.0, n)
    fig10 = vezzoli.voltage_sweep(eps_i)
    print("Fig 8 (140 V, 1 µm, eps_i 3.4) force at 100 Hz / 1 kHz / 10 kHz:")
    for h_s in SC_THICKNESSES:
        row = fig8.sel(h_s=h_s)
        values = [float(row.interp(frequency=f)) * 1e3 for f in (100.0, 1e3, 1e4)]
        print(f"  h_s = {h_s * 1e6:3.0f} µm: " + " / ".join(f"{v:.3f}" for v in values) + " mN")
    print("Fig 9 (500 Hz, 140 V) force at h_i = 1 µm:")
    for e in INSULATOR_PERMITTIVITIES:
        print(f"  eps_i = {e:4.1f}: {float(vezzoli.electrovibration_force(500.0, h_i=1e-6, eps_i=e, v_m=140.0)) * 1e3:.3f} mN")
    print("Fig 10 (0.01 N, 1 µm, 500 Hz) voltage needed: " + ", ".join(f"eps_i {e:g}: {float(vezzoli.voltage_for_force(0.01, 500.0, h_i=1e-6, eps_i=e)):.1f} V" for e in (1.0, 3.4, 12.0, 36.0)))
    return freq, fig8, h_i, fig9, eps_i, fig10


def main(argv=None):
    args = _example.parse_args(__doc__, argv)
    import matplotlib.pyplot as plt

    table2 = vezzoli.TABLE2
    force_440 = float(vezzoli.electrovibration_force(table2["frequency"]))
    tau = float(vezzoli.skin_time_constant())
    print("Vezzoli Table 2 — eq 10, time-averaged force")
    print("  parameters: " + ", ".join(f"{k} = {v:g}" for k, v in table2.items()))
    print(f"  F_e at 440 Hz = {force_440:.4f} N   (paper: 0.056 N)")
    print(f"  tau = eps0 eps_s rho_s = {tau * 1e3:.3f} ms, corner 1/(2 pi tau) = {1 / (2 * np.pi * tau):.0f} Hz")

    n = 60 if args.fast else 300
    with warnings.catch_warnings():  # the paper's Figs 8–10 lie outside eq 8's condition: said once, below
        warnings.simplefilter("ignore", vezzoli.Eq8ValidityWarning)
        freq, fig8, h_i, fig9, eps_i, fig10 = _paper_sweeps(n)
    ratios = [vezzoli.insulator_capacitance_ratio(h_i=1e-6, h_s=h, eps_i=3.4) for h in SC_THICKNESSES]
    print(f"note: Figs 8–10 use a 1 µm insulator, where C_i/C_s = eps_i h_s/(eps_s h_i) is {min(ratios):.2f}–{max(ratios):.2f} (Fig 8) "
          f"and up to {float(vezzoli.insulator_capacitance_ratio(h_i=1e-6, eps_i=36.0)):.1f} (Fig 10), above the {vezzoli.EQ8_RATIO_LIMIT:g} "
          "taken as eq 8's C_i << C_s: the curves follow the paper's equations, as the paper drew them")

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.8), layout="constrained")
    ax8, ax9, ax10 = axes
    for h_s in SC_THICKNESSES:
        ax8.semilogx(freq, fig8.sel(h_s=h_s) * 1e3, lw=2, label=f"h_s = {h_s * 1e6:.0f} µm")
    ax8.set(xlabel="frequency [Hz]", ylabel="time-averaged force F_e [mN]", title="Fig 8 — force vs frequency\n(140 V, insulator 1 µm, ε_i = 3.4)")
    ax8.legend(title="stratum corneum", fontsize=8)
    for e in INSULATOR_PERMITTIVITIES:
        ax9.loglog(h_i * 1e6, fig9.sel(eps_i=e), lw=2, label=f"ε_i = {e:g}")
    ax9.set(xlabel="insulator thickness h_i [µm]", ylabel="time-averaged force F_e [N]", title="Fig 9 — force vs insulator thickness\n(500 Hz, 140 V)")
    ax9.legend(fontsize=8)
    ax10.plot(eps_i, fig10, lw=2, color="C3", label="V_m for F_e = 0.01 N")
    ax10.set(xlabel="insulator permittivity ε_i [–]", ylabel="voltage amplitude V_m [V]", title="Fig 10 — voltage for 0.01 N\n(insulator 1 µm, 500 Hz)")
    ax10.legend(fontsize=8)
    for ax in axes:
        _example.decade_grid(ax)
    fig.suptitle(f"Vezzoli et al. — electrovibration force, eq 10 (Table 2: F_e = {force_440:.4f} N at 440 Hz, 2000 V)")
    _example.save(fig, args, "vezzoli_fig8_9_10_electrovibration.png")


if __name__ == "__main__":
    main()
