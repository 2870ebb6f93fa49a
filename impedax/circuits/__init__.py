"""Circuit language, element registry, compiler and probes.

spec (what an element is) ← elements (the built-ins) ← tree ← parser ← convert (other
notations), nesting (which circuit contains which); compile ← probes, program (the compiled forms). docs/circuits.md describes the
language and how to add an element.
"""

from .compile import CompiledCircuit as CompiledCircuit, compile_circuit as compile_circuit
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
from .probes import current_through as current_through, voltage_across as voltage_across
from .program import (
    PROGRAM_SCALES as PROGRAM_SCALES,
    CircuitProgram as CircuitProgram,
    ProgramLayout as ProgramLayout,
    default_theta as default_theta,
    evaluate_program as evaluate_program,
    program_value_and_columns as program_value_and_columns,
)
from .spec import (
    DCPath as DCPath,
    ElementLimit as ElementLimit,
    ElementSpec as ElementSpec,
    ParameterSpec as ParameterSpec,
    Registry as Registry,
    StartRole as StartRole,
)
from .tree import Circuit as Circuit, Element as Element, Parallel as Parallel, Series as Series, parallel as parallel, series as series
