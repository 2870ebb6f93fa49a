"""The exceptions impedax raises for bad input. Every one derives from `ImpedaxError`.

The CLI turns any `ImpedaxError` into one message on stderr and exit code 2; anything else
escaping is a bug in impedax.
"""

from __future__ import annotations

__all__ = [
    "ImpedaxError",
    "CircuitSyntaxError",
    "CircuitError",
    "DataError",
    "ParameterError",
    "FitError",
]


class ImpedaxError(Exception):
    """Base class of every error impedax raises on purpose."""


class CircuitSyntaxError(ImpedaxError, ValueError):
    """A circuit string that does not follow the grammar.

    The message shows the source, a caret under the offending column, what was expected and,
    when one exists, a hint (``did you mean C_sc?``).
    """

    def __init__(self, source: str, column: int, message: str, hint: str | None = None):
        self.source = source
        self.column = column  # 0-based offset into `source`
        self.reason = message
        self.hint = hint
        text = f"{message} at column {column + 1}\n  {source}\n  {' ' * column}^"
        if hint:
            text += f"\n  hint: {hint}"
        super().__init__(text)


class CircuitError(ImpedaxError, ValueError):
    """A circuit that parses but cannot be used as asked (duplicate names, unknown probe, ...)."""


class DataError(ImpedaxError, ValueError):
    """Spectrum data that cannot be read or is not valid (names the file and line when known)."""

    def __init__(self, message: str, *, path: object = None, line: int | None = None):
        self.path = None if path is None else str(path)
        self.line = line
        where = ""
        if self.path is not None:
            where = f"{self.path}"
            if line is not None:
                where += f", line {line}"
            where += ": "
        super().__init__(where + message)


class ParameterError(ImpedaxError, ValueError):
    """An unknown parameter name, or a value outside the parameter's bounds."""


class FitError(ImpedaxError, RuntimeError):
    """A fit that cannot be set up (more parameters than data, infeasible start, ...)."""
