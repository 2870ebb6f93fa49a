"""The distribution of relaxation times tells how many arcs a circuit needs, and where.

Reproduces: no paper figure. The DRT → circuit → fit → overlay workflow on a real spectrum.
Data: REAL. A Li-ion battery cell in the discharged state, cycle 0 of the 130-cycle set shipped
with AutoEIS 0.0.44 (MIT licence, examples/data/LICENSE-autoeis.txt): 57 frequencies from
9.9 kHz to 0.021 Hz, stored in examples/data/autoeis_battery_cycles.nc (cycles 0, 64, 129).
Steps: impedax.drt (γ ≥ 0, λ by modified GCV) → DRTResult.suggested_circuit(): R0 + one R‖CPE
per resolved peak inside the measured τ window, a series CPE for the peak beyond the slowest
point, started at the peaks' τ and R → impedax.fit → the fitted model's DRT (impedax.drt of
its Z at the same λ) laid over the data's, and unexplained_peaks as a check.
The same DRT of all three stored cycles shows how the arcs change with ageing.
What to look for: the data's DRT has three peaks — two arcs inside the measured range
(≈ 4 ms and ≈ 40 ms) and the diffusion tail beyond 0.02 Hz (τ ≈ 22 s, beyond the slowest
point: a series CPE, not an arc); the suggested circuit fits to ≈ 1 % and its DRT peaks sit on
the data's (the model explains all of them);
with ageing the middle (charge-transfer) peak grows and moves to longer τ.

Run: python examples/drt_guides_the_circuit.py [OUT_DIR] [--fast]
"""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import _example
import impedax
from impedax.data import format_band, format_percent
from impedax.fitting.drt import unexplained_peaks
from impedax.plotting.drt import plot_gamma

DATA = Path(__file__).resolve().parent / "data" / "autoeis_battery_cycles.nc"


def main(argv=None) -> None:
    args = _example.parse_args(__doc__, argv)
    cycles = impedax.load(DATA)
    data = cycles.isel(cycle=0)
    print(f"REAL data: a Li-ion battery cell, cycle 0 of AutoEIS's 130-cycle set (MIT), {data.sizes['frequency']} frequencies, {format_band(float(data['frequency'].min()), float(data['frequency'].max()))}")
    result = impedax.drt(data)
    print(result.report())
    suggestion = result.suggested_circuit()  # resolved peaks inside the measured τ window only
    model, init = suggestion.model, suggestion.init
    print(f"circuit from the DRT ({len(result.peaks)} peaks listed, {suggestion.n_arcs} arcs): {model}")
    print("\n".join(f"  {reason}" for reason in suggestion.reasons))
    fit = impedax.fit(model, data, init=init, n_starts=4 if args.fast else 16)
    print(f"fit {model}: rms_rel {format_percent(fit.rms_rel)}")
    # the fitted model's own DRT, solved as the data's was (a series CPE has no closed form)
    overlay = impedax.drt((fit.frequency, fit.z_model), lam=result.lam)
    evidence = unexplained_peaks(result, fit)
    print(evidence.text)
    print(f"peaks explained by the fitted circuit: {evidence.n_explained} of {len(result.peaks)}")

    fig = result.plot(overlay=overlay, title=f"battery cycle 0: DRT → {model} (rms_rel {fit.rms_rel * 100:.2g} %)")
    _example.save(fig, args, "drt_guides_the_circuit.png")

    batch = impedax.drt(cycles)
    fig, ax = plt.subplots(figsize=(7, 4.2), layout="constrained")
    for index, cycle in enumerate(cycles["cycle"].values):
        one = batch[index]
        ax.semilogx(one.tau, one.gamma, lw=1.6, label=f"cycle {int(cycle)}: {len(one.peaks)} peaks")
        print(f"cycle {int(cycle)}: peaks at " + ", ".join(f"{p.tau_s:.3g} s ({p.r_ohm:.3g} Ω)" for p in one.peaks))
    plot_gamma(ax, batch[0], label="cycle 0 (band, peaks)")
    ax.set_title("DRT of the battery over ageing (one vmapped call)")
    _example.decade_grid(ax)
    _example.save(fig, args, "drt_battery_ageing.png")


if __name__ == "__main__":
    main()
