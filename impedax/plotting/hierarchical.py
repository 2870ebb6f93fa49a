"""The figure of a hierarchical posterior (`HierarchicalPosterior.plot`): its population."""

from __future__ import annotations

from typing import Mapping, Sequence

import matplotlib.pyplot as plt
import numpy as np

from ..data import unit_text
from . import plain_linear_ticks, plain_log_ticks, prefixed_axis
from .bayes import DIMENSIONLESS, LOG_AXIS_SPAN

__all__ = ["plot_population"]


def plot_population(names: Sequence[str], units: Sequence[str], trial_draws: np.ndarray, population: Mapping[str, Mapping[str, float]],
                    new_trial: Mapping[str, Mapping[str, float]], trial_labels: Sequence[str], *, title: str, xlabel: str = "trial", figsize=None,
                    new_trial_label: str = "new trial, 90 %"):
    """A panel per per-trial quantity (log axis, its unit): each trial's posterior median with its
    90 % interval (``trial_draws`` (draws, trials, quantities)), the population median and its
    90 % interval (``population[name]``: value, q05, q95) as a line in a dark band, a new trial's
    90 % interval (``new_trial[name]``) as a light band, named in the legend by ``new_trial_label``
    (with a session level: a new trial of a new session). A panel whose values span more than
    `LOG_AXIS_SPAN` has a log axis ticked in plain numbers with an SI prefix (``10k``), a narrower
    one a linear axis counted in the SI prefix its label names (``CPE1.Q [µF s^(α-1)]``), as the
    corner plot's axes. Returns the Figure."""
    k, t = len(names), trial_draws.shape[1]
    longest = max(map(len, trial_labels), default=0)
    crowded = t > 12 or longest * t > 60  # (characters across ~7 in: the labels stand upright, the figure grows by their length)
    label_room = 0.09 * longest if crowded else 0.0
    fig, axes = plt.subplots(k, 1, figsize=figsize or (max(7.0, 0.35 * t + 2.5), 0.8 + 2.2 * k + label_room), sharex=True, squeeze=False, layout="constrained")
    x = np.arange(t)
    for j, (ax, name, unit) in enumerate(zip(axes[:, 0], names, units)):
        lo, med, hi = np.quantile(trial_draws[:, :, j], [0.05, 0.5, 0.95], axis=0)
        new, pop = new_trial[name], population[name]
        ax.axhspan(new["q05"], new["q95"], color="C0", alpha=0.12, label=new_trial_label)
        ax.axhspan(pop["q05"], pop["q95"], color="C0", alpha=0.3, label="population median, 90 %")
        ax.axhline(pop["value"], color="C0", lw=1.2)
        ax.errorbar(x, med, yerr=[med - lo, hi - med], fmt="o", color="k", ms=3.5, capsize=2, label="each trial: median, 90 %")
        shown = unit_text(unit)
        ax.set_ylabel(f"{name} [{shown}]" if shown else name)
        low, high = min(np.min(lo), new["q05"], pop["q05"]), max(np.max(hi), new["q95"], pop["q95"])
        if low > 0 and high > LOG_AXIS_SPAN * low:
            ax.set_yscale("log")
            plain_log_ticks(ax.yaxis, prefixes=unit not in DIMENSIONLESS)
        elif shown:  # (matplotlib's log ticks of a narrow range read "1.8 × 10⁰", of µm "2.7 × 10⁻⁶")
            prefixed_axis(ax.yaxis)
        else:  # (α's values on its ticks: a narrow band read "1e−5+8.5e−1" above the panel)
            plain_linear_ticks(ax.yaxis)
    axes[0, 0].legend(loc="best", fontsize="small")
    axes[-1, 0].set_xticks(x, list(trial_labels), rotation=90 if crowded else 0)
    axes[-1, 0].set_xlabel(xlabel)
    fig.suptitle(title)
    return fig
