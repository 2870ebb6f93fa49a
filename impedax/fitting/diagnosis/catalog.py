"""The types of the effect catalog: an `Effect` (a physical effect and its proposal function),
the `EffectCatalog` that holds them (a value, like the element registry), the `BaselineContext`
a proposal function looks at and the `Proposal` it returns. The effects themselves live in
`impedax.fitting.diagnosis.effects` (docs/diagnosis.md, section 4)."""

from __future__ import annotations

import difflib
import math
import re
from dataclasses import dataclass, field
from typing import Callable, Iterator, Mapping

import numpy as np

from ...circuits import Circuit, DEFAULT_REGISTRY, Registry
from ...arguments import shown
from ...errors import CircuitError, ParameterError
from ..drt import PeakEvidence

__all__ = ["Effect", "EffectCatalog", "Proposal", "BaselineContext"]


@dataclass(frozen=True)
class Proposal:
    """One augmented circuit: ``added`` (the new elements, as circuit text) placed ``where``;
    ``removed``: baseline elements the circuit leaves out (a series resistance that fell to zero,
    a branch of an R ∥ C block that carries no current the data resolve); ``vanished``: those of
    them that fell to zero where the circuit kept them (leaving them out changes nothing the
    other elements stand for); ``band``: the lowest and highest frequency (Hz) of the data it was
    proposed for (plausibility checks read it)."""

    effect: str
    circuit: Circuit
    added: str
    where: str
    starts: tuple[Mapping[str, float], ...]
    removed: tuple[str, ...] = ()
    band: tuple[float, float] = (0.0, math.inf)
    vanished: tuple[str, ...] = ()
    # what the data's evidence expects of the fit ({"CPE1.alpha": 0.80} from a
    # DRT peak's width) and the words that cite it; the explanation cites it only when the fit
    # agrees (`diagnosis._evidence_words`)
    expected: Mapping[str, float] = field(default_factory=dict)
    evidence: str = ""


@dataclass(frozen=True, eq=False)
class BaselineContext:
    """What a proposal function may look at: the baseline circuit, its fitted values and the
    data/model spectra (arrays sorted by frequency, ascending); ``drt_evidence``: the data's DRT
    peaks that the baseline does (not) explain (`impedax.fitting.drt.unexplained_peaks`), or None
    when the DRT was switched off or could not be computed."""

    circuit: Circuit
    values: Mapping[str, float]
    frequency: np.ndarray
    z_data: np.ndarray
    z_model: np.ndarray
    registry: Registry = field(default=DEFAULT_REGISTRY, repr=False)
    undetermined: frozenset = frozenset()  # baseline parameters the data did not determine
    drt_evidence: PeakEvidence | None = None

    @property
    def omega(self) -> np.ndarray:
        return 2 * np.pi * self.frequency

    def fresh(self, symbol: str, label: str) -> str:
        """An element name ``symbol_label`` not used in the baseline (``R_EP``, ``R_EP2``, ...)."""
        return self.fresh_group(label, symbol)[symbol]

    def fresh_group(self, label: str, *symbols: str) -> dict[str, str]:
        """Names ``symbol_label`` of elements added together (an arc's R and its C or CPE), one
        number for all so that they pair: {R: R_relax2, C: C_relax2, CPE: CPE_relax2} when any
        of ``R_relax``, ``C_relax``, ``CPE_relax`` is used in the baseline. Numbered one by one,
        a refine on REAL VersaStudio data ended with R_relax3 beside CPE_relax2 and R_relax2
        beside C_relax."""
        taken = set(self.circuit.element_names)
        suffix, k = "", 2
        while any(f"{s}_{label}{suffix}" in taken for s in symbols):
            suffix, k = str(k), k + 1
        return {s: f"{s}_{label}{suffix}" for s in symbols}

    def ends(self, k: int = 3):
        """Indices of the k lowest and k highest frequencies."""
        k = min(k, self.frequency.size)
        return np.arange(k), np.arange(self.frequency.size - k, self.frequency.size)

    def misfit_frequency(self) -> float:
        """Frequency where the relative misfit |Z_data − Z_model|/|Z_data| peaks (3-point smoothed)."""
        r = np.abs(self.z_data - self.z_model) / np.abs(self.z_data)
        smooth = np.convolve(r, np.ones(3) / 3, mode="same") if r.size >= 3 else r
        return float(self.frequency[int(np.argmax(smooth))])

    def start(self, **new: float) -> dict[str, float]:
        """Baseline values plus ``new``; undetermined baseline values are left to the data-driven
        guess (a resistance that collapsed to ~0 in log space cannot come back from there)."""
        out = {k: float(v) for k, v in self.values.items() if k not in self.undetermined}
        out.update({k: float(v) for k, v in new.items()})
        return out


@dataclass(frozen=True)
class Effect:
    """A physical effect: id (stable), physics, residual signature, circuit change, proposals;
    ``plausible(values, proposal)``: None when the fitted values of a candidate are plausible
    for this effect, else why not (the candidate is then not proposed; default: no check)."""

    id: str
    title: str
    physics: str
    signature: str
    change: str
    propose: Callable[[Circuit, BaselineContext], list[Proposal]] = field(repr=False, compare=False)
    plausible: Callable[[Mapping[str, float], Proposal], str | None] | None = field(default=None, repr=False, compare=False)


# where the built-in effects' proposal functions live (their errors are impedax's bugs, not a
# user's; that module imports this one, so it is named, not imported)
BUILT_IN_MODULE = f"{__package__}.effects"

REPR_IDS = 8  # effect ids an EffectCatalog's repr names


@dataclass(frozen=True)
class EffectCatalog:
    """An immutable, ordered set of effects; `register` returns an extended copy."""

    effects: tuple[Effect, ...]

    def __post_init__(self):
        ids = [e.id for e in self.effects]
        if len(set(ids)) != len(ids):
            raise ParameterError(f"duplicate effect ids in catalog: {ids}")

    def __iter__(self) -> Iterator[Effect]:
        return iter(self.effects)

    def __repr__(self) -> str:
        # short: the default of `effects=` in diagnose's and refine's signatures (help() printed
        # every effect's fields); the first ids, then how many more
        shown = ", ".join(self.ids()[:REPR_IDS]) + (f", … {len(self) - REPR_IDS} more" if len(self) > REPR_IDS else "")
        return f"EffectCatalog({len(self)} effects: {shown})"

    def __len__(self) -> int:
        return len(self.effects)

    def __getitem__(self, effect_id: str) -> Effect:
        for e in self.effects:
            if e.id == effect_id:
                return e
        guess = self.closest(effect_id)
        raise ParameterError(f"unknown effect {effect_id!r}" + (f" (did you mean {guess}?)" if guess else "") + f"; known: {', '.join(self.ids())}")

    def closest(self, word: str) -> str | None:
        """The effect id a mistyped ``word`` most likely means, or None: the id spelt with
        hyphens, spaces or capitals (``constant-phase``), the id or title nearest by `difflib`
        or the only one holding it (``inductance``), or the one effect whose circuit change
        names ``word`` as an element (``CPE``: ``replace an ideal C by a CPE``)."""
        key = str(word).strip().lower().replace("-", "_").replace(" ", "_")
        by_name = {e.id: e.id for e in self.effects} | {e.title.lower().replace("-", "_").replace(" ", "_"): e.id for e in self.effects}
        near = difflib.get_close_matches(key, list(by_name), n=1, cutoff=0.75)
        if near:
            return by_name[near[0]]
        holding = {i for name, i in by_name.items() if len(key) >= 4 and key in name}
        if len(holding) == 1:
            return holding.pop()
        element = str(word).strip()
        naming = [e.id for e in self.effects if len(element) >= 2 and re.search(rf"(?<!\w){re.escape(element)}(?!\w)", e.change)]
        return naming[0] if len(naming) == 1 else None

    def ids(self) -> tuple[str, ...]:
        return tuple(e.id for e in self.effects)

    def register(self, effect: Effect) -> "EffectCatalog":
        return EffectCatalog(self.effects + (effect,))

    def select(self, ids) -> "EffectCatalog":
        """A catalog restricted to ``ids`` (in the catalog's order)."""
        wanted = set(ids)
        for i in wanted:
            self[i]
        return EffectCatalog(tuple(e for e in self.effects if e.id in wanted))

    def proposals(self, ctx: BaselineContext) -> list[tuple[Effect, Proposal]]:
        """Every effect's proposals for the baseline ``ctx.circuit``, in catalog order, without
        the baseline itself or a circuit proposed twice (by text)."""
        seen = {str(ctx.circuit)}
        out = []
        for effect in self.effects:
            for proposal in _checked_proposals(effect, ctx):
                key = str(proposal.circuit)
                if key not in seen:
                    seen.add(key)
                    out.append((effect, proposal))
        return out


def _checked_proposals(effect: Effect, ctx: BaselineContext) -> list[Proposal]:
    """``effect.propose(ctx.circuit, ctx)``, a user's effect's mistakes refused naming it: a
    propose that raises, returns something other than a list of `Proposal`, a proposal of
    another effect's id, a circuit as text or with an element the registry lacks, starting
    values of parameters neither the proposed circuit nor the baseline has (a typo), or a start
    it sets outside its parameter's bounds (`_check_start_bounds`). The
    built-in effects are trusted: an error of theirs is a bug in impedax, shown as such."""
    if getattr(effect.propose, "__module__", None) == BUILT_IN_MODULE:
        return effect.propose(ctx.circuit, ctx)
    where = f"effect {effect.id!r}: its propose"
    try:
        proposals = effect.propose(ctx.circuit, ctx)
    except Exception as exc:  # (a user's function: whatever it raises is named)
        raise ParameterError(f"{where} raised {type(exc).__name__}: {exc}") from exc
    if isinstance(proposals, Proposal):
        proposals = [proposals]
    if not isinstance(proposals, (list, tuple)):
        raise ParameterError(f"{where} returned {type(proposals).__name__}, not a list of Proposal (an empty list when it has nothing to propose)")
    known = set(ctx.values)
    for i, p in enumerate(proposals):
        item = f"{where} returned, as item {i},"
        if not isinstance(p, Proposal):
            raise ParameterError(f"{item} {type(p).__name__}, not a Proposal(effect, circuit, added, where, starts)")
        if p.effect != effect.id:
            raise ParameterError(f"{item} a Proposal of effect {p.effect!r}: its first field is the proposing effect's id, {effect.id!r}")
        if not isinstance(p.circuit, Circuit):
            hint = f" (parse it: impedax.parse({str(p.circuit)!r}, ctx.registry), or build it: circuit + Element(symbol, name))" if isinstance(p.circuit, str) else ""
            raise ParameterError(f"{item} a circuit that is {type(p.circuit).__name__}, not a Circuit{hint}")
        try:
            names = set(p.circuit.parameter_names(ctx.registry))
        except CircuitError as exc:
            raise CircuitError(f"{item} the circuit {p.circuit}: {exc}") from None
        if not isinstance(p.starts, (tuple, list)) or not all(isinstance(start, Mapping) for start in p.starts):
            raise ParameterError(f"{item} starts that are not a tuple of name → value mappings (ctx.start(**new) makes one), got {type(p.starts).__name__}")
        for start in p.starts:
            unknown = sorted(set(start) - names - known)
            if unknown:
                raise ParameterError(f"{item} starting values of {', '.join(map(repr, unknown))}, which {p.circuit} does not have (its parameters: {', '.join(sorted(names))})")
            _check_start_bounds(start, p.circuit.parameter_specs(ctx.registry), ctx.values, item)
    return list(proposals)


def _check_start_bounds(start: Mapping[str, object], specs: Mapping, baseline: Mapping[str, float], item: str) -> None:
    """Refuse a start value the effect sets (one not the baseline's own fitted value, which may
    sit on a bound) that is not a number inside its element parameter's bounds
    (`ParameterSpec.contains`): a negative resistance, an alpha above 1. The fit would move it
    inside without a word (`values_inside`), so the effect's mistake would go unseen."""
    for name, value in start.items():
        spec = specs.get(name)
        if spec is None or (name in baseline and _same_number(value, baseline[name])):
            continue
        number = float(value) if isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool) else None
        if number is None or not spec.contains(number):
            raise ParameterError(f"{item} a start {name}={shown(value)}, outside {name}'s bounds {spec.bounds_text()} (a start lies strictly inside them)")


def _same_number(a, b) -> bool:
    try:
        return float(a) == float(b)
    except (TypeError, ValueError):
        return False
