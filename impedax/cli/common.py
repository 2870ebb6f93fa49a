"""Helpers shared by the CLI commands."""

from __future__ import annotations

import difflib
import json
import math
import sys
from typing import Iterable, Mapping

from ..errors import ParameterError

__all__ = [
    "parse_assignments", "check_parameter_names", "emit_json", "to_jsonable", "add_model_argument", "add_output_options",
    "check_outputs", "save_outputs", "print_result", "result_out_help",
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
    """``obj`` as strict-JSON values (`impedax.io.export.to_jsonable`)."""
    from ..io.export import to_jsonable as jsonable

    return jsonable(obj)


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


RESULT_OUT_METAVAR = "FILE.csv|.json|.nc"


def add_output_options(parser, *, json: str | None = "print the result as JSON", plot: str | None = None, out: str | None = None, out_metavar: str = RESULT_OUT_METAVAR) -> None:
    """The output options of a command: ``--json`` (help ``json``), ``--plot FILE.png`` (help
    ``plot``) and ``--out`` (help ``out``); an option whose help is None is not added."""
    if json:
        parser.add_argument("--json", action="store_true", help=json)
    if plot:
        parser.add_argument("--plot", metavar="FILE.png", help=plot)
    if out:
        parser.add_argument("--out", metavar=out_metavar, help=out)


def result_out_help(what: str) -> str:
    """The help of a result's ``--out``: the format follows the extension."""
    return f"save {what}: .csv a tidy table of parameters, .json the --json summary, .nc the full result as netCDF"


def check_outputs(*paths, result: str | None = None) -> None:
    """Every output path that was given is writable, and ``result`` (a result's ``--out``) has
    an extension `impedax.io.write_result` knows: checked before any work is done."""
    from ..io.atomic import check_writable
    from ..io.export import result_format

    if result:
        result_format(result)
    for path in (*paths, result):
        if path:
            check_writable(path)


def save_outputs(*, out=None, result=None, dataset=None, plot=None, figure=None) -> None:
    """Write ``result`` to ``out`` in the format of its extension (`impedax.io.write_result`),
    or the spectrum ``dataset()`` (CSV or netCDF by extension, `impedax.io.save`); save
    ``figure()`` to ``plot``. Each only when its path was given (the callables are called only
    then: no figure is drawn for nothing)."""
    if out:
        from ..io import save, write_result

        if result is not None:
            write_result(result, out)
        else:
            save(dataset(), out)
    if plot:
        from ..plotting import save_figure

        save_figure(figure(), plot)


def print_result(result, as_json: bool) -> None:
    """``result.summary()`` as JSON, or ``result.report()`` as text."""
    if as_json:
        emit_json(result.summary())
    else:
        print(result.report())
