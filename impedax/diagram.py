"""Circuit schematics drawn from the circuit tree with schemdraw (optional extra ``draw``).

Layout, recursively: the elements of a series chain sit in one row, left to right; the branches
of a parallel group are stacked downwards between two vertical rails, each branch padded with
wire to the widest one. Every block's two terminals lie on its top line, so blocks nest
without any search. Two parallel groups side by side are joined by a short wire, so that no
branch ends on the next group's rail, and every point where a branch joins a rail carries a
junction dot. Elements are labelled with their names and, when given, their values.
"""

from __future__ import annotations

import os
from typing import Mapping

from .arguments import checked_arguments, parameter_values, shown
from .circuits import DEFAULT_REGISTRY, Circuit, Element, Registry, Series, parse
from .data import SI_PREFIXES, format_quantity, si_prefix
from .errors import DataError, ImpedaxError, ParameterError
from .io.atomic import atomic_path, check_file_name, check_writable

__all__ = ["draw_circuit", "save_circuit_diagram"]

_UNIT = 3.0  # length of one element, schemdraw units
_ROW = 2.6  # vertical pitch of stacked parallel branches (room for the labels above and below)
_STUB = 0.75  # wire between a rail and a branch
_INCHES_PER_UNIT = 0.5  # the drawing's scale (schemdraw's), whatever the circuit's size: labels keep their size beside the parts
# widths of a label's characters at the drawing's font sizes (11 pt names, 9 pt values), in
# drawing units, with room to spare (DejaVu Sans averages about 0.6 em a character)
_NAME_CHAR = 11 / 72 * 0.65 / _INCHES_PER_UNIT
_VALUE_CHAR = 9 / 72 * 0.65 / _INCHES_PER_UNIT
_LABEL_MARGIN = 0.6  # free space between the labels of two neighbours
_SI = {"Ohm": "Ω", "F": "F", "H": "H"}
_GREEK = {"alpha": "α", "beta": "β", "tau": "τ", "sigma": "σ"}


def _schemdraw():
    try:
        import schemdraw
        import schemdraw.elements as elm
    except ImportError:
        raise ImpedaxError("circuit diagrams need schemdraw: pip install impedax[draw]") from None
    return schemdraw, elm


def _rail_at(node: Circuit, side: int) -> bool:
    """Whether ``node`` starts (``side=0``) or ends (``side=-1``) with a parallel group's rail."""
    if isinstance(node, Element):
        return False
    return _rail_at(node.children[side], side) if isinstance(node, Series) else True


def _gap_after(node: Circuit, following: Circuit) -> float:
    """Wire between two series neighbours: a stub where a rail would otherwise meet a rail."""
    return _STUB if _rail_at(node, -1) and _rail_at(following, 0) else 0.0


def _element_widths(circuit: Circuit, values: Mapping[str, float], registry: Registry) -> dict[str, float]:
    """Each element's length in the drawing: `_UNIT`, or more where its name or its values
    would be wider (a long name such as ``R_charge_transfer`` ran into its neighbour's)."""
    widths = {}
    for e in circuit.elements():
        lines = _value_text(e, values, registry).splitlines() if values else []
        needed = max([len(e.name) * _NAME_CHAR, *(len(line) * _VALUE_CHAR for line in lines)]) + _LABEL_MARGIN
        widths[e.name] = max(_UNIT, needed)
    return widths


def _size(node: Circuit, widths: Mapping[str, float]) -> tuple[float, float]:
    if isinstance(node, Element):
        return widths[node.name], _ROW
    sizes = [_size(c, widths) for c in node.children]
    if isinstance(node, Series):
        gaps = sum(_gap_after(a, b) for a, b in zip(node.children[:-1], node.children[1:]))
        return sum(w for w, _ in sizes) + gaps, max(h for _, h in sizes)
    return max(w for w, _ in sizes) + 2 * _STUB, sum(h for _, h in sizes)


def _si(value: float, unit: str) -> str:
    symbol = _SI[unit]
    magnitude = abs(value) / 0.9995  # (a value that rounds up to a scale takes its prefix)
    if magnitude < SI_PREFIXES[-1][0]:
        return f"{value:.3g} {symbol}"
    scale, prefix = si_prefix(magnitude)
    return f"{value / scale:.3g} {prefix}{symbol}"


def _value_text(element: Element, values: Mapping[str, float], registry: Registry) -> str:
    spec = registry[element.symbol]
    parts = []
    for p in spec.parameters:
        name = p.full_name(element.name)
        if name not in values:
            continue
        v = float(values[name])
        if p.suffix is None and p.unit in _SI:
            parts.append(_si(v, p.unit))
        else:  # (with its unit, as a fit's report writes it: τ=1 ms, Q=15 µF s^(α-1), not τ=0.001, Q=1.5e-05)
            parts.append(f"{_GREEK.get(p.suffix, p.suffix or element.name)}={format_quantity(v, p.unit)}")
    return "\n".join(parts)


def _element(elm, element: Element, registry: Registry):
    """The schemdraw part named by ``ElementSpec.draw``; without one (Warburg, Gerischer,
    Cole–Cole, a user's element), a box: the label says which element it is."""
    spec = registry[element.symbol]
    if spec.draw is None:
        return elm.RBox()
    maker = getattr(elm, spec.draw, None)
    if maker is None:
        import difflib

        parts = [name for name in dir(elm) if name[:1].isupper() and isinstance(getattr(elm, name), type)]
        close = difflib.get_close_matches(spec.draw, parts, n=1, cutoff=0.6)  # (a misspelt part is named with the one meant)
        hint = f": did you mean {close[0]!r}?" if close else ""
        raise ImpedaxError(f"element {spec.symbol} ({spec.name}) is drawn as {spec.draw!r} (its ElementSpec's draw=), which schemdraw does not have{hint} "
                           "(a name of schemdraw.elements, e.g. 'Resistor', 'Capacitor', 'Inductor2', 'CPE'; none draws a labelled box)")
    return maker()


def _place(d, elm, node: Circuit, x: float, y: float, values, registry, widths) -> None:
    if isinstance(node, Element):
        part = _element(elm, node, registry).at((x, y)).to((x + widths[node.name], y)).label(node.name, loc="top")
        if values:
            text = _value_text(node, values, registry)
            if text:
                part = part.label(text, loc="bottom", fontsize=9)
        d.add(part)
        return
    if isinstance(node, Series):
        for child, following in zip(node.children, [*node.children[1:], None]):
            _place(d, elm, child, x, y, values, registry, widths)
            x += _size(child, widths)[0]
            gap = 0.0 if following is None else _gap_after(child, following)
            if gap:
                d.add(elm.Line().at((x, y)).to((x + gap, y)))
                x += gap
        return
    width = _size(node, widths)[0]
    left, right = x, x + width
    yi = y
    for i, child in enumerate(node.children):
        cw, ch = _size(child, widths)
        d.add(elm.Line().at((left, yi)).to((left + _STUB, yi)))
        _place(d, elm, child, left + _STUB, yi, values, registry, widths)
        d.add(elm.Line().at((left + _STUB + cw, yi)).to((right, yi)))
        if i < len(node.children) - 1:  # a junction (the last branch turns the rails' corners)
            d.add(elm.Dot(radius=0.1).at((left, yi)))
            d.add(elm.Dot(radius=0.1).at((right, yi)))
        last = yi
        yi -= ch
    d.add(elm.Line().at((left, y)).to((left, last)))
    d.add(elm.Line().at((right, y)).to((right, last)))


@checked_arguments()
def draw_circuit(circuit: Circuit | str, values: Mapping[str, float] | None = None, *, registry: Registry = DEFAULT_REGISTRY):
    """Schematic of ``circuit`` as a matplotlib Figure.

    Series elements in a row, parallel branches stacked, groups nested recursively; each element
    labelled with its name and, for the parameters given in ``values`` (name → value, SI units,
    e.g. fitted values), its value. Needs the optional ``schemdraw`` (``pip install impedax[draw]``).
    """
    if not isinstance(circuit, (str, Circuit)):  # (a list: this message, not AttributeError)
        raise ParameterError(f"circuit must be circuit text or a Circuit, got {shown(circuit)} ({type(circuit).__name__})")
    if isinstance(values, (str, os.PathLike)):  # (a file name in the place of the values: not dict()'s ValueError)
        raise ParameterError(f"values must be a mapping name → value, got the file name {shown(os.fspath(values))}: draw_circuit returns a matplotlib Figure; "
                             f"to write a file call impedax.save_circuit_diagram(circuit, {shown(os.fspath(values))})")
    values = parameter_values()(values, "values") or {}
    circuit = parse(circuit, registry) if isinstance(circuit, str) else circuit
    known = circuit.parameter_names(registry)
    unknown = [n for n in values if n not in known]
    if unknown:
        raise ParameterError(f"unknown parameter(s) {unknown} for {circuit}; parameters: {', '.join(known)}")
    schemdraw, elm = _schemdraw()
    d = schemdraw.Drawing(canvas="matplotlib", show=False)
    d.config(fontsize=11, lw=1.4, inches_per_unit=_INCHES_PER_UNIT)
    widths = _element_widths(circuit, values, registry)
    width = _size(circuit, widths)[0]
    d.add(elm.Dot(open=True).at((0.0, 0.0)))
    d.add(elm.Line().at((0.0, 0.0)).to((_STUB, 0.0)))
    _place(d, elm, circuit, _STUB, 0.0, values, registry, widths)
    d.add(elm.Line().at((_STUB + width, 0.0)).to((2 * _STUB + width, 0.0)))
    d.add(elm.Dot(open=True).at((2 * _STUB + width, 0.0)))
    # (the figure sized by the drawing's scale, `getfig`: the bare ``.fig`` keeps matplotlib's
    # default 6.4 × 4.8 in, so a wide circuit would be shrunk into it under labels of full size, which
    # run into each other, and a small one blown up around small labels)
    fig = d.draw(show=False).getfig()
    for line in fig.axes[0].lines:  # (no snapping to the pixel grid: a straight wire snapped, the parts' leads did not, and met them a pixel off)
        line.set_snap(False)
    return fig


@checked_arguments()
def save_circuit_diagram(circuit: Circuit | str, path: str | os.PathLike, values: Mapping[str, float] | None = None, *, registry: Registry = DEFAULT_REGISTRY) -> None:
    """Draw ``circuit`` (see `draw_circuit`) and save it atomically as .png, .svg or .pdf.

    SVG keeps the labels as text (searchable, editable), not as glyph outlines.
    """
    check_file_name(path, "circuit.svg")
    path = check_writable(path)
    if path.suffix.lower() not in (".png", ".svg", ".pdf"):
        raise DataError(f"unknown diagram format {path.suffix!r}; use .png, .svg or .pdf", path=path)
    import matplotlib
    import matplotlib.pyplot as plt

    fig = draw_circuit(circuit, values, registry=registry)
    try:
        with matplotlib.rc_context({"svg.fonttype": "none"}), atomic_path(path) as tmp:
            fig.savefig(tmp, format=path.suffix.lower()[1:], dpi=150, bbox_inches="tight", pad_inches=0.1)
    finally:
        plt.close(fig)
