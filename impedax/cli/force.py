"""``impedax force meyer|vezzoli``: electrostatic force spectrum with the papers' parameters.

The peak over frequency is `impedax.models.force_maximum`: the grid's largest force refined by a
bounded Brent maximisation in log-frequency between its neighbouring grid points; a largest force
at an end of the band is reported as such (``at_band_edge``), not as a peak.
"""

from __future__ import annotations

import json
import math
import sys
import warnings
from pathlib import Path

import numpy as np

from ..arguments import number_text
from ..data import format_band, format_frequency, format_quantity
from .common import PAPER_MODELS, accept_negative_numbers, add_output_options, add_positional_model, check_band_options, check_memory, check_parameter_names, check_points, command_provenance, figure_options, figure_writer, number_option, parse_assignments, plan_outputs, to_jsonable

_MODELS = ("meyer", "vezzoli")
_RANGES = {"meyer": (10.0, 1e9), "vezzoli": (1.0, 1e6)}
CONVENTIONS = ("time-average", "peak")
OUT_SUFFIXES = (".csv", ".json")
# memory per frequency: the model's complex intermediates and the CSV/JSON text (measured: ~0.5 kB)
POINT_BYTES = 1024


MEYER_VARIANTS = ("rc", "cpe")
RELATIVE_PERMITTIVITIES = frozenset({"eps_i", "eps_s"})
"""The ``--param`` values that are relative permittivities (vezzoli's; meyer's circuit has none):
below 1 they are refused."""


def _defaults(model: str, variant: str = "rc", alpha: float | None = None) -> dict[str, float]:
    """The paper's parameters; Meyer's ``"cpe"`` variant has CPE_sc.Q = C_sc (2π·1 kHz)^(1−α)
    with α = ``alpha`` (default 0.8), the thesis's C_sc at 1 kHz (`meyer_model`)."""
    if model == "meyer":
        from ..models.meyer import THESIS_DRIVE_V, THESIS_PHYSICAL, meyer_model

        circuit = meyer_model(variant, **({} if alpha is None else {"alpha": alpha})).params
        return {**circuit, "area": THESIS_PHYSICAL.area, "v_a": THESIS_DRIVE_V}
    from ..models.vezzoli import TABLE2

    return {k: v for k, v in TABLE2.items() if k != "frequency"}


def _variant_of(params) -> str:
    """Meyer's variant of a parameter set: ``"cpe"`` when it holds CPE_sc.Q, else ``"rc"``."""
    return "cpe" if "CPE_sc.Q" in params else "rc"


def _meyer_variant(requested: str | None, given: dict[str, float]) -> str:
    """The Meyer variant: ``--variant`` when given, else read from the ``--param`` names
    (CPE_sc.* → ``"cpe"``, as `impedax.models.meyer`'s ``variant="auto"``); a ParameterError
    when the names belong to the other variant or to both."""
    from ..errors import ParameterError

    cpe = [n for n in given if n.startswith("CPE_sc.")]
    rc = [n for n in given if n == "C_sc"]
    takes = "--variant cpe takes CPE_sc.Q [F s^(α−1)] and CPE_sc.alpha in (0, 1] in place of C_sc"
    if cpe and rc:
        raise ParameterError(f"--param {rc[0]} and --param {cpe[0]} belong to different Meyer variants (rc: R_sc || C_sc, cpe: R_sc || CPE_sc): give one; {takes}")
    if requested == "rc" and cpe:
        raise ParameterError(f"--param {cpe[0]} belongs to the cpe variant (R_sc || CPE_sc), not to --variant rc; {takes}")
    if requested == "cpe" and rc:
        raise ParameterError(f"--param C_sc belongs to the rc variant (R_sc || C_sc), not to --variant cpe; {takes} (α = 1 with Q = C_sc is the rc variant)")
    return requested or ("cpe" if cpe else "rc")


def register(sub) -> None:
    from .common import add_quiet_option

    p = sub.add_parser(
        "force",
        help="electrostatic force spectrum of Meyer's or Vezzoli's model",
        description="Force over log-spaced frequencies (both ends included). meyer: thesis eq 3.6, "
        "thesis values (eq 3.13) and V_A = 140 V; vezzoli: eqs 7-10, Table 2 values. "
        "Parameters: meyer C_s C_i R_sc C_sc R_f [SI], area [m^2], v_a [V], or with --variant cpe (R_sc || CPE_sc, thesis Fig 5.3) "
        "CPE_sc.Q [F s^(alpha-1)] and CPE_sc.alpha in (0, 1] in place of C_sc (default alpha 0.8 and Q giving the thesis's C_sc at 1 kHz); vezzoli h_i h_s [m], area [m^2], eps_i eps_s, rho_s [ohm m], v_m [V]. "
        "The peak is the largest force refined between grid points (Brent, in log-frequency); when the force is largest at "
        "--fmin or --fmax, that is said instead of a peak, with what the band's end shows: still rising (its slope d ln F/d ln f there), levelled off, or on a plateau. "
        "vezzoli warns when C_i/C_s = eps_i h_s/(eps_s h_i) exceeds 0.1 (eq 8 assumes C_i << C_s).",
    )
    accept_negative_numbers(p)  # (--fmin -10: the value, refused by name, not argparse's "expected one argument")
    add_positional_model(p, type=str.lower, choices=_MODELS + tuple(n for n in PAPER_MODELS if n not in _MODELS), help="which paper's model (meyer-rc, meyer-cpe: meyer with --variant rc, cpe, as the names MODEL takes in every command)")
    p.add_argument("--param", action="append", metavar="NAME=VALUE", help="override a parameter; several after one --param (--param v_a=100 area=1e-4) or --param repeated; an area outside 1e-6–1e-2 m² (as impedax gap) or a meyer capacitance or resistance beyond 1000× either way of the thesis value (for CPE_sc.Q: its capacitance at 1 kHz, Q (2π·1 kHz)^(alpha−1), against C_sc's) is refused as a likely unit slip unless --no-param-check; a drive v_a or v_m outside 1 V–2 kV (as impedax gap --v0) or vezzoli's h_i outside 100 nm–900 µm, h_s outside 10 µm–5 mm or rho_s outside 300–3e6 ohm m gives a warning; meyer's area given alone scales the force as 1/A (C_i, C_sc, R_sc keep the thesis's values: a warning gives them scaled to the area)")
    p.add_argument("--variant", type=str.lower, choices=MEYER_VARIANTS, help="meyer's stratum corneum: rc (R_sc || C_sc, thesis Fig 3.3) or cpe (R_sc || CPE_sc, the fractional variant of Fig 5.3; parameters CPE_sc.Q, CPE_sc.alpha); default: cpe when a --param names CPE_sc.Q or CPE_sc.alpha, else rc")
    p.add_argument("--no-param-check", action="store_true", help="compute with any positive --param value: an implausible one gives a warning instead of an error")
    p.add_argument("--fmin", type=number_option, default=None, help="lowest frequency [Hz] (meyer 10, vezzoli 1)")
    p.add_argument("--fmax", type=number_option, default=None, help="highest frequency [Hz] (meyer 1e9, vezzoli 1e6)")
    p.add_argument("--points", type=int, default=None, help="number of frequencies (default 161; 1 when --fmin equals --fmax)")
    p.add_argument(
        "--convention", choices=CONVENTIONS, default="time-average",
        help="time-average (default): the mean force over a period of the sinusoidal drive; peak: the largest force over a period "
        "(vezzoli: exactly 2x the mean; meyer: at least 2x, more at low frequency where V_F and Q_f are out of phase)",
    )
    add_output_options(
        p, json="print JSON instead of CSV", plot="also save a plot of force against frequency",
        out="also write the spectrum to FILE: .csv as frequency_hz,force_n then, on every row, convention, model, the parameters (param_NAME) and impedax_version, written_utc; .json the --json document; nothing then goes to "
        "standard output unless --json is given ('-': standard output, as without --out)",
        out_metavar="FILE.csv|.json",
        title_names="the paper, the equation and the force convention; the drive and any changed parameters go in a subtitle",
    )
    add_quiet_option(p)  # (2026-12-03: every command takes --quiet, so a pipeline can pass it to each)
    p.set_defaults(run=run)


def _parameters(model: str, items, check: bool = True, variant: str | None = None) -> tuple[dict[str, float], dict[str, float], list[str]]:
    """The parameters (the paper's, overridden by ``--param``; Meyer's ``variant`` as
    `_meyer_variant`), those given, and warnings: a value given outside its plausible range
    (`models.plausible`) is a ParameterError, or with ``check`` False (``--no-param-check``) a
    warning; the drive (v_a, v_m) and Vezzoli's h_i, h_s, rho_s, eps_i, eps_s (`WARNED_ONLY`) are
    always only warned about, as gap's --v0. CPE_sc.alpha outside (0, 1] and a relative
    permittivity below 1 (`RELATIVE_PERMITTIVITIES`, `arguments.relative_permittivity`) are always refused."""
    from ..arguments import relative_permittivity
    from ..errors import ParameterError
    from ..models.plausible import WARNED_ONLY, implausible_cpe_message, implausible_message

    if variant is not None and model != "meyer":
        raise ParameterError(f"--variant {variant}: only meyer has variants (rc, cpe); {model} has none")
    listing = f"(parameters of {model}: {', '.join(_defaults(model))})"
    try:
        given = parse_assignments(items, "--param")
    except ParameterError as exc:
        raise ParameterError(f"{exc} {listing}") from None
    alpha = None
    if model == "meyer":
        variant = _meyer_variant(variant, given)
        alpha = given.get("CPE_sc.alpha") if variant == "cpe" else None
        if alpha is not None and not (math.isfinite(alpha) and 0 < alpha <= 1):
            raise ParameterError(f"--param CPE_sc.alpha={alpha:g}: must be in (0, 1] (1: CPE_sc is the capacitor C_sc = Q; 0: a resistor)")
    defaults = _defaults(model, variant or "rc", alpha)
    listing = f"(parameters of {model}{' --variant cpe' if variant == 'cpe' else ''}: {', '.join(defaults)})"
    check_parameter_names(given, defaults, "--param", model)
    for name, value in given.items():
        if not (math.isfinite(value) and value > 0):
            raise ParameterError(f"--param {name}={value:g}: must be positive {listing}")
        if name in RELATIVE_PERMITTIVITIES:
            relative_permittivity(value, f"--param {name}")
    notes = []
    for name, value in given.items():
        message = implausible_message(model, name, value)
        if name == "CPE_sc.Q":
            message = implausible_cpe_message(value, defaults["CPE_sc.alpha"])
        if message and name in WARNED_ONLY:
            notes.append(f"--param {name}={value:g}: {message}; computed as given")
            continue
        if message and check:
            raise ParameterError(f"--param {name}={value:g}: {message}; --no-param-check computes with it anyway")
        if message:
            notes.append(f"--param {name}={value:g}: {message}; computed as given (--no-param-check)")
    return {**defaults, **given}, given, notes


def _force(model: str, params: dict[str, float], freq: np.ndarray, convention: str) -> np.ndarray:
    if model == "meyer":
        from ..models.meyer import force_peak, force_time_average

        function = force_peak if convention == "peak" else force_time_average
        circuit = {k: v for k, v in params.items() if k not in ("area", "v_a")}  # (the variant read from the names)
        return np.asarray(function(circuit, freq, area=params["area"], v_a=params["v_a"], variant=_variant_of(params)))
    from ..models.vezzoli import Eq8ValidityWarning, electrovibration_force, electrovibration_force_peak

    function = electrovibration_force_peak if convention == "peak" else electrovibration_force
    with warnings.catch_warnings():  # said once by `run` (`_notes`), not at every evaluation
        warnings.simplefilter("ignore", Eq8ValidityWarning)
        return np.asarray(function(freq, **params))


def _finite_force(model: str, params: dict[str, float], given: dict[str, float], freq: np.ndarray, convention: str) -> np.ndarray:
    """`_force`, refused with one `ParameterError` naming the ``--param`` values given where it
    overflows (huge or tiny values make inf − inf or inf/inf: no maximum can be found)."""
    from ..errors import ParameterError

    try:
        force = _force(model, params, freq, convention)
    except OverflowError:  # (a Python float squared past 1e308)
        force = np.full(freq.shape, np.nan)
    bad = np.flatnonzero(~np.isfinite(force))
    if bad.size:
        others = f" and {bad.size - 1} other frequenc{'y' if bad.size == 2 else 'ies'}" if bad.size > 1 else ""
        where = f"the force is not finite (overflow) at {freq[bad[0]]:g} Hz{others}"
        values = ", ".join(f"{n}={v:g}" for n, v in given.items())
        frequencies_cause = not np.all(np.isfinite(_quiet_force(model, _defaults(model, _variant_of(params)), freq[bad], convention)))
        parameters_cause = bool(given) and not (frequencies_cause and np.all(np.isfinite(_quiet_force(model, params, _inside_default_band(model, freq[bad]), convention))))
        if frequencies_cause:
            low, high = _RANGES[model]
            options = " and ".join(o for o, out in (("raise --fmin", freq[bad].min() < low), ("lower --fmax", freq[bad].max() > high)) if out) or "narrow --fmin/--fmax"
            span = f"{freq[bad].min():g} Hz" if bad.size == 1 else f"{freq[bad].min():g}–{freq[bad].max():g} Hz"
            text = (
                f"{where}: the frequency range is the cause (--fmin {freq[0]:g} Hz, --fmax {freq[-1]:g} Hz; at {span} the model overflows "
                f"double precision even with the default parameters); {options} (the default band is {low:g}–{high:g} Hz)"
            )
            raise ParameterError(text + (f"; check the --param values too ({values})" if parameters_cause else ""))
        raise ParameterError(f"{where}; check the --param values ({values or 'the defaults'})")
    return force


def _quiet_force(model: str, params: dict[str, float], freq: np.ndarray, convention: str) -> np.ndarray:
    """`_force` with NumPy's overflow warnings silenced; an OverflowError gives NaN."""
    if freq.size == 0:
        return np.zeros(0)
    try:
        with np.errstate(all="ignore"):
            return _force(model, params, freq, convention)
    except OverflowError:
        return np.full(freq.shape, np.nan)


def _inside_default_band(model: str, freq: np.ndarray) -> np.ndarray:
    """The frequencies clipped to the command's default band (where the defaults are finite)."""
    low, high = _RANGES[model]
    return np.clip(freq, low, high)


# meyer's elements that thesis eq 3.13 derives from the contact area (`MeyerPhysical`): the
# capacitances grow with A, R_sc falls as 1/A (C_s, the cable, and R_f, the body, do not)
_AREA_SCALED = {"C_i": 1, "C_sc": 1, "CPE_sc.Q": 1, "R_sc": -1}


def _area_alone_note(params: dict[str, float], given: dict[str, float]) -> str | None:
    """meyer: a --param area without any of the elements eq 3.13 derives from it keeps their
    thesis values, so eq 3.6's 1/(2 A ε0) makes F ∝ 1/A, where a contact of that area, its layers
    unchanged, has C_i, C_sc ∝ A and R_sc ∝ 1/A (a walkthrough halved A and saw the force
    double, 2026-12-05). None otherwise."""
    from ..models.meyer import THESIS_PHYSICAL

    if "area" not in given or any(name in given for name in _AREA_SCALED):
        return None
    ratio = params["area"] / THESIS_PHYSICAL.area
    scaled = " ".join(f"{name}={params[name] * ratio**power:.4g}" for name, power in _AREA_SCALED.items() if name in params)
    return (f"--param area={params['area']:g} changes only eq 3.6's 1/A: the elements eq 3.13 derives from the area keep the thesis's values "
            f"for its {THESIS_PHYSICAL.area * 1e6:.4g} mm² contact, so the force is that contact's × {1 / ratio:.4g}; for a contact of this area with the same layers, "
            f"give them scaled too: --param area={params['area']:g} {scaled} (capacitances × A/A0, R_sc × A0/A)")


def _notes(model: str, params: dict[str, float], given: dict[str, float] | None = None) -> list[str]:
    """Warnings on the parameters: meyer's area given alone (`_area_alone_note`); vezzoli's
    C_i/C_s against eq 8's condition C_i ≪ C_s."""
    if model == "meyer":
        note = _area_alone_note(params, given or {})
        return [note] if note else []
    if model != "vezzoli":
        return []
    from ..models.vezzoli import eq8_validity_message

    message = eq8_validity_message(**{k: params[k] for k in ("h_i", "h_s", "eps_i", "eps_s")})
    return [message] if message else []


_UNITS = {"C_s": "F", "C_i": "F", "C_sc": "F", "R_sc": "Ω", "R_f": "Ω", "CPE_sc.Q": "F s^(α−1)", "area": "m²", "v_a": "V", "h_i": "m", "h_s": "m", "rho_s": "Ω m", "v_m": "V"}


def _changed(model: str, params: dict[str, float]) -> dict[str, float]:
    """The parameters whose values differ from the paper's (`_defaults`; Meyer's CPE variant:
    those of its α)."""
    defaults = _defaults(model, _variant_of(params), params.get("CPE_sc.alpha")) if model == "meyer" else _defaults(model)
    return {k: v for k, v in params.items() if v != defaults[k]}


def _plot_text(model: str, params: dict[str, float], convention: str) -> tuple[str, str]:
    """(title, subtitle) of the force plot. The title says the convention, and names the paper's
    figure only when the parameters and the convention are the figure's (Meyer Fig 3.4: the
    time average with the eq 3.13 values at V_A = 140 V; Vezzoli Fig 8: the time average under
    Meyer's conditions, one stratum corneum thickness); the subtitle gives the drive amplitude
    and the parameters changed from the paper's values."""
    changed = _changed(model, params)
    listed = ", ".join(f"{k} = {v:.4g} {_UNITS.get(k, '')}".rstrip() for k, v in changed.items() if k not in ("v_a", "v_m"))
    average = convention == "time-average"
    if model == "meyer":
        what = "time-averaged force" if average else "peak force (largest over a period)"
        cpe = _variant_of(params) == "cpe"
        figure = ", thesis Fig 3.4" if average and not changed and not cpe else ""
        title = f"Meyer (2012) thesis eq 3.6{', R_sc ∥ CPE_sc' if cpe else ''}: {what}{figure}"
        drive = f"V_A = {params['v_a']:.4g} V" + ("" if "v_a" not in changed else f" (thesis {_defaults(model)['v_a']:g} V)")
        if cpe:
            alpha = params["CPE_sc.alpha"]
            values = f"eq 3.13 values, CPE_sc α = {alpha:.4g}, Q = {params['CPE_sc.Q']:.4g} F s^(α−1)" + ("" if "CPE_sc.Q" in changed else " (C_sc of eq 3.13 at 1 kHz)")
            listed = ", ".join(f"{k} = {v:.4g} {_UNITS.get(k, '')}".rstrip() for k, v in changed.items() if k not in ("v_a", "CPE_sc.Q", "CPE_sc.alpha"))
            values += f"; changed: {listed}" if listed else ""
        elif not changed:
            values = "thesis eq 3.13 values" + ("" if average else " (Fig 3.4 shows their time average)")
        else:
            values = "eq 3.13 values" + (f"; changed: {listed}" if listed else "")
        return title, f"{drive}; {values}"
    from ..models.vezzoli import MEYER_CONDITIONS

    what = "eq 10, time-averaged force" if average else "eqs 7 + 9, peak force (2 × eq 10)"
    fig8 = average and set(changed) <= {*MEYER_CONDITIONS, "h_s"} and all(params[k] == v for k, v in MEYER_CONDITIONS.items())
    title = f"Vezzoli et al. {what}" + (f", Fig 8 conditions (h_s = {params['h_s'] * 1e6:.4g} µm)" if fig8 else "")
    drive = f"V_m = {params['v_m']:.4g} V" + ("" if "v_m" not in changed else f" (Table 2: {_defaults(model)['v_m']:g} V)")
    values = "Table 2 values" if not changed else "Table 2 values" + (f"; changed: {listed}" if listed else "")
    return title, f"{drive}; {values}"


_SYMBOLS = {"v_a": "V_A", "v_m": "V_m", "area": "A"}


def _value_text(name: str, value: float) -> str:
    """One parameter's value for the stderr line: SI prefixes where the unit takes them (``140 V``,
    ``1.7 nF``, ``90 µm``), an area in mm², a permittivity as a number."""
    if name == "area":
        return f"{value * 1e6:.4g} mm²"
    unit = _UNITS.get(name, "")
    if unit in ("F", "Ω", "V", "m"):
        return format_quantity(value, unit, 4)
    return f"{value:.4g} {unit}".rstrip()


def _conditions_text(model: str, params: dict[str, float]) -> str:
    """What the force is computed for, on the stderr line: the drive amplitude and the contact
    area, then whose values the rest are and which differ from the paper's, each with the
    paper's value (``at V_A = 100 V, A = 50.27 mm² (thesis eq 3.13 values except V_A: 140 V in
    the thesis)``)."""
    meyer = model == "meyer"
    defaults = _defaults(model, _variant_of(params), params.get("CPE_sc.alpha")) if meyer else _defaults(model)
    drive = "v_a" if meyer else "v_m"
    base, where = ("thesis eq 3.13 values", "the thesis") if meyer else ("Table 2 values", "Table 2")
    if meyer and _variant_of(params) == "cpe":
        base += f", R_sc ∥ CPE_sc with α = {params['CPE_sc.alpha']:.4g}"
    head = f"{_SYMBOLS[drive]} = {_value_text(drive, params[drive])}, A = {_value_text('area', params['area'])}"
    changed = _changed(model, params)
    if not changed:
        return f"at {head} ({base})"
    listed = "; ".join(f"{_SYMBOLS.get(k, k)}: {_value_text(k, defaults[k])} in {where}" for k in changed)
    return f"at {head} ({base} except {listed})"


def _figure(model: str, freq, force, peak: dict, params: dict[str, float], convention: str, notes: list[str]):
    """The force plot: `plot_force_spectrum` titled by `_plot_text`, with the warnings of
    `_notes` (Vezzoli eq 8's validity) under the axes."""
    from ..plotting.models import plot_force_spectrum

    title, subtitle = _plot_text(model, params, convention)
    return plot_force_spectrum(freq, force, title=title, convention=convention, peak=peak, subtitle=subtitle, notes=notes)


def _peak_text(peak: dict) -> str:
    """The stderr line's peak, in SI prefixes as the figure's legend: ``peak 164.2 mN at 37 kHz
    (refined between grid points; grid maximum 164.2 mN at 35.5 kHz)``."""
    from ..models.peak import FORCE_PLATEAU_REL, band_end_words

    where = f"{format_quantity(peak['force_n'], 'N', 4)} at {format_frequency(peak['frequency_hz'])}"
    if peak["band_edge"] == "fmin=fmax":
        return f"{where} (one frequency: no peak located)"
    if peak["band_edge"] == "flat":
        return f"no peak in the band: the force is {format_quantity(peak['force_n'], 'N', 4)} at every frequency"
    if peak["at_band_edge"]:
        option, side = ("--fmin", "below") if peak["band_edge"] == "fmin" else ("--fmax", "above")
        plateau = peak.get("plateau_hz")
        if plateau:  # (a high-pass's limit, as Vezzoli's eq 10: "still rises" alone read as still growing)
            band = format_band(*plateau)
            return (f"no peak in the band: the force is largest at {option}, {where}, on a plateau: within {FORCE_PLATEAU_REL * 100:.0f} % of it over {band}, "
                    f"where it levels off (it may still rise {side} {option})")
        # (what the band's end shows, 2026-12-06: over 10–50 kHz Vezzoli's eq 10 changes by 0.012 % per decade at 50 kHz, and
        # "and still rises above it" was said as of a force that grows; no plateau is judged on less than a decade)
        return f"no peak in the band: the force is largest at {option}, {where}, {band_end_words(peak.get('edge_slope'), side, option)}"
    grid = f"{format_quantity(peak['grid_force_n'], 'N', 4)} at {format_frequency(peak['grid_frequency_hz'])}"
    return f"peak {where} (refined between grid points; grid maximum {grid})"


def _out_path(path: str | None) -> str | None:
    """``--out``: None for none or ``-`` (standard output, as without --out); a FILE whose
    extension is not .csv or .json is refused before any work."""
    from ..errors import DataError
    from ..io.atomic import check_file_name

    if path is None or path == "-":
        return None
    if not path.strip():
        return path  # (`plan_outputs` says "empty file name")
    check_file_name(path, "force.csv", "--out")
    suffix = Path(path).suffix.lower()
    if suffix not in OUT_SUFFIXES:
        raise DataError(f"--out: unknown extension {suffix or '(none)'!r} for a force spectrum; use .csv (frequency_hz,force_n, ...) or .json (the --json document)", path=path)
    return path


def _csv_text(freq, force, model: str, convention: str, variant: str | None, params: dict[str, float], record: dict) -> str:
    """The force spectrum as CSV: ``frequency_hz,force_n``, then, the same on every row, what
    makes it (docs/models.md, "Force on the command line"): ``convention`` (time-average or
    peak: a factor 2 to 64 apart), ``model``, ``variant`` (meyer), each parameter as used
    (``param_NAME``, SI; the drive ``param_v_a``/``param_v_m`` [V] among them) and
    ``impedax_version``, ``written_utc``. Each number in its shortest exact form, as in the
    JSON: the CSV reads back bit for bit."""
    constant = {"convention": convention, "model": model, **({"variant": variant} if variant else {})}
    constant.update({f"param_{name}": number_text(value) for name, value in params.items()})
    constant.update({"impedax_version": record["impedax_version"], "written_utc": record["written_utc"]})
    tail = ",".join(str(v) for v in constant.values())
    lines = [",".join(["frequency_hz", "force_n", *constant])] + [f"{number_text(f)},{number_text(v)},{tail}" for f, v in zip(freq, force)]
    return "\n".join(lines) + "\n"


def named_variant(args) -> None:
    """MODEL meyer-rc or meyer-cpe (`common.PAPER_MODELS`) as meyer with its ``--variant``;
    a `ParameterError` when --variant names the other."""
    if args.model not in PAPER_MODELS or args.model in _MODELS:
        return
    variant = PAPER_MODELS[args.model]
    if args.variant is not None and args.variant != variant:
        from ..errors import ParameterError

        raise ParameterError(f"MODEL {args.model} is meyer --variant {variant}, and --variant {args.variant} names the other: give one")
    args.model, args.variant = "meyer", variant


def run(args) -> int:
    from ..data import log_frequencies

    named_variant(args)
    params, given, param_notes = _parameters(args.model, args.param, check=not args.no_param_check, variant=args.variant)
    out = _out_path(args.out)
    outputs = plan_outputs([("--out", out, "result"), ("--plot", args.plot, "figure")])
    low, high = _RANGES[args.model]
    check_band_options(args.fmin, args.fmax)  # (each option named before the model's defaults fill the other)
    fmin = low if args.fmin is None else args.fmin
    fmax = high if args.fmax is None else args.fmax
    points = check_points(args.points, fmin, fmax, default=161)
    check_memory("--points", points * POINT_BYTES, f"a force spectrum of {points} frequencies")
    notes = param_notes + _notes(args.model, params, given)
    freq = log_frequencies(fmin, fmax, points)
    force = _finite_force(args.model, params, given, freq, args.convention)
    from ..models.peak import force_maximum

    peak = force_maximum(lambda f: float(_force(args.model, params, np.array([f]), args.convention)[0]), freq, force).to_dict()
    document = {"frequency_hz": freq, "force_n": force, "peak": peak, "params": params, "convention": args.convention, "model": args.model, "warnings": notes}
    if args.model == "meyer":
        document["variant"] = _variant_of(params)
    record = command_provenance(args, fmin_used=fmin, fmax_used=fmax, points_used=points, variant_used=document.get("variant"), params_used=params)
    document["provenance"] = record
    json_text = json.dumps(to_jsonable(document), indent=2, allow_nan=False) + "\n"
    csv_text = _csv_text(freq, force, args.model, args.convention, document.get("variant"), params, record)

    def text_writer(path: Path) -> None:
        path.write_text(json_text if Path(out).suffix.lower() == ".json" else csv_text, encoding="utf-8")

    def figure():
        return _figure(args.model, freq, force, peak, params, args.convention, notes)

    outputs.save({"--out": text_writer, "--plot": figure_writer(figure, **figure_options(args))})
    if args.json:
        sys.stdout.write(json_text)
    elif out is None:
        sys.stdout.write(csv_text)
    for note in notes:
        print(f"impedax force {args.model}: warning: {note}", file=sys.stderr)
    if not args.json:  # (the JSON holds the peak)
        what = "time-averaged force" if args.convention == "time-average" else "peak force (largest over a period)"
        print(f"impedax force {args.model}: {what} {_conditions_text(args.model, params)}; {_peak_text(peak)}", file=sys.stderr)
    return 0
