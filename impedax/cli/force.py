"""``impedax force meyer|vezzoli``: electrostatic force spectrum with the papers' parameters."""

from __future__ import annotations

import math
import sys

import numpy as np

from .common import add_output_options, add_positional_model, check_memory, check_parameter_names, check_points, emit_json, figure_writer, number_option, parse_assignments, plan_outputs

_MODELS = ("meyer", "vezzoli")
_RANGES = {"meyer": (10.0, 1e9), "vezzoli": (1.0, 1e6)}
# memory per frequency: the model's complex intermediates and the CSV/JSON text (measured: ~0.5 kB)
POINT_BYTES = 1024


def _defaults(model: str) -> dict[str, float]:
    if model == "meyer":
        from ..models.meyer import THESIS_DRIVE_V, THESIS_PARAMS, THESIS_PHYSICAL

        return {**THESIS_PARAMS, "area": THESIS_PHYSICAL.area, "v_a": THESIS_DRIVE_V}
    from ..models.vezzoli import TABLE2

    return {k: v for k, v in TABLE2.items() if k != "frequency"}


def register(sub) -> None:
    p = sub.add_parser(
        "force",
        help="electrostatic force spectrum of Meyer's or Vezzoli's model",
        description="Force over log-spaced frequencies (both ends included). meyer: thesis eq 3.6 time-averaged, "
        "thesis values (eq 3.13) and V_A = 140 V; vezzoli: eq 10 time-averaged, Table 2 values. "
        "Parameters: meyer C_s C_i R_sc C_sc R_f [SI], area [m^2], v_a [V]; vezzoli h_i h_s [m], area [m^2], eps_i eps_s, rho_s [ohm m], v_m [V].",
    )
    add_positional_model(p, choices=_MODELS, help="which paper's model")
    p.add_argument("--param", action="append", metavar="NAME=VALUE", help="override a parameter (repeatable)")
    p.add_argument("--fmin", type=number_option, default=None, help="lowest frequency [Hz] (meyer 10, vezzoli 1)")
    p.add_argument("--fmax", type=number_option, default=None, help="highest frequency [Hz] (meyer 1e9, vezzoli 1e6)")
    p.add_argument("--points", type=int, default=161, help="number of frequencies (default 161)")
    add_output_options(p, json="print JSON instead of CSV", plot="also save a plot of force against frequency")
    p.set_defaults(run=run)


def _parameters(model: str, items) -> tuple[dict[str, float], dict[str, float]]:
    from ..errors import ParameterError

    defaults = _defaults(model)
    listing = f"(parameters of {model}: {', '.join(defaults)})"
    try:
        given = parse_assignments(items, "--param")
    except ParameterError as exc:
        raise ParameterError(f"{exc} {listing}") from None
    check_parameter_names(given, defaults, "--param", model)
    for name, value in given.items():
        if not (math.isfinite(value) and value > 0):
            raise ParameterError(f"--param {name}={value:g}: must be positive {listing}")
    return {**defaults, **given}, given


def _force(model: str, params: dict[str, float], freq: np.ndarray) -> np.ndarray:
    if model == "meyer":
        from ..models.meyer import force_time_average

        circuit = {k: params[k] for k in ("C_s", "C_i", "R_sc", "C_sc", "R_f")}
        return np.asarray(force_time_average(circuit, freq, area=params["area"], v_a=params["v_a"]))
    from ..models.vezzoli import electrovibration_force

    return np.asarray(electrovibration_force(freq, **params))


def run(args) -> int:
    from ..data import log_frequencies

    params, _ = _parameters(args.model, args.param)
    outputs = plan_outputs([("--plot", args.plot, "figure")])
    low, high = _RANGES[args.model]
    fmin = low if args.fmin is None else args.fmin
    fmax = high if args.fmax is None else args.fmax
    check_points(args.points, fmin, fmax)
    check_memory("--points", args.points * POINT_BYTES, f"a force spectrum of {args.points} frequencies")
    freq = log_frequencies(fmin, fmax, args.points)
    force = _force(args.model, params, freq)
    k = int(np.argmax(force))
    peak = {"frequency_hz": float(freq[k]), "force_n": float(force[k])}
    if args.json:
        emit_json({"frequency_hz": freq, "force_n": force, "peak": peak, "params": params, "convention": "time-average", "model": args.model})
    else:
        lines = ["frequency_hz,force_n"] + [f"{f:.10g},{v:.10g}" for f, v in zip(freq, force)]
        sys.stdout.write("\n".join(lines) + "\n")
        print(f"impedax force {args.model}: time-averaged force; peak {peak['force_n']:.4g} N at {peak['frequency_hz']:.4g} Hz", file=sys.stderr)

    def figure():
        from ..plotting.models import plot_force_spectrum

        source = "Meyer (2012) thesis eq 3.6, Fig 3.4" if args.model == "meyer" else "Vezzoli et al. eq 10"
        return plot_force_spectrum(freq, force, title=f"{source}: model prediction")

    outputs.save({"--plot": figure_writer(figure)})
    return 0
