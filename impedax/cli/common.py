"""Helpers shared by the CLI commands."""

from __future__ import annotations

import difflib
import json
import math
import sys
from typing import Iterable, Mapping

import numpy as np

from ..errors import ParameterError

__all__ = [
    "parse_assignments", "check_parameter_names", "emit_json", "to_jsonable", "add_model_argument", "add_output_options",
    "check_outputs", "save_outputs", "print_result",
]


def parse_assignments(items: Iterable[str] | None, flag: str) -> dict[str, float]:
    """``["R0=100", "C1=1e-6"]`` → ``{"R0": 100.0, "C1": 1e-06}`` with clear errors."""
    out: dict[str, float] = {}
    for item in items or ():
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise ParameterError(f"{flag} {item!r}: expected NAME=VALUE")
        try:
            number = float(value)
        except ValueError:
            raise ParameterError(f"{flag} {item!r}: {value!r} is not a number") from None
        if not math.isfinite(number):
            raise ParameterError(f"{flag} {item!r}: value must be finite")
        if name in out:
            raise ParameterError(f"{flag}: {name} given twice")
        out[name] = number
    return out


def check_parameter_names(names: Iterable[str], known: Iterable[str], flag: str, model: str) -> None:
    known = list(known)
    for name in names:
        if name not in known:
            close = difflib.get_close_matches(name, known, n=1)
            hint = f"; did you mean {close[0]}?" if close else ""
            raise ParameterError(f"{flag}: unknown parameter {name!r} for model {model!r}{hint} (parameters: {', '.join(known)})")


def check_bounds(values: Mapping[str, float], specs: Mapping, flag: str) -> None:
    for name, value in values.items():
        spec = specs[name]
        if not spec.contains(value):
            raise ParameterError(f"{flag}: {name}={value:g} is outside its bounds {spec.bounds_text()} [{spec.unit}]")


def model_and_values(model: str, items, flag: str):
    """Parse ``model`` and the ``NAME=VALUE`` ``items`` given with ``flag``; check the names and
    bounds. Returns (circuit, parameter specs, values)."""
    from .. import parse

    circuit = parse(model)
    specs = circuit.parameter_specs()
    values = parse_assignments(items, flag)
    check_parameter_names(values, specs, flag, model)
    check_bounds(values, specs, flag)
    return circuit, specs, values


def to_jsonable(obj):
    if isinstance(obj, Mapping):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [to_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return [to_jsonable(v) for v in obj.tolist()]
    if isinstance(obj, (np.floating, float)):
        v = float(obj)
        return v if math.isfinite(v) else None
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    return obj


def emit_json(obj) -> None:
    """Print ``obj`` as JSON (NaN/Inf become null, so the output is strict JSON)."""
    json.dump(to_jsonable(obj), sys.stdout, indent=2, allow_nan=False)
    sys.stdout.write("\n")


def add_model_argument(parser, *, positional: bool = False) -> None:
    help_text = "circuit text, e.g. 'R0 + R1 || C1' (quote it in the shell)"
    if positional:
        parser.add_argument("model", metavar="MODEL", help=help_text)
    else:
        parser.add_argument("--model", required=True, metavar="MODEL", help=help_text)


def add_output_options(parser, *, json: str | None = "print the result as JSON", plot: str | None = None, out: str | None = None, out_metavar: str = "FILE.nc") -> None:
    """The output options of a command: ``--json`` (help ``json``), ``--plot FILE.png`` (help
    ``plot``) and ``--out`` (help ``out``); an option whose help is None is not added."""
    if json:
        parser.add_argument("--json", action="store_true", help=json)
    if plot:
        parser.add_argument("--plot", metavar="FILE.png", help=plot)
    if out:
        parser.add_argument("--out", metavar=out_metavar, help=out)


def check_outputs(*paths) -> None:
    """Every output path that was given is writable: checked before any work is done."""
    from ..io.atomic import check_writable

    for path in paths:
        if path:
            check_writable(path)


def save_outputs(*, out=None, dataset=None, plot=None, figure=None, spectrum: bool = False) -> None:
    """Write ``dataset()`` to ``out`` and save ``figure()`` to ``plot``, each only when its path
    was given (the callables are called only then: no figure is drawn for nothing). A result
    goes to lossless netCDF; a ``spectrum`` to CSV or netCDF by extension (`impedax.io.save`)."""
    if out:
        from ..io import save, write_netcdf

        (save if spectrum else write_netcdf)(dataset(), out)
    if plot:
        from ..plotting import save_figure

        save_figure(figure(), plot)


def print_result(result, as_json: bool) -> None:
    """``result.summary()`` as JSON, or ``result.report()`` as text."""
    if as_json:
        emit_json(result.summary())
    else:
        print(result.report())
