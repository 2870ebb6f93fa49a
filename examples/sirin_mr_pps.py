"""Sirin et al. Figs 4c and 4d: how much skin, touchscreen and the remainder contribute.

Reproduces: Fig 4c, magnitude ratio MR_i = |Z_i|/|Z_total| (eq 3), and Fig 4d, percent phase
synchronization PPS_i = [1 − |Φ_i − Φ_total|/|Φ_total|]·100 (eq 4), for i = skin, touchscreen
and remaining impedance, against the total impedance of the sliding finger.
Data: the SYNTHETIC Sirin-style example shipped with impedax (`example_spectra`: trial means
over 3 sessions × 10 trials; skin phase maximum at 250 Hz, touchscreen at 100 kHz, remainder
R_EP ∥ CPE_EP ∥ C_gap with C_gap = 413 pF). Nothing here is measured data.
What to look for: as in the paper, the remaining impedance (the air gap) has the largest
magnitude ratio up to ≈ 100 kHz with its phase synchronized with the total's, then falls out
of sync; the touchscreen starts to contribute above ≈ 100 Hz; the skin's MR is largest at the
lowest frequencies (0.18 at 1 Hz, above the touchscreen's up to ≈ 160 Hz), flat near 0.07 from
≈ 30 Hz to ≈ 30 kHz, rises above ≈ 50 kHz (0.15 at 126 kHz) and takes over near 1 MHz (0.61) (the paper: the skin
contributes "after 10 kHz"); the PPS of skin and touchscreen peak near 250 Hz and 100 kHz
(the frequencies of the two force peaks in the paper's Fig 2f). The script prints them.

Run: python examples/sirin_mr_pps.py [OUT_DIR] [--fast]
"""

from __future__ import annotations

import numpy as np

import _example
from impedax.data import format_frequency
from impedax.models import example_spectra, sirin
from impedax.plotting import frequency_axis

LABELS = {"skin": "skin", "touchscreen": "touchscreen", "remaining": "remaining (air gap + EP)"}
STYLES = {"skin": ("C1", "-"), "touchscreen": ("C0", "--"), "remaining": ("C2", "-.")}


def main(argv=None):
    args = _example.parse_args(__doc__, argv)
    import matplotlib.pyplot as plt

    spectra = example_spectra()
    contributions = sirin.impedance_contributions(spectra["total_sliding"], spectra["skin"], spectra["touchscreen"])
    freq = contributions["frequency"].values
    mr = contributions["magnitude_ratio"]
    pps = contributions["phase_synchronization"]

    print("Sirin Figs 4c/4d — SYNTHETIC example (finger sliding, trial means)")
    for name in LABELS:
        i = int(np.argmax(pps.sel(component=name).values))
        print(f"  {name:<12} PPS peak {pps.sel(component=name).values[i]:5.1f} % at {format_frequency(freq[i]):>9}   MR at 1 kHz {float(mr.sel(component=name).interp(frequency=1e3)):.3f}")
    remaining = mr.sel(component="remaining").values
    others = np.maximum(mr.sel(component="skin").values, mr.sel(component="touchscreen").values)
    # the last frequency where the remainder leads (the first where it is overtaken lies one grid step above)
    leads = remaining > others
    last_lead = freq[np.flatnonzero(leads)[-1]] if np.any(leads) else np.nan
    print(f"  the remaining impedance has the largest MR up to {format_frequency(last_lead)}   (paper: until ≈ 100 kHz)")
    print("  (paper: skin PPS peaks near 250 Hz, touchscreen near 100 kHz)")
    skin, screen = mr.sel(component="skin"), mr.sel(component="touchscreen")
    flat = skin.sel(frequency=slice(30.0, 3e4)).values
    above_screen = freq[np.flatnonzero(skin.values > screen.values)]
    low_lead = above_screen[above_screen < 1e4].max() if np.any(above_screen < 1e4) else np.nan
    print(
        f"  skin MR {float(skin[0]):.3f} at {format_frequency(freq[0])} (above the touchscreen's up to {format_frequency(low_lead)}), {flat.min():.3f}–{flat.max():.3f} over 30 Hz–30 kHz,"
        f" {float(skin.interp(frequency=1e5)):.3f} at 100 kHz, {float(skin[-1]):.2f} at {format_frequency(freq[-1])}"
    )

    fig, (ax_mr, ax_pps) = plt.subplots(1, 2, figsize=(12, 4.8), layout="constrained")
    for name, label in LABELS.items():
        color, style = STYLES[name]
        ax_mr.semilogx(freq, mr.sel(component=name), style, color=color, lw=2, label=label)
        ax_pps.semilogx(freq, pps.sel(component=name), style, color=color, lw=2, label=label)
    for f_mark, text in ((250.0, "paper: 250 Hz"), (1e5, "paper: 100 kHz")):
        ax_pps.axvline(f_mark, color="0.5", ls=":", lw=1)
        ax_pps.annotate(text, (f_mark, 1.0), xycoords=("data", "axes fraction"), xytext=(3, -4), textcoords="offset points", va="top", fontsize=8)
    ax_mr.set(xlabel="frequency [Hz]", ylabel="magnitude ratio |Z_i|/|Z_total| [–]", title="Fig 4c — magnitude ratio (eq 3)")
    ax_pps.set(xlabel="frequency [Hz]", ylabel="phase synchronization PPS_i [%]", title="Fig 4d — percent phase synchronization (eq 4)")
    # the axis follows the data down to −100 %: PPS falls far below that only where the total
    # phase nears 0 (eq 4 divides by it), and is clipped there, as in the paper
    lowest = float(np.nanmin(pps.values))
    ax_pps.set_ylim(max(-100.0, 10.0 * np.floor(lowest / 10.0) - 10.0), 112)  # (room above 100 % for the marks' labels)
    for ax in (ax_mr, ax_pps):
        frequency_axis(ax.xaxis)  # (1, 10, 100, 1000, 10k, as every impedax figure's frequency axis)
        ax.legend(fontsize=9)
        _example.decade_grid(ax)
    fig.suptitle("Sirin et al. Figs 4c/4d — contributions to the total sliding impedance (SYNTHETIC example data)")
    _example.save(fig, args, "sirin_fig4cd_mr_pps.png")


if __name__ == "__main__":
    main()
