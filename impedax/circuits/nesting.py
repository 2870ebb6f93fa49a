"""When one circuit is a special case of another, and where in the larger one the smaller
one's optimum lies (docs/circuits.md, "Elements that contain others").

A circuit is nested in another when it is the other with elements removed (a series element
set to zero, a parallel branch opened) and/or elements replaced by the simpler ones they
contain in a limit (`ElementSpec.limits`: a capacitor is a CPE at α = 1, a W a Wo at τ → ∞).
`embedding` finds which element of the larger circuit stands for each element of the smaller;
`carried_values` turns the smaller circuit's parameters into the larger one's, so that a fit of
the larger circuit can start where the smaller one's optimum is and never end above it.
"""

from __future__ import annotations

from typing import Mapping

import numpy as np

from .elements import DEFAULT_REGISTRY
from .spec import ElementLimit, Registry
from .tree import Circuit, Element

__all__ = ["embedding", "carried_values"]


def _element_pair(a: Element, b: Element, registry: Registry) -> tuple[bool, ElementLimit | None]:
    """Whether element ``a`` is element ``b`` or one of its limits, and which limit (None: the
    same kind of element)."""
    kind_a, spec_b = registry[a.symbol].symbol, registry[b.symbol]
    if kind_a == spec_b.symbol:
        return True, None
    for limit in spec_b.limits:
        if limit.symbol in registry and registry[limit.symbol].symbol == kind_a:
            return True, limit
    return False, None


def _embed(a: Circuit, b: Circuit, registry: Registry) -> list[tuple[Element, Element, ElementLimit | None]] | None:
    if isinstance(a, Element) and isinstance(b, Element):
        ok, limit = _element_pair(a, b, registry)
        return [(a, b, limit)] if ok else None
    if isinstance(b, Element):
        return None
    if type(a) is type(b):
        return _embed_children(a.children, b.children, registry)
    for child in b.children:  # ``a`` inside one part of ``b``, the other parts removed
        pairs = _embed(a, child, registry)
        if pairs is not None:
            return pairs
    return None


def _embed_children(small, big, registry: Registry):
    """Each child of ``small`` embedded in a distinct child of ``big``, in any order (impedances
    in series and admittances in parallel add in any order: ``R1 || CPE1`` is nested in
    ``CPE1 || (R1 + W1)``), the first assignment found, preferring same-kind elements, then
    elements of the same name (``R0 + R1 || C1`` in ``R0 + R2 || C2 + R1 || C1``: R1 ∥ C1 in
    R1 ∥ C1, as a fit's values are carried by name)."""

    def match(i: int, used: frozenset):
        if i == len(small):
            return []
        tried = []
        for j in range(len(big)):
            if j in used:
                continue
            pairs = _embed(small[i], big[j], registry)
            if pairs is not None:
                tried.append((sum(limit is not None for _, _, limit in pairs), sum(x.name != y.name for x, y, _ in pairs), j, pairs))
        for *_, j, pairs in sorted(tried, key=lambda t: t[:3]):
            rest = match(i + 1, used | {j})
            if rest is not None:
                return pairs + rest
        return None

    return match(0, frozenset()) if len(small) <= len(big) else None


def embedding(small: Circuit, large: Circuit, registry: Registry = DEFAULT_REGISTRY) -> tuple[tuple[Element, Element, ElementLimit | None], ...] | None:
    """How ``small`` sits in ``large``: (element of ``small``, the element of ``large`` that
    stands for it, the `ElementLimit` that reduces the latter to the former or None for the
    same kind of element) for each element of ``small``; None when ``small`` is not ``large``
    with elements removed and/or replaced by the simpler elements they contain."""
    pairs = _embed(small, large, registry)
    return None if pairs is None else tuple(pairs)


def carried_values(small: Circuit, values: Mapping[str, object], large: Circuit, omega_min: float, omega_max: float, registry: Registry = DEFAULT_REGISTRY) -> dict[str, object]:
    """Parameters of ``large`` that reproduce ``small``'s impedance with parameters ``values``
    (name → number, or numpy arrays over spectra) within ω_min..ω_max [rad/s]: each element of
    ``small`` carried into the element of ``large`` that stands for it (`embedding`), through
    its limit where it is a simpler kind (a W's σ into a Wo's R = σ√(2τ) at ω_min·τ = 200).
    Elements of ``large`` with no counterpart get nothing (their usual start). When ``small``
    is not nested in ``large``: the parameters the two share by name."""
    pairs = embedding(small, large, registry)
    large_names = set(large.parameter_names(registry))
    if pairs is None:
        return {n: v for n, v in values.items() if n in large_names}
    out: dict[str, object] = {}
    for a, b, limit in pairs:
        ours = registry[a.symbol].parameter_names(a.name)
        if any(n not in values for n in ours):
            continue
        given = tuple(values[n] for n in ours)
        theirs = registry[b.symbol].parameter_names(b.name)
        carried = given if limit is None else limit.values(tuple(np.asarray(v, float) if np.ndim(v) else float(v) for v in given), float(omega_min), float(omega_max))
        out.update({n: (float(v) if np.ndim(v) == 0 else np.asarray(v, float)) for n, v in zip(theirs, carried)})
    return out
