"""impedax: equivalent-circuit modeling, fitting and diagnosis of impedance spectra on JAX.

Importing impedax switches JAX to 64-bit floats (``jax_enable_x64``) for the whole process:
impedance spectra span many decades and single precision loses the small arcs. Set
``IMPEDAX_NO_X64=1`` before importing to leave JAX's setting alone (not recommended).
If JAX has not run anything yet, it also gets one CPU device per core (`_use_every_core`).
"""

from __future__ import annotations

import importlib as _importlib
import os as _os
import sys as _sys

# JAX itself is imported when a name of impedax is first used (PEP 562, below), so
# ``impedax --help`` and ``--version`` start at once. Until then, the settings go through the
# environment variables JAX reads when it is imported (and which child processes inherit);
# a JAX already imported gets them through its config.
_jax_imported = "jax" in _sys.modules
if _os.environ.get("IMPEDAX_NO_X64") != "1":
    if _jax_imported:
        _sys.modules["jax"].config.update("jax_enable_x64", True)
    else:
        _os.environ["JAX_ENABLE_X64"] = "1"


def _cpu_device_count() -> int:
    chosen = _os.environ.get("IMPEDAX_CPU_DEVICES", "").strip()
    if chosen.isdecimal() and chosen.isascii() and int(chosen) >= 1:
        return int(chosen)
    if chosen:  # (at import: a line on stderr, not an error that would stop every command)
        _sys.stderr.write(f"impedax: IMPEDAX_CPU_DEVICES={chosen!r} is not a whole number of at least 1: ignored, one device per core\n")
    try:
        return min(len(_os.sched_getaffinity(0)), 8)
    except AttributeError:
        return min(_os.cpu_count() or 1, 8)


def _use_every_core() -> None:
    """One JAX CPU device per core, so batch fits run their chunks in parallel (XLA runs one
    computation at a time per device). Only before JAX has started and when neither the user
    nor XLA_FLAGS chose a count; ``IMPEDAX_CPU_DEVICES=N`` sets it (1: leave JAX alone)."""
    if "xla_force_host_platform_device_count" in _os.environ.get("XLA_FLAGS", ""):
        return
    count = _cpu_device_count()
    if not _jax_imported:
        if count > 1 and "JAX_NUM_CPU_DEVICES" not in _os.environ:
            _os.environ["JAX_NUM_CPU_DEVICES"] = str(count)
        return
    jax = _sys.modules["jax"]
    current = getattr(jax.config, "jax_num_cpu_devices", None)  # (JAX ≥ 0.4.38)
    if current is None or current != -1:
        return
    if count > 1:
        try:
            jax.config.update("jax_num_cpu_devices", count)
        except RuntimeError:  # JAX already ran something: its devices stay as they are
            pass


_use_every_core()

# public name → (module, attribute); attribute None: the module itself
_LAZY = {
    "Circuit": (".circuits", "Circuit"),
    "CircuitProgram": (".circuits", "CircuitProgram"),
    "DCPath": (".circuits", "DCPath"),
    "DEFAULT_REGISTRY": (".circuits", "DEFAULT_REGISTRY"),
    "Element": (".circuits", "Element"),
    "ElementSpec": (".circuits", "ElementSpec"),
    "Parallel": (".circuits", "Parallel"),
    "ParameterSpec": (".circuits", "ParameterSpec"),
    "Registry": (".circuits", "Registry"),
    "Series": (".circuits", "Series"),
    "StartRole": (".circuits", "StartRole"),
    "compile_circuit": (".circuits", "compile_circuit"),
    "current_through": (".circuits", "current_through"),
    "from_autoeis": (".circuits", "from_autoeis"),
    "from_cdc": (".circuits", "from_cdc"),
    "from_ec_lab": (".circuits", "from_ec_lab"),
    "from_impedance_py": (".circuits", "from_impedance_py"),
    "parse": (".circuits", "parse"),
    "to_cdc": (".circuits", "to_cdc"),
    "to_impedance_py": (".circuits", "to_impedance_py"),
    "voltage_across": (".circuits", "voltage_across"),
    "log_frequencies": (".data", "log_frequencies"),
    "make_spectrum": (".data", "make_spectrum"),
    "validate_spectrum": (".data", "validate_spectrum"),
    "CircuitError": (".errors", "CircuitError"),
    "CircuitSyntaxError": (".errors", "CircuitSyntaxError"),
    "DataError": (".errors", "DataError"),
    "FitError": (".errors", "FitError"),
    "FitsNotComparable": (".errors", "FitsNotComparable"),
    "ImpedaxError": (".errors", "ImpedaxError"),
    "ParameterError": (".errors", "ParameterError"),
    "SweepGridsDiffer": (".errors", "SweepGridsDiffer"),
    "draw_circuit": (".diagram", "draw_circuit"),
    "save_circuit_diagram": (".diagram", "save_circuit_diagram"),
    "DEFAULT_EFFECTS": (".fitting", "DEFAULT_EFFECTS"),
    "BatchFitResult": (".fitting", "BatchFitResult"),
    "SharedFitResult": (".fitting", "SharedFitResult"),
    "Diagnosis": (".fitting", "Diagnosis"),
    "FitResult": (".fitting", "FitResult"),
    "KKBatchResult": (".fitting", "KKBatchResult"),
    "KKResult": (".fitting", "KKResult"),
    "Posterior": (".fitting", "Posterior"),
    "SharedPosterior": (".fitting", "SharedPosterior"),
    "HierarchicalPosterior": (".fitting.bayes.hierarchical", "HierarchicalPosterior"),
    "sample_hierarchical": (".fitting.bayes.hierarchical", "sample_hierarchical"),
    "Prior": (".fitting", "Prior"),
    "Refinement": (".fitting", "Refinement"),
    "Reparametrization": (".fitting", "Reparametrization"),
    "compare": (".fitting", "compare"),
    "Comparison": (".fitting", "Comparison"),
    "BatchComparison": (".fitting", "BatchComparison"),
    "derive": (".fitting", "derive"),
    "diagnose": (".fitting", "diagnose"),
    "drt": (".fitting", "drt"),
    "DRTResult": (".fitting", "DRTResult"),
    "fit": (".fitting", "fit"),
    "gap_thickness_reparametrization": (".fitting", "gap_thickness_reparametrization"),
    "kk_test": (".fitting", "kk_test"),
    "kk_test_batch": (".fitting", "kk_test_batch"),
    "refine": (".fitting", "refine"),
    "sample": (".fitting", "sample"),
    "stratum_corneum_reparametrization": (".fitting", "stratum_corneum_reparametrization"),
    "zhit": (".fitting", "zhit"),
    "ZHITResult": (".fitting", "ZHITResult"),
    "zhit_batch": (".fitting", "zhit_batch"),
    "ZHITBatchResult": (".fitting", "ZHITBatchResult"),
    "load": (".io", "load"),
    "write_result": (".io", "write_result"),
    "save": (".io", "save"),
    "stack_files": (".io", "stack_files"),
    # the subpackages, so that ``import impedax`` then ``impedax.io.write_netcdf`` works as before
    "circuits": (".circuits", None),
    "cli": (".cli", None),
    "constants": (".constants", None),
    "data": (".data", None),
    "diagram": (".diagram", None),
    "errors": (".errors", None),
    "fitting": (".fitting", None),
    "io": (".io", None),
    "models": (".models", None),
    "plotting": (".plotting", None),
}


# the commands whose Python function has another name (``ix.kk(data)`` raised a bare AttributeError)
_COMMAND_FUNCTIONS = {
    "kk": "impedax.kk_test (several spectra: kk_test_batch; --method zhit: zhit, several spectra: zhit_batch)",
    "stack": "impedax.stack_files",
    "draw": "impedax.draw_circuit",
    "gap": "impedax.models.gap_analysis",
    "remaining": "impedax.models.gap.gap_remainder",
}


def clear_caches() -> None:
    """Release every compiled program impedax and JAX hold in this process: solvers, samplers,
    circuit programs, parsed circuits. Each compiled program keeps its machine code mapped, and
    Linux allows a process 65,530 memory maps, so a long session that fits thousands of different
    circuits can call this now and then; the next fit of a circuit compiles it again (or reads it
    from JAX's persistent cache)."""
    import gc

    for name, module in list(_sys.modules.items()):
        if module is not None and (name == __name__ or name.startswith(__name__ + ".")):
            for value in list(vars(module).values()):
                if not isinstance(value, type) and callable(getattr(value, "cache_clear", None)):  # (a class's is unbound)
                    value.cache_clear()
    if "jax" in _sys.modules:
        _sys.modules["jax"].clear_caches()
    gc.collect()


def use_compilation_cache(path: str | None = None) -> str | None:
    """Keep compiled programs on disk (JAX's persistent compilation cache, and impedax's stored
    programs beside it: docs/fitting.md, "Speed"), so that a new Python process reads them
    back instead of compiling again, as the ``impedax`` command does by itself. Call it once,
    before the first fit of a script or notebook. ``path``: the folder (default
    ``IMPEDAX_CACHE_DIR``, else ``~/.cache/impedax/jax``, the command's). Returns the folder,
    or None when it cannot be created (nothing is changed then).

    It does not import JAX: before JAX is imported, the two settings go through the
    environment variables JAX reads at its import (as ``jax_enable_x64`` does above), so a
    command that computes nothing (``impedax inspect``, ``info``) never loads JAX."""
    folder = path or _os.environ.get("IMPEDAX_CACHE_DIR") or _os.path.join(_os.path.expanduser("~"), ".cache", "impedax", "jax")
    try:
        _os.makedirs(folder, exist_ok=True)
    except OSError:
        return None
    # programs compiled in 0.05 s or more are kept: reading one back costs less (the single
    # fit's chi² evaluator compiles in ~0.13 s with `stored.QUICK_COMPILE`)
    settings = {"jax_compilation_cache_dir": folder, "jax_persistent_cache_min_compile_time_secs": 0.05}
    for name, value in settings.items():
        if "jax" in _sys.modules:
            _sys.modules["jax"].config.update(name, value)
        else:
            _os.environ[name.upper()] = str(value)
    return folder


def __getattr__(name: str):
    """Import what a public name needs on first use (PEP 562)."""
    try:
        module, attribute = _LAZY[name]
    except KeyError:
        command = f"; the command impedax {name} is {_COMMAND_FUNCTIONS[name]}" if name in _COMMAND_FUNCTIONS else ""
        raise AttributeError(f"module 'impedax' has no attribute {name!r}{command}") from None
    value = _importlib.import_module(module, __name__)
    value = value if attribute is None else getattr(value, attribute)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_LAZY))


__all__ = sorted([*_LAZY, "clear_caches", "use_compilation_cache"])

from .constants import IMPEDAX_VERSION as __version__  # noqa: E402 (one source: the writers record it, impedax.io.provenance)
