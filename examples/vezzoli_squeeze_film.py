"""Vezzoli et al. Fig 7: squeeze-film lift and friction reduction over vibration amplitude.

Reproduces: the model curves of Fig 7 — the friction reduction predicted by the squeeze-film
effect (eqs 2–6, σ → ∞) against the plate's vibration amplitude, for finger forces of
0.2–0.4 N (Table 1). The paper's measured points are not reproduced (no data are shipped).
Data: none measured — model curves with Table 1 (h_r = 1.8 µm, h_e = 50 µm, L_e = 350 µm,
f_r = 38.22 kHz, η = 1.85e-5 Pa·s, p0 = 1e5 Pa).
Assumptions (printed by the script; Table 1 omits A and l0, and eq 1 as printed is
inconsistent): contact area A = 1 cm² (Table 2's apparent area) and contact length l0 = √A =
1 cm; eq 5's "A" read as l0² so the squeeze number σ is dimensionless; eq 1 read as Δµ/µ =
F_s/F_n capped at 1 (levitation when the lift reaches the finger force): the paper prints
(µ − Δµ)/µ = F_s/F_n, which read literally makes the remaining friction rise with the lift;
Coulomb friction on the load the film does not carry, µ(F_n − F_s), gives Δµ/µ = F_s/F_n.
The theory curves are those of Fig 7's caption; the paper's text calls them "Figure 8".
What to look for: the lift grows steeply with amplitude; about 2 µm lifts ≈ 0.17 N, so just
above 2 µm a finger pressing with 0.2 N is levitated, as the paper states (its measurements
instead level off — the model cannot explain that, the paper says); σ ≫ 10 justifies σ → ∞.

Run: python examples/vezzoli_squeeze_film.py [OUT_DIR] [--fast]
"""

from __future__ import annotations

import numpy as np

import _example
from impedax.models import vezzoli
from impedax.data import format_quantity

NORMAL_FORCES = (0.2, 0.3, 0.4)  # N, Table 1 range
ASSUMPTIONS = (
    "contact area A = 1 cm² (Table 2's apparent area; Table 1 omits it)",
    "contact length l0 = √A = 1 cm",
    "eq 5's area read as l0², so the squeeze number σ = 12 η ω l0²/(p0 h0²) is dimensionless",
    "σ → ∞ pressure of eq 6, averaged exactly over a period and over x ∈ [−l0/2, l0/2]",
    "eq 1 read as Δµ/µ = F_s/F_n, capped at 1 (levitation when F_s ≥ F_n): the paper prints (µ − Δµ)/µ = F_s/F_n,"
    " which is inconsistent (read literally, friction rises with the lift and vanishes without it);"
    " friction µ(F_n − F_s) on the load the film does not carry gives Δµ/µ = F_s/F_n",
    "the theory curves are Fig 7's (its caption); the paper's text says \"Figure 8\", which is the electrovibration force",
)


TABLE1_UNITS = {"h_r": "m", "h_e": "m", "l_e": "m", "f_r": "Hz", "wavelength": "m", "normal_force": "N", "eta": "Pa·s", "p0": "Pa"}
"""The units of `vezzoli.TABLE1`'s SI values (the paper's Table 1 gives µm, Hz, cm, N, Pa.s, Pa)."""


def _with_unit(name, value) -> str:
    """A Table 1 value with its unit: lengths and frequencies with an SI prefix (``1.8 µm``,
    ``38.22 kHz``), the force range as ``0.2–0.4 N``, η and p0 as numbers (``1.85e-05 Pa·s``)."""
    unit = TABLE1_UNITS[name]
    if isinstance(value, tuple):
        return "–".join(f"{v:g}" for v in value) + f" {unit}"
    if unit in ("m", "Hz"):
        return format_quantity(value, unit, 4)
    return f"{value:g} {unit}"


def main(argv=None):
    args = _example.parse_args(__doc__, argv)
    import matplotlib.pyplot as plt

    amplitudes = np.linspace(0.0, 4e-6, 41 if args.fast else 161)
    points = 2001 if args.fast else 20001
    lift = np.array([vezzoli.squeeze_film_lift(a, points=points).force for a in amplitudes])
    at_2um = vezzoli.squeeze_film_lift(2e-6, normal_force=0.2, points=points)
    print("Vezzoli Fig 7 — squeeze-film model, Table 1 parameters: " + ", ".join(f"{k} = {_with_unit(k, v)}" for k, v in vezzoli.TABLE1.items()))
    print("assumptions:")
    for text in ASSUMPTIONS:
        print(f"  - {text}")
    print(f"lift at 2 µm amplitude: {at_2um.force:.3f} N   squeeze number σ = {at_2um.squeeze_number:.1f}   Δµ/µ at 0.2 N = {at_2um.friction_reduction:.2f}")
    for fn in NORMAL_FORCES:
        print(f"  levitation of a {fn:.1f} N finger at an amplitude of {np.interp(fn, lift, amplitudes) * 1e6:.2f} µm")

    fig, (ax_lift, ax_mu) = plt.subplots(1, 2, figsize=(12, 4.8), layout="constrained")
    ax_lift.plot(amplitudes * 1e6, lift, "k", lw=2, label="squeeze-film lift F_s")
    for k, fn in enumerate(NORMAL_FORCES):
        ax_lift.axhline(fn, color=f"C{k}", ls="--", lw=1, label=f"finger force F_n = {fn:.1f} N")
        reduction = vezzoli.friction_reduction(lift, fn)
        ax_mu.plot(amplitudes * 1e6, reduction, color=f"C{k}", lw=2, label=f"F_n = {fn:.1f} N")
    ax_lift.set(xlabel="vibration amplitude h_v [µm]", ylabel="lift force F_s [N]", title="squeeze-film lift (eq 2, σ → ∞)", ylim=(0, 0.6))
    ax_mu.set(xlabel="vibration amplitude h_v [µm]", ylabel="friction reduction Δµ/µ [–]", title="Fig 7 — predicted friction reduction", ylim=(0, 1.05))
    for ax in (ax_lift, ax_mu):
        ax.legend(fontsize=9, loc="upper left")
        _example.decade_grid(ax)
    fig.suptitle("Vezzoli et al. Fig 7 — squeeze-film model curves (Table 1; A = 1 cm², l0 = 1 cm assumed)")
    _example.save(fig, args, "vezzoli_fig7_squeeze_film.png")


if __name__ == "__main__":
    main()
