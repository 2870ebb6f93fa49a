"""Helpers shared by the CLI commands."""

from __future__ import annotations

import argparse
import contextlib
import decimal
import functools
import json
import math
import os
import re
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterable, Mapping, Sequence

from ..arguments import EXCLUDE_RTOL, literal_text, number_text, reversed_band_message
from ..errors import DataError, ParameterError
from ..progress import PROGRESS_AFTER_S as PROGRESS_AFTER_S_DEFAULT, progress_printer as core_progress_printer
from ..warning_groups import label_shown, labels_text

__all__ = [
    "parse_assignments", "prefixed_number", "number_option", "NUMBER_PREFIXES", "check_parameter_names", "emit_json", "to_jsonable", "add_model_argument", "add_output_options",
    "check_outputs", "save_outputs", "print_result", "each_spectrum_written", "result_out_help", "Output", "OutputPlan", "plan_outputs",
    "memory_limit", "check_memory", "MEMORY_LIMIT_ENV", "add_select_option", "load_selected", "select_spectra", "load_selected_files", "shown_path", "labels_text", "dimension_labels",
    "command_line_words", "naming_target", "part_of_joined", "announce_written", "option_words", "check_points", "check_band_options", "progress_printer", "PROGRESS_AFTER_S",
    "relative_noise", "fit_command", "add_figure_flag", "unused_figure_options", "exclude_points", "exclude_items", "exclude_frequency", "parse_bounds", "checked_bound_options", "command_provenance", "comma_names", "csv_sigma_note",
]


# the SI prefixes a number on the command line may end with (`prefixed_number`): 2.2k, 10n, 1M
# (mega) against 1m (milli), u or µ for micro
NUMBER_PREFIXES = {"f": 1e-15, "p": 1e-12, "n": 1e-9, "u": 1e-6, "µ": 1e-6, "μ": 1e-6, "m": 1e-3, "k": 1e3, "M": 1e6, "G": 1e9, "T": 1e12}
# each prefix's power of ten: 1.7n is read as the decimal 1.7e-9 (the float nearest it), not as
# 1.7 × 1e-9 = 1.7000000000000001e-09, which a JSON output or a saved fit would show
_PREFIX_EXPONENTS = {prefix: round(math.log10(scale)) for prefix, scale in NUMBER_PREFIXES.items()}
_PREFIXED = re.compile(r"\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*([fpnuµμmkMGT])\s*")


def prefixed_number(text: str) -> float:
    """A number as written on the command line: ``1000``, ``1e3`` or with an SI prefix,
    ``1k``, ``2.2u``, ``10n``, ``1M`` (`NUMBER_PREFIXES`; ``m`` is milli, ``M`` mega). Raises
    ValueError with the forms it takes, and for a number too small for a float, which would
    read as 0 (``1e-400``: "R1=0 is on its lower bound" named a value not typed)."""
    try:
        value = float(text)
        written = text
    except ValueError:
        match = _PREFIXED.fullmatch(text)
        if match is None:
            raise ValueError(f"{text!r} is not a number (write 1000, 1e3 or 1k; SI prefixes {' '.join(p for p in NUMBER_PREFIXES if p != 'μ')})") from None
        value = float(decimal.Decimal(match.group(1)).scaleb(_PREFIX_EXPONENTS[match.group(2)]))
        written = match.group(1)
    if value == 0 and _nonzero(written):
        raise ValueError(f"{text!r} is too small for a float: it reads as 0")
    return value


def _nonzero(text: str) -> bool:
    """Whether the number ``text`` (as `float` takes it) is not zero as written."""
    try:
        return decimal.Decimal(text.strip().replace("_", "")) != 0
    except (decimal.InvalidOperation, ValueError):
        return False


def number_option(text: str) -> float:
    """`prefixed_number` as an argparse ``type``: its message in argparse's error (exit 2)."""
    import argparse

    try:
        return prefixed_number(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


# what argparse should read as a negative number, not an option: -1e-4, -.5, -2.2n, -inf
# (its own pattern, ^-\d+$|^-\d*\.\d+$, leaves out exponents and SI prefixes)
NEGATIVE_NUMBER = re.compile(r"^-(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?\s*[fpnuµμmkMGT]?$|^-inf(?:inity)?$", re.IGNORECASE)


def accept_negative_numbers(parser) -> None:
    """Let ``parser`` (a command's, with no option that looks like a negative number) take
    ``--area -1e-4`` as the option and its value, so the command's own check names the value,
    instead of argparse's "expected one argument"."""
    parser._negative_number_matcher = NEGATIVE_NUMBER


def parse_assignments(items: Iterable[str] | None, flag: str) -> dict[str, float]:
    """``["R0=100", "C1=1u"]`` → ``{"R0": 100.0, "C1": 1e-06}`` (`prefixed_number`) with clear
    errors."""
    out: dict[str, float] = {}
    for item in items or ():
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise ParameterError(f"{flag} {item!r}: expected NAME=VALUE")
        try:
            number = prefixed_number(value)
        except ValueError as error:
            raise ParameterError(f"{flag} {item!r}: {error}") from None
        if not math.isfinite(number):
            raise ParameterError(f"{flag} {item!r}: value must be finite")
        if name in out:
            raise ParameterError(f"{flag}: {name} given twice")
        out[name] = number
    return out


def parse_bounds(items: Iterable[str] | None, flag: str = "--bound") -> dict[str, tuple[float | None, float | None, str]]:
    """``["R1=10:1k", "R0=:10"]`` → ``{"R1": (10.0, 1000.0, "R1=10:1k"), "R0": (None, 10.0,
    "R0=:10")}``: each NAME=LO:HI (`prefixed_number`) with the text given, an open side None
    (`checked_bound_options` puts the element's own bound there); clear errors naming ``flag``."""
    out: dict[str, tuple[float | None, float | None, str]] = {}
    for item in items or ():
        name, sep, ends = item.partition("=")
        name = name.strip()
        lower_text, colon, upper_text = ends.partition(":")
        if not sep or not name or not colon:
            raise ParameterError(f"{flag} {item!r}: expected NAME=LO:HI (e.g. R1=10:1k; leave a side empty to keep the element's own bound there: R0=:10)")
        pair = []
        for end, text in (("lower", lower_text.strip()), ("upper", upper_text.strip())):
            if not text:
                pair.append(None)
                continue
            try:
                number = prefixed_number(text)
            except ValueError as error:
                raise ParameterError(f"{flag} {item!r}: {end} end: {error}") from None
            if math.isnan(number):
                raise ParameterError(f"{flag} {item!r}: {end} end must be a number, got {text}")
            pair.append(number)
        if pair == [None, None]:
            raise ParameterError(f"{flag} {item!r}: give at least one end, LO:HI, LO: or :HI")
        if name in out:
            raise ParameterError(f"{flag}: {name} given twice")
        out[name] = (pair[0], pair[1], item)
    return out


def checked_bound_options(given: Mapping[str, tuple[float | None, float | None, str]], specs: Mapping, *, init: Mapping[str, float] | None = None,
                          fixed: Mapping[str, float] | None = None, flag: str = "--bound") -> dict[str, tuple[float, float]]:
    """The ``bounds=`` of `impedax.fit`/`impedax.sample` from ``given`` (`parse_bounds`; names
    among ``specs``, the parameters' `ParameterSpec`): an open side is the element's own bound.
    A `ParameterError` naming ``flag`` and the parameter, before any data are read, where the API
    would refuse later in its own words (`parameters.checked_bounds`, `outside_bounds_message`):
    LO ≥ HI, a bound outside the element's own range, one that narrows nothing (the fit's
    ``user_bounds`` would not list it), a parameter also fixed (``fixed``: --fix), or an ``init``
    (--init) value not strictly inside its bounds (a start on a bound would not move off it)."""
    from ..data import unit_text
    from ..fitting.parameters import outside_bounds_message

    out = {}
    for name, (lower, upper, item) in given.items():
        spec = specs[name]
        lo = float(spec.lower) if lower is None else lower
        hi = float(spec.upper) if upper is None else upper
        unit = unit_text(spec.unit)
        own = spec.bounds_text() + (f" [{unit}]" if unit else "")
        if not lo < hi:
            raise ParameterError(f"{flag} {item}: the lower end {number_text(lo)} must be below the upper end {number_text(hi)}")
        if lo < spec.lower or hi > spec.upper:
            raise ParameterError(f"{flag} {item}: ({number_text(lo)}, {number_text(hi)}) reaches outside {name}'s own range {own}")
        if lo == spec.lower and hi == spec.upper:
            raise ParameterError(f"{flag} {item}: {name}'s own range is {own}; this bound narrows nothing")
        if fixed and name in fixed:
            raise ParameterError(f"{flag} {item} and --fix {name}={number_text(fixed[name])}: a fixed parameter is not fitted, so it has no bounds; give one or the other")
        if init and name in init and not lo < init[name] < hi:
            raise ParameterError("--" + outside_bounds_message("init", name, init[name], lo, hi, False, unit) + f" ({flag} {item})")
        out[name] = (lo, hi)
    return out


def comma_names(items: Iterable[str] | None) -> list[str]:
    """The names of a repeatable ``--option NAME[,NAME]`` (``--shared``, ``--corner-params``):
    split at commas, blanks dropped, in the order given."""
    return [n.strip() for item in items or () for n in item.split(",") if n.strip()]


def check_parameter_names(names: Iterable[str], known: Iterable[str], flag: str, model: str, registry=None, *, paper: str | None = None) -> None:
    """`ParameterError` naming ``flag`` and the nearest known name (`closest_name`) for the
    first of ``names`` that is not one of ``known``, the parameters of ``model`` (elements of
    ``registry``, None: the default one). ``paper``: the paper model ``model`` is (a key of
    `PAPER_MODELS`); a name of another paper model's is said to be its (`other_paper_model`)."""
    known = list(known)
    for name in names:
        if name not in known:
            other = other_paper_model(name, paper)
            if other is not None:
                raise ParameterError(f"{flag}: {name} is a parameter of {other} ({paper_circuit(other)}), not of {paper} ({model}): "
                                     f"name the model {other} to set it (parameters of {paper}: {', '.join(known)})")
            from ..arguments import closest_name
            from ..circuits import DEFAULT_REGISTRY

            close = closest_name(name, known, impedance_py_symbols=(registry or DEFAULT_REGISTRY).impedance_py_symbols)
            hint = f"; did you mean {close}?" if close else ""
            raise ParameterError(f"{flag}: unknown parameter {name!r} for model {model!r}{hint} (parameters: {', '.join(known)})")


def check_band_options(fmin: float | None, fmax: float | None) -> None:
    """``--fmin``/``--fmax``: positive and finite, fmin ≤ fmax (the rule of the commands that fit,
    `kk` and `drt`)."""
    from ..errors import ParameterError

    for flag, value in (("--fmin", fmin), ("--fmax", fmax)):
        if value is not None and not math.isfinite(value):
            raise ParameterError(f"{flag} must be finite, got {value:g}")
        if value is not None and not value > 0:
            raise ParameterError(f"{flag} must be positive, got {value:g}")
    if fmin is not None and fmax is not None and fmax < fmin:
        raise ParameterError(reversed_band_message(fmin, fmax, ("--fmin", "--fmax")))


def relative_noise(text: str | None) -> float | None:
    """``--noise`` as a fraction of |Z| per component: ``0.05``, or a percentage, ``5%``. A
    bare value of 1 or more is refused (`ParameterError`): ``--noise 5`` means 5 %, not 500 %."""
    if text is None:
        return None
    written = text.strip()
    percent = written.endswith("%")
    try:
        value = float(written[:-1] if percent else written)
    except ValueError:
        from ..arguments import SAMPLE_NOISE_MODELS

        model = "; proportional and sigma are sample's noise models, here --noise is the level" if written.lower() in SAMPLE_NOISE_MODELS else ""
        raise ParameterError(f"--noise {text!r} is not a number: write a fraction of |Z| (0.05) or a percentage (5%){model}") from None
    if not (value > 0 and math.isfinite(value)):
        raise ParameterError(f"--noise must be positive and finite, got {text}")
    if percent:
        if value >= 100:
            raise ParameterError(f"--noise {written}: a noise level is below 100 % of |Z| (write 5% or 0.05 for 5 %)")
        return value / 100
    if value >= 1:
        raise ParameterError(f"--noise {written}: a bare value is a fraction of |Z| (0.05 for 5 %), so {written} would be {value * 100:g} %; write {written}% or {value / 100:g}")
    return value


def fit_command(args=None, *, kept=None, masked=(), data=None, program: str = "impedax fit") -> str:
    """The start of the ``impedax fit`` command that fits the spectrum and points a run of
    ``args`` (diagnose, refine) fitted: its file, shell-quoted (DATA when ``args`` names none),
    --select (with ``data``, the one spectrum the run took, a list or range that picked it
    becomes its label: `single_selects`), --weighting unless the default (modulus), --fmin,
    --fmax and --exclude; with the run's ``kept`` frequencies and the ``masked`` ones it left
    out, the --fmin/--fmax/--exclude that leave those out too (`left_out_options`). The advice
    of those commands ends it with --model and the values to start from. ``program``: another
    command that takes these options (``impedax kk``: its next step)."""
    import shlex

    data_file = getattr(args, "data", None)
    options = run_options(args, kept=kept, masked=masked, data=data)
    return " ".join([program, shlex.quote(data_file) if data_file else "DATA"] + [f"{flag} {shlex.quote(str(value))}" for flag, value in options if value is not None])


def diagnose_command(args, data, labels: dict, model: str) -> str:
    """``impedax diagnose FILE --select DIM=LABEL … --model MODEL`` for the spectrum of ``data``
    (a batch the run read) with ``labels``, with the run's other options (`run_options`: a
    --select list or range that held it becomes its label); a dimension without labels is
    selected by position, as --select reads it."""
    import shlex

    one = data.isel({d: v for d, v in labels.items() if d not in data.coords}).sel({d: v for d, v in labels.items() if d in data.coords})
    selected = {str(item).partition("=")[0].strip() for flag, item in run_options(args, data=one) if flag == "--select"}
    # (a float label as text writes it, soc=0.3 for 0.30000000000000004: --select finds it within `_label_slack`)
    others = "".join(f" --select {shlex.quote(f'{d}={label_shown(v)}')}" for d, v in labels.items() if d not in selected)
    return f"{fit_command(args, data=one, program='impedax diagnose')}{others} --model {shlex.quote(model)}"


def run_options(args=None, *, kept=None, masked=(), data=None) -> list[tuple[str, object]]:
    """The (flag, value) options of `fit_command` (value None: not given)."""
    band = {"--fmin": getattr(args, "fmin", None), "--fmax": getattr(args, "fmax", None)}
    excluded = [getattr(args, "exclude", None)] if getattr(args, "exclude", None) else []
    if kept is not None and len(masked):
        from ..fitting.kk import left_out_options

        for flag, value in left_out_options(kept, masked):
            if flag == "--exclude":
                excluded.append(value)
            else:
                band[flag] = value
    weighting = getattr(args, "weighting", None)
    select = getattr(args, "select", None) or ()
    options = [("--select", item) for item in (select if data is None else single_selects(select, data))]
    options += [("--weighting", weighting if weighting != "modulus" else None), *band.items(), ("--exclude", ",".join(excluded) or None)]
    options += [("--plugin", path) for path in getattr(args, "plugin", None) or ()]  # (the elements and reader the run used)
    return options


def single_selects(select: Sequence[str], data) -> list[str]:
    """The ``--select`` items ``select`` that left ``data`` one spectrum, each list or range
    written as the label it picked (``cycle=4:4`` → ``cycle=4``): `impedax fit` reads a list
    or range as a batch, of one here, where the advice means that spectrum. A dimension that
    ``data`` still has, or an item that is one label, is kept as written."""
    out = []
    for item in select:
        dim, label = _select_item(item)
        if ("," in label or ":" in label) and dim not in data["Z"].dims:
            if dim in data.coords and data[dim].ndim == 0:
                value = data[dim].item()
                label = number_text(value) if _is_number(value) else str(value)
            elif dim not in data.coords:  # (positions: one range FIRST:LAST, or FIRST: / :LAST, that picked one)
                first = label.partition(":")[0].strip()
                label = first or "0"
            item = f"{dim}={label}"
        out.append(item)
    return out


def exclude_items(text: str) -> list[str]:
    """The items of ``--exclude F,F,...`` (empty ones skipped); a `ParameterError` when it names
    none."""
    items = [t.strip() for t in text.split(",") if t.strip()]
    if not items:
        raise ParameterError(f"--exclude {text!r} names no frequency: give them in Hz, comma-separated (5.34,56.2,1.12M)")
    return items


def exclude_frequency(item: str) -> float:
    """One item of ``--exclude`` in Hz (SI prefixes as `prefixed_number`), positive and finite;
    a `ParameterError` otherwise."""
    try:
        value = prefixed_number(item)
    except ValueError as error:
        raise ParameterError(f"--exclude: {error}") from None
    if not (value > 0 and math.isfinite(value)):
        raise ParameterError(f"--exclude: frequencies are positive and finite, got {item}")
    return value


def exclude_points(data, text: str | None):
    """``data`` without the frequencies of ``--exclude F,F,...`` (Hz, SI prefixes as
    `prefixed_number`: 5.34,1.12M): each names the nearest measured frequency, within
    `EXCLUDE_RTOL` (0.5 %, so the three digits a report prints match). A value that names none,
    or names one twice, is a `ParameterError` naming the nearest measured frequencies."""
    if text is None:
        return data
    import numpy as np

    measured = np.asarray(data["frequency"].values, float)
    drop: dict[int, str] = {}
    for item in exclude_items(text):
        value = exclude_frequency(item)
        distance = np.abs(np.log(measured / value))
        i = int(np.argmin(distance))
        if abs(measured[i] / value - 1) > EXCLUDE_RTOL:
            nearest = sorted(np.argsort(distance)[:2], key=lambda j: measured[j])
            raise ParameterError(
                f"--exclude {item}: no measured frequency within {EXCLUDE_RTOL * 100:g} % of {number_text(value)} Hz; "
                f"the nearest are {' and '.join(f'{measured[j]:.6g} Hz' for j in nearest)}"
            )
        if i in drop:
            raise ParameterError(f"--exclude: {drop[i]} and {item} name the same measured frequency, {measured[i]:.6g} Hz")
        drop[i] = item
    keep = np.setdiff1d(np.arange(measured.size), list(drop))
    if not keep.size:
        raise ParameterError(f"--exclude leaves out every frequency of the data ({measured.size})")
    return data.isel(frequency=keep)


def check_points(points: int | None, fmin: float, fmax: float, *, default: int) -> int:
    """The number of frequencies from ``fmin`` to ``fmax`` (``--points``; None: not given, then
    ``default``, or 1 where the range is one frequency): at least 2, or exactly 1 where the range
    is one frequency (``--fmin`` equal to ``--fmax``, as `impedax.log_frequencies` takes it;
    more would repeat it: ``simulate`` refused the copies as duplicates, ``force`` printed each).
    One message for 0, -1 and 1 alike."""
    if points is None:
        return 1 if fmin == fmax else default
    if fmin == fmax and points != 1:
        raise ParameterError(f"--points must be 1 when --fmin equals --fmax (one frequency, {fmin:g} Hz), got {points}")
    if points >= 2 or (points == 1 and fmin == fmax):
        return points
    raise ParameterError(f"--points must be at least 2 (both ends of --fmin..--fmax), got {points}; --points 1 only with --fmin equal to --fmax")


def check_bounds(values: Mapping[str, float], specs: Mapping, flag: str) -> None:
    for name, value in values.items():
        spec = specs[name]
        if not spec.contains(value):
            from ..data import unit_text
            from ..fitting.parameters import outside_bounds_message

            unit = unit_text(spec.unit)
            raise ParameterError(outside_bounds_message(flag, name, value, spec.lower, spec.upper, spec.upper_inclusive, unit))


def model_and_values(model: str, items, flag: str, registry=None, *, paper: str | None = None):
    """Parse ``model`` (elements of ``registry``, None: the default one; the circuit of the
    paper model ``paper`` when given) and the ``NAME=VALUE`` ``items`` given with ``flag``;
    check the names and bounds. Returns (circuit, parameter specs, values)."""
    from .. import DEFAULT_REGISTRY, parse

    registry = registry or DEFAULT_REGISTRY
    circuit = parse(model, registry)
    specs = circuit.parameter_specs(registry)
    values = parse_assignments(items, flag)
    check_parameter_names(values, specs, flag, model, registry, paper=paper)
    check_bounds(values, specs, flag)
    return circuit, specs, values


def to_jsonable(obj):
    """``obj`` as strict-JSON values (`impedax.io.export.to_jsonable`)."""
    from ..io.export import to_jsonable as jsonable

    return jsonable(obj)


def with_source(summary: dict, source: str | None, provenance: Mapping | None = None) -> dict:
    """A result's JSON ``summary`` with the key ``source``: the data's file and any ``--select``
    (`data_source`), when given and the summary has none; and the key ``provenance``
    (`command_provenance`) when given."""
    if source is not None and "source" not in summary:
        summary = {**summary, "source": source}
    if provenance is not None:
        summary = {**summary, "provenance": dict(provenance)}
    return summary


# what `command_provenance` leaves out of a command's settings: where the outputs go, how they look and how
# the run talks (not how the result was made), and the data files (its ``data_files``: DATA, FILE, gap's three)
# (and what `--plugin` made: the files stay, as ``plugin``, when given)
_NOT_SETTINGS = frozenset({"run", "command", "json", "out", "plot", "corner", "corner_params", "dpi", "title", "quiet", "remaining", "data", "file", "files", "total", "skin", "touchscreen", "registry", "readers", "circuit_model", "paper_values"})  # (circuit_model: a parser flag, no option; paper_values: a paper model's, its name kept)


def command_provenance(args, *, source=None, data_files: Sequence[str] = (), **used) -> dict:
    """The `impedax.io.provenance.provenance` of a command run with ``args``: ``command``
    ``impedax NAME``, ``settings`` every option of the command as parsed (defaults included:
    the seed, weighting, convention a run used without naming them), updated by ``used``
    (values the run settled itself, e.g. the steps ``auto`` became); ``source`` and
    ``data_files`` as given. The same record goes to ``--json`` and ``--out``."""
    from ..io.provenance import provenance

    settings = {k: v for k, v in vars(args).items() if k not in _NOT_SETTINGS and not callable(v)}
    if not any(settings.get("paper_model") or ()):  # (a paper model's name when MODEL gave one; no key for a circuit)
        settings.pop("paper_model", None)
    if settings.get("plugin"):  # (the --plugin files a run used, as absolute paths)
        settings["plugin"] = [os.path.abspath(p) for p in settings["plugin"]]
    else:
        settings.pop("plugin", None)
    settings.update(used)
    name = getattr(args, "command", None)
    return provenance(command=f"impedax {name}" if name else None, settings=settings, source=source, data_files=data_files)


#: What every argument naming a spectrum to read (DATA, FILE, DATA_TOTAL, --frequencies FILE) says of
#: '-', in one wording (`data_help`; not inspect's FILE alone).
STDIN_HELP = "'-' reads standard input, recognised by content as a file is (a reader of your own that goes by the extension does not claim it)"


def data_help(what: str) -> str:
    """The help of an argument naming a spectrum file to read: ``what`` it holds, then `STDIN_HELP`."""
    return f"{what}; {STDIN_HELP}"


JSON_SUMMARY_HELP = "print a JSON summary of what was written on standard output (docs/robustness.md, \"JSON for programs\")"


def check_json_with_spectrum_out(as_json: bool, out: str | None, command: str) -> None:
    """``--json`` of a command that prints its spectrum as CSV without ``--out`` (simulate,
    remaining): refused unless ``--out FILE`` takes the spectrum, as standard output holds one
    of the two (``--out -`` with ``--json`` `plan_outputs` refuses)."""
    if as_json and (out is None or out == ""):
        raise ParameterError(f"impedax {command} --json prints its summary on standard output, where the spectrum goes without --out: give --out FILE.csv or FILE.nc")


def spectrum_summary(ds) -> dict:
    """The shape of a written spectrum file for the ``--json`` of stack, simulate and remaining:
    ``dims`` (each dimension of Z and its size, frequency included, as inspect --json gives
    them), ``spectra`` (their number), ``frequencies``, ``frequency_min_hz``,
    ``frequency_max_hz`` and ``has_sigma``."""
    import numpy as np

    freq = np.asarray(ds["frequency"].values, dtype=float)
    return {
        "dims": {str(k): int(v) for k, v in ds["Z"].sizes.items()},
        "spectra": int(ds["Z"].size // max(ds.sizes["frequency"], 1)),
        "frequencies": int(freq.size),
        "frequency_min_hz": float(freq.min()),
        "frequency_max_hz": float(freq.max()),
        "has_sigma": "sigma" in ds,
    }


def emit_json(obj) -> None:
    """Print ``obj`` as JSON (NaN/Inf become null, so the output is strict JSON)."""
    json.dump(to_jsonable(obj), sys.stdout, indent=2, allow_nan=False)
    sys.stdout.write("\n")


def add_model_argument(parser, *, positional: bool = False, default: str | None = None) -> None:
    """MODEL (``positional``: first argument, or --model as the commands that fit take it) or
    --model, required unless a ``default`` is given."""
    help_text = ("circuit text, e.g. 'R0 + R1 || C1', or the same in impedance.py's, AutoEIS's, CDC or EC-Lab notation: "
                 "'R0-p(R1,C1)', 'R0-[R1,C1]', 'R(RC)', 'R0+R1/C1' (quote it in the shell); or a paper model's name: "
                 f"{', '.join(PAPER_MODELS)} (Meyer's finger-on-screen circuit with the thesis's eq 3.13 values, docs/models.md)")
    parser.set_defaults(circuit_model=True)  # (read by `read_impedance_py_model`)
    if positional:
        add_positional_model(parser, help=help_text)
    elif default is not None:
        parser.add_argument("--model", action=OneModel, default=default, metavar="MODEL", help=f"{help_text}; default '{default}'")
    else:
        parser.add_argument("--model", action=OneModel, required=True, metavar="MODEL", help=help_text)


class OneModel(argparse.Action):
    """``--model`` of a command that takes one model: a second one is refused (exit 2) where
    argparse kept the last in silence (``diagnose --model A --model B`` diagnosed B alone)."""

    def __call__(self, parser, namespace, values, option_string=None):
        before = getattr(namespace, self.dest, None)
        if before is not None and before is not self.default:  # (until one is given it holds the default itself)
            several = "; impedax compare fits several to one spectrum" if any(a.dest == "data" for a in parser._actions) else ""
            parser.error(f"--model given twice ({before!r} and {values!r}): {parser.prog} takes one model{several}")
        setattr(namespace, self.dest, values)


def looks_like_impedance_py(text: str) -> bool:
    """Circuit text written in impedance.py's notation: ``p(`` (``p (``) or a ``-`` between elements
    (impedax writes series ``+``; its own text never holds either)."""
    return re.search(r"(?<![A-Za-z0-9_])p\s*\(", text) is not None or re.search(r"[A-Za-z0-9_)]\s*-\s*[A-Za-z(]", text) is not None


#: Paper models a MODEL may name (any case), in every command that takes one: Meyer's
#: finger-on-screen circuit, thesis Fig 3.3 (rc) or its fractional variant of Fig 5.3 (cpe), with
#: the thesis's eq 3.13 values (`impedax.models.meyer_model`; the cpe variant's α = 0.8 and Q from
#: C_sc at 1 kHz): the defaults of ``simulate``, the starting values of the commands that fit.
PAPER_MODELS = {"meyer": "rc", "meyer-rc": "rc", "meyer-cpe": "cpe"}


def paper_model(model: str | None) -> tuple[str | None, dict[str, float]]:
    """(the name of the paper model ``model`` names, its parameter values) for a name of
    `PAPER_MODELS`; (None, {}) for a circuit."""
    name = (model or "").strip().lower() if isinstance(model, str) else ""
    if name not in PAPER_MODELS:
        return None, {}
    from ..models.meyer import meyer_model

    return name, dict(meyer_model(PAPER_MODELS[name]).params)


def other_paper_model(name: str, paper: str | None) -> str | None:
    """The first paper model (`PAPER_MODELS`) other than the variant of ``paper`` that has the
    parameter ``name`` (``CPE_sc.alpha`` of meyer: meyer-cpe; ``C_sc`` of meyer-cpe: meyer);
    None when ``paper`` is None or none has it."""
    if paper not in PAPER_MODELS:
        return None
    from ..circuits import parse

    return next((other for other, variant in PAPER_MODELS.items() if variant != PAPER_MODELS[paper] and name in parse(paper_circuit(other)).parameter_names()), None)


def paper_circuit(name: str) -> str:
    """The circuit text of the paper model ``name`` (a key of `PAPER_MODELS`)."""
    from ..models.meyer import meyer_circuit

    return str(meyer_circuit(PAPER_MODELS[name]))


@contextlib.contextmanager
def band_named(loaded, data, fmin: float | None, fmax: float | None):
    """A `DataError` raised inside for too few frequencies (``the KK test needs at least 4
    frequencies, got 1``) names the band that left them when --fmin/--fmax left points of
    ``loaded`` out of ``data``, as fit's refusal does: "got 1" alone sent the user to a file that
    holds 21 (REAL ZPlot, ``impedax kk … --fmin 250k``)."""
    from ..errors import DataError
    from ..fitting.problem import band_text

    try:
        yield
    except DataError as exc:
        n, kept = loaded.sizes["frequency"], data.sizes["frequency"]
        if "needs at least" not in str(exc) or kept == n:
            raise
        raise DataError(f"{exc} ({kept} of the data's {n} {band_text(fmin, fmax)}); use a wider band") from None


def paper_start(values: Mapping[str, float], init: Mapping[str, float], *, held: Iterable[str] = ()) -> dict[str, float]:
    """The starting values of a fit of a paper model: its ``values`` (`paper_model`) under the
    ``init`` given (--init overrides), none for a parameter ``held`` (--fix, --bound: the user's
    own value or range)."""
    held = set(held)
    return {**{k: v for k, v in values.items() if k not in held}, **init}


def paper_start_note(command: str, name: str, circuit: str, values: Mapping[str, float], init: Mapping[str, float] | None = None, *, starts: bool = True,
                     fixed: Iterable[str] = (), bounded: Iterable[str] = ()) -> str:
    """The stderr line of a command that fits the paper model ``name``: its circuit, and that
    the thesis's eq 3.13 ``values`` are starting values, not fixed ones (``starts`` False: the
    command takes no start, and its fit guesses one from the data); those ``init`` overrides
    are named, and the parameters ``fixed`` (--fix) and ``bounded`` (--bound), which take no
    thesis start (`paper_start`), are named instead of their thesis values."""
    from ..data import format_bound
    from ..circuits import DEFAULT_REGISTRY, parse

    init = init or {}
    fixed, bounded = [n for n in fixed if n in values], [n for n in bounded if n in values]
    specs = parse(circuit).parameter_specs(DEFAULT_REGISTRY)
    shown = ", ".join(f"{n} = {format_bound(float(v), specs[n].unit)}" for n, v in values.items() if n not in init and n not in fixed and n not in bounded)
    if not starts:
        return f"impedax {command}: {name} is {circuit}; the fit starts from values guessed from the data (the thesis's eq 3.13 values are simulate's defaults, not used here)"
    given = "; ".join([*([f"--init gives {', '.join(init)}"] if init else []), *([f"--fix holds {', '.join(fixed)}"] if fixed else []),
                       *([f"{', '.join(bounded)} under --bound start{'s' if len(bounded) == 1 else ''} from the data, within {'its range' if len(bounded) == 1 else 'their ranges'}"] if bounded else [])])
    return f"impedax {command}: {name} is {circuit}, fitted from the thesis's eq 3.13 values as starting values, not fixed ones: {shown}" + (f" ({given})" if given else "")


def resolve_paper_model(args) -> None:
    """``args.model`` that names a paper model (`PAPER_MODELS`) as its circuit text, with
    ``args.paper_model`` (its name, else None) and ``args.paper_values`` (its values, else {})
    set for the command to start from; a list of models (``compare``) each read alike, the
    names and values then lists."""
    model = getattr(args, "model", None)
    if isinstance(model, list):
        read = [paper_model(m) for m in model]
        args.paper_model = [name for name, _ in read]
        args.paper_values = [values for _, values in read]
        args.model = [paper_circuit(name) if name else m for m, (name, _) in zip(model, read)]
        return
    name, values = paper_model(model)
    args.paper_model, args.paper_values = name, values
    if name:
        args.model = paper_circuit(name)


def read_impedance_py_model(args, command: str) -> None:
    """``args.model`` of a command that takes a circuit (`add_model_argument`) as impedax text
    (`impedax_text`: a string in another notation read by its reader, with the elements of
    ``args.registry``, the --plugin files' too); a paper model's name (`PAPER_MODELS`) as its
    circuit (`resolve_paper_model`)."""
    if getattr(args, "circuit_model", False):
        resolve_paper_model(args)
    model = getattr(args, "model", None)
    if getattr(args, "circuit_model", False) and isinstance(model, str) and not getattr(args, "paper_model", None):
        args.model, notation = impedax_text(model, command, getattr(args, "registry", None))
        if notation == IMPEDANCE_PY_NOTATION:
            note_impedance_py_weighting(command, getattr(args, "weighting", None))


IMPEDANCE_PY_WEIGHTING_NOTE = (
    "impedax weights the residuals by 1/|Z| by default (--weighting modulus, impedance.py's weight_by_modulus=True); "
    "impedance.py's default is unweighted, here --weighting unit (docs/migrating.md, \"The default weighting differs\")"
)


def note_impedance_py_weighting(command: str, weighting: str | None) -> None:
    """One note on stderr, after a model was read as impedance.py notation, when the command fits
    with ``weighting`` "modulus" (impedax's default; None: the command has no --weighting): an
    impedance.py user's numbers differ from impedance.py's default, unweighted fit (R0 0.015167
    against 0.015642 on its REAL exampleData.csv, docs/migrating.md), and the header's
    "weighting modulus" alone does not say so (a walkthrough)."""
    if weighting == "modulus":
        print(f"impedax {command}: note: {IMPEDANCE_PY_WEIGHTING_NOTE}", file=sys.stderr)


# how `impedax_text` says it read a model written in another notation
CDC_NOTATION = "as Boukamp's circuit description code (CDC)"
AUTOEIS_NOTATION = "as AutoEIS notation"
IMPEDANCE_PY_NOTATION = "as impedance.py notation"  # (the one the note on impedance.py's default weighting follows)
EC_LAB_NOTATION = "with '/' as parallel (EC-Lab's notation)"


def ec_lab_notation(model: str, registry) -> str:
    """How `impedax_text` says it read ``model`` as EC-Lab notation: `EC_LAB_NOTATION`, or with
    the EC-Lab symbols it read as impedax's (``as EC-Lab notation (its Wd is impedax's Ws, with
    the same R and tau; '/' as parallel)``)."""
    from ..circuits.parser import ec_lab_symbols

    renamed = ec_lab_symbols(model, registry)
    if not renamed:
        return EC_LAB_NOTATION
    symbols = " and ".join(f"its {ec} is impedax's {ours}" for ec, ours in renamed.items())
    slash = "; '/' as parallel" if "/" in model else ""
    return f"as EC-Lab notation ({symbols}, with the same R and tau{slash})"


def impedax_text(model: str, command: str, registry=None) -> tuple[str, str | None]:
    """``model`` as impedax circuit text, and how it was read (None: as impedax text): itself
    when it parses; else, read in the notation it is written in, with one note on stderr saying
    how: Boukamp's CDC (`impedax.circuits.looks_like_cdc`, ``R(RC)``: `impedax.from_cdc`),
    AutoEIS's (`impedax.circuits.looks_like_autoeis`, ``R1-[R2,P3]``: `impedax.from_autoeis`),
    impedance.py's (`looks_like_impedance_py`, ``R0-p(R1,C1)``: `impedax.from_impedance_py`), or
    EC-Lab's (a ``/`` and no ``|``, or its Wd or M: ``R1+Q2/(R2+Wd2)``, `impedax.from_ec_lab`). A string that neither
    reads is refused with that reader's message, or the impedax parser's when it holds impedax's
    operators (``+``, ``|``: impedax text with a stray ``-``) or looks like no other notation."""
    from ..circuits import DEFAULT_REGISTRY, from_autoeis, from_cdc, from_ec_lab, from_impedance_py, looks_like_autoeis, looks_like_cdc, parse
    from ..circuits.parser import ec_lab_symbols
    from ..errors import CircuitSyntaxError

    registry = registry or DEFAULT_REGISTRY
    try:
        parse(model, registry)
        return model, None  # (impedax text first: a user's element P1 is no AutoEIS CPE)
    except CircuitSyntaxError as exc:
        impedax_error = exc
    refuse_a_file_name(model, command)
    if looks_like_cdc(model, registry):
        text, notation = str(from_cdc(model, registry)), CDC_NOTATION
    elif looks_like_autoeis(model):
        text, notation = str(from_autoeis(model, registry)), AUTOEIS_NOTATION
    elif looks_like_impedance_py(model):
        if "+" in model or "|" in model:
            raise impedax_error
        text, notation = str(from_impedance_py(model, registry)), IMPEDANCE_PY_NOTATION
    elif not ("/" in model and "|" in model) and ("/" in model or ec_lab_symbols(model, registry)):  # (both signs: neither notation)
        text, notation = str(from_ec_lab(model, registry)), ec_lab_notation(model, registry)
    else:
        return model, None  # (the command's own parse gives the error)
    print(f"impedax {command}: read {notation}: {text}", file=sys.stderr)
    return text, notation


def refuse_a_file_name(model: str, command: str) -> None:
    """One `ParameterError` when circuit text ``model``, which does not parse, is a file or ends
    in a spectrum file's extension (``impedax info run1.mpt``: a file given where a model is
    asked for): it names `impedax inspect`, which reads files, in place of a circuit-syntax
    caret under the name's '.'; nothing otherwise."""
    import shlex
    from pathlib import Path

    from ..errors import ParameterError
    from ..io import READERS
    from ..io.loader import SPECTRUM_SUFFIXES

    example = "impedax info 'R0 + R1 || C1'" if command == "info" else "--model 'R0 + R1 || C1'"
    if model.strip() == "-":  # (cat run.z | impedax info -: standard input, which only the file arguments read)
        raise ParameterError(f"'-' is standard input, not a circuit: impedax {command} takes a model there ({example}); "
                             "what impedax reads from a spectrum piped in, and how: impedax inspect -")
    path = Path(model)
    suffixes = {s.lower() for s in SPECTRUM_SUFFIXES if s} | {e.lower() for reader in READERS for e in reader.extensions}
    try:
        is_file = path.is_file()
    except (OSError, ValueError):  # (text too long for a file name, or holding a NUL: no file)
        return
    if is_file:
        what = "is a file"
    elif path.suffix.lower() in suffixes:
        what = "looks like a spectrum file's name (no such file)"
    else:
        return
    raise ParameterError(f"{model!r} {what}, not a circuit: impedax {command} takes a model there ({example}); "
                         f"what impedax reads from a spectrum file, and how: impedax inspect {shlex.quote(model)}")


def add_positional_model(parser, **kwargs) -> None:
    """MODEL as the first argument, or as ``--model MODEL`` (the spelling of the commands that
    fit); `positional_model` reads the one given. ``kwargs`` go to both (``choices``, ``help``)."""
    parser.add_argument("model", metavar="MODEL", nargs="?", **kwargs)
    parser.add_argument("--model", dest="model_option", action=OneModel, metavar="MODEL", **{**kwargs, "help": "the same as MODEL"})


def positional_model(parser, args) -> None:
    """Set ``args.model`` from MODEL or ``--model`` (see `add_positional_model`); exit 2 with
    the command's usage when neither or both are given."""
    if not hasattr(args, "model_option"):
        return
    given = [value for value in (args.model, args.model_option) if value is not None]
    if not given:
        parser.error("the following arguments are required: MODEL (or --model MODEL)")
    if len(given) == 2:
        parser.error(f"MODEL given twice: {given[0]!r} and --model {given[1]!r}; give one")
    args.model = given[0]
    del args.model_option


#: ``--select``'s help after what the command does with it: the syntax of LABEL.
SELECT_SYNTAX_HELP = (
    "LABEL is DIM's coordinate value, or its 0-based position where DIM has no labels (only there). Several: a list "
    "L1,L2,... (cycle=3,5,9) or a range FIRST:LAST of numeric labels or positions, both ends included, by value as "
    "xarray's .sel(DIM=slice(FIRST, LAST)) (cycle=10:40: cycles 10 to 40; cycle=10: from 10 on). "
    "Repeat for each dimension (`impedax inspect` lists them)"
)


def add_select_option(parser, *, several: bool | str = True) -> None:
    """``--select DIM=LABEL`` (repeatable). ``several``: the command takes a file of several
    spectra (fit, kk, drt, inspect), so a list or range keeps the spectra it picks; False: it
    takes one, so the selection must leave one; a text: when it takes several (sample:
    "with --shared")."""
    what = "one spectrum of a file that holds several (sheets, measurements, cycles): the one whose DIM is LABEL"
    if several is True:
        what = "spectra of a file that holds several (sheets, measurements, cycles): the ones whose DIM is LABEL"
    elif several:
        what += f" (several {several})"
    else:
        what += "; a list or range must leave one"
    parser.add_argument("--select", action="append", metavar="DIM=LABEL", help=f"{what}. {SELECT_SYNTAX_HELP}")


def dimension_labels(data, dim: str) -> list:
    """The labels of ``data``'s spectra along ``dim``: its coordinate's values, or the positions
    where ``dim`` has no coordinate."""
    from ..data import coordinate_labels

    return coordinate_labels(data, dim)


def _position(data, dim: str, label: str, path: str, item: str | None = None) -> int:
    """The position along ``dim`` of the spectrum labelled ``label`` (its coordinate's value as
    text, or equal as a number), or at 0-based position ``label`` where ``dim`` has no coordinate.
    ``item``: the whole ``DIM=...`` text when ``label`` is one item of a list, which messages name."""
    size = data.sizes[dim]
    said = f"--select {dim}={label}" if item is None else f"--select {item}"
    if dim not in data.coords:
        if label.strip().lstrip("-").isdigit() and 0 <= int(label) < size:
            return int(label)
        which = "" if item is None else f" {_quoted(label)} is not a position:"
        raise ParameterError(f"{said}:{which} {path} has no labels along {dim}; give a position 0..{size - 1}{_unquote_hint(label, range(size))}")
    labels = data[dim].values.tolist()
    try:
        number = float(label)
    except ValueError:
        number = None
    moment = _as_moment(data, dim, label)
    found = [i for i, v in enumerate(labels) if str(v) == label or (number is not None and _is_number(v) and v == number)]
    if not found and number is not None:  # (a label written with rounding error: 0.30000000000000004 of np.arange(6) * 0.1 is 0.3)
        slack = _label_slack(labels)
        found = [i for i, v in enumerate(labels) if _is_number(v) and abs(v - number) <= slack]
    if moment is not None:
        found = [i for i, v in enumerate(data[dim].values) if v == moment]
    if not found:
        that = "that label" if item is None else f"the label {_quoted(label)}"
        raise ParameterError(f"{said}: no spectrum of {path} has {that}; its {dim} labels: {labels_text(labels)}{_unquote_hint(label, labels)}")
    if len(found) > 1:
        that = "that label" if item is None else f"the label {_quoted(label)}"
        raise ParameterError(f"{said}: {len(found)} spectra of {path} have {that} (positions {', '.join(map(str, found))})")
    return found[0]


def _as_moment(data, dim: str, text: str):
    """``text`` as a date and time (``numpy.datetime64``) when ``dim``'s labels are dates and
    ``text`` reads as one in ISO form (``2026-11-04T10:00`` finds the label written
    ``2026-11-04T10:00:00.000000000``), else None."""
    import numpy as np

    if dim not in data.coords or data[dim].dtype.kind != "M":
        return None
    try:
        return np.datetime64(text.strip())
    except ValueError:
        return None


# numeric labels within this fraction of the labels' largest magnitude are the same label: floats
# computed as 0.1 * 3 (0.30000000000000004) are found by the 0.3 a user reads and types
LABEL_RTOL = 1e-9


def _label_slack(labels) -> float:
    """How far a number typed for a numeric label may be from it: `LABEL_RTOL` of the largest
    |label| (0 when no label is a number)."""
    return LABEL_RTOL * max((abs(v) for v in labels if _is_number(v) and math.isfinite(v)), default=0.0)


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _quoted(text: str) -> str:
    """``text`` in quotes, control characters escaped (`impedax.errors.escape_text`)."""
    from ..errors import escape_text

    return "'" + escape_text(text) + "'"


def _unquote_hint(label: str, labels) -> str:
    """A hint for a label written in quotes that the shell kept (``--select "cycle='3'"``)
    whose text without them is a label."""
    if len(label) >= 2 and label[0] == label[-1] and label[0] in "'\"":
        bare = label[1:-1]
        if any(str(v) == bare or (_is_number(v) and _as_number(bare) == v) for v in labels):
            return f"; write {bare} without the quotes"
    return ""


def _as_number(text: str) -> float | None:
    """``text`` as a finite number, or None."""
    try:
        value = float(text)
    except ValueError:
        return None
    return value if math.isfinite(value) else None


def _picked(data, dim: str, text: str, path: str, item: str) -> int | list[int]:
    """What ``--select DIM=TEXT`` picks along ``dim``: the position of one label (`_position`,
    the dimension then goes), or the positions of a list ``L1,L2,...`` and/or ranges
    ``FIRST:LAST`` (in the order written; a range's in the file's order; the dimension stays).
    A text that is one of ``dim``'s labels whole (a sheet named ``a,b``, a temperature
    ``25,5``) is that label; a list that picks nothing but reads as a decimal-comma number
    equal to a label (``25,5`` for 25.5) is refused with that number suggested."""
    labels = dimension_labels(data, dim)
    if ("," not in text and ":" not in text) or (dim in data.coords and any(str(v) == text for v in labels)) or _as_moment(data, dim, text) is not None:
        return _position(data, dim, text, path)
    try:
        return _listed_positions(data, dim, text, path, item)
    except ParameterError as error:
        meant = _decimal_comma_label(data, dim, text)
        if meant is None:
            raise
        raise ParameterError(f"{error}; did you mean {meant}? --select takes '.' as the decimal mark; ',' separates a list") from None


#: A number written with a decimal comma (25,5): one comma between digits, nothing else.
DECIMAL_COMMA_NUMBER = re.compile(r"[-+]?\d+,\d+")


def _decimal_comma_label(data, dim: str, text: str) -> str | None:
    """``text`` with its comma as the decimal mark (``25,5`` → ``25.5``) when that is a
    number equal to one of ``dim``'s labels (a number, or a text that is one), else None: the
    hint for a list that picks nothing, typed with a European decimal comma."""
    if dim not in data.coords or not DECIMAL_COMMA_NUMBER.fullmatch(text):
        return None
    meant = text.replace(",", ".")
    value = float(meant)
    labels = dimension_labels(data, dim)
    if any((_is_number(v) and v == value) or (isinstance(v, str) and _as_number(v) == value) for v in labels):
        return meant
    return None


def _listed_positions(data, dim: str, text: str, path: str, item: str) -> list[int]:
    """The positions of a list ``L1,L2,...`` and/or ranges ``FIRST:LAST`` (`_picked`)."""
    labels = dimension_labels(data, dim)
    positions: list[int] = []
    parts = text.split(",")
    for k, part in enumerate(parts):
        part = part.strip()
        which = f"item {k + 1} of {len(parts)}"
        if not part:
            raise ParameterError(f"--select {item}: {which} is empty; write {dim}=L1,L2,... (labels separated by commas) or {dim}=FIRST:LAST")
        if part.count(":") > 1:
            raise ParameterError(f"--select {item}: {_quoted(part)} is not a range: a range is FIRST:LAST (both included), without a step")
        found = _range_positions(data, dim, part, path, item) if ":" in part else [_position(data, dim, part, path, item)]
        for i in found:
            if i in positions:
                raise ParameterError(f"--select {item}: {dim} {labels[i]} is picked twice; name each spectrum once")
        positions += found
    return positions


def _range_positions(data, dim: str, part: str, path: str, item: str) -> list[int]:
    """The positions, in the file's order, of the spectra whose ``dim`` label lies in
    ``FIRST:LAST`` (``part``): both ends included, compared by value (a label range, as
    xarray's ``sel(DIM=slice(FIRST, LAST))``; the ends need not be labels); an end left out
    is open. Labels must be numbers (or texts that are all numbers); where ``dim`` has no
    labels, its positions 0..n-1 are its labels."""
    first, _, last = (end.strip() for end in part.partition(":"))
    labels = dimension_labels(data, dim)
    if dim not in data.coords:
        values = list(range(len(labels)))
        kind = f"{path} has no labels along {dim}, so a range is of positions 0..{len(labels) - 1}"
        for end in (first, last):
            if end and not end.isdigit():
                raise ParameterError(f"--select {item}: {_quoted(end)} in {_quoted(part)} is not a position; {kind}")
        ends = [int(end) if end else None for end in (first, last)]
    else:
        values = [v if _is_number(v) else _as_number(v) if isinstance(v, str) else None for v in labels]
        if any(v is None for v in values):
            example = ",".join([str(v) for v in labels if not set(str(v)) & set(",:")][:2])
            example = "L1,L2" if example in map(str, labels) else example  # (a label of its own: not a list)
            raise ParameterError(
                f"--select {item}: a range FIRST:LAST needs numeric labels, and {path}'s {dim} labels are not all numbers "
                f"({labels_text(labels)}): list the ones you want with commas, e.g. --select {dim}={example}"
            )
        ends = []
        for end in (first, last):
            number = _as_number(end) if end else None
            if end and number is None:
                raise ParameterError(f"--select {item}: {_quoted(end)} in {_quoted(part)} is not a number; the {dim} labels are numbers: {labels_text(labels)}")
            ends.append(number)
    lo, hi = ends
    if lo is not None and hi is not None and lo > hi:
        raise ParameterError(f"--select {item}: the range {part} is reversed (its first end is above its last); write {last}:{first}")
    slack = _label_slack([v for v in values if v is not None])  # (0.1:0.7 keeps a label 0.7000000000000001)
    found = [i for i, v in enumerate(values) if v is not None and (lo is None or v >= lo - slack) and (hi is None or v <= hi + slack)]
    if not found:
        raise ParameterError(f"--select {item}: no spectrum of {path} has a {dim} label in {part} (both ends included); its {dim} labels: {labels_text(labels)}")
    if dim in data.coords and all(end == "" or end.isdigit() for end in (first, last)):
        _note_labels_not_positions(item if item == f"{dim}={part}" else f"{item} (its range {part})", dim, labels, found, range(int(first or 0), min(int(last) + 1 if last else len(labels), len(labels))))
    return found


def _note_labels_not_positions(item: str, dim: str, labels: Sequence, found: Sequence[int], by_position: range) -> None:
    """One line on stderr when a range of labels (``found``) picks other spectra than the same
    ends read as positions would (``by_position``): ``--select cycle=0:20`` of the REAL battery
    cycles labelled 0, 64, 129 keeps cycle 0 alone, which a user counting spectra does not
    expect, and its "1 spectrum" alone says so too quietly."""
    if by_position and list(found) != list(by_position):  # (ends past the last position: no one meant positions)
        kept = [labels[i] for i in found]
        print(f"impedax: note: --select {item} keeps {dim} {labels_text(kept)} ({len(found)} of {len(labels)}): a range is of {dim} labels, by value "
              f"(the file's: {labels_text(labels)}), not of positions", file=sys.stderr)


def part_of_joined(text: str, prefixes: Sequence[str], i: int) -> str | None:
    """The part after ``prefixes[i]`` of ``text`` made of ``"; "``-joined parts each led by
    its prefix in order (``sheet A: ...; sheet B: ...``), or None when ``text`` is not such."""
    starts = []
    for k, prefix in enumerate(prefixes):
        at = text.find(prefix if k == 0 else "; " + prefix, starts[-1] + len(prefixes[k - 1]) if starts else 0)
        if at < 0 or (k == 0 and at != 0):
            return None
        starts.append(at + (2 if k else 0))
    end = starts[i + 1] - 2 if i + 1 < len(starts) else len(text)
    return text[starts[i] + len(prefixes[i]) : end]


def _attrs_of_pick(attrs: dict, dim: str, labels: Sequence[str], i: int | Sequence[int]) -> dict:
    """``attrs`` of a file of several spectra along ``dim`` narrowed to the spectrum at
    position ``i``: a text the reader joined from each spectrum's own (``sheet A: ...; sheet B:
    ...``, `impedax.io` stacking) becomes that spectrum's, and its skipped rows only are kept.
    ``i`` a list of positions (a list or range of labels): the joined text and the skipped
    rows of those spectra, each still led by its label."""
    prefixes = [f"{dim} {label}: " for label in labels]
    several = not isinstance(i, int)
    out = {}
    for key, value in attrs.items():
        if key == "skipped_rows" and not isinstance(value, str):
            rows = [str(r) for r in value]
            if any(r.startswith(p) for r in rows for p in prefixes):
                if several:
                    value = [r for r in rows if any(r.startswith(prefixes[k]) for k in i)]
                else:
                    value = [r[len(prefixes[i]):] for r in rows if r.startswith(prefixes[i])]
        elif isinstance(value, str):
            if several:
                if part_of_joined(value, prefixes, 0) is not None:
                    value = "; ".join(prefixes[k] + part_of_joined(value, prefixes, k) for k in i)
            else:
                part = part_of_joined(value, prefixes, i)
                value = value if part is None else part
        out[key] = value
    return out


def _select_item(item: str) -> tuple[str, str]:
    """``DIM=LABEL`` of one ``--select`` as (DIM, LABEL), or `ParameterError`."""
    dim, sep, label = item.partition("=")
    dim, label = dim.strip(), label.strip()
    if not sep or not dim or not label:
        raise ParameterError(f"--select: expected DIM=LABEL, got {item!r}")
    return dim, label


def _extra_dims(data) -> list[str]:
    return [d for d in data["Z"].dims if d != "frequency"]


#: Notes of a reader (``attrs``) that a command prints as warnings: what was read may not be
#: what the file meant.
LOAD_WARNINGS = ("phase_unit_note", "stdin_note", "polar_columns_note")  # (stdin_note: standard input your --plugin readers did not claim; polar_columns_note: |Z| or the phase beside Z', Z'' disagreeing, io.consistency)


def _load_noting(path: str, warn: bool = True, select: Sequence[str] | None = None, readers=None):
    """`impedax.io.load` with ``readers`` (None: the built-in ones; a run's ``args.readers``
    adds the --plugin files'), printing the reader's `LOAD_WARNINGS` notes to stderr. A file of
    sweeps on different frequency grids (`SweepGridsDiffer`) is read one sweep alone when
    ``select`` names one (`_sweep_alone`), else refused with the reader's message."""
    from ..errors import SweepGridsDiffer
    from ..io import load

    try:
        data = load(path, readers)
    except SweepGridsDiffer as exc:
        data = _sweep_alone(exc, path, select, readers)
    for key in LOAD_WARNINGS if warn else ():
        if key in data.attrs:
            print(f"impedax: warning: {data.attrs.get('path', path)}: {data.attrs[key]}", file=sys.stderr)  # (<stdin> for -)
    return data


def _sweep_alone(exc, path: str, select: Sequence[str] | None, readers=None):
    """The one sweep ``--select DIM=LABEL`` names of a file whose sweeps lie on different grids
    (``exc``, a `SweepGridsDiffer`), read alone (`impedax.io.load`'s ``sweep``) and recorded as
    a selection (``source`` ``path [DIM=LABEL]``, ``selection``); ``exc`` itself when no item
    names one, a `ParameterError` for a list, range or unknown label (one grid at a time)."""
    from ..io import load

    items = [item for item in select or () if _select_item(item)[0] == exc.dim]
    if not items:
        raise exc
    item = items[0]
    label = _select_item(item)[1]
    name = shown_path(path)
    if label not in exc.labels:
        raise ParameterError(
            f"--select {item}: {name} holds {len(exc.labels)} {exc.dim}s on different frequency grids, each read alone: "
            f"give one label ({exc.dim}: {', '.join(exc.labels)}), e.g. --select {exc.dim}={exc.labels[0]}"
        )
    data = exc.spectrum(label) if path == "-" else load(path, readers, sweep=label)  # (standard input is read once: its sweeps came with the error)
    shown = f"{exc.dim}={label}"
    data.attrs = {**data.attrs, "selection": shown, "source": f"{name} [{shown}]"}
    return data


def shown_path(path: str) -> str:
    """``path`` as messages and a selection's ``source`` name it: ``<stdin>`` for ``-``."""
    from ..io.loader import STDIN, STDIN_NAME

    return STDIN_NAME if str(path) == STDIN else path


def load_selected(path: str, select: Sequence[str] | None, *, single: str | None = None, or_else: str = "", warn: bool = True, readers=None):
    """The spectra of file ``path`` (`impedax.io.load` with ``readers``, None: the built-in
    ones), narrowed by ``--select DIM=LABEL`` items (`select_spectra`); ``warn`` prints the
    reader's `LOAD_WARNINGS` notes. Sweeps on different grids are read one alone (`_sweep_alone`)."""
    return select_spectra(_load_noting(path, warn, select, readers), shown_path(path), select, single=single, or_else=or_else)


def note_unused_sigma(data, command: str, used: bool, option: str) -> None:
    """One line on stderr when ``data`` carry σ per point (a ``sigma`` variable: a sigma, std
    or sem column) that the command's weighting or noise model does not use (``used`` false):
    a walkthrough's file with a sigma column was fitted by |Z| without a word, and the
    uneven-noise warning then asked for a sigma column. ``option``: the flag that uses it."""
    if not used and "sigma" in data:
        print(f"impedax {command}: note: the data carry sigma (σ per point), which this run does not use: {option} weighs by it", file=sys.stderr)


def skipped_rows(data) -> list[str]:
    """The rows of the file the reader skipped (its ``attrs["skipped_rows"]``: DC rows at f = 0,
    repeated headers; narrowed to the spectra a ``--select`` picked), one text per range of
    lines, as ``impedax inspect --json`` lists them under ``skipped_rows``; [] when none."""
    rows = data.attrs.get("skipped_rows", [])
    return [rows] if isinstance(rows, str) else [str(r) for r in rows]


def note_skipped_rows(data, command: str, path: str) -> None:
    """One line on stderr naming the rows of file ``path`` the reader skipped (`skipped_rows`),
    for a command's text report; its JSON holds them under ``skipped_rows`` (the 781
    DC rows of a REAL Parstat file would otherwise be skipped without a word, listed only by
    ``impedax inspect``)."""
    rows = skipped_rows(data)
    if rows:
        shown = "; ".join(rows[:SKIPPED_ROWS_SHOWN]) + (f"; … ({len(rows)} ranges in all: impedax inspect lists them)" if len(rows) > SKIPPED_ROWS_SHOWN else "")
        print(f"impedax {command}: note: {shown_path(path)}: rows skipped as no impedance points: {shown}", file=sys.stderr)


SKIPPED_ROWS_SHOWN = 3
"""The ranges of skipped rows `note_skipped_rows` names on its one line (inspect lists 20)."""


class WithSummaryKeys:
    """``result`` whose ``summary()`` (``--json``, ``--out FILE.json``) also holds ``keys``
    (``skipped_rows``: what the reader of the data left out), so that both outputs stay the
    same; every other attribute is the result's own."""

    def __init__(self, result, keys: Mapping[str, object]):
        self._result, self._keys = result, dict(keys)

    def summary(self) -> dict:
        return {**self._result.summary(), **self._keys}

    def __getattr__(self, name: str):
        return getattr(self._result, name)


def load_selected_files(paths: Sequence[str], select: Sequence[str] | None, readers=None) -> list:
    """The spectra of several files (a command of several inputs: ``impedax gap``), each
    narrowed by the ``--select DIM=LABEL`` items whose DIM it has, as a dimension or as the
    value its one spectrum carries (`select_spectra`, `_carried_value`: the same checks and
    messages); a DIM that none of them has is a `ParameterError` naming their dimensions."""
    datasets = [_load_noting(p, select=select, readers=readers) for p in paths]
    items = [(item, _select_item(item)[0]) for item in select or ()]

    def has(data, dim: str) -> bool:
        return dim in _extra_dims(data) or _carried_value(data, dim) is not None

    for item, dim in items:
        if not any(has(d, dim) for d in datasets):
            have = sorted({d for data in datasets for d in _extra_dims(data)})
            listed = f"their dimensions besides frequency: {', '.join(have)}" if have else "each holds one spectrum"
            raise ParameterError(f"--select {item}: none of {', '.join(paths)} has a dimension {dim!r} to select from; {listed}")
    return [select_spectra(data, shown_path(path), [item for item, dim in items if has(data, dim)]) for data, path in zip(datasets, paths)]


def _carried_value(data, dim: str):
    """The value of ``dim`` that ``data`` carries without a dimension of it, as `impedax
    inspect` shows it (a BioLogic file's ``cycle: 1``, a selection saved to .nc): a scalar
    coordinate, else a number or text attribute; None when it carries none."""
    if dim in data.coords and data.coords[dim].ndim == 0:
        return data.coords[dim].values.item()
    value = data.attrs.get(dim)
    if isinstance(value, (str, int, float)) and not isinstance(value, bool):
        return value
    return None


def _carries(data, dim: str, label: str, path: str, item: str) -> bool:
    """Does ``--select DIM=LABEL`` (one label, a list or a range) name the value of ``dim``
    that the spectra carry (`_carried_value`), by the rules a dimension's labels follow
    (`_picked`)? True: the selection is a no-op. False when they carry none; a
    `ParameterError` naming the value when it differs (inspect showed "cycle: 1", and
    ``--select cycle=1`` was refused for want of a dimension)."""
    import xarray as xr

    value = _carried_value(data, dim)
    if value is None:
        return False
    number = _as_number(value) if isinstance(value, str) else None  # (a reader's text "1" is the number 1, as a coordinate would be)
    probe = value if number is None else int(number) if number.is_integer() else number
    try:
        _picked(xr.Dataset(coords={dim: [probe]}), dim, label, path, item)
    except ParameterError:
        raise ParameterError(f"--select {item}: the file holds {dim} {value} only ({path} holds one {dim}, not a dimension of them to select from)") from None
    return True


#: Attributes of a file that describe all of it (its ``title``: "..., all 130 cycles"): a
#: ``--select`` notes itself in them (`select_spectra`).
DESCRIBING_ATTRS = ("title", "description", "summary", "comment")


def select_spectra(data, path: str, select: Sequence[str] | None, *, single: str | None = None, or_else: str = ""):
    """``data`` (the spectra of file ``path``) narrowed by ``--select DIM=LABEL`` items: one
    label picks one spectrum along DIM (the dimension goes); a list ``L1,L2,...`` or a range
    ``FIRST:LAST`` (both ends included, by value; `_picked`) keeps DIM with the spectra picked,
    labelled as in the file (positions where DIM has no labels become its coordinate).
    ``single``: the command takes one spectrum; data that still hold several raise
    `DataError` naming the dimensions, their labels (how many a list or range picked, and
    which), ``--select`` and ``or_else`` (the command's other way with several: "or sample
    them jointly with --shared NAMES"); a list or range that picks one is that one spectrum.
    A selection is recorded in the data's ``source`` (``path [DIM=LABEL]``), which later
    messages name, and in ``selection`` (``DIM=LABEL``); the other attributes are kept, and the
    `DESCRIBING_ATTRS` among them, which describe the whole file, end in ``[selection: DIM=LABEL]``."""
    picks: dict[str, int | list[int]] = {}
    written: dict[str, str] = {}
    for item in select or ():
        dim, label = _select_item(item)
        extra = _extra_dims(data)
        if dim not in extra and _carries(data, dim, label, path, item):
            continue  # (the label the spectra carry: a no-op)
        if dim not in extra:
            have = f"its dimensions besides frequency: {', '.join(extra)}" if extra else "it holds one spectrum"
            raise ParameterError(f"--select {item}: {path} has no dimension {dim!r} to select from; {have}")
        if dim in picks:
            raise ParameterError(f"--select: {dim} given twice")
        pick = _picked(data, dim, label, path, f"{dim}={label}")
        if single is not None and not isinstance(pick, int) and len(pick) == 1:
            pick = pick[0]  # (a list or range of one: that spectrum, as its label would pick it)
        picks[dim], written[dim] = pick, label
    if picks:
        shown = ", ".join(f"{d}={label_shown(dimension_labels(data, d)[i])}" if isinstance(i, int) else f"{d}={written[d]}" for d, i in picks.items())
        attrs = dict(data.attrs)
        for d, i in picks.items():
            attrs = _attrs_of_pick(attrs, d, [str(v) for v in dimension_labels(data, d)], i)
        unlabelled = {d: i for d, i in picks.items() if not isinstance(i, int) and d not in data.coords}
        data = data.isel(picks)
        if unlabelled:  # (their labels are their positions in the file, not in the pick)
            data = data.assign_coords(unlabelled)
        for key in DESCRIBING_ATTRS:  # (they describe the whole file: "..., all 130 cycles")
            if isinstance(attrs.get(key), str):
                attrs[key] = f"{attrs[key]} [selection: {shown}]"
        data.attrs = {**attrs, "selection": shown, "source": f"{path} [{shown}]"}
        if unlabelled:  # (which dims were picked by position, not label: `impedax gap` reports it per file)
            data.attrs["selected_by_position"] = ",".join(unlabelled)
    extra = [d for d in data["Z"].dims if d != "frequency"]
    if single is not None and extra:
        n = math.prod(data.sizes[d] for d in extra)
        several = [d for d in extra if d in picks]
        if several:
            dim = several[0]
            labels = dimension_labels(data, dim)
            rest = [d for d in extra if d != dim]
            raise DataError(
                f"{single} takes one spectrum; --select {dim}={written[dim]} picks {len(labels)} ({dim}: {labels_text(labels)})"
                + (f", {n} spectra over {', '.join(extra)} in all" if rest else "")
                + f": give one label, e.g. --select {dim}={labels[0]}" + (f", and pick one along {', '.join(rest)} too" if rest else "")
                + (f"; {or_else}" if or_else else ""),
                path=path,
            )
        # every extra dimension's labels and one --select each: one spectrum needs a label along all of them
        # (a walkthrough's material × voltage file was shown only material's, and tried --select material=glass alone)
        labels = {d: dimension_labels(data, d) for d in extra}
        held = "; ".join(f"{d}: {labels_text(v)}" for d, v in labels.items())
        picks_text = " ".join(f"--select {d}=LABEL" for d in extra)
        example = " ".join(f"--select {d}={v[0]}" for d, v in labels.items())
        raise DataError(
            f"{single} takes one spectrum; the file holds {n} over {', '.join(extra)} ({held}): "
            f"pick one with {picks_text}" + (" (a label along each dimension)" if len(extra) > 1 else "") + f", e.g. {example}"
            + (f"; {or_else}" if or_else else ""),
            path=path,
        )
    return data


RESULT_OUT_METAVAR = "FILE.csv|.json|.nc"
PLOT_METAVAR = "FILE"
# the resolution of a raster figure without --dpi: `impedax.plotting.FIGURE_DPI`, repeated so
# that --help does not import matplotlib (tests/test_figure_output.py checks that they agree)
FIGURE_DPI = 120
PLOT_FORMATS_HELP = "the format follows the extension: .png, .pdf, .svg, .eps (vector: .pdf, .svg, .eps); none: PNG"


# what the title impedax writes names, in ``--title``'s help (a command without a data file,
# `impedax force`, says what its title names instead)
DEFAULT_TITLE_NAMES = "the data file"


def add_output_options(parser, *, json: str | None = "print the result as JSON", plot: str | None = None, out: str | None = None, out_metavar: str = RESULT_OUT_METAVAR,
                       title_names: str = DEFAULT_TITLE_NAMES) -> None:
    """The output options of a command: ``--json`` (help ``json``), ``--plot FILE`` with
    ``--dpi`` and ``--title`` (help ``plot`` and ``title_names``, `add_plot_option`) and
    ``--out`` (help ``out``); an option whose help is None is not added."""
    if json:
        parser.add_argument("--json", action="store_true", help=json)
    if plot:
        add_plot_option(parser, plot, title_names=title_names)
    if out:
        parser.add_argument("--out", metavar=out_metavar, help=out)


def add_plot_option(parser, help: str, *, flag: str = "--plot", title_names: str = DEFAULT_TITLE_NAMES) -> None:
    """``flag FILE`` (help ``help``, and that the format follows the extension), with the
    figure options ``--dpi N`` and ``--title TEXT`` (`figure_options`; its help says the
    default title names ``title_names``), once per parser."""
    parser.add_argument(flag, metavar=PLOT_METAVAR, help=f"{help} ({PLOT_FORMATS_HELP})")
    add_figure_flag(parser, flag)
    if not any("--dpi" in action.option_strings for action in parser._actions):
        parser.add_argument("--dpi", type=dpi_option, default=None, metavar="N",
                            help=f"resolution of a raster figure (.png, .jpg, .tif) in dots per inch (default {FIGURE_DPI}, at least {MIN_DPI}, at most {MAX_DPI}); a vector figure has none")
        parser.add_argument("--title", type=title_option, default=None, metavar="TEXT",
                            help=f"the figure's title in place of the one impedax writes (which names {title_names}); --title '' for none; text between two $ is matplotlib math text, \\$ a dollar sign")


def add_figure_flag(parser, flag: str) -> None:
    """Record ``flag`` (``--plot``, ``--corner``, fit's ``--residual-map``) as an option of
    ``parser`` that draws a figure, which ``--dpi`` and ``--title`` apply to (`unused_figure_options`)."""
    parser.figure_flags = [*getattr(parser, "figure_flags", []), flag]


def unused_figure_options(parser, args) -> list[str]:
    """The notes for ``--dpi`` and ``--title`` given in ``args`` (parsed by ``parser``) with none of
    the parser's figure options (`add_figure_flag`): they change nothing then, which the run says
    on stderr rather than ignoring them silently (a walkthrough's ``--dpi 300`` without --plot)."""
    flags = getattr(parser, "figure_flags", [])
    if not flags or any(getattr(args, parser._option_string_actions[flag].dest, None) is not None for flag in flags):
        return []
    wanted = ", ".join(flags[:-1]) + (" or " if len(flags) > 1 else "") + flags[-1]
    return [f"{option} has no effect without {wanted}" for option in ("--dpi", "--title") if getattr(args, option[2:], None) is not None]


MAX_DPI = 1200
"""The largest ``--dpi``: the top of what journals ask of line art. A walkthrough's ``--dpi 3000``
drew a KK figure for 38 s in 3.9 GB of memory (2026-12-05); an 11 × 4.5 in figure at 1200 dpi
holds 71 million pixels, about 0.3 GB."""


MIN_DPI = 20
"""The least ``--dpi``: FreeType draws no text below one pixel per em, which the 5–7 pt labels of
impedax's figures reach below about 15 dpi (``--dpi 5`` would end in matplotlib's RuntimeError
"invalid ppem value", ``--dpi 1e-300`` in "cannot write empty image": values the fuzz matrix,
tests/cli_fuzz_matrix.py, gave). At 20 dpi a 6 pt label is 1.7 pixels tall: a thumbnail, nothing smaller is legible."""


def dpi_option(text: str) -> float:
    """``--dpi``: a number (`prefixed_number`) from `MIN_DPI` to `MAX_DPI`, as an argparse ``type`` (exit 2)."""
    import argparse

    value = number_option(text)
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"expected a positive number of dots per inch, got {text!r}")
    if value < MIN_DPI:
        raise argparse.ArgumentTypeError(f"{text} dots per inch is too few to draw the figure's text; use at least {MIN_DPI} (the default is {FIGURE_DPI})")
    if value > MAX_DPI:
        raise argparse.ArgumentTypeError(f"{text} dots per inch is more than the {MAX_DPI} print needs, and the figure would take minutes and gigabytes to draw; use at most {MAX_DPI}, or a vector format (.pdf, .svg), which has no resolution")
    return value


def title_option(text: str) -> str:
    """``--title``: any text; a part between dollar signs is matplotlib math text, which must
    parse, as an argparse ``type`` (exit 2): ``--title '$\\undefined$'`` would end in matplotlib's
    ParseFatalException when the figure is saved, after the analysis (a value the fuzz matrix,
    tests/cli_fuzz_matrix.py, gave). matplotlib is imported only when --title is given."""
    import argparse

    from matplotlib import cbook

    if cbook.is_math_text(text):
        from matplotlib.mathtext import MathTextParser

        try:
            MathTextParser("path").parse(text)
        except ValueError as exc:
            found = str(exc).strip().splitlines()[-1].split(": ", 1)[-1].split(" (at char")[0]  # (its last line, "ParseFatalException: Unknown symbol: \\x, found '\\'")
            found = found.strip() if len(found) <= 80 else found[:79] + "…"
            raise argparse.ArgumentTypeError(f"'{text}' is not matplotlib math text between its dollar signs ({found}); write \\$ for a dollar sign") from None
    return text


def figure_options(args) -> dict:
    """The ``--dpi`` and ``--title`` of a command's ``args`` as keywords of `figure_writer`."""
    return {"dpi": getattr(args, "dpi", None), "title": getattr(args, "title", None)}


def result_out_help(what: str) -> str:
    """The help of a result's ``--out``: the format follows the extension."""
    return f"save {what}: .csv a tidy table of parameters, .json the --json summary, .nc the full result as netCDF; '-' the JSON to standard output"


def check_outputs(*paths, result: str | None = None) -> None:
    """Every output path that was given is writable, and ``result`` (a result's ``--out``) has
    an extension `impedax.io.write_result` knows: checked before any work is done. (Commands use
    `plan_outputs`, which also checks figure extensions, inputs and clashes; this stays for
    callers of the older form.)"""
    from ..io.atomic import check_writable
    from ..io.export import result_format

    if result:
        result_format(result)
    for path in (*paths, result):
        if path:
            check_writable(path)


def save_outputs(*, out=None, result=None, dataset=None, plot=None, figure=None) -> None:
    """Write ``result`` to ``out`` (`impedax.io.write_result`) or the spectrum ``dataset()``
    (`impedax.io.save`), and ``figure()`` to ``plot``, together (`OutputTransaction`); each only
    when its path was given (no figure is drawn for nothing)."""
    from ..io.atomic import OutputTransaction

    with OutputTransaction(to_stdout=write_stdout) as transaction:
        if out:
            output = Output("--out", out, "result" if result is not None else "spectrum")
            writer = result_writer(result) if result is not None else spectrum_writer(dataset)
            transaction.write(out, naming_target(writer, out), suffix=output.suffix())
        if plot:
            suffix = Output("--plot", plot, "figure").suffix()
            transaction.write(plot, naming_target(figure_writer(figure), plot), suffix=suffix)
    announce_written(transaction.committed)


# --- outputs: checked before any work, written together -----------------------------------------

def naming_target(writer: Callable[[Path], None], target: str) -> Callable[[Path], None]:
    """``writer``, made to name ``target`` (the user's path) in its errors wherever they name
    the temporary file it was given (`OutputTransaction` stages every output beside its target,
    with the output's extension, ``--plot out`` as ``.png``)."""
    from ..errors import ImpedaxError

    def write(tmp: Path) -> None:
        try:
            writer(tmp)
        except ImpedaxError as exc:
            text = str(exc)
            if str(tmp) in text:
                if isinstance(exc, DataError) and str(exc.path) == str(tmp):
                    exc.path = target
                exc.args = (text.replace(str(tmp), target),)
            raise

    return write


LATEX_SUFFIX = ".tex"


def latex_writer(result) -> Callable[[Path], None]:
    """A writer of ``result.to_latex()`` (a LaTeX table of a fit's parameters), UTF-8."""
    def write(path: Path) -> None:
        Path(path).write_text(result.to_latex(), encoding="utf-8")

    return write


class InCommandWords:
    """``result`` whose ``summary()``, ``to_table()`` and ``to_xarray()`` give their prose (a
    row's ``warnings``; the dataset's `PROSE_KEYS` variables and attributes) in the words of
    ``impedax command`` (`json_in_command_words`, `dataset_in_command_words`), so that a
    command's ``--out FILE.json`` (or ``--out -``) is its ``--json`` document and its CSV and
    netCDF say what its text says; every other attribute is the result's own."""

    def __init__(self, result, command: str):
        self._result, self._command = result, command

    def summary(self) -> dict:
        return json_in_command_words(self._result.summary(), self._command)

    def to_xarray(self):
        return dataset_in_command_words(self._result.to_xarray(), self._command)

    @property
    def to_table(self):
        table = self._result.to_table  # (AttributeError for a result without a table, as the result's own)
        return lambda: json_in_command_words(table(), self._command)

    def __getattr__(self, name: str):
        return getattr(self._result, name)


def dataset_in_command_words(ds, command: str | None):
    """A result's Dataset ``ds`` (`to_xarray`) with its prose in the words of ``impedax command``
    (`command_line_words`: ``raise --max-steps`` where Python says ``raise max_steps``): the text
    variables named in `PROSE_KEYS` (a DRT's ``warnings``, ``lambda_note``, ``sign_hint``) and
    the strings under those keys in its attributes, nested ones too (a fit's ``warnings``, a
    posterior's ``notes`` and its start fit's ``warnings``), as `json_in_command_words` gives the
    JSON; keys, values, labels and models as they are. ``command`` None: ``ds`` unchanged."""
    if command is None:
        return ds
    import numpy as np

    def words(text):
        return command_line_words(text, command) if isinstance(text, str) else text

    prose = {name: ds[name].copy(data=np.vectorize(words, otypes=[object])(ds[name].values)) for name in ds.data_vars
             if name in PROSE_KEYS and ds[name].dtype.kind in "OU" and ds[name].size}
    return ds.assign(prose).assign_attrs(json_in_command_words(dict(ds.attrs), command))


def result_writer(result, source: str | None = None, provenance: Mapping | None = None) -> Callable[[Path], None]:
    """A writer of ``result`` in the format of the path's extension (`impedax.io.write_result`),
    naming the data's ``source`` (`data_source`) and recording ``provenance``
    (`command_provenance`) when given; a JSON, CSV or netCDF file's prose in the words of the
    command that ``provenance`` names (`InCommandWords`, as its ``--json``: JSON and
    netCDF alike, so that ``impedax fit --out FILE.nc`` holds "raise --max-steps" as its JSON
    does, not "raise max_steps")."""
    command = str((provenance or {}).get("command") or "").removeprefix("impedax ")
    command = command if command in COMMANDS_IN_THEIR_WORDS else None

    def write(path: Path) -> None:
        from ..io import write_result

        write_result(InCommandWords(result, command) if command and callable(getattr(result, "summary", None)) else result, path, source=source, provenance=provenance)

    return write


def spectrum_writer(dataset: Callable[[], object], provenance: Mapping | None = None, path: str | None = None) -> Callable[[Path], None]:
    """A writer of the spectrum ``dataset()`` (CSV or netCDF by extension, `impedax.io.save`),
    recording ``provenance`` (`command_provenance`) when given, unless the output's ``path`` is
    ``-``: a spectrum on standard output stays the canonical columns a pipe reads, as the CSV
    `simulate` and `remaining` print without ``--out`` (docs/io.md, "Provenance")."""
    provenance = None if path == "-" else provenance
    def write(path: Path) -> None:
        from ..io import save

        save(dataset(), path, provenance=provenance)

    return write


def figure_writer(figure: Callable[[], object], source: str | None = None, *, dpi: float | None = None, title: str | None = None,
                  subtitle: str | None = None) -> Callable[[Path], None]:
    """A writer of the matplotlib figure ``figure()`` (drawn only when written) at ``dpi``
    (`impedax.plotting.save_figure`; None: its default); ``source`` (`data_source`) is added to
    its title as `short_source`, unless ``title`` is given: the figure's title then ("" none),
    followed by ``subtitle`` (a circuit the figure names nowhere else), wrapped as a circuit."""
    def write(path: Path) -> None:
        import warnings

        from ..plotting import save_figure, wrap_model

        with warnings.catch_warnings(record=True) as caught:  # (said below as notes, not as matplotlib's file:line and source line)
            fig = figure()
            if title is not None:
                replace_title(fig, title)
                if title and subtitle:
                    append_title_line(fig, subtitle, wrap_model)
            elif source:
                title_with_source(fig, source)
            save_figure(fig, path, **({} if dpi is None else {"dpi": dpi}))  # (no keyword unless given: a save_figure stand-in of two arguments still works)
        figure_notes(caught)

    return write


def figure_notes(caught) -> None:
    """The warnings drawing a figure raised (matplotlib's: "Data has no positive values, and
    therefore cannot be log-scaled." for a |Z| panel of a spectrum 0 everywhere), each once, as
    one line on stderr, ``impedax: note: the figure: …``, where Python printed the file and line
    in matplotlib or impedax.plotting that raised it and that line's source."""
    said: list[str] = []
    for item in caught:
        text = " ".join(str(item.message).split())
        if text not in said:
            said.append(text)
            print(f"impedax: note: the figure: {text}", file=sys.stderr)


def data_source(data) -> str | None:
    """Where ``data`` came from: its ``source`` attribute, the file and any ``--select``
    (``path [cycle=3]``, `select_spectra`); None for data built in memory."""
    from ..errors import IN_MEMORY

    source = data.attrs.get("source")
    return None if source in (None, "", IN_MEMORY) else str(source)


def short_source(source: str) -> str:
    """``source`` (``path [DIM=LABEL]``) with the path shortened to the file's name."""
    path, sep, selection = str(source).partition(" [")
    return Path(path).name + (f" [{selection}" if sep else "")


def title_with_source(fig, source: str) -> None:
    """Add `short_source` of ``source`` to ``fig``'s title (a line of its own, wrapped to the
    figure's width), unless the title names it already."""
    shown = literal_text(short_source(source))
    if fig._suptitle is None or shown not in fig._suptitle.get_text():
        append_title_line(fig, shown, lambda text, width: "\n".join(_wrapped(text, width)))


def append_title_line(fig, text: str, wrap: Callable[[str, int], str]) -> None:
    """``text`` as the last line of ``fig``'s title (its title when it has none), wrapped to
    the figure's width by ``wrap(text, characters)`` (e.g. `impedax.plotting.wrap_model`)."""
    from ..plotting import characters_across, font_size

    line = wrap(text, characters_across(fig.get_figwidth() - 0.4, font_size("suptitle", 12)))
    title = fig._suptitle.get_text() if fig._suptitle is not None else ""
    if title:
        fig._suptitle.set_text(f"{title}\n{line}")
    else:
        fig.suptitle(line)


def replace_title(fig, title: str) -> None:
    """``title`` as ``fig``'s title (its suptitle; the title of a figure of one panel without
    one): "" removes it."""
    if fig._suptitle is None and len(fig.axes) == 1 and fig.axes[0].get_title():
        fig.axes[0].set_title(title)
    elif fig._suptitle is not None and not title:
        fig._suptitle.remove()
        fig._suptitle = None
    elif title:
        fig.suptitle(title)


def _wrapped(text: str, width: int) -> list[str]:
    """``text`` on lines of at most ``width`` characters (a path without spaces broken anywhere)."""
    import textwrap

    return textwrap.wrap(text, width, break_long_words=True, break_on_hyphens=False) or [text]


def write_stdout(data: bytes) -> None:
    """``data`` to standard output, after whatever the command printed before."""
    sys.stdout.flush()
    buffer = getattr(sys.stdout, "buffer", None)
    if buffer is not None:
        buffer.write(data)
        buffer.flush()
    else:
        sys.stdout.write(data.decode("utf-8"))
        sys.stdout.flush()


def _missing_tool(extension: str) -> str | None:
    """Why matplotlib cannot write a figure of this type here, or None: PGF needs the LaTeX
    program of ``rcParams["pgf.texsystem"]`` (checked before any work, not after the fit)."""
    if extension != ".pgf":
        return None
    import shutil

    from matplotlib import rcParams

    tex = rcParams["pgf.texsystem"]
    return None if shutil.which(tex) else f"'.pgf' needs a LaTeX install ({tex} not found)"


def _figure_extensions() -> tuple[str, ...]:
    from matplotlib.backend_bases import FigureCanvasBase

    return tuple(sorted(e for e in (f".{ext}" for ext in FigureCanvasBase.get_supported_filetypes()) if _missing_tool(e) is None))


def _result_extensions() -> tuple[str, ...]:
    from ..io.export import RESULT_FORMATS

    return tuple(RESULT_FORMATS)


def _spectrum_extensions() -> tuple[str, ...]:
    from ..io.loader import SPECTRUM_SUFFIXES

    return SPECTRUM_SUFFIXES


@dataclass(frozen=True)
class OutputKind:
    """What an output option writes: the extensions it accepts (``extensions()``; "" means
    none, taken as ``default_suffix``) and, when it can go to standard output (``-``), as what."""

    name: str
    extensions: Callable[[], tuple[str, ...]]
    default_suffix: str
    stdout_suffix: str | None


OUTPUT_KINDS = {
    "result": OutputKind("result", _result_extensions, ".json", ".json"),
    # (a fit of one spectrum: also .tex, `FitResult.to_latex`; ``impedax fit --out``)
    "fit": OutputKind("result", lambda: (*_result_extensions(), LATEX_SUFFIX), ".json", ".json"),
    "spectrum": OutputKind("spectrum", _spectrum_extensions, ".csv", ".csv"),
    "figure": OutputKind("figure", lambda: ("", *_figure_extensions()), ".png", None),
    "diagram": OutputKind("circuit diagram", lambda: ("", ".png", ".svg", ".pdf"), ".png", None),
    "drt": OutputKind("DRT", _result_extensions, ".csv", ".csv"),
}


@dataclass(frozen=True)
class Output:
    """One output option of a command as given: ``flag`` (``--plot``), ``path``, ``kind`` (a key
    of `OUTPUT_KINDS`)."""

    flag: str
    path: str
    kind: str

    @property
    def to_stdout(self) -> bool:
        return self.path == "-"

    def suffix(self) -> str:
        """The extension a temporary copy of this output gets (its own, or the kind's default)."""
        kind = OUTPUT_KINDS[self.kind]
        if self.to_stdout:
            return kind.stdout_suffix or kind.default_suffix
        return Path(self.path).suffix or kind.default_suffix


def _same_file(a: str, b: str) -> bool:
    try:
        if os.path.exists(a) and os.path.exists(b):
            return os.path.samefile(a, b)
    except OSError:
        return False
    return os.path.realpath(a) == os.path.realpath(b)


class OutputPlan:
    """The output files of one command run, checked together before any work (`plan_outputs`)
    and written together by `save`: all appear, or none (`impedax.io.atomic.OutputTransaction`)."""

    def __init__(self, outputs: Sequence[Output]):
        self.outputs = tuple(outputs)

    @property
    def uses_stdout(self) -> bool:
        """An output goes to standard output (``-``): the command prints nothing else there."""
        return any(o.to_stdout for o in self.outputs)

    def given(self, flag: str) -> bool:
        return any(o.flag == flag for o in self.outputs)

    def save(self, writers: Mapping[str, Callable[[Path], None]]) -> tuple[str, ...]:
        """Write each planned output with ``writers[flag](path)`` to a temporary file, then move
        them all into place, and say ``wrote FILE`` on stderr for each file (`announce_written`;
        not for ``-``, standard output); returns the paths written."""
        from ..io.atomic import OutputTransaction

        with OutputTransaction(to_stdout=write_stdout) as transaction:
            for output in self.outputs:
                transaction.write(output.path, naming_target(writers[output.flag], output.path), suffix=output.suffix())
        kinds = {o.path: o.kind for o in self.outputs}
        for path in transaction.committed:
            if path != "-":
                print(f"wrote {path}{_written_as(path, kinds.get(path))}", file=sys.stderr)
        return transaction.committed


def _written_as(path: str, kind: str | None) -> str:
    """What a spectrum file whose name does not say its format holds, for its ``wrote`` line:
    ``.txt`` and no extension are CSV, ``.tsv`` tab-separated (`impedax.io.save`); "" otherwise.
    Those extensions are kept for spectra (docs/io.md), and the line says what they hold, which
    ``--out out.txt`` wrote without a word."""
    if kind != "spectrum":
        return ""
    suffix = Path(path).suffix.lower()
    if suffix in (".txt", ""):
        return " (the spectrum as CSV text, as impedax load reads it)"
    return " (the spectrum as tab-separated text, as impedax load reads it)" if suffix == ".tsv" else ""


def announce_written(paths: Iterable[str]) -> None:
    """``wrote FILE`` on stderr for each file of ``paths`` (``-``, standard output, is not a
    file): every command says so for each figure and ``--out`` file it writes, never on
    stdout, which holds the command's report, CSV or JSON."""
    for path in paths:
        if path != "-":
            print(f"wrote {path}", file=sys.stderr)


# the file name `plan_outputs` suggests inside a folder given as an output (``--plot figs/``:
# "e.g. figs/plot.png"), by option, else by the kind of output
_EXAMPLE_STEM = {"--plot": "plot", "--corner": "corner", "--trace": "trace", "result": "result", "fit": "result",
                 "spectrum": "spectrum", "figure": "figure", "diagram": "circuit", "drt": "drt"}


def plan_outputs(outputs: Iterable[tuple[str, str | None, str]], *, inputs: Iterable[str | None] = (), stdout: str | None = None) -> OutputPlan:
    """Check every output option before any work: ``outputs`` are (flag, path or None, kind)
    triples; ``inputs`` the files the command reads; ``stdout`` names an option that prints to
    standard output in this run (``--json``), which ``-`` may not share.

    Refused with one `DataError` or `ParameterError` naming the option and the file: an
    extension the kind cannot write (a ``--plot`` extension matplotlib does not know, ...), a
    path that cannot be written (`impedax.io.atomic.check_writable`), an output that is one of
    the inputs, two outputs at one path, ``-`` for an output that cannot go to standard output.
    """
    from ..io.atomic import check_file_name, check_writable

    planned: list[Output] = []
    inputs = [str(p) for p in inputs if p]
    if sum(p == "-" for p in inputs) > 1:
        raise ParameterError("standard input ('-') can be read only once; give the other spectra as files")
    for flag, path, kind_name in outputs:
        if path is None:
            continue
        path = str(path)
        kind = OUTPUT_KINDS[kind_name]
        if not path.strip():
            raise ParameterError(f"{flag}: empty file name")
        output = Output(flag, path, kind_name)
        if output.to_stdout:
            if kind.stdout_suffix is None:
                raise ParameterError(f"{flag} -: a {kind.name} cannot go to standard output; give a file name")
            clash = next((o.flag for o in planned if o.to_stdout), None) or stdout
            if clash:
                raise ParameterError(f"{flag} - and {clash} both write to standard output; give {flag} a file name")
            planned.append(output)
            continue
        check_file_name(path, f"{_EXAMPLE_STEM.get(flag) or _EXAMPLE_STEM[kind_name]}{kind.default_suffix}", flag)
        suffix = Path(path).suffix.lower()
        known = kind.extensions()
        if suffix not in known:
            listed = ", ".join(e for e in known if e) + (f" (or none: written as {kind.default_suffix[1:].upper()})" if "" in known else "")
            shown = suffix or "(none)"
            why = (_missing_tool(suffix) if kind_name == "figure" else None) or f"unknown {kind.name} extension {shown!r}"
            raise DataError(f"{flag}: {why}; use one of {listed}", path=path)
        check_writable(path)
        for source in inputs:
            if source != "-" and _same_file(path, source):
                raise DataError(f"{flag} is the input file {source}; impedax never replaces its input: choose another name", path=path)
        for other in planned:
            if not other.to_stdout and _same_file(path, other.path):
                raise DataError(f"{other.flag} and {flag} name the same file; give each output its own name", path=path)
        planned.append(output)
    return OutputPlan(planned)


def check_output_folder(path: str, flag: str = "--out") -> Path:
    """A folder output (``demo --out``): it exists as a writable folder, or can be created in a
    writable folder; nothing is created here."""
    from ..io.atomic import probe_folder

    folder = Path(path)
    if not path.strip():
        raise ParameterError(f"{flag}: empty folder name")
    if folder.exists() or folder.is_symlink():
        if not folder.is_dir():
            raise DataError(f"{flag}: exists and is not a folder; give a folder name", path=folder)
        if not os.access(folder, os.W_OK | os.X_OK):
            raise DataError(f"{flag}: folder is not writable", path=folder)
        probe_folder(folder, path=folder, text=f"{flag}: cannot create files in the folder")
        return folder
    for ancestor in folder.absolute().parents:
        if ancestor.exists() or ancestor.is_symlink():
            if not ancestor.is_dir():
                raise DataError(f"{flag}: {ancestor} is a file, so no folder can be made under it", path=folder)
            if not os.access(ancestor, os.W_OK | os.X_OK):
                raise DataError(f"{flag}: cannot create the folder: {ancestor} is not writable", path=folder)
            probe_folder(ancestor, path=folder, text=f"{flag}: cannot create the folder in {ancestor}")
            return folder
    raise DataError(f"{flag}: no existing parent folder", path=folder)


# --- memory limits ----------------------------------------------------------------------------

MEMORY_LIMIT_ENV = "IMPEDAX_MEMORY_LIMIT"
_UNITS = {"": 1, "k": 2**10, "m": 2**20, "g": 2**30, "t": 2**40}


def _format_bytes(n: float) -> str:
    for unit, size in (("TB", 2**40), ("GB", 2**30), ("MB", 2**20), ("kB", 2**10)):
        if n >= size:
            return f"{n / size:.0f} {unit}" if n / size >= 100 else f"{n / size:.3g} {unit}"  # (1000 kB, not 1e+03 kB)
    return f"{n:.0f} B"


def memory_limit() -> tuple[float, str]:
    """The most memory a command may plan to use [bytes] and where that limit comes from:
    ``IMPEDAX_MEMORY_LIMIT`` (bytes, or with a k/M/G/T suffix: ``32G``) or half the machine's RAM."""
    text = os.environ.get(MEMORY_LIMIT_ENV, "").strip()
    if text:
        number, unit = text.rstrip("bB"), ""
        if number and number[-1].lower() in _UNITS:
            number, unit = number[:-1], number[-1].lower()
        try:
            value = float(number) * _UNITS[unit]
        except ValueError:
            value = float("nan")
        if not value > 0 or not math.isfinite(value):
            raise ParameterError(f"{MEMORY_LIMIT_ENV}={text!r}: expected a size such as 16G, 500M or 2e9 (bytes)")
        return value, f"{MEMORY_LIMIT_ENV}={text}"
    try:
        ram = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        ram = 8 * 2**30
    return ram / 2, "half of this machine's RAM"


def check_memory(flag: str, needed_bytes: float, what: str) -> None:
    """`ParameterError` naming ``flag`` when ``what`` needs more memory than `memory_limit`
    allows, checked before anything is allocated; the message says how to raise the limit."""
    limit, origin = memory_limit()
    if needed_bytes > limit:
        raise ParameterError(
            f"{flag}: {what} needs about {_format_bytes(needed_bytes)} of memory, more than the limit of "
            f"{_format_bytes(limit)} ({origin}); lower {flag}, or set {MEMORY_LIMIT_ENV}=SIZE (e.g. 64G) to raise the limit"
        )


# the keys of a result's JSON summary whose strings are prose a user reads (warnings, notes,
# messages, hints and reasons), which ``--json`` gives in the words of the command's text output
# (`json_in_command_words`); values, labels, models, paths and keys stay as they are
PROSE_KEYS = frozenset({
    "warnings", "warning", "notes", "note", "message", "hints", "misfit_hints", "best_misfit_hint", "best_misfit_hints", "reason", "reasons",
    "removal_reasons", "suggestion_reasons", "explanation", "pattern", "sign_hint", "alarms", "advice", "lambda_note", "f_test_note", "candidate_warning", "waic_note",
    "words",  # (kk's passing_edge.words)
    "model_comparison_notes",  # (a posterior's .nc: those of its notes, in the notes' words)
    "data_limit_note", "data_limit_hint", "misfit_note", "sigma_residual_notes",  # (a fit's .nc: a warning as a value, found among the warnings only in their words)
    "warning_tags",  # (a fit's .nc: a sign hint's tag holds the end of its warning, "sign_hint=; hint: …"; the tags' names are no Python words)
})
_NOT_PROSE_KEYS = frozenset({"spectra", "labels", "worst", "model", "models", "source", "provenance", "label", "spectra_with_warnings"})


# the commands whose text output (`print_result`, compare's) and so --json say Python's words as their options
# (kk and drt too: their notes would otherwise say both, "(signed=True, --signed)", in Python too)
COMMANDS_IN_THEIR_WORDS = frozenset({"fit", "compare", "diagnose", "refine", "sample", "gap", "kk", "drt"})


def json_in_command_words(summary, command: str | None):
    """``summary`` (a result's JSON) with each string under a `PROSE_KEYS` key in the words of
    ``impedax command`` (`command_line_words`: ``consider weighting='modulus'`` → ``consider
    --weighting modulus``, ``steps=45000`` → ``--steps 45000``), as its text output says them;
    keys, values, labels and models are left as they are (``--json`` does not keep
    Python's words where the text says the option). ``command`` None: ``summary`` unchanged."""
    if command is None:
        return summary

    def walk(obj, prose: bool):
        if isinstance(obj, Mapping):
            return {k: walk(v, (prose or k in PROSE_KEYS) and k not in _NOT_PROSE_KEYS) for k, v in obj.items()}
        if isinstance(obj, (list, tuple)):
            return [walk(v, prose) for v in obj]
        if prose and isinstance(obj, str):
            return command_line_words(obj, command)
        return obj

    return walk(summary, False)


@contextlib.contextmanager
def to_terminal(text: bool, table_head: str | None = None):
    """What is printed inside, wrapped to the terminal's width (`progress.terminal_text`) when
    ``text`` goes to a terminal (standard output a TTY of at least 40 columns,
    `progress.terminal_width`; the progress lines on stderr are wrapped alike,
    `progress.terminal_line`); else printed as it is. The reports of diagnose, refine, fit,
    sample, kk, drt, gap and compare (not its table, whose rows keep their columns).
    ``table_head``: the start of a table's header line (``"parameter "``), which and whose rows
    (up to a blank line or a ``warning:``, ``note:`` or ``hint:`` line) keep their columns, as a
    wrapped row would not: sample's rows end in a prior column past 80 characters. What goes
    to stderr inside (a note of skipped rows) is written where it was printed (`_Recorder`)."""
    from ..progress import terminal_text, terminal_width

    width = terminal_width(sys.stdout) if text else None
    if width is None:
        yield
        return
    events: list[list] = []  # [stream, text] in the order written: a note on stderr stays where it was printed
    out, err = sys.stdout, sys.stderr
    with contextlib.redirect_stdout(_Recorder(out, events)), contextlib.redirect_stderr(_Recorder(err, events)):
        try:
            yield
        finally:  # (what was printed before an error is shown, as it would have been unwrapped)
            in_table = False
            for stream, written in events:
                if stream is err:
                    out.flush()
                    err.write(written)
                    err.flush()
                    continue
                lines = written.split("\n")
                for k, line in enumerate(lines[:-1]):
                    if table_head is not None and line.startswith(table_head):
                        in_table = True
                    elif in_table and (not line.strip() or line.startswith(("warning:", "note:", "hint:"))):
                        in_table = False
                    lines[k] = line if in_table else terminal_text(line, width)
                out.write("\n".join(lines))
            out.flush()


class _Recorder:
    """A stand-in for standard output or error inside `to_terminal`: each write joins ``events``
    (the last entry's text when it is of the same ``stream``), so the report is wrapped and the
    notes on stderr come where they were printed, as in a pipe (they came before the report)."""

    def __init__(self, stream, events: list[list]):
        self.stream, self.events = stream, events

    def write(self, text: str) -> int:
        if self.events and self.events[-1][0] is self.stream:
            self.events[-1][1] += text
        else:
            self.events.append([self.stream, text])
        return len(text)

    def flush(self) -> None:
        pass

    def isatty(self) -> bool:
        return self.stream.isatty()


def print_result(result, as_json: bool, source: str | None = None, provenance: Mapping | None = None, *, command: str | None = None, written: str | None = None, **report_options) -> None:
    """``result.summary()`` as JSON (with ``source`` and ``provenance``, `with_source`; its
    warnings and notes in the words of the text: `json_in_command_words`), or
    ``result.report(**report_options)`` as text (in the words of ``impedax command``:
    `command_line_words`). ``written``: the run's ``--out`` FILE, which a batch's report names
    as where each spectrum's values are (`each_spectrum_written`) instead of suggesting the
    options that write them."""
    if as_json:
        emit_json(with_source(json_in_command_words(result.summary(), command), source, provenance))
        return
    text = result.report(**report_options)
    where = each_spectrum_written(written)
    if where:
        from ..fitting.least_squares.batch import EACH_SPECTRUM_WHERE

        text = text.replace(EACH_SPECTRUM_WHERE, where)
    print(command_line_words(text, command))


def each_spectrum_written(out: str | None, rows: str = "a row per spectrum and parameter", netcdf: str = "value, stderr and rms_rel over the batch's dimensions") -> str | None:
    """Where a run's ``--out`` FILE holds each spectrum's results, in the words of a batch
    report's closing line ("written to fits.csv (a row per spectrum and parameter)"; ``rows``:
    what a CSV row is; ``netcdf``: what a .nc holds); None without a file (no ``--out``, or ``-``: the JSON went to standard
    output and no report is printed). A run with ``--out batch.json`` does not end by
    suggesting ``--out FILE.csv … or --json``."""
    if not out or out == "-":
        return None
    suffix = Path(out).suffix.lower()
    if suffix == ".csv":
        return f"written to {out} ({rows})"
    if suffix == ".json":
        return f'written to {out} (its "spectra")'
    if suffix == ".nc":
        return f"written to {out} (netCDF: {netcdf})"
    if suffix == LATEX_SUFFIX:  # (impedax fit of several spectra: `BatchFitResult.to_latex`)
        return f"written to {out} (a LaTeX table, a row per spectrum)"
    return None


# the Python keywords that messages of the fitting code name, and the options that set them on
# the command line (the JSON keeps the messages as the Python API gives them)
_OPTION_OF_KEYWORD = {"max_steps": "--max-steps"}


# phrases of the fitting code's messages that name a Python call, what the command line says
# instead, and the options of the command those words name: a command without one of them keeps
# the Python words (`impedax gap` has no --bound)
_PHRASE_OF_CALL: dict[str, tuple[str, tuple[str, ...]]] = {
    "(bounds=)": ("(--bound)", ("--bound",)),
    "thin less (thin=)": ("thin less (--thin)", ("--thin",)),  # (`fitting.bayes.diagnostics.more_draws_advice`)
    "leave them out (fmin/fmax)": ("leave them out (--fmin/--fmax)", ("--fmin", "--fmax")),
    "e.g. --noise 1% (noise=0.01)": ("e.g. --noise 1%", ("--noise",)),
    # (the validity tests and the DRT, in Python's words, where their notes would otherwise
    # say both, "(signed=True, --signed)", in Python too: `kk.NON_PASSIVE_LEAVE_OUT`, the sigma
    # line of `KKResult.report`, `DRTResult.warnings` and the report's dropped peaks)
    "leave them out (data.drop_sel(frequency=result.non_passive_frequencies))": ("leave them out with --fmin/--fmax", ("--fmin", "--fmax")),
    "kk_test(noise='residuals')": ("impedax kk --noise residuals", ()),
    "leave the top points out (`data.where(data.frequency <= f, drop=True)`, in either order of the points)": ("leave the top points out (--fmax)", ("--fmax",)),
    "give a smaller λ (lam)": ("give a smaller λ (--lam)", ("--lam",)),
    ": min_peak_fraction)": (": --min-peak-fraction)", ("--min-peak-fraction",)),
    "(signed=True)": ("(--signed)", ("--signed",)),
    # (`models.gap.SUBTRACTION_LEAVE_OUT`, `TRIAL_MEANS_CALL`: a remainder's Re Z < 0)
    "leave them out (data.drop_sel(frequency=[...]) of each input spectrum, or a narrower band of all)":
        ("leave them out (--exclude F,F or --fmin/--fmax, which impedax gap, remaining and fit take)", ("--exclude", "--fmin", "--fmax")),
    "(gap_remainder(..., kind='mean'))": ("(impedax remaining without --trials)", ("--trials",)),  # (a remainder of trials: impedax remaining --trials)
    # (`models.gap._gap_bound_cause`: u at a bound of its prior; the gap analysis has no option for u's bounds)
    "(area= in m²;": ("(--area in m²;", ("--area",)),
    # (`kk.BAND_CUT_AT_END`: the points from an end of the data through a band there)
    "(data.where(data.frequency >= f, drop=True) and data.where(data.frequency <= f, drop=True))": ("(--fmin/--fmax)", ("--fmin", "--fmax")),
    "(data.where(data.frequency >= f, drop=True))": ("(--fmin)", ("--fmin",)),
    "(data.where(data.frequency <= f, drop=True))": ("(--fmax)", ("--fmax",)),
    # (`problem.SIGMA_SOURCES`: a command reads σ from the file's column or netCDF variable)
    "or make_spectrum(sigma=...)": ("or a 'sigma' variable of a netCDF file", ()),
    # (a large batch's report: `least_squares.batch.EACH_SPECTRUM_WHERE`)
    "batch.to_table() or ix.write_result(batch, 'FILE.csv') (a row per spectrum and parameter), batch.summary()['spectra']":
        ("--out FILE.csv (a row per spectrum and parameter) or --json (\"spectra\")", ("--out", "--json")),
    # (a batch report's warnings that name only the first of their spectra: `least_squares.batch.WARNED_SPECTRA_WHERE`)
    "batch.summary()['warning_kinds'] (each spectrum's own: batch.warnings, or the warnings column of ix.write_result(batch, 'FILE.csv'))":
        ("--json (\"warning_kinds\"; each spectrum's own: its row of \"spectra\", or the warnings column of --out FILE.csv)", ("--out", "--json")),
}

# a refinement's note on a start from earlier values (`refinement.py`), which `impedax refine`
# turns into the `impedax fit --init` command it prints after its report (cli/refine.py)
_INIT_PHRASE = ("(pass init=)", "(impedax fit --init NAME=VALUE …: the command is printed last)")
_COMMANDS_PRINTING_FIT_COMMAND = ("refine",)

# a fixed value named as Python's keyword (``fixed={'C_i': VALUE}``, diagnose's note on
# parameters not separately determined: `diagnosis.unidentified_note`), which the command line
# sets with --fix NAME=VALUE
_FIXED_KEYWORD = re.compile(r"fixed=\{'([^']+)': VALUE\}")

# a keyword named with its value in Python's words (``consider weighting='modulus'``, ``use
# noise='proportional'``, ``over='session'``, ``over=['session', 'trial']``, ``steps='auto'``),
# which the command line sets with the option of its name: --weighting modulus, --noise
# proportional, --over session, --over session,trial, --steps auto, and impedax drt's lam='auto' → --lam auto,
# lam_method='gcv' → --lam-method gcv
_VALUED_KEYWORDS = ("weighting", "noise", "over", "steps", "lam_method", "lam")
_VALUED_KEYWORD = re.compile(r"(?<![\w.-])(" + "|".join(_VALUED_KEYWORDS) + r")=(?:(['\"])([\w.-]+)\2|\[((?:'[\w.-]+'(?:, )?)+)\])")


# a chain length in Python's words (``steps=4500``: the sampler's chain-length advice,
# `fitting.bayes.diagnostics.steps_advice`), which the command line sets with --steps 4500
_STEPS_NUMBER = re.compile(r"(?<![\w.-])steps=(\d+)(?![\w.])")

# a DRT's λ in Python's words (``lam=1e-3``: the DRT solve's failure, `drt._drt`), which impedax
# drt sets with --lam 1e-3
# the band a half decade further in of a KK test's passing band (`KKResult.passing_edge_words`) in
# Python's words, ``(data.where((data.frequency >= 1) & (data.frequency <= 1e5), drop=True))``,
# which the command line gives as --fmin 1 --fmax 1e5
_FURTHER_IN = re.compile(r"a half decade further in \(data\.where\((?:\(data\.frequency >= (?P<lo>\d[\w.+-]*)\) & \(data\.frequency <= (?P<hi>\d[\w.+-]*)\)"
                         r"|data\.frequency (?P<op>>=|<=) (?P<value>\d[\w.+-]*)), drop=True\)\)")


def _further_in_options(match: re.Match) -> str:
    """`_FURTHER_IN`'s band as the options ``--fmin LO --fmax HI``."""
    if match.group("lo") is not None:
        words = f"--fmin {match.group('lo')} --fmax {match.group('hi')}"
    else:
        words = f"{'--fmin' if match.group('op') == '>=' else '--fmax'} {match.group('value')}"
    return f"a half decade further in ({words})"


_MORE_CHAINS = re.compile(r", or more chains \(\d+ now\): chains=\d+")
_WARMUP_WORDS = ", unless warmup= is given"  # (`models.gap.WARMUP_WORDS`)
_LAM_NUMBER = re.compile(r"(?<![\w.-])lam=(\d[\d.]*(?:[eE][+-]?\d+)?)(?![\w.])")


def _valued_option(match: re.Match) -> str:
    """``--KEYWORD VALUE`` of a `_VALUED_KEYWORD` match: a list's values joined by commas."""
    keyword, value, listed = match.group(1), match.group(3), match.group(4)
    return f"{_flag_of(keyword)} {value if value is not None else ','.join(v.strip(chr(39)) for v in listed.split(', '))}"


def _flag_of(keyword: str) -> str:
    """The option of a Python keyword: ``lam_method`` → ``--lam-method``."""
    return "--" + keyword.replace("_", "-")


def command_options(command: str) -> frozenset[str]:
    """The option strings ``impedax command`` accepts (``--weighting``, ``-h``, ...), read from
    its argparse parser (`impedax.cli.build_parser`)."""
    return _command_options(command)


@functools.lru_cache(maxsize=None)
def _command_options(command: str) -> frozenset[str]:
    import argparse

    from . import build_parser

    parser = build_parser(command)
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices[command]
    return frozenset(s for action in sub._actions for s in action.option_strings)


def _phrased(text: str, command: str | None = None) -> str:
    """``text`` with the Python calls and keywords it names (`_PHRASE_OF_CALL`, ``fixed={'C_i':
    VALUE}``, ``weighting='NAME'`` and the other `_VALUED_KEYWORDS`) in the words of ``impedax
    command``, each only where that command has the options the words name (`command_options`):
    ``impedax gap``, which has no --weighting, keeps ``weighting='modulus'``. ``command`` None:
    every translation."""
    options = None if command is None else command_options(command)

    def has(*flags: str) -> bool:
        return options is None or all(f in options for f in flags)

    for phrase, (words, flags) in _PHRASE_OF_CALL.items():
        if has(*flags):
            text = text.replace(phrase, words)
    if command is None or command in _COMMANDS_PRINTING_FIT_COMMAND:
        text = text.replace(*_INIT_PHRASE)
    if has("--fix"):
        text = _FIXED_KEYWORD.sub(r"--fix \1=VALUE", text)
    if has("--steps"):
        text = _STEPS_NUMBER.sub(r"--steps \1", text)
    if has("--lam"):
        text = _LAM_NUMBER.sub(r"--lam \1", text)
    if has("--fmin", "--fmax"):
        text = _FURTHER_IN.sub(_further_in_options, text)
    if not has("--chains"):  # (`models.gap.hierarchical_advice_of_gap`: Python's gap_analysis takes chains= and warmup=, impedax gap neither)
        text = _MORE_CHAINS.sub("", text)
    if not has("--warmup"):
        text = text.replace(_WARMUP_WORDS, "")
    return _VALUED_KEYWORD.sub(lambda m: _valued_option(m) if has(_flag_of(m.group(1))) else m.group(0), text)


# per command, the Python keywords whose names the errors of the functions it calls start
# with (``max_rc must be ...``, ``fixed: unknown parameter ...``), and the options that set
# them on the command line (`option_words`); the Python API keeps its own words
OPTION_OF_KEYWORD_BY_COMMAND: dict[str, dict[str, str]] = {
    "simulate": {"points": "--points", "fmin": "--fmin", "fmax": "--fmax"},
    "fit": {"fixed": "--fix", "init": "--init", "bounds": "--bound", "max_steps": "--max-steps", "fmin": "--fmin", "fmax": "--fmax", "weighting": "--weighting", "shared": "--shared", "over": "--over"},
    "compare": {"fixed": "--fix", "init": "--init", "bounds": "--bound", "max_steps": "--max-steps", "fmin": "--fmin", "fmax": "--fmax", "weighting": "--weighting"},
    "sample": {"fixed": "--fix", "init": "--init", "bounds": "--bound", "max_steps": "--max-steps", "steps": "--steps", "burn": "--burn", "thin": "--thin", "walkers": "--walkers", "seed": "--seed", "priors": "--prior", "noise": "--noise", "fmin": "--fmin", "fmax": "--fmax", "shared": "--shared", "over": "--over"},
    "kk": {"c": "--c", "max_rc": "--max-rc", "fmin": "--fmin", "fmax": "--fmax"},
    "drt": {"lam": "--lam", "lam_method": "--lam-method", "method": "--method", "min_peak_fraction": "--min-peak-fraction", "fmin": "--fmin", "fmax": "--fmax"},
    "diagnose": {"fixed": "--fix", "bounds": "--bound", "noise": "--noise", "effects": "--effects", "max_steps": "--max-steps", "fmin": "--fmin", "fmax": "--fmax", "weighting": "--weighting"},
    "refine": {"fixed": "--fix", "bounds": "--bound", "noise": "--noise", "effects": "--effects", "max_effects": "--max-effects", "solver_steps": "--max-steps", "fmin": "--fmin", "fmax": "--fmax", "weighting": "--weighting"},
    "force": {"points": "--points", "fmin": "--fmin", "fmax": "--fmax"},
    "gap": {"area": "--area", "v0": "--v0", "steps": "--steps", "seed": "--seed", "cutoff_hz": "--cutoff-hz"},
    "stack": {"dim": "--dim", "coords": "--coords"},
}


# where the circuit parser, the converters and the registry send a user to declare an element
# of their own (Python's words), and how the command line takes one: a --plugin file
def _plugin_words() -> dict[str, str]:
    from ..circuits.spec import ADDING_AN_ELEMENT, PASS_DECLARING_REGISTRY, PASS_OWN_REGISTRY

    return {
        ADDING_AN_ELEMENT: ADDING_AN_ELEMENT[:-1] + "; on the command line: declare it in a Python file and pass --plugin FILE.py)",
        PASS_OWN_REGISTRY: "an element of your own: declare it in a Python file and pass --plugin FILE.py, docs/circuits.md",
        PASS_DECLARING_REGISTRY: "declare it in a Python file and pass --plugin FILE.py (docs/circuits.md)",
    }


def plugin_words(error: Exception) -> str:
    """The message of ``error`` with the Python recipe for an element of one's own
    (`_plugin_words`: the parser's hint for an unknown symbol a user could declare, ``Gx1``, and
    the converters' and the registry's words) in the command line's words, ``--plugin FILE.py``."""
    text = str(error)
    for phrase, words in _plugin_words().items():
        text = text.replace(phrase, words)
    return text


def option_words(command: str, error: Exception) -> str:
    """The message of ``error`` as ``impedax command`` prints it: a Python keyword of
    `OPTION_OF_KEYWORD_BY_COMMAND` that names what the message is about is replaced by the
    option that sets it — at the start of the message when followed by ``must``, ``:`` or ``=``
    (``max_rc must be ...`` → ``--max-rc must be ...``, ``fixed: unknown ...``), and a band's
    ends anywhere as ``from fmin = 10 Hz`` or ``fmax (1 Hz) is below fmin (100 Hz)``; a keyword
    with its value anywhere as the option with that value (``use noise='proportional'`` → ``use
    --noise proportional``, `_phrased`, first: ``noise='sigma' needs`` → ``--noise sigma needs``). A file name that leads a
    `DataError` (``c: line 3: ...``) is left as it is. An element of one's own is declared with --plugin
    (`plugin_words`)."""
    text = plugin_words(error)
    keywords = OPTION_OF_KEYWORD_BY_COMMAND.get(command, {})
    if not keywords:
        return text
    text = _phrased(text, command)
    head = ""
    path = getattr(error, "path", None)
    if isinstance(error, DataError) and path is not None and text.startswith(str(path)):
        cut = text.find(": ", len(str(path)))
        if cut >= 0:
            head, text = text[: cut + 2], text[cut + 2 :]
    names = "|".join(re.escape(k) for k in sorted(keywords, key=len, reverse=True))
    leading = re.compile(r"^(" + names + r")(?=\s+must\b|:|=)")
    band = "|".join(k for k in ("fmin", "fmax") if k in keywords) or "(?!)"
    valued = re.compile(r"(?<![\w.'\"/-])(" + band + r")(?= = | \()")  # (``from fmin = 10 Hz``, ``fmax (1 Hz) is below fmin (100 Hz)``)
    text = valued.sub(lambda m: keywords[m.group(1)], leading.sub(lambda m: keywords[m.group(1)], text))
    return head + text


def command_line_words(text: str, command: str | None = None) -> str:
    """``text`` with the Python keywords it names replaced by the options of ``impedax
    command`` that set them (``raise max_steps`` → ``raise --max-steps``, ``(pass init=)`` →
    the ``impedax fit --init`` command, ``weighting='modulus'`` → ``--weighting modulus``:
    `_phrased`); a keyword the command has no option for keeps its Python words (``impedax
    gap`` has neither --max-steps nor --weighting, so its report does not say "consider
    --weighting modulus", an option it refuses). ``command`` None: every translation."""
    options = None if command is None else command_options(command)
    for keyword, option in _OPTION_OF_KEYWORD.items():
        if options is None or option in options:
            text = re.sub(rf"(?<![\w-]){keyword}\b", option, text)
    return _phrased(text, command)


# --- progress of long runs ----------------------------------------------------------------------

PROGRESS_AFTER_S = PROGRESS_AFTER_S_DEFAULT
"""Progress lines go to stderr once a run has taken this long (`progress.PROGRESS_AFTER_S`)."""


QUIET_HELP = "no progress lines on stderr (warnings and notes still go there)"


def add_quiet_option(parser) -> None:
    """``--quiet``: no progress lines (`progress_printer`'s, a sampler's) on stderr; warnings and
    notes are still printed there (every analysis command takes it, kk too, which prints none:
    a pipeline's log would otherwise hold 79 progress lines of one refine run under --json);
    ``-q`` for short, the convention a walkthrough reached for."""
    parser.add_argument("-q", "--quiet", action="store_true", help=QUIET_HELP)


def progress_printer(after_s: float | None = None, stream=None, *, quiet: bool = False):
    """The CLI's progress callback: `progress.progress_printer` after ``after_s`` seconds (None:
    `PROGRESS_AFTER_S`); ``quiet`` (``--quiet``): a printer that prints nothing."""
    return core_progress_printer(PROGRESS_AFTER_S if after_s is None else after_s, stream, quiet=quiet)


def contact_paths(args, command: str) -> dict[str, str]:
    """The spectrum files of ``impedax gap`` and ``impedax remaining`` by role: total, skin and
    touchscreen, or the total alone (a single contact, nothing subtracted). One file after
    DATA_TOTAL is a `ParameterError` (argparse fills DATA_SKIN first, whichever file it is)."""
    if args.skin is not None and args.touchscreen is None:
        example = "impedax gap PAD --area A" if command == "gap" else "impedax remaining PAD"
        raise ParameterError(f"one spectrum file after DATA_TOTAL: give DATA_SKIN and DATA_TS both (the remainder total − skin − touchscreen) "
                             f"or neither (a single contact, e.g. a gripper pad: {example})")
    return {name: path for name, path in (("total", args.total), ("skin", args.skin), ("touchscreen", args.touchscreen)) if path is not None}


def check_distinct_paths(paths: dict[str, str]) -> None:
    """A `ParameterError` when two of the three inputs name the same file (the same path, or
    two paths to one file); identical spectra in different files are refused by
    `gap_analysis` (`models.gap_inputs`). For ``impedax gap`` and ``impedax remaining``."""
    names = list(paths)
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            pa, pb = paths[a], paths[b]
            if pa == "-" or pb == "-":
                continue
            try:
                same = os.path.samefile(pa, pb)
            except OSError:  # (a missing file: the reader names it)
                same = os.path.abspath(pa) == os.path.abspath(pb)
            if same:
                raise ParameterError(
                    f"{a} and {b} are the same file, {pb}: the gap analysis needs three different measurements "
                    "(DATA_TOTAL: finger on the screen, DATA_SKIN: the skin alone, DATA_TS: the touchscreen alone), given in that order"
                )


def remainder_with_paths(remaining, paths: dict[str, str]):
    """The remainder Dataset with the paths of the three spectra it was subtracted from as its
    attrs (`REMAINDER_ATTRS`: total, skin, touchscreen), as ``impedax remaining`` and
    ``impedax gap --remaining`` both write it: a fit of the file then knows it is a remainder
    (`is_remainder`) and blames Re Z < 0 on the subtraction, not the instrument. A single
    contact's (``impedax gap PAD``: ``paths`` holds the total alone) gets that path only, and is
    no remainder: nothing was subtracted."""
    from ..fitting.least_squares.result import REMAINDER_ATTRS

    return remaining.assign_attrs({k: str(paths[k]) for k in REMAINDER_ATTRS if k in paths})


def csv_sigma_note(remaining, out: str | None, option: str) -> str | None:
    """The note of a trial-mean remainder written as CSV (``out``; None: standard output) by
    ``option`` (``impedax remaining --out``, ``impedax gap --remaining``): a CSV keeps no attrs, so a
    fit of it by sigma cannot tell that sigma is the trial means' SEM (`trial_means_of_sigma`) and
    warns that it overstates the noise, as impedax fit would of any remainder without those attrs; None
    for a netCDF file, which keeps them, or a sigma of another kind."""
    from pathlib import Path

    from ..fitting.least_squares.result import trial_means_of_sigma

    if not trial_means_of_sigma(remaining.attrs) or (out is not None and Path(out).suffix.lower() in (".nc", ".nc4", ".cdf")):
        return None
    return (f"{'the CSV' if out is None else out} keeps no attributes, so impedax fit of it cannot tell that its sigma is the standard error of trial means "
            f"and may warn that σ overstates the noise; write .nc ({option} FILE.nc) to keep what sigma is")
