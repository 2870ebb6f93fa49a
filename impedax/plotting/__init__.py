"""Nyquist and Bode plots of data against a model, with a relative-residual panel.

Every function returns a matplotlib `Figure`; nothing is shown or saved implicitly.
"""

from __future__ import annotations

import functools
import math
import re
import types
from typing import Sequence

import matplotlib.pyplot as plt
from matplotlib.axes import Axes
from matplotlib.transforms import Bbox
from matplotlib.ticker import AutoLocator, Formatter, Locator, LogLocator, MaxNLocator, ScalarFormatter
import numpy as np
import xarray as xr

from ..arguments import figure_size, literal_text, shown
from ..data import SI_PREFIXES, format_frequency, format_quantity, si_prefix
from ..errors import ParameterError
from ..io.atomic import atomic_path

__all__ = ["plot_spectrum", "model_curve", "dense_model", "plot_nyquist", "equal_aspect", "nyquist_frame", "tail_frame", "mark_tail", "nyquist_view", "prefixed_axis", "nyquist_shape", "nyquist_panel_height", "spectrum_layout", "label_bode_above_residuals", "plot_bode", "save_figure", "FIGURE_DPI", "fitting_ylabel", "shade_bands", "refresh_legend", "legends_off_data", "drawn_points", "twin_axes", "bar_points", "plain_log_ticks", "frequency_axis", "time_axis", "FREQUENCY_PLAIN_FROM", "TIME_PLAIN_FROM", "labelled_log_ticks", "LabelledLogLocator", "LOG_LABEL_ROOM_EM", "magnitude_axis", "MagnitudeMinorLocator", "END_MANTISSAS", "SPAN_MAX_DECADES", "DECADE_TICKS_ALONE", "plain_linear_ticks", "PlainTicks", "residual_axis", "ROUNDING_RESIDUAL", "frame_points", "frame_spectra", "BEYOND_CELLS", "FRAME_ROOM_PT", "prefixable_unit", "wrap_model", "characters_across", "font_size", "label_spectra_axis", "drawn_label", "SpectraLocator", "plot_spectra"]


# the rcParams key each kind of impedax's text follows (`font_size`)
FONT_ROLES = {
    "legend": "legend.fontsize",
    "title": "axes.titlesize",
    "suptitle": "figure.titlesize",
    "label": "axes.labelsize",
    "tick": "xtick.labelsize",
    "text": "font.size",
}


def font_size(role: str, points: float) -> float:
    """The size [pt] of a ``role`` text (a key of `FONT_ROLES`) that impedax draws at ``points``
    with matplotlib's default rcParams: the rcParams size of that role when it was changed
    from matplotlib's default (``plt.rcParams["legend.fontsize"] = 14``, a style sheet), else
    ``points`` scaled by ``font.size`` over its default (10 pt): with default rcParams every
    figure looks as before, and a style or a larger base font takes effect."""
    from matplotlib import rcParams, rcParamsDefault
    from matplotlib.font_manager import FontProperties

    key = FONT_ROLES[role]
    if key != "font.size" and rcParams[key] is not None and rcParams[key] != rcParamsDefault[key]:
        return float(FontProperties(size=rcParams[key]).get_size_in_points())
    return points * float(rcParams["font.size"]) / float(rcParamsDefault["font.size"])


def _as_arrays(spectrum, what: str = "data", function: str = "plot_spectrum", *, frequency_needed: bool = True):
    """(frequency, Z) from a 1-D Dataset or a (frequency, Z) pair; without
    ``frequency_needed`` (a Nyquist plot) also from a 1-D complex array of Z, as (None, Z).
    Anything else is a `ParameterError` naming ``function``'s argument ``what``."""
    if spectrum is None:
        return None
    if isinstance(spectrum, xr.Dataset):
        z = spectrum["Z"]
        if z.ndim != 1:
            z = z.mean([d for d in z.dims if d != "frequency"])
        return np.asarray(spectrum["frequency"].values), np.asarray(z.values)
    pair_text = "a pair (frequency [Hz], Z [Ω])"
    takes = f"a spectrum Dataset (impedax.load) or {pair_text}" if frequency_needed else f"a spectrum Dataset (impedax.load), {pair_text} or a complex array of Z"
    pair = isinstance(spectrum, (tuple, list)) and len(spectrum) == 2 and all(np.ndim(part) >= 1 for part in spectrum)
    if not pair:
        try:
            z = np.asarray(spectrum)
        except (TypeError, ValueError):  # (a ragged list)
            z = np.zeros(0)
        if z.ndim == 1 and np.iscomplexobj(z):
            if frequency_needed:
                raise ParameterError(f"{function}: {what} is a complex array of Z without frequencies; pass {takes}")
            return None, z.astype(complex)
        raise ParameterError(f"{function}: {what} must be {takes}; got {shown(spectrum)} ({type(spectrum).__name__})")
    try:
        f, z = np.asarray(spectrum[0], dtype=float), np.asarray(spectrum[1], dtype=complex)
    except (TypeError, ValueError):
        raise ParameterError(f"{function}: {what} must be {takes}; got a pair that is not numbers") from None
    if f.shape != z.shape:
        raise ParameterError(f"{function}: {what}: frequency and Z differ in shape, {f.shape} and {z.shape}")
    return f, z


# a fit's model is drawn as a curve through this many points per decade of the data's band (at
# least `MODEL_POINTS_MIN`), not as a polygon through the data's frequencies: BioLogic's real
# spectrum, 7 points a decade, drew its arc as a few chords and a start's kinks looked like
# features of the model
MODEL_POINTS_PER_DECADE = 50
MODEL_POINTS_MIN = 200


def model_curve(fit) -> tuple[np.ndarray, np.ndarray]:
    """(frequency [Hz], Z [Ω]) of a fit's model (anything with ``frequency`` and ``z_model``)
    on a log grid over the data's band, `MODEL_POINTS_PER_DECADE` points a decade, by its
    ``predict`` (`FitResult.predict`); at the data's own frequencies for a result without one,
    or where the prediction is not finite."""
    predict = getattr(fit, "predict", None)
    return dense_model(fit.frequency, fit.z_model, predict if callable(predict) else None)


def dense_model(freq, z_model, predict) -> tuple[np.ndarray, np.ndarray]:
    """`model_curve` of a model known at ``freq`` as ``z_model`` and elsewhere by ``predict(grid)``
    (None: only at ``freq``, in order of frequency)."""
    freq, z_model = np.asarray(freq, float), np.asarray(z_model, complex)
    order = np.argsort(freq)
    freq, z_model = freq[order], z_model[order]
    band = freq[np.isfinite(freq) & (freq > 0)]
    if predict is None or band.size < 2 or band.min() == band.max():
        return freq, z_model
    lo, hi = float(band.min()), float(band.max())
    grid = np.geomspace(lo, hi, max(MODEL_POINTS_MIN, int(math.ceil(MODEL_POINTS_PER_DECADE * math.log10(hi / lo))) + 1))
    with np.errstate(all="ignore"):
        z = np.asarray(predict(grid), complex)
    if not np.all(np.isfinite(z)):
        return freq, z_model
    return grid, z


def _model_at(freq, model):
    """Model impedance at the data frequencies (log-frequency interpolation if they differ)."""
    f, z = model
    if np.array_equal(f, freq):
        return z
    order = np.argsort(f)
    x = np.log(f[order])
    return np.interp(np.log(freq), x, z[order].real) + 1j * np.interp(np.log(freq), x, z[order].imag)


def plot_nyquist(ax, data=None, model=None, *, data_label="data", model_label="model", curves=(), points=()):
    """Nyquist plot (Z' vs −Z'', equal axes) on ``ax``. ``data``, ``model``: a spectrum
    Dataset, a pair (frequency [Hz], Z [Ω]) or a complex array of Z [Ω] (impedance.py's
    ``plot_nyquist(Z)``). The panel's range and box follow the data (`nyquist_view`), the
    model's curve and ``curves`` (complex Z of further curves the caller draws on ``ax``)
    widening it by at most `MODEL_OVERSHOOT` of the data's span, ``points`` (complex Z the
    caller draws as data, masked points) held inside. A model alone is followed as data are,
    a capacitive tail zoomed on as theirs (else `impedax simulate --plot` of Meyer's finger would
    draw a vertical line on a GΩ axis)."""
    d = _as_arrays(data, "data", "plot_nyquist", frequency_needed=False)
    m = _as_arrays(model, "model", "plot_nyquist", frequency_needed=False)
    if d is not None:
        ax.plot(d[1].real, -d[1].imag, "o", ms=3.5, mfc="none", label=data_label)
    if m is not None:
        ax.plot(m[1].real, -m[1].imag, "-", lw=1.5, label=model_label)
    ax.set_xlabel("Z' [Ω]")
    ax.set_ylabel("−Z'' [Ω]")
    if d is not None:
        nyquist_view(ax, d[1], *([m[1]] if m is not None else []), *curves, frequency=d[0], points=points)
    elif m is not None:
        nyquist_view(ax, m[1], m[1], *curves, frequency=m[0], points=points)
    else:
        equal_aspect(ax)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=font_size("legend", 8))


# the margin a Nyquist panel keeps below (left of) the data on the side its widened range does
# not take: a fraction of the data's own span, and at least this fraction of the panel's, so
# that the markers of the lowest points of a very flat spectrum are not cut by the axis
NYQUIST_EDGE_MARGIN = 0.03


def equal_aspect(ax, *, frame: tuple[float, float, float, float] | None = None, fill: bool = False) -> None:
    """Equal scales on a Nyquist panel ``ax``: an arc is drawn as the semicircle it is. The
    range that fills the panel beyond the data is put above a flat spectrum (right of a steep
    one), where matplotlib would widen it about the middle: half of a flat spectrum's panel
    lay at −Z'' < 0, where no point is. Done at every draw (`_anchored_aspect`), so it holds
    at any figure size; limits set by hand (a zoom) are left alone. Both axes count in the same
    SI prefix of Ω (`prefixed_axis`). ``frame``: (Z' min, Z' max, −Z'' min, −Z'' max) the panel
    shows (`nyquist_frame`), in place of everything drawn on it; the panel's box narrows to
    its shape rather than widen the range past it (a frame that follows the data ends near
    them, where a wide panel ran far beyond). ``fill``: the panel keeps its box and the range
    widens beyond ``frame`` as beyond the data without one (a capacitive tail's zoom,
    `tail_frame`, 3 times taller than wide, would narrow the box to a strip)."""
    ax.set_aspect("equal", adjustable="datalim" if frame is None or fill else "box")
    ax.apply_aspect = types.MethodType(functools.partial(_anchored_aspect, frame=frame), ax)
    prefixed_axis(ax.xaxis, along=(ax.yaxis,))
    prefixed_axis(ax.yaxis, along=(ax.xaxis,))


# how far a model curve may take a Nyquist panel that follows the data (`nyquist_frame`)
# beyond them: this fraction of the data's span on each side; farther, the curve leaves the frame
MODEL_OVERSHOOT = 0.1


def nyquist_frame(z_data, *z_models, overshoot: float = MODEL_OVERSHOOT) -> tuple[float, float, float, float] | None:
    """(Z' min, Z' max, −Z'' min, −Z'' max) of a Nyquist panel that follows the data ``z_data``
    (complex Z): their extent, widened where a curve of ``z_models`` runs beyond it, by at most
    ``overshoot`` of the data's span on each side (a poor model that runs off to 29 kΩ beside
    data that end at 17 kΩ leaves the frame there). None when the data have no extent."""
    z = np.asarray(z_data, complex).ravel()
    z = z[np.isfinite(z)]
    if not z.size:
        return None
    x0, x1, y0, y1 = z.real.min(), z.real.max(), (-z.imag).min(), (-z.imag).max()
    if not (x1 > x0 and y1 > y0):
        return None
    reach = overshoot * max(x1 - x0, y1 - y0)
    for zm in z_models:
        zm = np.asarray(zm, complex).ravel()
        zm = zm[np.isfinite(zm)]
        if zm.size:
            x0, x1 = min(x0, max(zm.real.min(), x0 - reach)), max(x1, min(zm.real.max(), x1 + reach))
            y0, y1 = min(y0, max((-zm.imag).min(), y0 - reach)), max(y1, min((-zm.imag).max(), y1 + reach))
    return float(x0), float(x1), float(y0), float(y1)


# a Nyquist plot whose −Z'' spans this many times the Z' span of its structure or more has a
# capacitive tail (a capacitance in series) that flattens everything else to a vertical line
# at Z' ≈ 0: a SYNTHETIC finger (C_s + C_i in series with a skin R_sc || C_sc) reaches −Z'' =
# 1.2 GΩ at 1 Hz beside Z' ≤ 130 kΩ (`tail_frame`). The real spectra of tests/fixtures/real
# reach 2.8 (CHI), the battery benchmark 0.34, a blocking electrode's CPE line
# tan(α·90°) (12.7 at α = 0.95, 100 at α = 0.9936), whose Z' grows with −Z'' and which reads as it is
TAIL_RATIO = 100.0
# ... the panel then shows −Z'' up to this many times that Z' span above the lowest −Z''
TAIL_VIEW = 3.0
# a tail from this ratio on where the structure sits at the bottom: the points within `TAIL_VIEW`
# spans of the lowest −Z'' cover at least `TAIL_COVER` of the structure's Z' span (a SYNTHETIC
# R0 + R1 || CPE1 + Wo1 + G1 from 10 mHz, its Wo a capacitor at low frequency, reaches 58×;
# unzoomed it is a strip 2 mm wide under a legend that spills over its axis).
# A blocking electrode's CPE line covers only TAIL_VIEW/tan(α·90°) of its Z' span there (24 %
# at α = 0.95) and keeps its whole line
STRUCTURED_TAIL_RATIO = 10.0
TAIL_COVER = 0.5


# a model curve whose Z' spans less than this fraction of its largest |Z| has no Z' structure
# (`tail_frame` then takes the data's): round-off of 1/(jωC) computed in float64 is ~1e-16 of it
REACTIVE_ROUNDOFF = 1e-9


def tail_frame(z_data, *z_models, overshoot: float = MODEL_OVERSHOOT) -> tuple[float, float, float, float] | None:
    """(Z' min, Z' max, −Z'' min, −Z'' max) of a Nyquist panel zoomed on the structure of a
    spectrum with a capacitive tail, or None for one of ordinary shape. The structure's Z' span
    is that of the model curves ``z_models`` (noise-free) within the data's, else (no model, or
    models with no Z' beyond round-off, `REACTIVE_ROUNDOFF`) the data's
    (complex Z ``z_data``); a tail is a −Z'' span of `TAIL_RATIO` times that or more (the
    equal scales then draw the spectrum as a vertical line), or of `STRUCTURED_TAIL_RATIO`
    times that or more where the points within `TAIL_VIEW` spans of the lowest −Z'' cover
    `TAIL_COVER` of the Z' span (a strip of a panel otherwise). The frame's −Z'' runs from the
    lowest point (a model's by at most ``overshoot`` of the span below) to `TAIL_VIEW` spans
    above it; its Z' over the structure and the data inside (`mark_tail` names where the tail
    leaves it). impedance.py's ``plot_nyquist`` sets equal scales over all it draws, the whole tail."""
    z = np.asarray(z_data, complex).ravel()
    z = z[np.isfinite(z)]
    if z.size < 2:
        return None
    x0, x1 = float(z.real.min()), float(z.real.max())
    models = [m[np.isfinite(m)] for m in (np.asarray(m, complex).ravel() for m in z_models)]
    models = [m for m in models if m.size]
    curves = np.concatenate(models) if models else np.zeros(0, complex)
    # (a purely reactive model, a capacitor alone, has no Z' but round-off: the demo's naive C_gap
    # fit, Z' within ±4 nΩ beside data to 57 MΩ, framed 6 nΩ of −Z'' around the top point)
    if curves.size and np.ptp(curves.real) > REACTIVE_ROUNDOFF * float(np.abs(curves).max()):
        x0, x1 = max(x0, float(curves.real.min())), min(x1, float(curves.real.max()))
    span = x1 - x0
    y = -z.imag
    if not span > 0 or np.ptp(y) < STRUCTURED_TAIL_RATIO * span:
        return None
    if np.ptp(y) < TAIL_RATIO * span:  # (a tail only where the structure sits below it)
        low = z.real[(y <= y.min() + TAIL_VIEW * span) & (z.real >= x0) & (z.real <= x1)]
        if low.size < 2 or np.ptp(low) < TAIL_COVER * span:
            return None
    y0 = float(y.min())
    for m in models:
        y0 = min(y0, max(float((-m.imag).min()), y0 - overshoot * span))
    top = y0 + TAIL_VIEW * span
    inside = z[y <= top]  # (no shown point is cut at the sides)
    return min(x0, float(inside.real.min(initial=x0))), max(x1, float(inside.real.max(initial=x1))), y0, top


def mark_tail(ax, frame, z_data, frequency=None) -> None:
    """An arrow on the top edge of a Nyquist panel zoomed by `tail_frame` (``frame``) where the
    data (complex Z ``z_data``, at ``frequency`` [Hz] when known) leave it, and a line of text
    saying so: how high −Z'' runs, and below which frequency the points lie beyond the top."""
    from matplotlib.transforms import blended_transform_factory

    z = np.asarray(z_data, complex).ravel()
    f = None if frequency is None else np.asarray(frequency, float).ravel()
    keep = np.isfinite(z) & (np.ones(z.size, bool) if f is None else np.isfinite(f))
    z, f = z[keep], None if f is None else f[keep]
    y = -z.imag
    above = y > frame[3]
    if not above.any():
        return
    # the arrow stands where the data leave: at the highest point still inside, within the frame
    shown = np.flatnonzero(~above)
    x = float(z.real[shown[np.argmax(y[shown])]]) if shown.size else 0.5 * (frame[0] + frame[1])
    x = min(max(x, frame[0]), frame[1])
    peak = int(np.argmax(y))
    text = f"−Z'' runs off the top, to {format_quantity(float(y[peak]), 'Ω')}"
    if f is not None:
        text += f" at {format_frequency(float(f[peak]))}\n(every point below {format_frequency(float(f[above].max()))})"
    where = blended_transform_factory(ax.transData, ax.transAxes)
    ax.annotate("", xy=(x, 1.0), xycoords=where, xytext=(x, 0.88), textcoords=where, arrowprops=dict(arrowstyle="-|>", color="0.3", lw=1.2))
    ax.annotate(text, xy=(x, 0.94), xycoords=where, xytext=(16, 0), textcoords="offset points", ha="left", va="center", fontsize=font_size("text", 8),
                color="0.2", bbox=dict(boxstyle="round,pad=0.2", fc="white", ec="none", alpha=0.8))


def nyquist_view(ax, z_data, *z_models, frequency=None, frame: tuple[float, float, float, float] | str | None = None, points=()) -> None:
    """Equal scales on a Nyquist panel ``ax`` (`equal_aspect`) whose range and box follow the
    data ``z_data`` (`nyquist_frame`: the model curves ``z_models`` widen it by at most
    `MODEL_OVERSHOOT` of the data's span, farther they run off; ``points``, complex Z drawn as
    data apart, masked points, are held inside as the data are); over ``frame`` when given, or
    over all that is drawn with ``frame="drawn"`` (its extent when called, the box narrowed to it). For data with a capacitive tail beside the
    model curves (`tail_frame`): zoomed on the structure with the tail marked (`mark_tail`,
    ``frequency`` [Hz] of the data when known). Every Nyquist panel of a single spectrum (fit,
    KK, DRT, diagnosis, refinement, comparison) is framed here: framed otherwise, equal scales
    over a panel capped in height (`TALLEST_PANEL`) would widen the range past the data: REAL
    ZPlot's fit to 900 Ω beside data that end at 615 Ω, Gamry's KK test to 23 kΩ beside 18 kΩ."""
    if isinstance(frame, str) and frame != "drawn":
        raise ParameterError(f"nyquist_view: frame must be (Z' min, Z' max, −Z'' min, −Z'' max), None (the data's) or \"drawn\"; got {frame!r}")
    zoom = tail_frame(z_data, *z_models)
    if zoom is None:
        if frame is None:
            held = np.concatenate([np.asarray(z_data, complex).ravel(), np.asarray(points, complex).ravel()])
            frame = nyquist_frame(held, *z_models)
        elif isinstance(frame, str):  # (the extent of what is drawn as a frame: the box narrows to it, as to the data's, where
            lim = ax.dataLim          # equal scales over the whole box ran REAL ZPlot's posterior to 920 Ω beside curves that end at 620 Ω)
            frame = (lim.x0, lim.x1, lim.y0, lim.y1) if np.isfinite([lim.x0, lim.x1, lim.y0, lim.y1]).all() and lim.width > 0 and lim.height > 0 else None
        equal_aspect(ax, frame=frame)
        return
    equal_aspect(ax, frame=zoom, fill=True)
    mark_tail(ax, zoom, z_data, frequency)


def _anchored_aspect(ax, position=None, *, frame=None) -> None:
    """``ax.apply_aspect`` of a Nyquist panel (`equal_aspect`): from the data's limits (or
    ``frame``) with their margins, matplotlib's widening to the box's shape, then the widened
    axis moved so that the data sit at its low end."""
    lim = ax.dataLim if frame is None else Bbox.from_extents(frame[0], frame[2], frame[1], frame[3])
    anchored = ax.get_autoscalex_on() and ax.get_autoscaley_on() and np.isfinite([lim.x0, lim.x1, lim.y0, lim.y1]).all() and lim.width > 0 and lim.height > 0
    if anchored:
        (mx, my) = ax.margins()
        ax.set_xbound(lim.x0 - mx * lim.width, lim.x1 + mx * lim.width)
        ax.set_ybound(lim.y0 - my * lim.height, lim.y1 + my * lim.height)
    Axes.apply_aspect(ax, position)
    if not anchored:
        return
    for get, set_, low, size, margin in ((ax.get_xbound, ax.set_xbound, lim.x0, lim.width, mx), (ax.get_ybound, ax.set_ybound, lim.y0, lim.height, my)):
        a, b = get()
        if low - a > 2 * margin * size:  # (widened on this axis: the data sit in the middle)
            pad = max(margin * size, NYQUIST_EDGE_MARGIN * (b - a))
            set_(low - pad, low - pad + (b - a))


class _PrefixedFormatter(ScalarFormatter):
    """Tick labels of a linear axis in Ω, F, H or m (the unit in its label's brackets), counted in
    the SI prefix that suits the largest value in view of this axis and of ``along``: ``0.5,
    1.0, 1.5`` under ``Z' [MΩ]`` instead of ``0.5 1.0 1.5`` with a detached ``1e6``. Chosen
    anew at every draw (`set_locs`), so a zoom relabels the axis (and the axes that share it).
    An axis of another unit, or whose label already carries a prefix of the user's (values
    plotted in kΩ), is labelled as matplotlib does."""

    def __init__(self, along=(), label=None):
        super().__init__()
        self.along = tuple(along)
        self.label = label  # (the text that names the unit: the axis label when None)
        self.written: dict[int, str] = {}  # (the label texts this formatter wrote, by id)
        self.scale = None  # (None: the label names no unit to prefix; matplotlib's labels)
        self.decimals = 0

    def _labels(self):
        """The texts that name this axis' unit: its label (or ``label``), and the labels of the
        axes that share it (matplotlib gives them this one formatter)."""
        if self.label is not None:
            return [self.label]
        ax = self.axis.axes
        name = "x" if self.axis is ax.xaxis else "y"
        siblings = (ax.get_shared_x_axes() if name == "x" else ax.get_shared_y_axes()).get_siblings(ax)
        return [self.axis.get_label()] + [getattr(other, f"{name}axis").get_label() for other in siblings if other is not ax]

    def _ours(self, text) -> bool:
        """Whether ``text``'s bracketed unit is one to prefix (`_prefixable_label`)."""
        return _prefixable_label(text, self.written)

    def set_locs(self, locs):
        labels = self._labels()
        if not self._ours(labels[0]):
            self.scale = None
            return super().set_locs(locs)
        self.scale, prefix = view_prefix(self.axis, *self.along)
        _prefix_labels(labels, prefix, self.written)
        # as few decimals as tell the ticks apart at the scale (a lone tick: as write its value,
        # "20", not "20.0")
        scaled = np.asarray(locs, float) / self.scale
        tolerance = 1e-9 * (np.ptp(scaled) if scaled.size > 1 else np.max(np.abs(scaled), initial=0.0))
        self.decimals = next((d for d in range(7) if np.allclose(np.round(scaled, d), scaled, rtol=0, atol=max(tolerance, 1e-300))), 6)

    def get_offset(self):
        return "" if self.scale is not None else super().get_offset()

    def __call__(self, x, pos=None):
        if self.scale is None:
            return super().__call__(x, pos)
        return f"{x / self.scale:.{self.decimals}f}".replace("-", "\N{MINUS SIGN}")

    def format_data_short(self, value):
        """The cursor's readout in an interactive window: in the ticks' prefix (12.345 under
        [kΩ], where it read 12345.2)."""
        if self.scale is None:
            return super().format_data_short(value)
        return f"{value / self.scale:.5g}".replace("-", "\N{MINUS SIGN}")


# the unit in an axis label's brackets that `prefixed_axis` scales: [Ω], [kΩ], [µF], [m] → [µm]
# (a gap thickness u, which would read 2.8055 ×10⁻⁶ m beside matplotlib's 1e−6), and a
# compound unit led by one of them, [F s^(α-1)] → [nF s^(α-1)] (a CPE's Q) ...
_BRACKETED_UNIT = re.compile(r"\[(T|G|M|k|m|µ|n|p|f)?(Ω|F|H|m)((?: [^\]]*)?)\]")


def view_prefix(*axes) -> tuple[float, str]:
    """The (scale, prefix) of `si_prefix` for the largest value in view on ``axes`` (matplotlib
    axis objects: ``ax.xaxis``, ``ax.yaxis``); (1, "") when none is nonzero."""
    top = max((abs(v) for axis in axes for v in axis.get_view_interval() if np.isfinite(v)), default=0.0)
    return si_prefix(top) if top > 0 else (1.0, "")


def _prefixable_label(text, written: dict) -> bool:
    """Whether the label ``text``'s bracketed unit is one to prefix: bare (``[Ω]``), or a prefix
    a formatter wrote (``written``: the texts it wrote, by the label's id)."""
    match = _BRACKETED_UNIT.search(text.get_text())
    return match is not None and (not match.group(1) or written.get(id(text)) == text.get_text())


def _prefix_labels(labels, prefix: str, written: dict) -> None:
    """Write ``prefix`` into the bracketed unit of each of ``labels`` that is one to prefix
    (`_prefixable_label`), noting the texts in ``written``."""
    for label in labels:
        if _prefixable_label(label, written):
            label.set_text(_BRACKETED_UNIT.sub(lambda m: f"[{prefix}{m.group(2)}{m.group(3)}]", label.get_text()))
            written[id(label)] = label.get_text()


def prefixed_axis(axis, *, along=(), label=None, max_bins="auto") -> None:
    """Count the linear ``axis`` (``ax.xaxis``) of a quantity in Ω, F, H or m, named in its label's
    brackets (``Z' [Ω]``), in the SI prefix that suits its values (`_PrefixedFormatter`), with
    as many ticks as their labels fit (`FittingLocator`, at most ``max_bins`` intervals);
    ``along``: axes that share the scale (a Nyquist panel's two); ``label``: the text that
    names the unit and gets the prefix when it is not the axis label (a panel's title)."""
    axis.set_major_formatter(_PrefixedFormatter(along, label))
    axis.set_major_locator(FittingLocator(max_bins))


# a label's width per character, in em: a conservative average (tick labels, `characters_across`' titles)
LABEL_CHAR_EM = 0.62
# the free space kept between neighbouring tick labels, in em
LABEL_GAP_EM = 0.5


def tick_label_size(axis) -> float:
    """The font size [pt] of ``axis``' major tick labels."""
    return float(axis.get_major_ticks(1)[0].label1.get_fontsize())


def axis_length_pt(axis) -> float:
    """The length [pt] of ``axis`` on the figure (its axes' box width or height)."""
    ax = axis.axes
    box = ax.get_position()  # (figure fraction, after the aspect is applied at draw)
    width, height = ax.figure.get_size_inches() * 72
    return float(box.width * width if axis is ax.xaxis else box.height * height)


class FittingLocator(MaxNLocator):
    """matplotlib's tick choice (`MaxNLocator`, at most ``nbins`` intervals) thinned until the
    labels fit between their neighbours: on an x axis each label's width (its characters at
    `LABEL_CHAR_EM`, as the axis' formatter writes them, plus `LABEL_GAP_EM`), on a y axis its
    height, at most the ticks' spacing on the figure. A Nyquist panel a few millimetres wide
    ran ``0``, ``0.001``, ``0.002`` into "00002"; it keeps one tick where no two fit."""

    def __init__(self, nbins="auto"):
        super().__init__(nbins=nbins, steps=[1, 2, 2.5, 5, 10])
        self.most = nbins

    def tick_values(self, vmin, vmax):
        axis = self.axis
        locs = super().tick_values(vmin, vmax)  # (matplotlib's choice, kept where its labels fit)
        if axis is None or not np.isfinite([vmin, vmax]).all() or vmax == vmin:
            return locs
        lo, hi = sorted((vmin, vmax))
        size, per_unit = tick_label_size(axis), axis_length_pt(axis) / (hi - lo)
        in_view = lambda values: values[(values >= lo - 1e-9 * (hi - lo)) & (values <= hi + 1e-9 * (hi - lo))]  # noqa: E731
        nbins = len(in_view(locs)) - 1
        try:
            while nbins >= 1 and len(in_view(locs)) >= 2 and not self._fit(in_view(locs), size, per_unit):
                nbins -= 1
                self.set_params(nbins=max(nbins, 1))
                locs = super().tick_values(vmin, vmax)
        finally:
            self.set_params(nbins=self.most)
        shown = in_view(locs)
        if len(shown) >= 2 and not self._fit(shown, size, per_unit):
            return shown[[np.argmin(np.abs(shown - (lo + hi) / 2))]]  # (no two labels fit: the one nearest the middle alone)
        return locs

    def _fit(self, shown, size: float, per_unit: float) -> bool:
        """Whether the labels of ticks ``shown`` (values) fit between neighbours at ``per_unit``
        points per axis unit and font ``size`` [pt]."""
        spacing = float(np.min(np.diff(shown))) * per_unit
        if self.axis.axes.yaxis is self.axis:
            return spacing >= (1 + LABEL_GAP_EM) * size
        formatter = self.axis.get_major_formatter()
        formatter.set_locs(shown)
        texts = [formatter(x) for x in shown]
        widest = max(len(t) for t in texts)
        return spacing >= (widest * LABEL_CHAR_EM + LABEL_GAP_EM) * size


def prefixable_unit(text: str) -> bool:
    """Whether ``text`` (an axis label or a panel's title) names a unit in brackets that
    `prefixed_axis` counts in an SI prefix: ``[Ω]``, ``[F]``, ``[H]``, ``[m]`` (or one of them prefixed),
    or a compound unit led by one (``[F s^(α-1)]``)."""
    return _BRACKETED_UNIT.search(text) is not None


class PlainTicks(Formatter):
    """Tick labels of a linear axis as plain numbers, with as few digits as tell the ticks
    apart: ``1760, 1770`` or ``0.25, 0.5``; where the largest is 10⁶ or more, or below 10⁻⁴, in
    e-notation (``1e-13, 1.2e-13``). Never an offset or a multiplier beside the axis
    (matplotlib's ``1e-9+1.767766953e3`` over ticks 5, 6, 7)."""

    form = "{:g}"

    def set_locs(self, locs):
        super().set_locs(locs)
        self.form = _tick_form(np.asarray(locs, float))

    def __call__(self, x, pos=None):
        return "0" if x == 0 else self.form.format(x).replace("-", "\N{MINUS SIGN}")

    def format_data_short(self, value):
        return f"{value:.7g}"


def _tick_form(locs: np.ndarray) -> str:
    """The format `PlainTicks` writes the tick values ``locs`` in: fixed decimals where the
    largest is from 10⁻⁴ to 10⁶, else e-notation; the fewest digits that keep every tick exact
    to 1e-9 of their spacing."""
    locs = locs[np.isfinite(locs)]
    if not locs.size:
        return "{:g}"
    top = float(np.max(np.abs(locs)))
    step = float(np.min(np.diff(np.sort(locs)))) if locs.size > 1 else 0.0
    tolerance = 1e-9 * (step if step > 0 else top if top > 0 else 1.0)
    fixed = top == 0 or 1e-4 <= top < 1e6
    for digits in range(16):
        form = f"{{:.{digits}f}}" if fixed else f"{{:.{digits}e}}"
        if all(abs(float(form.format(v)) - v) <= tolerance for v in locs):
            break
    return form if fixed else f"{{:.{digits + 1}g}}"


def plain_linear_ticks(axis) -> None:
    """Label the linear ``axis`` (``ax.yaxis``) with `PlainTicks`: no offset, no multiplier."""
    axis.set_major_formatter(PlainTicks())


def plot_bode(ax_mod, ax_phase, data=None, model=None, *, data_label="data", model_label="model", nyquist=None):
    """|Z| (log-log) and phase [deg] against frequency (`frequency_axis`); |Z| in the SI prefix
    of the Nyquist panel ``nyquist`` of the same figure when given (`plain_log_ticks`)."""
    for spec, style, label in ((_as_arrays(data, "data", "plot_bode"), "o", data_label), (_as_arrays(model, "model", "plot_bode"), "-", model_label)):
        if spec is None:
            continue
        f, z = spec
        kw = dict(ms=3.5, mfc="none") if style == "o" else dict(lw=1.5)
        ax_mod.loglog(f, np.abs(z), style, label=label, **kw)
        ax_phase.semilogx(f, np.degrees(np.angle(z)), style, label=label, **kw)
    ax_mod.set_ylabel("|Z| [Ω]")
    magnitude_axis(ax_mod.yaxis, nyquist=nyquist)
    ax_phase.set_ylabel("phase [deg]")
    ax_phase.set_xlabel("frequency [Hz]")
    for ax in (ax_mod, ax_phase):
        frequency_axis(ax.xaxis)
        ax.grid(alpha=0.3, which="both")
    ax_mod.legend(fontsize=font_size("legend", 8))


def shade_bands(axes: Sequence, bands, *, color="tab:red", alpha=0.12, label="model fails"):
    """Shade frequency bands [(f_min, f_max), ...] on frequency axes; ``label`` names the shading
    in the first axis' legend (a legend drawn before is redrawn to include it)."""
    for ax in axes:
        for i, (lo, hi) in enumerate(bands):
            ax.axvspan(lo, hi, color=color, alpha=alpha, label=label if i == 0 and ax is axes[0] else None)
    if label and bands and len(axes):
        refresh_legend(axes[0])


def refresh_legend(ax) -> None:
    """Redraw ``ax``'s legend, if it has one, with every labelled artist drawn since (same font
    size and columns): a legend lists only what was on the axis when it was made."""
    legend = ax.get_legend()
    if legend is None:
        return
    texts = legend.get_texts()
    size = texts[0].get_fontsize() if texts else 8
    ax.legend(fontsize=size, ncol=getattr(legend, "_ncols", 1))


def drawn_points(ax) -> np.ndarray:
    """The display coordinates (N, 2) of what ``ax`` draws inside its frame: every point of its
    lines, with points put along each segment (a line between two markers crosses what lies
    between), the offsets of its scatter collections, and the bars of its histograms (`bar_points`).
    Shaded bands and the frame are not data."""
    inside = ax.get_window_extent()
    parts = [bar_points(ax)]
    for line in ax.get_lines():
        if not line.get_visible():
            continue
        xy = line.get_transform().transform(np.asarray(line.get_xydata(), float))
        xy = xy[np.all(np.isfinite(xy), axis=1)]
        if len(xy) > 1 and line.get_linestyle() not in ("None", "none", "", " "):
            t = np.linspace(0.0, 1.0, 9)[:-1]
            xy = np.concatenate([(xy[:-1, None, :] * (1 - t[None, :, None]) + xy[1:, None, :] * t[None, :, None]).reshape(-1, 2), xy[-1:]])
        parts.append(xy)
    for collection in ax.collections:
        offsets = np.asarray(collection.get_offsets(), float)
        if offsets.size and collection.get_visible():
            parts.append(collection.get_offset_transform().transform(offsets))
    xy = np.concatenate(parts)
    keep = (xy[:, 0] >= inside.x0) & (xy[:, 0] <= inside.x1) & (xy[:, 1] >= inside.y0) & (xy[:, 1] <= inside.y1)
    return xy[keep]


def bar_points(ax) -> np.ndarray:
    """The display coordinates (N, 2) of a grid over each bar ``ax`` draws (its `BarContainer`s:
    a histogram's, ``ax.bar``'s; not the shaded bands of ``axvspan``), 5 across and 5 up, edges
    included: a legend over the bars lies on at least one of them (the gap figure's legend of u
    covered the posterior's bars on REAL data.dfr, whose draws fill the panel)."""
    from matplotlib.container import BarContainer

    t = np.linspace(0.0, 1.0, 5)
    grid = np.stack(np.meshgrid(t, t), axis=-1).reshape(-1, 2)
    parts = []
    for container in ax.containers:
        if not isinstance(container, BarContainer):
            continue
        for bar in container.patches:
            if bar.get_visible() and bar.get_height() != 0:
                x0, y0, w, h = bar.get_x(), bar.get_y(), bar.get_width(), bar.get_height()
                parts.append(bar.get_transform().transform(np.column_stack([x0 + w * grid[:, 0], y0 + h * grid[:, 1]])))
    return np.concatenate(parts) if parts else np.empty((0, 2))


def legends_off_data(fig) -> None:
    """Move each legend of ``fig`` that covers drawn data (`drawn_points` of its axes and of their
    twins, `twin_axes`, after the figure's layout) out of its axes, across their width (same entries, columns, font size and title):
    above the frame, or, when the axes has a title (centred or at a side), below its tick labels and axis label; the
    figure's constrained layout then makes room for it. Matplotlib's "best" spot is the least
    covering of nine, not one that covers nothing: the legend of the CHI refine's tall Nyquist
    panel sat on its high-|Z| data and fitted curve, and the diagnosis' |Z| legend on the
    baseline. Also each legend that reaches beyond its frame (`_sticks_out`: over the axis and
    its tick labels). (Beside the frame, a legend of wrapped model names squeezed the panels to
    nothing.) A legend moved out changes the layout, so the others are checked again (at most
    `LEGEND_PASSES` times). Call it last (a legend redrawn after, `refresh_legend`, goes back inside)."""
    from matplotlib.transforms import offset_copy

    moved: set[int] = set()
    for _ in range(LEGEND_PASSES):
        fig.draw_without_rendering()
        covering = [ax for ax in fig.axes if id(ax) not in moved and ax.get_legend() is not None and (_covers_data(ax) or _sticks_out(ax))]
        if not covering:
            return
        for ax in covering:
            legend = ax.get_legend()
            texts = legend.get_texts()
            title = legend.get_title().get_text()
            options = dict(
                fontsize=texts[0].get_fontsize() if texts else font_size("legend", 8),
                title=title or None, title_fontsize=legend.get_title().get_fontsize() if title else None, borderaxespad=0.0,
            )
            frame = ax.get_window_extent()
            if any(ax.get_title(loc=loc) for loc in ("left", "center", "right")):  # (below: the title holds the space above; the joint bands' "trial=1" stands on the left)
                drop = (frame.y0 - ax.get_tightbbox(for_layout_only=True).y0) * 72.0 / fig.dpi + 3.0  # [pt]: the tick labels and the axis label
                options.update(loc="upper center", bbox_to_anchor=(0.5, 0.0), bbox_transform=offset_copy(ax.transAxes, fig=fig, y=-drop, units="points"))
            else:
                options.update(loc="lower center", bbox_to_anchor=(0.5, 1.02), bbox_transform=ax.transAxes)
            # as many columns as fit the panel's width (a legend wider than its panel would
            # squeeze the panel in the layout), one at least
            for ncol in range(max(len(texts), 1), 0, -1):
                placed = ax.legend(ncol=ncol, **options)
                if ncol == 1 or placed.get_window_extent(fig.canvas.get_renderer()).width <= frame.width:
                    break
            moved.add(id(ax))


LEGEND_PASSES = 3
"""`legends_off_data` checks the legends again after moving some out (the panels narrow), at
most this many times."""


def _sticks_out(ax) -> bool:
    """Whether ``ax``'s legend reaches beyond its frame (over the axis, its tick labels or the
    panel beside): a legend of long model names in a narrow Nyquist panel (model comparison)."""
    box, frame = ax.get_legend().get_window_extent(), ax.get_window_extent()
    return box.x0 < frame.x0 - 0.5 or box.x1 > frame.x1 + 0.5 or box.y0 < frame.y0 - 0.5 or box.y1 > frame.y1 + 0.5


def _covers_data(ax) -> bool:
    """Whether ``ax``'s legend (inside its frame) lies over a point it or a twin of it
    (`twin_axes`) draws (`drawn_points`): the gap figure's force legend, on the force axis, sat
    on the gap voltage's curves of its twin (the right axis)."""
    box = ax.get_legend().get_window_extent()
    xy = np.concatenate([drawn_points(a) for a in (ax, *twin_axes(ax))])
    return bool(np.any((xy[:, 0] >= box.x0) & (xy[:, 0] <= box.x1) & (xy[:, 1] >= box.y0) & (xy[:, 1] <= box.y1)))


def twin_axes(ax) -> list:
    """The other axes of ``ax``'s figure drawn in its frame and sharing one of its axes
    (``ax.twinx()``, ``ax.twiny()``, and ``ax`` itself seen from its twin)."""
    frame = ax.get_window_extent().bounds
    shared = set(ax.get_shared_x_axes().get_siblings(ax)) | set(ax.get_shared_y_axes().get_siblings(ax))
    return [other for other in ax.get_figure().axes if other is not ax and other in shared and np.allclose(other.get_window_extent().bounds, frame)]


def plot_spectrum(
    data=None, model=None, *, title: str | None = None, bands=None, data_label="data", model_label="model", residual_labels=("Re", "Im"), model_at_data=None,
    band_label="model fails", band_color="tab:red", figsize: tuple[float, float] | None = None, nyquist_curves=(), nyquist_points=(),
):
    """Nyquist, Bode (|Z|, phase) and, when both are given, relative residuals (Re, Im) of
    ``(Z_model − Z_data)/|Z_data|`` in percent: of ``model_at_data`` (the model at the data's
    frequencies) when given, so that a model drawn on its own grid (`model_curve`) is not
    interpolated for them. ``bands`` are shaded on the frequency axes (``band_label``, ``band_color``).
    The axes are Nyquist, |Z|, phase (and residuals), in that order, in either layout
    (`spectrum_layout`, which ``figsize`` (width, height) [in] sizes). The Nyquist panel follows
    the data (`plot_nyquist`); ``nyquist_curves`` and ``nyquist_points`` (complex Z) are the
    curves and points a caller draws on it afterwards (a diagnosis' suggestion and masked
    points), which its frame takes in as the model's curve and the data."""
    d, m = _as_arrays(data), _as_arrays(model)
    with_residuals = d is not None and m is not None
    shape = nyquist_shape(d, m)
    fig, (ax_nyq, ax_mod, ax_ph, ax_res) = spectrum_layout(shape, with_residuals, figsize=figsize)
    plot_nyquist(ax_nyq, data, model, data_label=data_label, model_label=model_label, curves=nyquist_curves, points=nyquist_points)
    plot_bode(ax_mod, ax_ph, data, model, data_label=data_label, model_label=model_label, nyquist=ax_nyq)
    freq_axes = [ax_mod, ax_ph]
    if with_residuals:
        z_model = _model_at(d[0], m) if model_at_data is None else np.asarray(model_at_data, complex)
        r = (z_model - d[1]) / np.abs(d[1])
        plot_residuals(ax_res, d[0], r.real, r.imag, labels=residual_labels, ylabel="residual (Z_model − Z)/|Z| [%]")
        label_bode_above_residuals(shape, ax_mod, ax_ph)
        freq_axes.append(ax_res)
    if bands:
        shade_bands(freq_axes, bands, label=band_label, color=band_color)
    if title:  # (each line wrapped to the figure, before a ' + ': a long model's title ran off it)
        width = characters_across(fig.get_figwidth(), font_size("suptitle", 12))
        fig.suptitle("\n".join(wrap_model(line, width) for line in title.split("\n")))
    # (the residual legend of data.dfr's fit, with its rounding-level entry, sat on the Re
    # residuals at 10–14 Hz: as the diagnosis, KK and comparison figures do)
    legends_off_data(fig)
    return fig


def plot_spectra(spectra: Sequence, labels: Sequence[str], *, title: str | None = None, legend_title: str | None = None):
    """Several spectra ((frequency, Z) pairs) on one Nyquist and one Bode figure, coloured
    from dark to light in their order (viridis) and named in the legend by ``labels``
    (titled ``legend_title``)."""
    arrays = [_as_arrays(s, f"spectra[{i}]", "plot_spectra") for i, s in enumerate(spectra)]
    fig, (ax_nyq, ax_mod, ax_ph, _) = spectrum_layout(nyquist_shape(*arrays), False)
    colours = plt.get_cmap("viridis")(np.linspace(0.0, 0.9, max(len(arrays), 1)))
    for (f, z), label, colour in zip(arrays, labels, colours):
        kw = dict(ms=3.5, mfc="none", lw=0.8, color=colour, label=str(label))
        ax_nyq.plot(z.real, -z.imag, "o-", **kw)
        ax_mod.loglog(f, np.abs(z), "o-", **kw)
        ax_ph.semilogx(f, np.degrees(np.angle(z)), "o-", **kw)
    ax_nyq.set(xlabel="Z' [Ω]", ylabel="−Z'' [Ω]")
    if arrays:  # (a tail: each spectrum's highest point named, `mark_tail` of them all)
        nyquist_view(ax_nyq, np.concatenate([z for _, z in arrays]), frequency=np.concatenate([f for f, _ in arrays]))
    else:
        equal_aspect(ax_nyq)
    ax_mod.set_ylabel("|Z| [Ω]")
    magnitude_axis(ax_mod.yaxis, nyquist=ax_nyq)
    ax_ph.set(ylabel="phase [deg]", xlabel="frequency [Hz]")
    for ax in (ax_mod, ax_ph):
        frequency_axis(ax.xaxis)
    for ax in (ax_nyq, ax_mod, ax_ph):
        ax.grid(alpha=0.3, which="both")
    ax_nyq.legend(fontsize=font_size("legend", 7), title=legend_title, title_fontsize=font_size("legend", 7), ncol=2 if len(arrays) > 5 else 1)
    if title:
        fig.suptitle(title)
    return fig


# a Nyquist plot this flat or flatter (height/width of what it draws) gets a panel across the
# figure's top (`spectrum_layout`): in the tall left panel of the other layout a battery's
# spectrum (about 1:3) filled a third of the panel, the rest empty plane
FLAT_NYQUIST = 0.6
# ... whose height follows the spectrum's shape down to this (a flatter one widens its range)
FLATTEST_PANEL = 0.25
# ... and up to this many inches (an arc of height/width 0.5 would make a figure of 11 inches;
# the range beyond the data widens to the right instead)
TALLEST_PANEL = 4.0


def nyquist_panel_height(shape: float, width: float) -> float:
    """Height [in] of a Nyquist panel across a figure ``width`` inches wide for a flat spectrum
    of ``shape`` (`nyquist_shape`): the shape times the width left for the axes, between
    `FLATTEST_PANEL` × that and `TALLEST_PANEL`."""
    return min(max(shape, FLATTEST_PANEL) * (width - 1.0), TALLEST_PANEL)


def nyquist_shape(*spectra) -> float:
    """Height/width of what a Nyquist panel draws for ``spectra`` ((frequency, Z) pairs, None
    skipped): the span of −Z'' over that of Z' (inf for a vertical line, nan for nothing)."""
    z = np.concatenate([np.asarray(s[1], complex).ravel() for s in spectra if s is not None] or [np.zeros(0, complex)])
    z = z[np.isfinite(z)]
    if not z.size:
        return math.nan
    width, height = float(np.ptp(z.real)), float(np.ptp(z.imag))
    return height / width if width > 0 else math.inf


def spectrum_layout(shape: float, with_residuals: bool, *, width: float = 11.0, figsize: tuple[float, float] | None = None):
    """A figure and its axes (Nyquist, |Z|, phase, residuals or None) for a spectrum whose
    Nyquist plot has ``shape`` (`nyquist_shape`). Up to `FLAT_NYQUIST`: the Nyquist panel
    across the top, as high as the spectrum's shape asks (`nyquist_panel_height`), |Z| and
    phase side by side below, the residuals across the bottom. Otherwise: the Nyquist panel
    down the left, |Z|, phase and residuals stacked on the right. The frequency axes are
    shared. ``figsize`` (width, height) [in]: the figure's size (the panels keep their
    proportions), in place of ``width`` and the height the layout asks (`figure_size`: two
    positive numbers, else a `ParameterError`)."""
    figsize = figure_size(figsize, "figsize")
    if figsize is not None:
        width = float(figsize[0])
    if shape <= FLAT_NYQUIST:
        heights = [nyquist_panel_height(shape, width), 2.6] + ([2.2] if with_residuals else [])
        fig = plt.figure(figsize=figsize or (width, sum(heights) + 0.6), layout="constrained")
        grid = fig.add_gridspec(len(heights), 2, height_ratios=heights)
        ax_nyq = fig.add_subplot(grid[0, :])
        ax_mod = fig.add_subplot(grid[1, 0])
        ax_ph = fig.add_subplot(grid[1, 1], sharex=ax_mod)
        ax_res = fig.add_subplot(grid[2, :], sharex=ax_mod) if with_residuals else None
        if not with_residuals:  # (|Z| stands beside the phase panel, which names the axis)
            ax_mod.set_xlabel("frequency [Hz]")
    else:
        fig = plt.figure(figsize=figsize or (width, 6.5 if with_residuals else 5), layout="constrained")
        grid = fig.add_gridspec(3 if with_residuals else 2, 2, width_ratios=[1, 1.2])
        ax_nyq = fig.add_subplot(grid[:, 0])
        ax_mod = fig.add_subplot(grid[0, 1])
        ax_ph = fig.add_subplot(grid[1, 1], sharex=ax_mod)
        ax_res = fig.add_subplot(grid[2, 1], sharex=ax_mod) if with_residuals else None
    return fig, (ax_nyq, ax_mod, ax_ph, ax_res)


def label_bode_above_residuals(shape: float, ax_mod, ax_ph) -> None:
    """The frequency labels of the |Z| and phase panels of `spectrum_layout` (with residuals)
    for a Nyquist ``shape``: none where they are stacked above the residual panel (its label
    names the column's shared axis), ``frequency [Hz]`` on each where they stand side by side
    above it (a flat spectrum), their ticks apart from the wide panel's, which they read
    without a unit."""
    for ax in (ax_mod, ax_ph):
        ax.set_xlabel("" if shape > FLAT_NYQUIST else "frequency [Hz]")


def plot_residuals(ax, freq, real, imag, *, labels=("Re", "Im"), ylabel="residual [%]", limit=None):
    """Relative residuals (fractions, drawn in %) of the real and imaginary parts against
    frequency, sorted; ``limit`` (a fraction) draws ±limit as the threshold."""
    order = np.argsort(freq)
    f = np.asarray(freq)[order]
    ax.semilogx(f, np.asarray(real)[order] * 100, "o-", ms=3, lw=0.8, label=labels[0])
    ax.semilogx(f, np.asarray(imag)[order] * 100, "s-", ms=3, lw=0.8, label=labels[1])
    if limit is not None:
        for sign in (-1, 1):
            ax.axhline(sign * limit * 100, color="tab:red", lw=0.7, ls="--", label="point threshold" if sign > 0 else None)
    ax.axhline(0, color="k", lw=0.6)
    fitting_ylabel(ax, ylabel)
    ax.set_xlabel("frequency [Hz]")
    frequency_axis(ax.xaxis)
    ax.grid(alpha=0.3, which="both")
    residual_axis(ax, np.concatenate([np.ravel(real), np.ravel(imag)]))
    ax.legend(fontsize=font_size("legend", 8), ncol=3 if limit is not None else 2)


# a residual within this fraction of |Z| is the round-off of float64 arithmetic, not a misfit:
# fits to noise-free SYNTHETIC data end at 1e-16 – 1e-13 of |Z|; a file written to 6 significant
# digits leaves 1e-7 or more
ROUNDING_RESIDUAL = 1e-10


def residual_axis(ax, residuals) -> bool:
    """Finish a residual panel ``ax`` (values drawn in %): on a linear y axis, tick labels as
    plain numbers (`PlainTicks`: ``−4e−14 … 4e−14``, where matplotlib wrote ticks −4 … 4 under
    a detached "1e−14" and the residuals of a fit to noise-free SYNTHETIC data read as a few
    percent); and where every residual (``residuals``: fractions of |Z|, real or complex, NaN
    ignored) lies within `ROUNDING_RESIDUAL`, a legend entry that says so, with the largest:
    "rounding level: |residual| ≤ 5.5e−14 %" (a legend made before is redrawn with it). Whether
    it added the entry: a caller that draws no legend otherwise then makes one. The fit, KK,
    DRT, Z-HIT, diagnosis, refinement and comparison figures finish their residual panels here."""
    if ax.get_yscale() == "linear":
        plain_linear_ticks(ax.yaxis)
    r = np.asarray(residuals)
    parts = np.abs(np.concatenate([np.real(r).ravel(), np.imag(r).ravel()]).astype(float))
    parts = parts[np.isfinite(parts)]
    if not parts.size or parts.max() > ROUNDING_RESIDUAL:
        return False
    largest = f"{parts.max() * 100:.2g}"  # (as the title and the report write rms_rel: 3.01e-14 %)
    ax.plot([], [], ls="none", label=f"rounding level: |residual| ≤ {largest} %")
    refresh_legend(ax)
    return True


# the room [pt] between a panel's frame and the centres of the points nearest it (`frame_points`):
# a marker of 4 pt (radius 2) and 4 pt of space
FRAME_ROOM_PT = 6.0


def frame_points(ax, values, *, room_pt: float = FRAME_ROOM_PT, axis: str = "y") -> None:
    """Widen ``ax``'s y range (linear or log) until the points ``values`` (y data; NaN, and on a
    log axis values ≤ 0, ignored) lie at least ``room_pt`` points inside its top and bottom, on
    the figure as laid out now (it is drawn to measure the panel: call it after the layout's last
    change, `legends_off_data`). matplotlib's margin is 5 % of the range: on the short rms_rel
    panel of the DRT figure of the REAL 130-cycle battery set, 3.4 pt, and cycle 22's point
    (0.92 %) touched the top of the frame. A range set by hand (a zoom) is widened alike; none is
    narrowed. ``axis="x"``: the same across, ``values`` x data, inside the left and right of the
    frame (`frame_spectra`)."""
    ax.get_figure().draw_without_rendering()
    _widen_to_frame(ax, values, room_pt, axis)


def _widen_to_frame(ax, values, room_pt: float, axis: str) -> None:
    """`frame_points` on the figure as last drawn."""
    y = np.asarray(values, float).ravel()
    across = axis == "x"
    log = (ax.get_xscale() if across else ax.get_yscale()) == "log"
    y = y[np.isfinite(y) & ((y > 0) if log else True)]
    if not y.size:
        return
    fig = ax.get_figure()
    box = ax.get_window_extent()
    height = (box.width if across else box.height) * 72.0 / fig.dpi  # [pt]
    if not height > 4 * room_pt:  # (a panel too small to keep the room: as matplotlib framed it)
        return
    forward, back = (np.log10, lambda v: 10.0**v) if log else (float, float)
    a, b = float(forward(y.min())), float(forward(y.max()))
    low, high = sorted(ax.get_xlim() if across else ax.get_ylim())
    lo, hi = float(forward(low)), float(forward(high))
    k = room_pt / height  # (the room as a fraction of the range)
    for _ in range(200):  # (widening the range widens the room in data units: to the fixed point)
        new_lo, new_hi = min(lo, a - k * (hi - lo)), max(hi, b + k * (hi - lo))
        if new_lo - lo > -1e-12 * (hi - lo) and new_hi - hi < 1e-12 * (hi - lo):
            break
        lo, hi = new_lo, new_hi
    if back(lo) < low or back(hi) > high:
        (ax.set_xlim if across else ax.set_ylim)(back(lo), back(hi))


def frame_spectra(axes, n: int, *, maps=()) -> None:
    """Keep the first and last of ``n`` spectra drawn at positions 0 … n − 1 of a batch's panels
    ``axes`` (one or several; `label_spectra_axis`) `FRAME_ROOM_PT` inside their left and right
    frame (`frame_points` across, the figure drawn once; call it last): at −0.5 … n − 0.5, half a
    spectrum's width, the end markers of the REAL 130 battery cycles stood 0.8 pt inside the
    frame, cut in half. ``maps``: panels sharing the x axis of the one panel ``axes`` whose cells
    span −0.5 … n − 0.5; the room beyond their cells is shaded grey (`BEYOND_CELLS`), where white
    read as a residual of 0. A marker larger than the 4 pt `FRAME_ROOM_PT` counts on (the
    rms_rel panel's rings, 7 pt) gets as much more room."""
    axes = list(axes) if isinstance(axes, (list, tuple)) else [axes]
    if not axes:
        return
    axes[0].get_figure().draw_without_rendering()
    for ax in axes:
        sizes = [line.get_markersize() for line in ax.get_lines() if line.get_marker() not in ("None", None, "", " ")]
        _widen_to_frame(ax, np.array([0.0, n - 1.0]), FRAME_ROOM_PT + max(0.0, max(sizes, default=0.0) / 2 - 2.0), "x")
    lo, hi = sorted(axes[0].get_xlim())
    for other in maps:
        for start, stop in ((lo, -0.5), (n - 0.5, hi)):
            if stop > start:
                other.axvspan(start, stop, color=BEYOND_CELLS, lw=0, zorder=0.5)
        other.set_xlim(lo, hi)  # (axvspan does not widen a shared range; set again all the same)


BEYOND_CELLS = "0.85"
"""The grey of a batch map's margin beyond its first and last spectrum (`frame_spectra`)."""


# how far [× the panel's height] a y label may run along its panel before `fitting_ylabel`
# takes a shorter form: the residual label of a fit's figure at matplotlib's default 10 pt runs
# 8 % past its 1.9 in panel, into the space between the panels, and is kept as it was
LABEL_OVERRUN = 1.15


def fitting_ylabel(ax, label: str) -> None:
    """Set ``label`` on ``ax``'s y axis, or, where it is longer than the panel is high (at a
    large font or a small figure, `LABEL_OVERRUN`) and has the form ``NAME (FORMULA... [UNIT]``,
    the first of ``NAME [UNIT]`` over ``(FORMULA...`` and ``NAME [UNIT]`` that fits: a 14 pt
    label ran past its panel into the next one. Chosen each time the figure's layout engine
    places the panels (the label as given first, then the layout again if it changed), so it
    holds at any figure size."""
    ax.set_ylabel(label)
    match = re.fullmatch(r"(.+?) (\(.+) (\[[^\[\]]+\])", label)
    if match is None:
        return
    name, formula, unit = match.groups()
    forms = (label, f"{name} {unit}\n{formula}", f"{name} {unit}")
    fig = ax.get_figure()
    engine = fig.get_layout_engine()
    if engine is None:  # (no layout: measured once, on the panel's place now)
        _shortest_fitting(ax, forms)
        return
    fitted = getattr(engine, "fitted_labels", None)
    if fitted is None:
        fitted = engine.fitted_labels = []
        layout = engine.execute

        def execute(figure):
            for axes, texts in fitted:
                axes.set_ylabel(texts[0])
            layout(figure)
            if any([_shortest_fitting(axes, texts) for axes, texts in fitted]):
                layout(figure)

        engine.execute = execute
    fitted.append((ax, forms))


def _shortest_fitting(ax, forms: Sequence[str]) -> bool:
    """Label ``ax``'s y axis with the first of ``forms`` whose longest line fits
    `LABEL_OVERRUN` × the panel's height (the last if none does); whether it is not the first."""
    from matplotlib.textpath import TextPath

    room = LABEL_OVERRUN * ax.get_position().height * ax.get_figure().get_figheight() * 72.0  # [pt]
    font = ax.yaxis.label.get_fontproperties()
    for i, text in enumerate(forms):
        if max(TextPath((0, 0), line, prop=font).get_extents().width for line in text.split("\n")) <= room:
            break
    ax.set_ylabel(text)
    return i > 0


# the smallest value a frequency axis [Hz] writes without an SI prefix (0.001; 500µ below it),
# and the smallest a time axis [s] does (0.1: 10 ms reads 10m, 1 ms 1m), `_plain_number`
FREQUENCY_PLAIN_FROM = 1e-3
TIME_PLAIN_FROM = 0.1


def _plain_number(x: float, prefix_from: float = 1e4, *, prefixes: bool = True, plain_from: float = FREQUENCY_PLAIN_FROM) -> str:
    """A tick value as printed: ``0.2``, ``40``, ``2000``; from 10⁴ up and below 10⁻³ with an SI
    prefix (``10k``, ``2M``, ``500µ``), where ``1e+06`` beside ``100000`` read badly; beyond the
    prefixes (below 1 f, from 1000 T up) in plain exponent form (``1e-20``, ``1e+18``), not
    ``1e-05f``. ``prefix_from``: the value from which a prefix is written (1000: the minor
    ticks of a log axis, 2k beside 20k); ``plain_from``: the smallest value written without one
    (0.1 on a time axis in s, `time_axis`: 10 ms reads ``10m``, as a time is said). ``prefixes``
    False (an axis in %, which a prefix misreads: "1µ" of a percent): the exponent form there
    too (``1e-6``, ``1e6``)."""
    if x == 0 or plain_from <= abs(x) < prefix_from:
        return f"{x:g}"
    smallest, largest = SI_PREFIXES[-1][0], SI_PREFIXES[0][0]
    if not prefixes:  # (``{:g}`` writes 10⁴ and 10⁵ out in full: "10000" beside "1e6" on one axis)
        return re.sub(r"e\+?(-?)0*(\d)", r"e\1\2", re.sub(r"\.?0+e", "e", f"{x:e}"))
    if not smallest <= abs(x) < 1e3 * largest:
        return f"{x:g}"
    scale, prefix = si_prefix(abs(x))
    return f"{x / scale:g}{prefix}"


def plain_log_ticks(axis, *, nyquist=None, prefixes: bool = True, own_prefix: bool = False, minor_labels: bool = False, plain_from: float = FREQUENCY_PLAIN_FROM) -> None:
    """Tick labels of a log-scaled ``axis`` (``ax.yaxis``) as plain numbers (0.2, 0.6, 2, 40,
    10k, 1M) instead of 2×10⁻¹ or 1e+06 (`_plain_number`): percentages read as they are
    printed. Which ticks are labelled is matplotlib's choice, thinned where the labels of the
    minor ticks (an axis over about a decade) would not fit between each other (`_MinorLogLabels`);
    those count in an SI prefix from 1000 up (2k, 3k next to 10k, 20k: "2000 3000 4000 6000"
    would run into one string beside "20k 30k"). An axis in % (``[%]`` in its label, `percent_axis`)
    gets no prefix: ``1e-6`` (a comparison's residuals would read "1µ, 100p" of a percent).

    ``nyquist``: the Nyquist panel (Axes) of the same figure; the axis, in Ω (``|Z| [Ω]``), then
    counts in that panel's prefix (`view_prefix` of its two axes, as `equal_aspect` counts it),
    named in its label (``|Z| [mΩ]``, ticks 20, 30, 40), and writes no prefix of its own on a
    tick (``1e-4`` of MΩ): else REAL exampleData.csv's comparison would have a Nyquist panel in
    mΩ beside |Z| in Ω ticked 0.02, 0.03, 0.04.

    ``prefixes`` False: no SI prefix on any tick (``1e-5``, ``1e5``), for a dimensionless
    quantity, which a prefix misreads: a corner plot's CPE exponent α would read "10µ".

    ``own_prefix``: with no Nyquist panel (the Z-HIT figure), the axis counts in the prefix of
    its own view (`view_prefix` of the axis alone), the same rule as ``nyquist``'s: a battery's
    |Z| of 15 – 45 mΩ reads ``|Z| [mΩ]``, ticks 20, 30, 40, as the fit and KK figures of the
    same spectrum read it, not 0.02, 0.03, 0.04 Ω.

    ``minor_labels``: label the minor ticks (thinned to fit) up to two decade ticks in view, where
    matplotlib labels the decades alone from one up: a range widened to 1 – 10 kΩ reads 1, 2, 3,
    4, 6, 10 (`magnitude_axis`). An axis that must read two labels or more at any range (rms_rel,
    a batch's parameters) is ticked by `labelled_log_ticks`.

    ``plain_from``: the smallest value written without an SI prefix (`_plain_number`; 0.1 on a
    time axis, `time_axis`)."""
    from matplotlib.ticker import LogFormatter

    prefix_of = (nyquist.xaxis, nyquist.yaxis) if nyquist is not None else (axis,) if own_prefix else None

    def scaled(formatter, x, prefix_from=1e4):
        scale = getattr(axis.get_major_formatter(), "scale", 1.0)
        return _plain_number(x / scale, prefix_from, prefixes=prefixes and scale == 1.0 and not percent_axis(formatter.axis), plain_from=plain_from)

    class _Plain(LogFormatter):
        def __init__(self):
            super().__init__()
            self.scale, self.written = 1.0, {}  # (the scale the ticks count in; the label texts written, `_prefix_labels`)

        def set_locs(self, locs=None):
            super().set_locs(locs)
            if prefix_of is not None and _prefixable_label(self.axis.label, self.written):
                self.scale, prefix = view_prefix(*prefix_of)
                _prefix_labels([self.axis.label], prefix, self.written)

        def __call__(self, x, pos=None):
            return scaled(self, x) if super().__call__(x, pos) else ""

    class _MinorLogLabels(LogFormatter):
        def set_locs(self, locs=None):
            super().set_locs(locs)
            _thin_minor_labels(self)

        def __call__(self, x, pos=None):
            minor = self.axis.get_minor_locator()
            if isinstance(minor, MagnitudeMinorLocator) and x > 0 and (minor.is_end(x) or not _integer_mantissa(x)):
                # (an end of a |Z| axis' range `_span_labels` set; an evenly spaced tick of a short one, each labelled, 0.98k too)
                return scaled(self, x, 1e3) if minor.is_end(x) or minor.linear else ""
            return scaled(self, x, 1e3) if super().__call__(x, pos) else ""

    axis.set_major_formatter(_Plain())
    axis.set_minor_formatter(_MinorLogLabels(labelOnlyBase=False))
    axis.get_minor_formatter().plain_from = plain_from  # (the labels' widths `_thin_minor_labels` measures)
    if minor_labels:
        axis.get_minor_formatter().minor_thresholds = (2, 0.4)


def frequency_axis(axis) -> None:
    """The one rule of every frequency axis of impedax's figures (``ax.xaxis`` of a Bode,
    residual, Z-HIT, diagnosis, comparison, posterior-band, gap or force panel; ``ax.yaxis`` of
    a batch's residual and KK maps): a log scale read in plain numbers, 0.01, 0.1, 1, 10, 100,
    1000, 10k, 100k, 1M, an SI prefix from 10⁴ up and below 10⁻³ (`plain_log_ticks`), not
    matplotlib's 10⁰ … 10⁶ beside the gap figures' 1, 10 … 1M. Its major ticks are matplotlib's
    (every decade, every k-th where 3 em of label each would not fit), so the widest label,
    ``0.001`` (2.9 em), clears its neighbour on a narrow panel over 8 decades as 10⁻³ did. Call
    it after the curves are drawn: ``semilogx`` and ``loglog`` set the scale again, and with it
    matplotlib's labels, on every axis shared with this one. The scale is set here too, even on
    an axis that reads log already: one joined by ``sharex`` to a log axis reads log but draws
    linearly until its scale is set (the joint posterior bands' second phase panel)."""
    _plain_log_axis(axis, FREQUENCY_PLAIN_FROM)


def time_axis(axis) -> None:
    """The one rule of every relaxation-time axis τ [s] of impedax's figures (the DRT's γ(τ)
    panel, a DRT batch's curves and its map over the spectra): `frequency_axis`'s rule, the same
    code (a log scale, matplotlib's major ticks, plain labels, minor labels thinned to fit, an SI
    prefix from 10⁴ up), with times below 0.1 s in their prefix as times are said: 1µ, 10µ, 100µ,
    1m, 10m, 0.1, 1, 10, 100, 1000, 10k, where matplotlib wrote 10⁻⁶ … 10⁴ beside frequency
    axes reading 0.01 … 10k. The axis' label names the unit, seconds (``τ [s]``), so a tick
    ``10m`` reads 10 ms. Call it after the curves are drawn, as `frequency_axis`."""
    _plain_log_axis(axis, TIME_PLAIN_FROM)


def _plain_log_axis(axis, plain_from: float) -> None:
    """The rule `frequency_axis` and `time_axis` share: ``axis`` log-scaled (set again: an axis
    joined by ``sharex`` to a log one draws linearly until then) and ticked by `plain_log_ticks`,
    written plainly from ``plain_from`` up."""
    (axis.axes.set_xscale if axis is axis.axes.xaxis else axis.axes.set_yscale)("log")
    plain_log_ticks(axis, plain_from=plain_from)


# the least distance between the centres of neighbouring labels of a `LabelledLogLocator`
# axis [em of its tick labels' font]: the font's height and a gap (a y axis), or a label's width
# and `LABEL_GAP_EM` (an x axis)
LOG_LABEL_ROOM_EM = 1.5


class LabelledLogLocator(Locator):
    """Major ticks of a log axis, each labelled (`labelled_log_ticks`): the richest of
    1 … 9 × 10ⁿ and the mantissas of `MINOR_LABEL_CHOICES` (1, 2, 3, 4, 6; 1, 2, 5; 1, 3; the
    decades, every k-th where they crowd) that puts two ticks or more in view with their labels
    `LOG_LABEL_ROOM_EM` apart (the widest label's width and `LABEL_GAP_EM` on an x axis); with fewer than `LINEAR_BELOW_MARKS` of 1 … 9 × 10ⁿ in view
    (under about half a decade, as `MagnitudeMinorLocator`), evenly spaced round values
    (`MaxNLocator`, as many as fit).
    matplotlib's log ticks labelled one value alone on a short range (a panel from 0.068 to
    0.195 % read "0.1") and the decades alone over three decades or more (a refinement's step at
    0.426 % stood against 1, 10 and 100)."""

    def __call__(self):
        return self.tick_values(*self.axis.get_view_interval())

    def _room(self, values) -> float:
        """The distance [pt] the labels of ``values`` need between their centres."""
        size = tick_label_size(self.axis)
        if self.axis is not None and self.axis is self.axis.axes.xaxis:
            widest = max((len(_plain_number(v)) for v in values), default=1)
            return (widest * LABEL_CHAR_EM + LABEL_GAP_EM) * size
        return LOG_LABEL_ROOM_EM * size

    def tick_values(self, vmin, vmax):
        lo, hi = sorted((float(vmin), float(vmax)))
        if not (lo > 0 and math.isfinite(hi) and hi > lo):
            return LogLocator().tick_values(vmin, vmax)
        length = axis_length_pt(self.axis)
        per_decade = length / math.log10(hi / lo)
        decades = range(math.floor(math.log10(lo)) - 1, math.ceil(math.log10(hi)) + 1)
        values = []
        if len(_marks_between(lo, hi)) >= LINEAR_BELOW_MARKS:
            for marks in (range(1, 10), *MINOR_LABEL_CHOICES):
                values = [m * 10.0**d for d in decades for m in marks if lo * (1 - 1e-9) <= m * 10.0**d <= hi * (1 + 1e-9)]
                if len(values) >= 2 and np.all(np.diff(np.log10(values)) * per_decade >= self._room(values)):
                    return np.array(values)
        if len(values) >= 2:  # decades too close for their labels: every k-th
            step = math.ceil(self._room(values) / per_decade)
            return np.array(values[::step] if len(values[::step]) >= 2 else values[:: max(len(values) - 1, 1)])
        for bins in range(max(2, int(length / self._room([lo, hi]))), 0, -1):  # (the most that fit)
            linear = MaxNLocator(nbins=bins, steps=[1, 2, 2.5, 5, 10]).tick_values(lo, hi)
            linear = linear[(linear >= lo * (1 - 1e-9)) & (linear <= hi * (1 + 1e-9)) & (linear > 0)]
            if len(linear) >= 2 and np.all(np.diff(np.log10(linear)) * per_decade >= self._room(linear)):
                break
        return linear


class _PlainLogLabels(Formatter):
    """Every tick of a `labelled_log_ticks` axis as a plain number (`_plain_number`): an SI
    prefix from 10⁴ up and below 10⁻³ where ``prefixes``, none on an axis in % (`percent_axis`)."""

    def __init__(self, prefixes: bool = True):
        self.prefixes = prefixes

    def __call__(self, x, pos=None):
        return _plain_number(float(x), prefixes=self.prefixes and not percent_axis(self.axis))


def labelled_log_ticks(axis, *, prefixes: bool = True) -> None:
    """Tick a log-scaled ``axis`` of values read off a figure (rms_rel [%], a batch's fitted
    parameters) at the labelled major ticks of `LabelledLogLocator`: two labels or more at any
    range, none running into the next, each a plain number (`_plain_number`; ``prefixes`` as
    `plain_log_ticks`'); unlabelled minor ticks at 2 … 9 × 10ⁿ for the grid. The one rule of
    the rms_rel panels (refinement, batch fit, KK and DRT batch) and of a batch's parameter
    panels."""
    from matplotlib.ticker import NullFormatter

    axis.set_major_locator(LabelledLogLocator())
    axis.set_major_formatter(_PlainLogLabels(prefixes))
    axis.set_minor_locator(LogLocator(subs=np.arange(2, 10)))
    axis.set_minor_formatter(NullFormatter())


def _integer_mantissa(x: float) -> bool:
    """Whether ``x`` > 0 is 1 … 9 × 10ⁿ (a log axis' decade or minor tick)."""
    mantissa = x / 10.0 ** math.floor(math.log10(x) + 1e-9)
    return abs(mantissa - round(mantissa)) < 1e-6


def _marks_between(lo: float, hi: float) -> list[float]:
    """The values 1 … 9 × 10ⁿ from ``lo`` to ``hi`` (both > 0)."""
    return [m * 10.0**d for d in range(math.floor(math.log10(lo)) - 1, math.ceil(math.log10(hi)) + 1) for m in range(1, 10) if lo <= m * 10.0**d <= hi]


# a |Z| axis with fewer than this many of 1 … 9 × 10ⁿ in view (under about half a decade) is
# ticked linearly (`MagnitudeMinorLocator`)
LINEAR_BELOW_MARKS = 3


class MagnitudeMinorLocator(LogLocator):
    """The minor ticks of a |Z| axis (`magnitude_axis`): matplotlib's (2 … 9 × 10ⁿ), or, where
    fewer than `LINEAR_BELOW_MARKS` of 1 … 9 × 10ⁿ lie in view, evenly spaced round values
    (matplotlib's `AutoLocator`, as many as the axis' length holds), each labelled: |Z| from 160
    to 340 Ω reads 150, 200, 250, 300, 350 (matplotlib turns linear only below two, and read 200,
    300 alone)."""

    def __init__(self):
        super().__init__(subs="auto")
        self.linear = False  # (the ticks last given are the evenly spaced ones)
        self.ends: set[float] = set()  # (ends of the range `_span_labels` set: ticked and labelled)

    def tick_values(self, vmin, vmax):
        lo, hi = sorted((vmin, vmax))
        self.linear = bool(lo > 0 and np.isfinite(hi) and len(_marks_between(lo, hi)) < LINEAR_BELOW_MARKS)
        if self.linear:
            linear = AutoLocator()
            linear.set_axis(self.axis)
            ticks = linear.tick_values(lo, hi)
        else:
            ticks = super().tick_values(vmin, vmax)
        ends = [e for e in self.ends if lo * (1 - 1e-9) <= e <= hi * (1 + 1e-9) and not np.any(np.isclose(ticks, e, rtol=1e-9, atol=0))]
        return np.sort(np.concatenate([ticks, ends])) if ends else ticks

    def is_end(self, x: float) -> bool:
        """Whether ``x`` is one of `ends`."""
        return any(abs(x - e) <= 1e-9 * e for e in self.ends)


# the most ticks `magnitude_axis` moves each end of its range outwards by, one at a time
SPAN_STEPS = 12
# the values between 1 … 9 × 10ⁿ an end of a |Z| axis' range may stand at, ticked and labelled
# there (`_span_labels`): |Z| from 57 to 112 Ω ends at 120, where the next tick, 200, left the
# top 40 % of the panel empty
END_MANTISSAS = (1.2, 1.5, 2.5)


def magnitude_axis(axis, *, nyquist=None, own_prefix: bool = False) -> None:
    """A log axis of impedance magnitude (``ax.yaxis`` of a Bode |Z| panel): plain tick labels,
    in the prefix of the ``nyquist`` panel when given (`plain_log_ticks`); short axes ticked
    linearly (`MagnitudeMinorLocator`); and a range that reaches a labelled tick at or below the
    lowest point drawn and one at or above the highest, two labels at least, no further than
    `SPAN_MAX_DECADES` beyond the points (`_span_labels`, at every draw, on the figure as laid out): |Z| from 150 to 450 Ω was labelled 200, 300, 400,
    none at or below the lowest point, and on a small figure one label alone. Range set by hand
    after this (a zoom) is left as it is. Every |Z| panel of impedax's figures is made so (fit,
    KK, DRT, diagnosis, comparison, posterior bands, Z-HIT, the gap analysis' |Z_R|).
    ``own_prefix``: no Nyquist panel, the prefix of the axis' own view (`plain_log_ticks`)."""
    plain_log_ticks(axis, nyquist=nyquist, own_prefix=own_prefix, minor_labels=True)
    axis.set_minor_locator(MagnitudeMinorLocator())
    ax = axis.axes
    state = {"ours": None if ax.get_autoscaley_on() else tuple(sorted(ax.get_ylim()))}
    ax.apply_aspect = types.MethodType(functools.partial(_spanning_aspect, state=state), ax)


def _spanning_aspect(ax, position=None, *, state) -> None:
    """``ax.apply_aspect`` of a |Z| panel (`magnitude_axis`): matplotlib's, then `_span_labels`."""
    Axes.apply_aspect(ax, position)
    if state.get("busy"):  # (measuring the panel, `axis_length_pt`, applies the aspect again)
        return
    # (the same range, data, panel and figure size as when it last ran: nothing to do; a figure's
    # layout and legends measure the panel many times per draw)
    seen = (ax.get_ylim(), tuple(ax.dataLim.intervaly), tuple(ax.get_position(original=True).bounds), tuple(ax.get_figure().get_size_inches()))
    if state.get("seen") == seen:
        return
    state["busy"] = True
    try:
        _span_labels(ax, state)
    finally:
        state["busy"] = False
    state["seen"] = (ax.get_ylim(), *seen[1:])


def _labelled_ticks(axis) -> list[float]:
    """The tick values ``axis`` labels in view (major and minor), as its formatters write them now."""
    lo, hi = sorted(axis.get_view_interval())
    shown: set[float] = set()
    for locator, formatter in ((axis.get_major_locator(), axis.get_major_formatter()), (axis.get_minor_locator(), axis.get_minor_formatter())):
        locs = np.asarray(locator(), float)
        locs = locs[(locs >= lo * (1 - 1e-9)) & (locs <= hi * (1 + 1e-9))]
        shown.update(float(v) for v, text in zip(locs, formatter.format_ticks(locs)) if text)
    return sorted(shown)


# a |Z| axis over more than this many decade ticks labels the decades alone (its minor
# formatter's threshold, `magnitude_axis`): its range ends at a decade (`_tick_beyond`)
DECADE_TICKS_ALONE = 2


def _tick_beyond(axis, bound: float, direction: int) -> float:
    """The nearest tick position beyond ``bound`` (below for ``direction`` −1, above for +1):
    of the axis' locators on the present view, 1 … 9 × 10ⁿ and `END_MANTISSAS` × 10ⁿ; a decade
    on an axis that labels the decades alone (`DECADE_TICKS_ALONE`: a |Z| over 7 decades ends
    at 1000 MΩ, not at 1200 or 200 MΩ beside labels 1, 100)."""
    lo, hi = sorted(axis.get_view_interval())
    d = math.floor(math.log10(bound))
    if math.floor(math.log10(hi)) - math.floor(math.log10(lo) - 1e-12) > DECADE_TICKS_ALONE:
        candidates = 10.0 ** np.arange(d - 1, d + 3, dtype=float)
    else:
        ends = [m * 10.0**k for k in range(d - 1, d + 2) for m in END_MANTISSAS]
        candidates = np.concatenate([np.asarray(axis.get_major_locator()(), float), np.asarray(axis.get_minor_locator()(), float), _marks_between(bound / 10.0, bound * 10.0), ends])
    candidates = candidates[np.isfinite(candidates) & (candidates > 0)]
    beyond = candidates[candidates < bound * (1 - 1e-9)] if direction < 0 else candidates[candidates > bound * (1 + 1e-9)]
    if not beyond.size:
        return bound / 2.0 if direction < 0 else bound * 2.0
    return float(beyond.max() if direction < 0 else beyond.min())


def _crowded(axis, value: float, others) -> bool:
    """Whether a label at ``value`` on the log y ``axis`` lies closer to one at ``others`` than
    the font's height and `LABEL_GAP_EM` (`FittingLocator`'s measure of a y axis)."""
    lo, hi = sorted(axis.get_view_interval())
    others = np.asarray(others, float)
    if not others.size or not hi > lo > 0:
        return False
    per_decade = axis_length_pt(axis) / math.log10(hi / lo)
    return bool(np.min(np.abs(np.log10(others / value))) * per_decade < (1 + LABEL_GAP_EM) * tick_label_size(axis))


# the farthest a |Z| axis' range reaches beyond its lowest and highest point drawn [decades]
# (`_span_labels`): the demo's naive C_gap fit, |Z| 166 Ω – 166 MΩ labelled every other decade,
# was widened to the next label, 10000 MΩ, 1.8 decades above its highest point
SPAN_MAX_DECADES = 0.5


def _span_labels(ax, state) -> None:
    """Widen the log y range of ``ax``, a tick at a time (`_tick_beyond`, at most `SPAN_STEPS`
    each way), until a labelled tick (`_labelled_ticks`) lies at or below the lowest point drawn
    in the range matplotlib chose and one at or above the highest, and two are labelled; as it
    was if none does. An end goes no further than `SPAN_MAX_DECADES` beyond the points drawn
    (matplotlib's margin is cut to it too): where the next label lies beyond, that end stays, and
    the labels nearest the extreme point lie inside the range. Not on a range set by hand
    (``state["ours"]``: the range the figure set)."""
    axis = ax.yaxis
    if ax.get_yscale() != "log":
        return
    low, high = sorted(ax.get_ylim())
    if not ax.get_autoscaley_on() and (low, high) != state["ours"]:
        return
    top, bottom = ax.dataLim.y1, ax.dataLim.y0 if ax.dataLim.y0 > 0 else axis.get_minpos()
    d_lo, d_hi = max(bottom, low), min(top, high)
    if not (np.all(np.isfinite([d_lo, d_hi, low, high])) and 0 < d_lo <= d_hi and 0 < low < high):
        return
    minor = axis.get_minor_locator()
    ends = minor.ends if isinstance(minor, MagnitudeMinorLocator) else set()
    reach = 10.0**SPAN_MAX_DECADES
    floor, ceiling = d_lo / reach, d_hi * reach
    lo, hi = max(low, floor), min(high, ceiling)
    if (lo, hi) != (low, high):
        ax.set_ybound(lo, hi)
    for _ in range(2 * SPAN_STEPS + 1):
        # (the ends it set, those still ends of the range whose labels clear their neighbours': an
        # end whose label would run into its neighbour's is not labelled, and the range moves on)
        ends.intersection_update({e for e in ends if min(abs(e - lo), abs(e - hi)) <= 1e-9 * e})
        for end in list(ends):
            if _crowded(axis, end, [v for v in _labelled_ticks(axis) if abs(v - end) > 1e-9 * end]):
                ends.discard(end)
        shown = _labelled_ticks(axis)
        below = any(v <= d_lo * (1 + 1e-9) for v in shown)
        above = any(v >= d_hi * (1 - 1e-9) for v in shown)
        if below and above and len(shown) >= 2:
            break
        moved = False
        if (not below or len(shown) < 2) and (step := _tick_beyond(axis, lo, -1)) >= floor * (1 - 1e-9):
            lo, moved = step, True
            ends.add(lo)
        if (not above or len(shown) < 2) and (step := _tick_beyond(axis, hi, +1)) <= ceiling * (1 + 1e-9):
            hi, moved = step, True
            ends.add(hi)
        if not moved:  # (the next label lies beyond `SPAN_MAX_DECADES`: the range as it is)
            break
        ax.set_ybound(lo, hi)
    else:
        ends.clear()
        ax.set_ybound(low, high)
    if not ax.get_autoscaley_on():
        state["ours"] = tuple(sorted(ax.get_ylim()))


def percent_axis(axis) -> bool:
    """Whether ``axis`` (None: not yet placed) counts in percent: ``[%]`` in its label."""
    return axis is not None and "[%]" in axis.get_label_text()


# the sets of mantissas a log axis' minor ticks are labelled at, from the most to the fewest,
# tried in turn after matplotlib's own choice until the labels fit (`_thin_minor_labels`; the
# major ticks of `LabelledLogLocator` after 1 … 9 × 10ⁿ)
MINOR_LABEL_CHOICES = ((1, 2, 3, 4, 6), (1, 2, 5), (1, 3), (1,))


def _thin_minor_labels(formatter) -> None:
    """Narrow the mantissas ``formatter`` (a `LogFormatter` of minor ticks) labels to the first
    of matplotlib's own choice and `MINOR_LABEL_CHOICES` (each no larger than it) whose labels fit between their
    neighbours (`FittingLocator`'s measure: characters at `LABEL_CHAR_EM` and `LABEL_GAP_EM`
    on an x axis, the font's height on a y axis); then add the mantissa of the tick nearest
    each end of the axis when its label fits too, so that the curve's extremes do not lie past
    the last label (an axis of 94–523 Ω labelled up to 400 now reads 500 as well)."""
    axis = formatter.axis
    chosen = getattr(formatter, "_sublabels", None)
    if axis is None or not chosen or chosen == {1}:
        return
    vmin, vmax = sorted(axis.get_view_interval())
    if not (vmin > 0 and vmax > vmin):
        return
    size = tick_label_size(axis)
    per_decade = axis_length_pt(axis) / math.log10(vmax / vmin)
    horizontal = axis is axis.axes.xaxis
    decades = range(math.floor(math.log10(vmin)), math.ceil(math.log10(vmax)) + 1)

    def labelled(marks):
        return [m * 10.0**d for d in decades for m in sorted(marks) if vmin <= m * 10.0**d <= vmax]

    def fits(values):
        where = np.log10(values) * per_decade
        widths = [(len(_plain_number(v, prefix_from=1e3, prefixes=not percent_axis(axis), plain_from=getattr(formatter, "plain_from", FREQUENCY_PLAIN_FROM))) * LABEL_CHAR_EM if horizontal else 1.0) * size for v in values]
        gaps = np.diff(where) - (np.array(widths[:-1]) + np.array(widths[1:])) / 2
        return bool(np.all(gaps >= LABEL_GAP_EM * size))

    for choice in (tuple(chosen), *(c for c in MINOR_LABEL_CHOICES if len(c) < len(chosen))):
        marks = set(choice) | {1}
        values = labelled(marks)
        if len(values) < 2:
            break
        if fits(values):
            break
    ticks = labelled(range(1, 10))
    for end in (ticks[-1:], ticks[:1]) if len(labelled(marks)) >= 2 else ():
        mantissa = {round(v / 10.0 ** math.floor(math.log10(v) + 1e-9)) for v in end}
        if not mantissa <= marks and fits(labelled(marks | mantissa)):
            marks |= mantissa
    formatter._sublabels = marks


def characters_across(width_in: float, fontsize: float) -> int:
    """How many characters of text at ``fontsize`` [pt] fit across ``width_in`` inches (a
    conservative average character width of `LABEL_CHAR_EM`, so titles are wrapped, never cut)."""
    return max(20, int(width_in * 72 / (LABEL_CHAR_EM * fontsize)))


def wrap_model(text: str, width: int) -> str:
    """``text`` (a circuit, a title) on lines of at most ``width`` characters, broken before a
    `` + `` where it can be, else at spaces."""
    import textwrap

    if len(text) <= width:
        return text
    lines: list[str] = []
    line = ""
    for k, piece in enumerate(text.split(" + ")):
        token = piece if k == 0 else "+ " + piece
        joined = token if not line else f"{line} {token}"
        if len(joined) <= width or not line:
            line = joined
        else:
            lines.append(line)
            line = token
    lines.append(line)
    return "\n".join(part for each in lines for part in (textwrap.wrap(each, width) or [each]))


# the steps between the labelled spectra of a batch axis (`SpectraLocator`): these, times 1, 10,
# 100, ..., tried from the smallest until the labels fit
SPECTRUM_STEPS = (1, 2, 5)
# a batch axis' labels longer than this many characters ("3, 0.5") are tilted by
# `SPECTRUM_LABEL_TILT` degrees; shorter ones stand upright
SPECTRUM_LABEL_LONG = 6
SPECTRUM_LABEL_TILT = 30.0
SPECTRUM_LABEL_SIZE = 8.0  # [pt]


class SpectraLocator(Locator):
    """Ticks of an axis whose positions 0, 1, ... are the spectra of a batch: every ``k``-th
    spectrum from the first (0, k, 2k, ...), ``k`` the smallest of `SPECTRUM_STEPS` × 10ⁿ whose
    labels fit between their neighbours on the figure (`FittingLocator`'s measure: upright,
    the widest label's characters at `LABEL_CHAR_EM` plus `LABEL_GAP_EM`; tilted by ``tilt``
    degrees, the font's height plus the gap across the slant). Chosen at every draw, so it
    follows the panel's width. Ten days on a panel 3 inches wide are all labelled; before, an
    even spread of 8 rounded to positions left out days 3 and 8, the very two the batch's
    Nyquist panel does not draw."""

    def __init__(self, labels: Sequence[str], tilt: float = 0.0):
        self.labels = [str(label) for label in labels]
        self.tilt = tilt

    def __call__(self):
        return self.tick_values(*self.axis.get_view_interval())

    def step(self, span: float) -> int:
        """Spectra between labelled ticks on a view ``span`` positions wide."""
        n = len(self.labels)
        if self.axis is None or n < 2 or not span > 0:
            return 1
        size = tick_label_size(self.axis)
        per_spectrum = axis_length_pt(self.axis) / span
        if self.tilt:
            needed = (1 + LABEL_GAP_EM) * size / math.sin(math.radians(self.tilt))
        else:
            needed = (max(len(label) for label in self.labels) * LABEL_CHAR_EM + LABEL_GAP_EM) * size
        for decade in range(int(math.log10(n)) + 2):
            for base in SPECTRUM_STEPS:
                if base * 10**decade * per_spectrum >= needed or base * 10**decade >= n:
                    return base * 10**decade
        return n

    def tick_values(self, vmin, vmax):
        lo, hi = sorted((vmin, vmax))
        first, last = max(0, math.ceil(lo)), min(len(self.labels) - 1, math.floor(hi))
        if last < first:
            return np.zeros(0)
        step = self.step(hi - lo)
        return np.arange(math.ceil(first / step) * step, last + 1, step, dtype=float)


def frequency_cell_edges(f: np.ndarray) -> np.ndarray:
    """The edges of a map's cells around ascending frequencies ``f`` [Hz]: halfway (in log f)
    between neighbours, the outer ones as far beyond the ends (±20 % for one frequency); the
    KK/Z-HIT and residual maps of a batch (`plotting.kk`, `plotting.fit`)."""
    if f.size < 2:
        return np.array([f[0] / 1.2, f[0] * 1.2])
    inner = np.sqrt(f[1:] * f[:-1])
    return np.concatenate([[f[0] ** 2 / inner[0]], inner, [f[-1] ** 2 / inner[-1]]])


def drawn_label(label) -> str:
    """A spectrum's label (a coordinate value, `data.label_text`) as a figure draws it: literally,
    its ``$`` escaped (`arguments.literal_text`), since a sheet or a ``stack --coords`` label named
    ``$\\bad$`` ended the figure in matplotlib's ParseFatalException."""
    from ..data import label_text

    return literal_text(label_text(label))


def label_spectra_axis(ax, labels: Sequence[str], dims: Sequence[str]) -> None:
    """Mark an x axis whose positions 0, 1, ... are the spectra of a batch with their labels
    (``129``, or ``1, 2`` over several dimensions): every spectrum, or every k-th where their
    labels do not all fit (`SpectraLocator`), and name the dimensions."""
    from matplotlib.ticker import FuncFormatter

    labels = [str(label) for label in labels]
    n = len(labels)
    tilt = SPECTRUM_LABEL_TILT if max(map(len, labels), default=0) > SPECTRUM_LABEL_LONG else 0.0
    ax.xaxis.set_major_locator(SpectraLocator(labels, tilt))
    ax.xaxis.set_major_formatter(FuncFormatter(lambda x, pos=None: labels[int(round(x))] if 0 <= round(x) < n and abs(x - round(x)) < 1e-6 else ""))
    ax.tick_params(axis="x", labelsize=font_size("tick", SPECTRUM_LABEL_SIZE), labelrotation=tilt)
    for tick in ax.xaxis.get_major_ticks():  # (ticks made later copy the first one's alignment)
        tick.label1.set_horizontalalignment("right" if tilt else "center")
    ax.set_xlim(-0.5, n - 0.5)
    ax.set_xlabel(", ".join(dims), fontsize=font_size("label", 8))


# the resolution [dots per inch] of a raster figure `save_figure` writes unless told
FIGURE_DPI = 120


def save_figure(fig, path, *, dpi: float | None = None) -> None:
    """Save ``fig`` atomically and close it. The format follows the extension (``.png``,
    ``.pdf``, ``.svg``, ``.eps``, any matplotlib writes; none: PNG); ``dpi`` the resolution of
    a raster format (default `FIGURE_DPI`)."""
    with atomic_path(path) as tmp:
        fmt = str(path).rsplit(".", 1)[-1].lower() if "." in str(path) else "png"
        fig.savefig(tmp, dpi=FIGURE_DPI if dpi is None else dpi, format=fmt)
    plt.close(fig)
