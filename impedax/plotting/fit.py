"""Figure of a batch fit (`impedax.fitting.least_squares.batch.BatchFitResult.plot`): how each
free parameter and the relative error vary across the spectra."""

from __future__ import annotations

import math

import numpy as np
from matplotlib.ticker import MaxNLocator

from ..arguments import figure_size, shown
from ..data import coordinate_labels, unit_text
from ..errors import ParameterError
from . import TAIL_RATIO, drawn_label, font_size, tail_frame


def plot_batch(batch, *, title: str | None = None, figsize: tuple[float, float] | None = None, params=None, x: str | None = None, spectra: str = "auto"):
    """One panel per free parameter (value ± stderr for each spectrum, in the order of the batch
    dimensions, the x axis marked with the spectra's labels; a value at its bound has no bar, as
    text and JSON give it no standard error, and an open square marked "at bound") and one for rms_rel; log scale
    where a parameter spans decades; and a Nyquist panel of data and fits (`_plot_fits`) in
    the last row's free places (a row of its own when fewer than two are free). ``figsize``
    (width, height) [in]: the figure's size, the panels keeping their proportions. ``params``:
    the parameters to draw, in that order (a list of names, or one name; None: every free one),
    the rms_rel panel after them; an unknown name is a `ParameterError`
    naming the circuit's parameters. ``x``: a batch dimension with a numeric coordinate
    (``"voltage"``) to draw against, its coordinate on the x axis and one series (colour,
    shifted sideways by a few % of the coordinate's smallest step so that bars of one x stay
    apart) per label of the other dimensions (`_x_series`). ``spectra``:
    the spectra panel, "nyquist", "phase" (against frequency) or "auto" (the phase where the
    spectra have a capacitive tail, `phase_panel`). Returns a matplotlib Figure."""
    import matplotlib.pyplot as plt

    from . import characters_across, frame_spectra, label_spectra_axis, labelled_log_ticks, nyquist_panel_height, nyquist_shape, plain_linear_ticks, prefixable_unit, prefixed_axis, wrap_model

    figsize = figure_size(figsize, "figsize")
    ds = batch.dataset
    free = [str(p) for p, fixed in zip(ds["param"].values, ds["fixed"].values) if not fixed] if params is None else _chosen(batch, params)
    panels = free + ["rms_rel"]
    cols = min(4, len(panels))
    rows = math.ceil(len(panels) / cols)
    left = rows * cols - len(panels)  # free places in the last row
    with_fits = "Z" in ds
    phase = phase_panel(ds, batch.dims, spectra)
    own_row = with_fits and left < 2
    width = 3.2 * max(cols, 2) if figsize is None else float(figsize[0])
    # (a row of its own as high as the drawn spectra's shape asks, `nyquist_panel_height`, from
    # `FITS_ROW`; its box narrows to that shape, `_plot_fits`)
    fits_row = (FITS_ROW if phase else max(FITS_ROW, nyquist_panel_height(nyquist_shape(*((None, z) for z in _drawn_spectra(ds, batch.dims)[1])), width))) if own_row else 0.0
    fig = plt.figure(figsize=figsize or (width, 2.6 * rows + fits_row), layout="constrained")
    grid = fig.add_gridspec(rows + own_row, max(cols, 2), height_ratios=[2.6] * rows + ([fits_row] if own_row else []))
    axes = [fig.add_subplot(grid[i // cols, i % cols]) for i in range(len(panels))]
    index = np.arange(batch.n_spectra)
    series = None if x is None else _x_series(batch, x)
    whole = series is not None and bool(np.all(np.mod(np.asarray(ds[x].values, float), 1.0) == 0))  # (a coordinate of whole numbers)
    for _, members, position in series or ():  # (each spectrum at its coordinate)
        index = np.where(members, position, index)
    places = [coordinate_labels(ds, d) for d in batch.dims]
    labels = [", ".join(drawn_label(places[k][i]) for k, i in enumerate(at)) for at in np.ndindex(*(ds.sizes[d] for d in batch.dims))]
    specs = batch.circuit.parameter_specs(batch.registry)
    shared = set(getattr(batch, "shared", ()))  # (a global fit's shared parameters)
    for ax, name in zip(axes, panels):
        if name == "rms_rel":
            y, err, unit = ds["rms_rel"].transpose(*batch.dims).values.ravel() * 100, None, "%"
        else:
            y = ds["value"].sel(param=name).transpose(*batch.dims).values.ravel()
            # (the bars are the reported stderr, as text and JSON: none at a bound)
            err = ds["stderr"].sel(param=name).transpose(*batch.dims).values.ravel()
            linearised = ds["linearised_stderr" if "linearised_stderr" in ds else "stderr"].sel(param=name).transpose(*batch.dims).values.ravel()
            unit = unit_text(specs[name].unit)
        at = np.zeros(y.size, bool) if name == "rms_rel" else ds["at_bound"].sel(param=name).transpose(*batch.dims).values.ravel().astype(bool)
        # (the undetermined, and values at a bound the data cannot place them from: a resistor open at ∞)
        loose = np.zeros(y.size, bool) if name == "rms_rel" else batch.undetermined(name).transpose(*batch.dims).values.ravel() | (at & np.isinf(linearised))
        kept = ~loose
        barred = kept & ~at
        bars = None if err is None else _bounded_bars(y, np.where(np.isfinite(err), err, 0.0), _bounds(ds, name, specs[name]))[:, kept]
        if series is not None:  # (against a coordinate: each series its own colour)
            all_bars = None if err is None else _bounded_bars(y, np.where(np.isfinite(err), err, 0.0), _bounds(ds, name, specs[name]))
            for k, (label, members, position) in enumerate(series):
                chosen = barred & members
                ax.errorbar(position[chosen], y[chosen], yerr=None if all_bars is None else all_bars[:, chosen], fmt="o", ms=3, lw=0.8, capsize=1.5, color=f"C{k % 10}", label=label or None)
            if len(series) > 1 and ax is axes[0]:  # (below the panels: inside the first one it covered its values)
                fig.legend(*ax.get_legend_handles_labels(), fontsize=font_size("legend", 6.5), loc="outside lower center", ncol=min(len(series), 4), handlelength=1.0)
        elif name in shared:  # (one value and one ± per global fit: a band, not the same bar on every spectrum)
            ax.plot(index[kept], y[kept], "o", ms=3, color="C0")
            _shared_band(ax, batch, name)
        elif barred.any() or not (kept & at).any():
            ax.errorbar(index[barred], y[barred], yerr=None if bars is None else bars[:, ~at[kept]], fmt="o", ms=3, lw=0.8, capsize=1.5)
        if (kept & at).any():  # (no bar: text and JSON give no standard error at a bound)
            ax.plot(index[kept & at], y[kept & at], "s", ms=3, mfc="none", color="C3", label="at bound (no stderr)")
            ax.legend(fontsize=font_size("legend", 6.5), loc="best", handlelength=1.0, borderaxespad=0.3)
        if name == "rms_rel":  # (the fits whose model misses structure, by `misses_structure`'s rule: ringed)
            _ring_missing_structure(ax, batch, index, y)
        scaled = y[kept & np.isfinite(y)]
        spread = scaled if scaled.size else y[np.isfinite(y)]  # (every value undetermined: all of them)
        if spread.size and np.all(spread > 0) and spread.max() > 20 * spread.min():
            ax.set_yscale("log")
            # (1M, 2M, 500k as on every other log axis, labels as many as fit, two at least:
            # matplotlib's "4×10⁶" ran into "3×10⁶" on R2 over 1.5 decades, and REAL battery
            # cycles' CPE2.Q of 0.48 read against 1 and 10 alone)
            labelled_log_ticks(ax.yaxis)
        if loose.any():
            # (the rule on its own line: on one, the legend was wider than the panel)
            _mark_undetermined(ax, index[loose], y[loose], scaled, f"undetermined\n({batch.UNDETERMINED_RULE})")
        ax.set_title((f"{name} [{unit}]" if unit else name) + (" (shared)" if name in shared else ""), fontsize=font_size("title", 9))
        if ax.get_yscale() == "linear":
            shown = y[np.isfinite(y)] if loose.all() else y[kept & np.isfinite(y)]
            _window_flat(ax, shown, None if bars is None else bars[:, np.isfinite(y[kept])], None if name == "rms_rel" else _bounds(ds, name, specs[name]))
            if prefixable_unit(ax.get_title()):  # (R_sc [MΩ] with ticks 1.0, 1.5, not 1e6 apart)
                prefixed_axis(ax.yaxis, label=ax.title)
            else:  # (σ 1760, 1770, not 6.4 under "1e-9+1.767766953e3"; rms_rel 1e-13, not 1.0 under "1e-13")
                plain_linear_ticks(ax.yaxis)
        if series is None:
            label_spectra_axis(ax, labels, batch.dims)
        else:
            ax.set_xlabel(x, fontsize=font_size("label", 8))
            if whole:  # (cycles 1, 2, 3 ticked 1, 2, 3: matplotlib put ticks at 1.5 and 2.5, half a cycle)
                ax.xaxis.set_major_locator(MaxNLocator(integer=True))
        ax.grid(alpha=0.3, which="both")
    if with_fits:
        ax_nyq = fig.add_subplot(grid[rows, :] if own_row else grid[rows - 1, cols - left :])
        _plot_fits(ax_nyq, ds, batch.dims, labels, batch.circuit.compile(batch.registry), phase)
    converged = float(ds["converged"].mean()) * 100
    fig.suptitle(title or wrap_model(f"{batch.model}: {batch.n_spectra} spectr{'um' if batch.n_spectra == 1 else 'a'}{sharing_text(batch)}, {converged:.0f}\u00a0% converged, {batch.weighting} weighting", characters_across(fig.get_figwidth() if figsize else 3.2 * cols, font_size("suptitle", 12))))
    if series is None:  # (on the final layout: the first and last spectrum inside the frame)
        frame_spectra(axes, batch.n_spectra)
    return fig


MISSES_STRUCTURE_LABEL = "model misses structure\n(a warning or the misfit hint)"


def _ring_missing_structure(ax, batch, x, rms) -> None:
    """Ring the rms_rel of each fit whose model misses structure the data hold
    (`BatchFitResult.misses_structure`: a warning or the misfit hint says so), named in the
    panel's legend; none where none does. On the REAL 130 battery cycles the hint names 49 fits
    the figure would not otherwise tell from the others."""
    misses = getattr(batch, "misses_structure", None)
    flags = np.zeros(rms.size, bool) if misses is None else np.asarray(misses.transpose(*batch.dims).values, bool).ravel()
    if flags.any():
        ax.plot(x[flags], rms[flags], "o", ms=7, mfc="none", mec="C3", mew=1.0, label=MISSES_STRUCTURE_LABEL)
        ax.legend(fontsize=font_size("legend", 6.5), loc="best", handlelength=1.0, borderaxespad=0.3)


def _shared_band(ax, batch, name: str) -> None:
    """A global fit's shared parameter ``name`` as its value ± standard error, a band across the
    panel per global fit (its value's points drawn by the caller), labelled with the number: the
    same bar drawn at each of the REAL 130 battery cycles would read as a wall of bars."""
    value = batch.values(name).values.ravel()
    error = batch.stderr(name).values.ravel()
    for v, e in zip(value, error):
        if np.isfinite(e) and e > 0:
            ax.axhspan(v - e, v + e, color="C0", alpha=0.15, lw=0, label="shared ± stderr" if len(value) == 1 else None)
    if len(value) == 1 and np.isfinite(error[0]) and error[0] > 0:
        ax.legend(fontsize=font_size("legend", 6.5), loc="best", handlelength=1.0, borderaxespad=0.3)


# the sideways shift between the series of `plot_batch(x=...)`, a fraction of the coordinate's
# smallest step: bars of one x drawn apart (a choice of legibility, not of data)
SERIES_SHIFT = 0.04


def numeric_coordinate(ds, dim: str) -> bool:
    """Whether ``dim`` has a coordinate of numbers in ``ds`` (a Dataset): what a batch's
    parameters are drawn against (`plot_batch`'s ``x``; `impedax fit --plot-x`)."""
    return dim in ds.coords and np.issubdtype(ds[dim].dtype, np.number)


def _x_series(batch, x) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """For `plot_batch(x=...)`: per label of the batch's dimensions other than ``x`` (in C
    order), its text (``repeat=1``; empty for a batch over ``x`` alone), which spectra (flat, in
    the batch's order) it holds and each spectrum's position (``x``'s coordinate, shifted by
    `SERIES_SHIFT` of its smallest step per series). `ParameterError` unless ``x`` is a batch
    dimension with a numeric coordinate."""
    from ..errors import ParameterError

    ds = batch.dataset
    if not isinstance(x, str) or x not in batch.dims:
        raise ParameterError(f"plot(x=...): a dimension of the batch ({', '.join(batch.dims)}), got {x!r}")
    if not numeric_coordinate(ds, x):
        raise ParameterError(f"plot(x={x!r}): {x} has no numeric coordinate to draw against; give the data one (data.assign_coords({x}=[...])) or leave x out")
    shape = tuple(ds.sizes[d] for d in batch.dims)
    axis = batch.dims.index(x)
    coordinate = np.asarray(ds[x].values, float)
    at = np.stack(np.unravel_index(np.arange(batch.n_spectra), shape)) if shape else np.zeros((0, 1), int)
    others = [d for d in batch.dims if d != x]
    steps = np.diff(np.unique(coordinate))
    step = float(steps.min()) if steps.size else 1.0
    groups = list(np.ndindex(*(ds.sizes[d] for d in others)))
    out = []
    for k, group in enumerate(groups):
        members = np.ones(batch.n_spectra, bool)
        for d, j in zip(others, group):
            members &= at[batch.dims.index(d)] == j
        shift = (k - (len(groups) - 1) / 2) * SERIES_SHIFT * step
        label = ", ".join(f"{d}={drawn_label(coordinate_labels(ds, d)[j])}" for d, j in zip(others, group))
        out.append((label, members, coordinate[at[axis]] + shift))
    return out


def _chosen(batch, params) -> list[str]:
    """The parameter names ``params`` (`plot_batch`) as a list, each a parameter of the batch's
    circuit (`unknown_parameter` otherwise: the names and the closest one), none twice."""
    from ..arguments import shown, unknown_parameter
    from ..errors import ParameterError

    names = [str(p) for p in batch.dataset["param"].values]
    chosen = [params] if isinstance(params, str) else params
    try:
        chosen = list(chosen)
    except TypeError:
        raise ParameterError(f"plot(params=...): a list of parameter names ({', '.join(names)}), got {shown(params)}") from None
    if not chosen:
        raise ParameterError(f"plot(params=...): no parameter named; give some of {', '.join(names)} (None draws every free one)")
    for name in chosen:
        if not isinstance(name, str) or name not in names:
            raise unknown_parameter("plot(params=...)", name, names, batch.model)
    return list(dict.fromkeys(chosen))


# values of a parameter across the spectra that span less than this, relative to their size,
# are one value for the figure (identical sheets fitted to within rounding: 100.000000 Ω on every
# tick, or an axis "1e-9+1.767766953e3"); their panel shows ±`FLAT_WINDOW` of it, symmetric
FLAT_SPAN = 1e-6
FLAT_WINDOW = 0.01
FLAT_BOUND_MARGIN = 0.05  # (of a flat window's height: room above a bound for the markers on it)


def _window_flat(ax, values, bars=None, bounds=None) -> None:
    """A linear panel of ``values`` (with error ``bars``, 2 × n, below and above) that barely
    vary (their extent below `FLAT_SPAN` of their size): y limits centred on their median,
    ±`FLAT_WINDOW` of it (±1 around 0), so its ticks read 99, 99.5, 100, 100.5, 101; a window
    that would cross one of the parameter's ``bounds`` (lower, upper) the values do not pass is
    moved inside it, up to `FLAT_BOUND_MARGIN` of its height (α = 1 in every spectrum: 0.981–1.001,
    not 0.99–1.01, where α cannot go)."""
    values = np.asarray(values, float)
    if not values.size:
        return
    low, high = values, values
    if bars is not None and bars.shape[1] == values.size:
        low, high = values - np.nan_to_num(bars[0]), values + np.nan_to_num(bars[1])
    centre = float(np.median(values))
    size = max(abs(centre), float(np.max(np.abs(values))))
    if float(np.max(high) - np.min(low)) > FLAT_SPAN * size:
        return
    half = FLAT_WINDOW * abs(centre) if centre != 0 else 1.0
    bottom, top = centre - half, centre + half
    lower, upper = bounds if bounds is not None else (-np.inf, np.inf)
    margin = FLAT_BOUND_MARGIN * 2 * half
    if top > upper + margin and float(np.max(high)) <= upper:
        bottom, top = upper + margin - 2 * half, upper + margin
    elif bottom < lower - margin and float(np.min(low)) >= lower:
        bottom, top = lower - margin, lower - margin + 2 * half
    ax.set_ylim(bottom, top)


def _bounds(ds, name: str, spec) -> tuple[float, float]:
    """The fit's bounds of parameter ``name`` (the user's where given), from the batch's Dataset;
    the natural ones of its ``spec`` for a Dataset written before they were stored."""
    if "lower" in ds:
        return float(ds["lower"].sel(param=name)), float(ds["upper"].sel(param=name))
    return spec.lower, spec.upper


def _bounded_bars(value, err, bounds) -> np.ndarray:
    """Error bars (2, n: below, above) that stop at a parameter's bounds (``bounds``: the fit's
    lower and upper, natural or the user's), whether the value sits on one or near it: a CPE's
    α = 1 ± 0.03 was drawn up to 1.03, and α = 0.979 ± 0.058 up to 1.037, where α cannot go."""
    lower, upper = bounds
    with np.errstate(invalid="ignore"):
        below = np.minimum(err, np.maximum(value - lower, 0.0))
        above = np.minimum(err, np.maximum(upper - value, 0.0))
    return np.stack([below, above])


def _mark_undetermined(ax, x, y, determined, label: str) -> None:
    """Values the data do not determine (`BatchFitResult.undetermined`) as open grey markers
    without error bars (theirs span decades and flattened the panel: a battery's idle R2 at
    1e30 ± 1e52 Ω), the axis scaled to the determined ones; values beyond it sit at its edge as
    ▲ / ▼, each named in the legend."""
    if determined.size:
        ax.autoscale_view()
        lo, hi = ax.get_ylim()
        above, below = y > hi, y < lo
        inside = ~(above | below)
        ax.plot(x[inside], y[inside], "o", ms=3.5, mfc="none", color="0.55", label=label)
        for beyond, edge, marker, side in ((above, hi, "^", "above"), (below, lo, "v", "below")):
            if beyond.any():  # (an empty unclipped line would stretch the layout's box to the figure's corner)
                ax.plot(x[beyond], np.full(beyond.sum(), edge), marker, ms=4, mfc="none", color="0.55", clip_on=False, label=f"undetermined, {side} the axis")
        ax.set_ylim(lo, hi)
    else:
        ax.plot(x, y, "o", ms=3.5, mfc="none", color="0.55", label=label)
    # the best place among the markers, the ▲ / ▼ at the edge included (they count as data)
    ax.legend(fontsize=font_size("legend", 6.5), loc="best", handlelength=1.0, borderaxespad=0.3)


# a batch's Nyquist panel draws at most this many of its spectra (evenly spaced, the first and
# the last among them): more overlap into one band
FITS_DRAWN = 8
# the least height [in] of a batch's Nyquist panel in a row of its own (`plot_batch`)
FITS_ROW = 3.2


def _drawn_spectra(ds, dims) -> tuple[np.ndarray, np.ndarray]:
    """(indices, Z) of the spectra a batch's Nyquist panel draws: up to `FITS_DRAWN`, evenly
    spaced from the first to the last, in the batch's flat order."""
    z = ds["Z"].transpose(*dims, "frequency").values.reshape(-1, ds.sizes["frequency"])
    drawn = np.unique(np.linspace(0, len(z) - 1, min(len(z), FITS_DRAWN)).round().astype(int))
    return drawn, z[drawn]


def phase_panel(ds, dims, spectra: str) -> bool:
    """Whether a batch's spectra panel draws the phase against frequency (``spectra`` "phase",
    or "auto" where the drawn spectra have a capacitive tail beside their fits, `tail_frame`:
    at equal scales even the zoomed Nyquist panel showed a SYNTHETIC finger's 8 spectra as one
    vertical line at Z' ≈ 0 beside an axis to 1.9 MΩ) or a Nyquist panel ("nyquist")."""
    if spectra not in SPECTRA_PANELS:
        raise ParameterError(f"spectra must be one of {', '.join(SPECTRA_PANELS)}, got {shown(spectra)}")
    if spectra != "auto" or "Z" not in ds:
        return spectra == "phase"
    drawn, z = _drawn_spectra(ds, dims)
    z_model = ds["Z_model"].transpose(*dims, "frequency").values.reshape(-1, ds.sizes["frequency"])[drawn]
    return tail_frame(z, z_model) is not None


SPECTRA_PANELS = ("auto", "nyquist", "phase")


def _plot_fits(ax, ds, dims, labels, model, phase: bool = False) -> None:
    """Nyquist panel of a batch: the data (circles) and the fit (a curve of the compiled
    ``model`` at each spectrum's values, `dense_model`) of up to `FITS_DRAWN` spectra, each
    pair in one colour along the batch's order, at equal scales over the range of what is drawn
    (`nyquist_frame`: the panel's box narrows to it). Before, the equal scales widened a wide
    panel's Z' range to 8 MΩ beside data that end at 3.1 MΩ. ``phase`` (`phase_panel`): the
    phase against frequency instead."""
    import matplotlib as mpl

    from . import dense_model, frequency_axis, nyquist_frame, nyquist_view

    z = ds["Z"].transpose(*dims, "frequency").values.reshape(-1, ds.sizes["frequency"])
    z_model = ds["Z_model"].transpose(*dims, "frequency").values.reshape(z.shape)
    n = len(z)
    drawn = _drawn_spectra(ds, dims)[0]
    colours = mpl.colormaps["viridis"](np.linspace(0, 0.9, drawn.size))
    values = ds["value"].transpose(*dims, "param").values.reshape(n, -1)
    names = [str(p) for p in ds["param"].values]
    freq = ds["frequency"].values
    dense = []
    for i in drawn.tolist():
        params = dict(zip(names, values[i].tolist()))
        dense.append(dense_model(freq, z_model[i], lambda grid, params=params: model(params, grid)))
    curves = [curve for _, curve in dense]
    for colour, i, (grid, curve) in zip(colours, drawn.tolist(), dense):
        if phase:
            ax.semilogx(freq, np.degrees(np.angle(z[i])), "o", ms=2.5, mfc="none", color=colour, label=labels[i])
            ax.semilogx(grid, np.degrees(np.angle(curve)), "-", lw=1.0, color=colour)
        else:
            ax.plot(z[i].real, -z[i].imag, "o", ms=2.5, mfc="none", color=colour, label=labels[i])
            ax.plot(curve.real, -curve.imag, "-", lw=1.0, color=colour)
    if phase:
        frequency_axis(ax.xaxis)
    what = f"{drawn.size} of {n} spectra" if drawn.size < n else f"{n} spectr{'um' if n == 1 else 'a'}"
    # beside the panel, where it covers no data (inside, the spectra's curves run everywhere)
    ax.legend(fontsize=font_size("legend", 7), title=", ".join(dims), title_fontsize=font_size("legend", 7), ncol=2 if drawn.size > 4 else 1, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    ax.grid(alpha=0.3, which="both" if phase else "major")
    if phase:
        ax.set_xlabel("frequency [Hz]", fontsize=font_size("label", 8))
        ax.set_ylabel("phase [deg]", fontsize=font_size("label", 8))
        tail = f"\n(at equal scales a Nyquist panel shows a line: −Z'' spans ≥ {TAIL_RATIO:g}× Z')" if tail_frame(z[drawn], *curves) is not None else ""
        ax.set_title(f"phase of data (○) and fits (—), {what}{tail}", fontsize=font_size("title", 9))
        return
    ax.set_xlabel("Z' [Ω]", fontsize=font_size("label", 8))
    ax.set_ylabel("−Z'' [Ω]", fontsize=font_size("label", 8))
    ax.set_title(f"data (○) and fits (—), {what}", fontsize=font_size("title", 9))
    nyquist_view(ax, z[drawn], *curves, frequency=np.broadcast_to(freq, z[drawn].shape), frame=nyquist_frame(z[drawn], *curves))


# the most cells a map (`plot_residual_map`, `plotting.kk.plot_validity_batch`) draws as vector
# shapes in a PDF, SVG or EPS; more are one raster image at the figure's dpi: 1,000 SYNTHETIC
# spectra × 40 frequencies made an SVG of 7.9 MB, 40,000 quadrilaterals
MAP_VECTOR_CELLS = 5000


def sharing_text(batch) -> str:
    """", R0 shared over trial" for a global fit (`SharedFitResult`), "" for independent fits:
    the two figures of one series read alike without it."""
    shared, over = tuple(getattr(batch, "shared", ())), tuple(getattr(batch, "over", ()))
    return f", {', '.join(shared)} shared over {', '.join(over)}" if shared else ""


def residuals_shown(batch) -> tuple[np.ndarray, str, str]:
    """The residuals a batch's residual map draws, (spectra, frequency as stored): in units of
    the data's σ, (Z_model − Z)/σ, where the fits were weighted by it (``sigma``: what they
    minimised, judged against the noise), else relative to |Z| in % (`plot_residual_map`); with
    the colour bar's quantity and unit. Model minus data, as `FitResult.residuals` and a single
    fit's figure (docs/physics.md), so that one residual has one colour in both."""
    ds = batch.dataset
    dims = tuple(batch.dims)
    z = ds["Z"].transpose(*dims, "frequency").values.reshape(batch.n_spectra, -1)
    z_model = ds["Z_model"].transpose(*dims, "frequency").values.reshape(batch.n_spectra, -1)
    with np.errstate(divide="ignore", invalid="ignore"):
        if batch.weighting == "sigma" and "sigma" in ds:
            sigma = ds["sigma"].transpose(*dims, "frequency").values.reshape(z.shape)
            return (z_model - z) / sigma, "(Z_model − Z)/σ", "σ"
        return (z_model - z) / np.abs(z) * 100, "(Z_model − Z)/|Z|", "%"


def excluded_rows(fitted, excluded) -> np.ndarray:
    """Of the frequencies ``excluded`` [Hz] left out of the fits (``--exclude``), those inside
    the fitted band ``fitted`` (ascending) and not fitted themselves, ascending: the rows a
    residual map marks (outside the band they have no row)."""
    if excluded is None:
        return np.empty(0)
    try:
        out = np.asarray(excluded, float)
    except (TypeError, ValueError):
        out = None
    if out is None or out.ndim > 1 or not np.all(np.isfinite(out) & (out > 0)):
        raise ParameterError(f"plot_residual_map(excluded=...): frequencies [Hz] left out of the fits, positive and finite (a list of numbers, or None), got {shown(excluded)}")
    out = np.unique(out.reshape(-1))
    keep = (out > fitted[0]) & (out < fitted[-1]) & ~np.isin(out, fitted)
    return out[keep]


def plot_residual_map(batch, *, title: str | None = None, excluded=None):
    """Where a model fails across a batch: the residuals of every spectrum, real and imaginary
    parts, as two maps over the spectra (x, in the batch's order, marked with their labels) and
    frequency (y, log): relative to |Z|, (Z_model − Z)/|Z| [%], or, for fits weighted by the
    data's σ, in units of it, (Z_model − Z)/σ (`residuals_shown`, the colour bar says which); on
    one diverging colour scale symmetric about 0 (its ends at the 99th percentile of |residual|,
    so a few outliers do not pale the rest; beyond it the colour saturates), and each fit's
    rms_rel below (in σ: its chi2_red, a dashed line at 1). ``excluded``: frequencies [Hz] left
    out of the fits (``--exclude``), each drawn as a hatched grey row of its own and named in a
    legend, where their neighbours' cells would stretch over them. A model
    that misses an effect leaves the same
    sign pattern at the same frequencies in spectrum after spectrum, where noise leaves speckle
    (`BatchFitResult.plot_residual_map`; ``impedax fit FILE --residual-map FIG.png``). Returns a
    matplotlib Figure."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import Normalize
    from matplotlib.patches import Patch

    from . import PlainTicks, characters_across, frame_spectra, frequency_axis, frequency_cell_edges, label_spectra_axis, labelled_log_ticks, plain_linear_ticks, wrap_model

    ds = batch.dataset
    dims = tuple(batch.dims)
    f = np.asarray(ds["frequency"].values, float)
    order = np.argsort(f)
    f = f[order]
    residuals, quantity, unit = residuals_shown(batch)
    residuals = residuals[:, order]
    left_out = excluded_rows(f, excluded)
    rows = np.concatenate([f, left_out])
    by_row = np.argsort(rows)
    f_edges = frequency_cell_edges(rows[by_row])  # (every row its own cell: a left-out one too)
    fitted_row = np.argsort(by_row)[: f.size]  # (each fitted frequency's row among them)
    x_edges = np.arange(batch.n_spectra + 1) - 0.5
    parts = np.concatenate([residuals.real.ravel(), residuals.imag.ravel()])
    parts = parts[np.isfinite(parts)]
    scale = float(np.percentile(np.abs(parts), 99)) if parts.size else 1.0
    scale = scale if scale > 0 else 1.0
    fig, (ax_re, ax_im, ax_rms) = plt.subplots(3, 1, figsize=(8, 8), height_ratios=[2.2, 2.2, 1.1], sharex=True, layout="constrained")
    norm = Normalize(-scale, scale)
    for ax, part, name in ((ax_re, residuals.real, "Re"), (ax_im, residuals.imag, "Im")):
        cells = np.full((rows.size, batch.n_spectra), np.nan)
        cells[fitted_row] = part.T
        mesh = ax.pcolormesh(x_edges, f_edges, np.ma.masked_invalid(cells) if left_out.size else part.T, norm=norm, cmap="RdBu_r", shading="flat", rasterized=part.size > MAP_VECTOR_CELLS)
        for k in np.flatnonzero(~np.isin(np.arange(rows.size), fitted_row)):
            ax.axhspan(f_edges[k], f_edges[k + 1], facecolor="0.85", edgecolor="0.45", hatch="///", lw=0.0)
        ax.set_yscale("log")
        ax.set_ylim(f_edges[0], f_edges[-1])
        ax.set_ylabel(f"frequency [Hz]\n({name})", fontsize=font_size("label", 9))
        frequency_axis(ax.yaxis)
    if left_out.size:
        from ..data import format_frequency
        from ..warning_groups import labels_text

        ax_re.legend(handles=[Patch(facecolor="0.85", edgecolor="0.45", hatch="///", label=f"left out of the fits: {labels_text([format_frequency(v) for v in left_out])}")],
                     fontsize=font_size("legend", 7), loc="lower left", bbox_to_anchor=(0.0, 1.0), borderaxespad=0.2, frameon=False)
    # (the saturated ends shown as arrows, and the largest |residual| named: a SYNTHETIC 1000 %
    # outlier drew as ±0.8 % with nothing to say the colour stopped there)
    above, below = bool(parts.size and parts.max() > scale), bool(parts.size and parts.min() < -scale)
    bar = fig.colorbar(mesh, ax=[ax_re, ax_im], shrink=0.9, extend={(True, True): "both", (True, False): "max", (False, True): "min"}.get((above, below), "neither"))
    beyond = f"; beyond it, up to {float(np.max(np.abs(parts))):.3g} {unit}" if above or below else ""
    bar.set_label(f"{quantity} [{unit}]\n(± {scale:.3g} {unit}: the 99th percentile{beyond})")  # (two lines: one ran past the figure's top)
    bar.formatter = PlainTicks()  # (as every residual axis, `residual_axis`: −4e−14 … 4e−14, not −4 … 4 under a detached "1e−14")
    bar.update_ticks()
    places = [coordinate_labels(ds, d) for d in dims]
    labels = [", ".join(drawn_label(places[k][i]) for k, i in enumerate(at)) for at in np.ndindex(*(ds.sizes[d] for d in dims))]
    # (in σ, each fit's chi2_red, about 1 at the noise σ states, as the report gives it; else
    # rms_rel [%])
    per_fit = "chi2_red" if unit == "σ" and "chi2_red" in ds else "rms_rel"
    rms = ds[per_fit].transpose(*dims).values.reshape(-1) * (100 if per_fit == "rms_rel" else 1)
    ax_rms.plot(np.arange(batch.n_spectra), rms, "o-", ms=3, lw=0.8)
    _ring_missing_structure(ax_rms, batch, np.arange(batch.n_spectra), rms)  # (as `plot_batch`'s rms_rel panel)
    ax_rms.set_ylabel("rms_rel [%]" if per_fit == "rms_rel" else "chi2_red", fontsize=font_size("label", 9))
    # (as `plot_batch`'s rms_rel panel: over decades log; equal fits of the four REAL data.ods
    # sheets, 11.08 %, read "1e-11+1.107680505e1" under ticks 4 and 5 on a linear axis)
    rms_shown = rms[np.isfinite(rms)]
    if rms_shown.size and np.all(rms_shown > 0) and rms_shown.max() > 20 * rms_shown.min():
        ax_rms.set_yscale("log")
        labelled_log_ticks(ax_rms.yaxis)
    else:
        _window_flat(ax_rms, rms_shown)
        plain_linear_ticks(ax_rms.yaxis)
    if per_fit == "chi2_red":  # (the noise σ states: where a fit at it lies)
        ax_rms.axhline(1.0, color="0.4", lw=0.8, ls="--")
    ax_rms.grid(alpha=0.3, which="both")
    label_spectra_axis(ax_rms, labels, dims)
    in_sigma = " (map in σ)" if unit == "σ" else ""
    fig.suptitle(title or wrap_model(f"{batch.model}: residuals of {batch.n_spectra} spectr{'um' if batch.n_spectra == 1 else 'a'}{sharing_text(batch)}, {batch.weighting} weighting{in_sigma}",
                                     characters_across(8, font_size("suptitle", 12))))
    frame_spectra(ax_rms, batch.n_spectra, maps=(ax_re, ax_im))  # (last: on the final layout)
    return fig
