"""Figure of a batch fit (`impedax.fitting.least_squares.batch.BatchFitResult.plot`): how each
free parameter and the relative error vary across the spectra."""

from __future__ import annotations

import math

import numpy as np

from ..data import unit_text


def plot_batch(batch, *, title: str | None = None):
    """One panel per free parameter (value ± stderr for each spectrum, in the order of the batch
    dimensions, the x axis marked with the spectra's labels) and one for rms_rel; log scale
    where a parameter spans decades. Returns a matplotlib Figure."""
    import matplotlib.pyplot as plt

    from . import characters_across, label_spectra_axis, wrap_model

    ds = batch.dataset
    free = [str(p) for p, fixed in zip(ds["param"].values, ds["fixed"].values) if not fixed]
    panels = free + ["rms_rel"]
    cols = min(4, len(panels))
    rows = math.ceil(len(panels) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 2.6 * rows), layout="constrained", squeeze=False)
    index = np.arange(batch.n_spectra)
    places = [ds[d].values.tolist() if d in ds.coords else list(range(ds.sizes[d])) for d in batch.dims]
    labels = [", ".join(str(places[k][i]) for k, i in enumerate(at)) for at in np.ndindex(*(ds.sizes[d] for d in batch.dims))]
    specs = batch.circuit.parameter_specs(batch.registry)
    for ax, name in zip(axes.flat, panels):
        if name == "rms_rel":
            y, err, unit = ds["rms_rel"].transpose(*batch.dims).values.ravel() * 100, None, "%"
        else:
            y = ds["value"].sel(param=name).transpose(*batch.dims).values.ravel()
            err = ds["stderr"].sel(param=name).transpose(*batch.dims).values.ravel()
            unit = unit_text(specs[name].unit)
        ax.errorbar(index, y, yerr=None if err is None else np.where(np.isfinite(err), err, 0.0), fmt="o", ms=3, lw=0.8, capsize=1.5)
        positive = y[np.isfinite(y)]
        if positive.size and np.all(positive > 0) and positive.max() > 20 * positive.min():
            ax.set_yscale("log")
        ax.set_title(f"{name} [{unit}]" if unit else name, fontsize=9)
        label_spectra_axis(ax, labels, batch.dims)
        ax.grid(alpha=0.3, which="both")
    for ax in list(axes.flat)[len(panels):]:
        ax.set_visible(False)
    converged = float(ds["converged"].mean()) * 100
    fig.suptitle(title or wrap_model(f"{batch.model}: {batch.n_spectra} spectra, {converged:.0f}% converged", characters_across(3.2 * cols, 12)))
    return fig
