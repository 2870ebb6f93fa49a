"""The exceptions impedax raises for bad input. Every one derives from `ImpedaxError`.

The CLI turns any `ImpedaxError` into one message on stderr and exit code 2; anything else
escaping is a bug in impedax.
"""

from __future__ import annotations

import unicodedata

__all__ = [
    "ImpedaxError",
    "CircuitSyntaxError",
    "CircuitError",
    "DataError",
    "ArgumentsSwapped",
    "SweepGridsDiffer",
    "ParameterError",
    "ArgumentNeeded",
    "FitError",
    "FitsNotComparable",
    "IN_MEMORY",
]


class ImpedaxError(Exception):
    """Base class of every error impedax raises on purpose."""


class CircuitSyntaxError(ImpedaxError, ValueError):
    """A circuit string that does not follow the grammar.

    The message shows the source around the offending column (at most `SOURCE_WINDOW`
    characters, control and formatting characters escaped so a terminal shows them as text),
    a caret under the column, what was expected and, when one exists, a hint
    (``did you mean C_sc?``). ``source`` and ``column`` keep the whole text and the offset;
    ``unknown_symbol``: the element symbol the registry lacks, when that is the error (a user's
    element read without its registry).
    """

    def __init__(self, source: str, column: int, message: str, hint: str | None = None, *, unknown_symbol: str | None = None):
        self.source = source
        self.column = column  # 0-based offset into `source`
        self.reason = message
        self.hint = hint
        self.unknown_symbol = unknown_symbol
        shown, caret = source_window(source, column)
        text = f"{escape_text(message)} at column {column + 1}\n  {shown}\n  {' ' * caret}^"
        if hint:
            text += f"\n  hint: {escape_text(hint)}"
        super().__init__(text)


SOURCE_WINDOW = 80  # characters of source shown around the caret


def _shown(ch: str) -> tuple[str, int]:
    """How one character is shown (escaped if a terminal would act on it or hide it) and its
    width in terminal columns (2 for East Asian wide and full-width characters)."""
    category = unicodedata.category(ch)
    if category[0] == "C" or category in ("Zl", "Zp") or (category == "Zs" and ch != " "):
        code = ord(ch)
        text = f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}" if code < 0x10000 else f"\\U{code:08x}"
        return text, len(text)
    if category in ("Mn", "Me"):  # a combining mark would merge with its neighbour
        text = f"\\u{ord(ch):04x}"
        return text, len(text)
    return ch, 2 if unicodedata.east_asian_width(ch) in ("W", "F") else 1


def escape_text(text: str) -> str:
    """``text`` with control, formatting (e.g. U+202E right-to-left override) and other
    invisible characters written as ``\\x1b`` / ``\\u202e``: shown, never acted on."""
    if text.isascii() and text.isprintable():
        return text
    return "".join(_shown(ch)[0] for ch in text)


def source_window(source: str, column: int, width: int = SOURCE_WINDOW) -> tuple[str, int]:
    """(at most ``width`` columns of ``source`` around ``column``, escaped, with ``…`` where it
    is cut; the caret's offset in that text)."""
    column = max(0, min(column, len(source)))
    left, right = column, column  # the shown slice is source[left:right]
    used = 0
    pieces: dict[int, tuple[str, int]] = {}

    def piece(i: int) -> tuple[str, int]:
        if i not in pieces:
            pieces[i] = _shown(source[i])
        return pieces[i]

    budget = width - 2  # room for an ellipsis at either end
    # the caret's own character, then alternately one to the right and two to the left
    # (context before an error says more than what follows it)
    if right < len(source) and piece(right)[1] <= budget:
        used += piece(right)[1]
        right += 1
    while True:
        grew = False
        for _ in range(2):
            if left > 0 and used + piece(left - 1)[1] <= budget:
                left -= 1
                used += piece(left)[1]
                grew = True
        if right < len(source) and used + piece(right)[1] <= budget:
            used += piece(right)[1]
            right += 1
            grew = True
        if not grew:
            break
    head = "…" if left > 0 else ""
    tail = "…" if right < len(source) else ""
    before = "".join(piece(i)[0] for i in range(left, column))
    shown = head + before + "".join(piece(i)[0] for i in range(column, right)) + tail
    caret = len(head) + sum(piece(i)[1] for i in range(left, column))
    return shown, caret


class CircuitError(ImpedaxError, ValueError):
    """A circuit that parses but cannot be used as asked (duplicate names, unknown probe, ...)."""


# the source of a spectrum built in a session (`data.make_spectrum`), not read from a file
IN_MEMORY = "memory"


class DataError(ImpedaxError, ValueError):
    """Spectrum data that cannot be read or is not valid (names the file and line when known)."""

    def __init__(self, message: str, *, path: object = None, line: int | None = None):
        self.path = None if path is None else str(path)
        self.line = line
        self.detail = message  # (without the file and line: for a message that names them itself)
        where = ""
        if self.path is not None:
            where = "in-memory data" if self.path == IN_MEMORY else self.path
            if line is not None:
                where += f", line {line}"
            where += ": "
        super().__init__(where + message)


class ArgumentsSwapped(DataError, CircuitError):
    """A circuit and a spectrum given in each other's places (``fit``, ``sample`` take
    ``(circuit, data)``; ``diagnose``, ``refine`` take ``(data, circuit)``): the message names the
    function and the call in its order. Both a `DataError` and a `CircuitError`, as the two
    messages it replaces were."""


class SweepGridsDiffer(DataError):
    """A file holding several sweeps one after another (or sheets, curves, measurements) on
    different frequency grids, which impedax will not merge into one spectrum. ``dim`` ('sweep',
    'cycle', 'sheet', ...), ``labels`` (one per sweep) and `spectrum` (one sweep alone) let a
    caller read one of them:
    ``impedax.io.load(path, sweep=LABEL)``, ``--select sweep=LABEL`` in the CLI."""

    def __init__(self, message: str, *, path: object, line: int | None, dim: str, spectra: dict, found: str = ""):
        super().__init__(message, path=path, line=line)
        self.found = found or message  # (what the file holds, without how to proceed)
        self.dim = dim
        self.labels = list(spectra)
        self._spectra = spectra

    def spectrum(self, label: str):
        """Sweep ``label`` alone (a `DataError` naming the labels when there is none such)."""
        if str(label) not in self._spectra:
            raise DataError(f"no {self.dim} {label!s}; its {self.dim}s: {', '.join(self.labels)}", path=self.path)
        return self._spectra[str(label)]


class ParameterError(ImpedaxError, ValueError):
    """An unknown parameter name, or a value outside the parameter's bounds."""


class ArgumentNeeded(ParameterError):
    """A saved result that can be rebuilt only with an argument the file cannot hold (a custom
    reparametrization's functions): the file is whole, the call lacks something."""


class FitError(ImpedaxError, RuntimeError):
    """A fit that cannot be set up (more parameters than data, infeasible start, ...)."""


class FitsNotComparable(FitError, ValueError):
    """Fits that `compare` cannot rank together: none, of different spectra or weightings, fits
    of one spectrum beside batches, a shared fit. The input is at fault, so it is
    a `ValueError` as the API's other argument errors, and a `FitError`, the class these messages
    were raised as."""
