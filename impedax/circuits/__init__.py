"""Circuit language, element registry, compiler and probes."""

from .compile import (
    PROGRAM_SCALES as PROGRAM_SCALES,
    ProgramLayout as ProgramLayout,
    default_theta as default_theta,
    CircuitProgram as CircuitProgram,
    CompiledCircuit as CompiledCircuit,
    compile_circuit as compile_circuit,
    current_through as current_through,
    evaluate_program as evaluate_program,
    voltage_across as voltage_across,
)
from .elements import (
    DEFAULT_REGISTRY as DEFAULT_REGISTRY,
    ElementSpec as ElementSpec,
    ParameterSpec as ParameterSpec,
    Registry as Registry,
)
from .parser import from_cdc as from_cdc, from_impedance_py as from_impedance_py, parse as parse, tokenize as tokenize
from .tree import Circuit as Circuit, Element as Element, Parallel as Parallel, Series as Series, parallel as parallel, series as series
