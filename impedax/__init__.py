"""impedax: equivalent-circuit modeling, fitting and diagnosis of impedance spectra on JAX.

Importing impedax switches JAX to 64-bit floats (``jax_enable_x64``) for the whole process:
impedance spectra span many decades and single precision loses the small arcs. Set
``IMPEDAX_NO_X64=1`` before importing to leave JAX's setting alone (not recommended).
If JAX has not run anything yet, it also gets one CPU device per core (`_use_every_core`).
"""

from __future__ import annotations

import os as _os

import jax as _jax

if _os.environ.get("IMPEDAX_NO_X64") != "1":
    _jax.config.update("jax_enable_x64", True)


def _use_every_core() -> None:
    """One JAX CPU device per core, so batch fits run their chunks in parallel (XLA runs one
    computation at a time per device). Only before JAX has started and when neither the user
    nor XLA_FLAGS chose a count; ``IMPEDAX_CPU_DEVICES=N`` sets it (1: leave JAX alone)."""
    chosen = _os.environ.get("IMPEDAX_CPU_DEVICES")
    current = getattr(_jax.config, "jax_num_cpu_devices", None)  # (JAX ≥ 0.4.38)
    if current is None or current != -1 or "xla_force_host_platform_device_count" in _os.environ.get("XLA_FLAGS", ""):
        return
    try:
        count = int(chosen) if chosen else min(len(_os.sched_getaffinity(0)), 8)
    except (ValueError, AttributeError):
        count = min(_os.cpu_count() or 1, 8)
    if count > 1:
        try:
            _jax.config.update("jax_num_cpu_devices", count)
        except RuntimeError:  # JAX already ran something: its devices stay as they are
            pass


_use_every_core()

from .circuits import (  # noqa: E402
    Circuit as Circuit,
    CircuitProgram as CircuitProgram,
    DCPath as DCPath,
    DEFAULT_REGISTRY as DEFAULT_REGISTRY,
    Element as Element,
    ElementSpec as ElementSpec,
    Parallel as Parallel,
    ParameterSpec as ParameterSpec,
    Registry as Registry,
    Series as Series,
    StartRole as StartRole,
    compile_circuit as compile_circuit,
    current_through as current_through,
    from_cdc as from_cdc,
    from_impedance_py as from_impedance_py,
    parse as parse,
    to_cdc as to_cdc,
    to_impedance_py as to_impedance_py,
    voltage_across as voltage_across,
)
from .data import log_frequencies as log_frequencies, make_spectrum as make_spectrum, validate_spectrum as validate_spectrum  # noqa: E402
from .errors import (  # noqa: E402
    CircuitError as CircuitError,
    CircuitSyntaxError as CircuitSyntaxError,
    DataError as DataError,
    FitError as FitError,
    ImpedaxError as ImpedaxError,
    ParameterError as ParameterError,
)
from .diagram import draw_circuit as draw_circuit, save_circuit_diagram as save_circuit_diagram  # noqa: E402
from .fitting import (  # noqa: E402
    DEFAULT_EFFECTS as DEFAULT_EFFECTS,
    BatchFitResult as BatchFitResult,
    Diagnosis as Diagnosis,
    FitResult as FitResult,
    KKBatchResult as KKBatchResult,
    KKResult as KKResult,
    Posterior as Posterior,
    Prior as Prior,
    Refinement as Refinement,
    Reparametrization as Reparametrization,
    compare as compare,
    derive as derive,
    diagnose as diagnose,
    drt as drt,
    DRTResult as DRTResult,
    fit as fit,
    gap_thickness_reparametrization as gap_thickness_reparametrization,
    kk_test as kk_test,
    kk_test_batch as kk_test_batch,
    refine as refine,
    sample as sample,
    stratum_corneum_reparametrization as stratum_corneum_reparametrization,
    zhit as zhit,
    ZHITResult as ZHITResult,
)
from .io import load as load, save as save  # noqa: E402
from . import models as models  # noqa: E402

__version__ = "0.1.0"
