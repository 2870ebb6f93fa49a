"""Circuit language, element registry, compiler and probes.

spec (what an element is) ← elements (the built-ins) ← tree ← parser ← convert (other
notations), nesting (which circuit contains which); compile ← probes, program (the compiled forms). docs/circuits.md describes the
language and how to add an element.

The compiled forms import JAX, so their names are imported on first use (PEP 562,
`__getattr__` below): parsing, converting and reading the registry (``impedax info``,
``draw``, ``inspect``) do not load JAX.
"""

from __future__ import annotations

from .convert import (
    CDCConvention as CDCConvention,
    from_autoeis as from_autoeis,
    from_cdc as from_cdc,
    from_ec_lab as from_ec_lab,
    from_impedance_py as from_impedance_py,
    to_cdc as to_cdc,
    to_impedance_py as to_impedance_py,
)
from .elements import DEFAULT_REGISTRY as DEFAULT_REGISTRY
from .parser import looks_like_autoeis as looks_like_autoeis, looks_like_cdc as looks_like_cdc, parse as parse, tokenize as tokenize
from .spec import (
    DCPath as DCPath,
    ElementLimit as ElementLimit,
    ElementSpec as ElementSpec,
    ParameterSpec as ParameterSpec,
    Registry as Registry,
    StartRole as StartRole,
)
from .tree import Circuit as Circuit, Element as Element, Parallel as Parallel, Series as Series, parallel as parallel, series as series

# the names of the compiled forms (modules that import JAX): module → names
_COMPILED_FORMS = {
    "compile": ("CompiledCircuit", "compile_circuit"),
    "probes": ("current_through", "voltage_across"),
    "program": ("PROGRAM_SCALES", "CircuitProgram", "ProgramLayout", "default_theta", "evaluate_program", "program_value_and_columns"),
}


def __getattr__(name: str):
    """A name of the compiled forms, imported with its module (and JAX) on first use."""
    if name in _COMPILED_FORMS["compile"]:
        from . import compile as module
    elif name in _COMPILED_FORMS["probes"]:
        from . import probes as module
    elif name in _COMPILED_FORMS["program"]:
        from . import program as module
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(module, name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | {n for names in _COMPILED_FORMS.values() for n in names})


# (``from impedax.circuits import *`` gives the compiled forms too, as before they were lazy)
__all__ = [
    "CDCConvention", "Circuit", "DCPath", "DEFAULT_REGISTRY", "Element", "ElementLimit", "ElementSpec", "Parallel", "ParameterSpec", "Registry", "Series", "StartRole",
    "from_autoeis", "from_cdc", "from_ec_lab", "from_impedance_py", "looks_like_autoeis", "looks_like_cdc", "parallel", "parse", "series", "to_cdc", "to_impedance_py", "tokenize",
    *(n for names in _COMPILED_FORMS.values() for n in names),
]
