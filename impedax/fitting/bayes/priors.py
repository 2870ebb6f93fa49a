"""Prior distributions for Bayesian fits, by parameter name.

Four kinds, each with two numbers (SI units of the parameter):

* ``uniform:lo,hi``      p(x) = 1/(hi − lo) on [lo, hi]
* ``loguniform:lo,hi``   p(x) = 1/(x ln(hi/lo)) on [lo, hi], 0 < lo (flat in log x; the default)
* ``normal:mu,sd``       Gaussian, truncated to the parameter's bounds and renormalised
* ``lognormal:median,s`` ln x ~ N(ln median, s²) (s is the standard deviation of ln x), truncated
  to the parameter's bounds and renormalised

Every density is normalised (evidence values need that). The default priors a run chooses
and the checks of user priors against the parameter bounds live here too.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass
from typing import Mapping

import jax.numpy as jnp
import numpy as np

from ...arguments import shown
from ...errors import ParameterError

__all__ = [
    "Prior",
    "PriorKind",
    "parse_prior",
    "PRIOR_KINDS",
    "SIGMA_REL_PRIOR",
    "DEFAULT_SPAN_DECADES",
    "coerce_priors",
    "default_prior",
    "check_prior_inside",
    "prior_log_density",
]


class PriorKind(enum.StrEnum):
    """The prior families; the values are the names users write (``--prior R1=loguniform:…``)."""

    UNIFORM = "uniform"
    LOGUNIFORM = "loguniform"
    NORMAL = "normal"
    LOGNORMAL = "lognormal"


PRIOR_KINDS = {
    PriorKind.UNIFORM: "uniform:LO,HI — flat on [LO, HI]",
    PriorKind.LOGUNIFORM: "loguniform:LO,HI — flat in log x on [LO, HI], 0 < LO (the default)",
    PriorKind.NORMAL: "normal:MU,SD — Gaussian (truncated to the parameter's bounds)",
    PriorKind.LOGNORMAL: "lognormal:MEDIAN,S — ln x Gaussian with standard deviation S (truncated to the bounds)",
}
_CODES = {PriorKind.UNIFORM: 0, PriorKind.LOGUNIFORM: 1, PriorKind.NORMAL: 2, PriorKind.LOGNORMAL: 3}  # the switch of `prior_log_density`


@dataclass(frozen=True)
class Prior:
    """One prior: ``Prior("loguniform", 1e2, 1e5)``; see the module docstring for the kinds."""

    kind: PriorKind
    a: float
    b: float

    def __post_init__(self):
        if self.kind not in PRIOR_KINDS:
            raise ParameterError(f"unknown prior kind {self.kind!r}; choose one of {', '.join(PRIOR_KINDS)}")
        object.__setattr__(self, "kind", PriorKind(self.kind))
        a, b = float(self.a), float(self.b)
        if not (math.isfinite(a) and math.isfinite(b)):
            raise ParameterError(f"prior {self}: both numbers must be finite")
        if self.bounded and not a < b:
            raise ParameterError(f"prior {self}: lower {a:g} must be below upper {b:g}")
        if self.kind is PriorKind.LOGUNIFORM and a <= 0:
            raise ParameterError(f"prior {self}: a log-uniform prior needs a positive lower end")
        if self.kind is PriorKind.NORMAL and b <= 0:
            raise ParameterError(f"prior {self}: the standard deviation must be positive")
        if self.kind is PriorKind.LOGNORMAL and (a <= 0 or b <= 0):
            raise ParameterError(f"prior {self}: the median and S must be positive")
        object.__setattr__(self, "a", a)
        object.__setattr__(self, "b", b)

    def __str__(self) -> str:
        return f"{self.kind}:{self.a:g},{self.b:g}"

    @property
    def code(self) -> int:
        """The integer `prior_log_density` switches on."""
        return _CODES[self.kind]

    @property
    def bounded(self) -> bool:
        """Whether the two numbers are the ends of the support (uniform, log-uniform)."""
        return self.kind in (PriorKind.UNIFORM, PriorKind.LOGUNIFORM)

    def support(self, lower: float, upper: float) -> tuple[float, float]:
        """The prior's support within the parameter bounds (lower, upper)."""
        if self.bounded:
            return max(self.a, lower), min(self.b, upper)
        return lower, upper

    def log_normaliser(self, lower: float, upper: float) -> float:
        """ln of the probability mass the untruncated prior puts inside (lower, upper)."""
        from scipy import stats

        if self.kind is PriorKind.NORMAL:
            mass = stats.norm.cdf(upper, self.a, self.b) - stats.norm.cdf(lower, self.a, self.b)
        elif self.kind is PriorKind.LOGNORMAL:
            lo = math.log(lower) if lower > 0 else -math.inf
            hi = math.log(upper) if math.isfinite(upper) and upper > 0 else math.inf
            mass = stats.norm.cdf(hi, math.log(self.a), self.b) - stats.norm.cdf(lo, math.log(self.a), self.b)
        else:
            return 0.0
        return math.log(mass) if mass > 0 else -math.inf

    def median(self, lower: float, upper: float) -> float:
        """A central value of the prior (used only when a start must come from the prior)."""
        if self.kind is PriorKind.UNIFORM:
            lo, hi = self.support(lower, upper)
            return 0.5 * (lo + hi)
        if self.kind is PriorKind.LOGUNIFORM:
            lo, hi = self.support(lower, upper)
            return math.sqrt(lo * hi)
        return self.a


def parse_prior(text: str) -> tuple[str, Prior]:
    """``"R1=loguniform:1e2,1e5"`` → ``("R1", Prior("loguniform", 100.0, 100000.0))``."""
    name, sep, spec = text.partition("=")
    name = name.strip()
    if not sep or not name:
        raise ParameterError(f"--prior {text!r}: expected NAME=KIND:ARGS, e.g. R1=loguniform:1e2,1e5")
    kind, sep, args = spec.partition(":")
    kind = kind.strip().lower().replace("-", "").replace("_", "")
    if kind not in PRIOR_KINDS:
        raise ParameterError(f"--prior {text!r}: unknown prior kind {kind!r}; choose one of {', '.join(PRIOR_KINDS)}")
    parts = [p.strip() for p in args.split(",")] if sep else []
    if len(parts) != 2:
        raise ParameterError(f"--prior {text!r}: {kind} takes two numbers ({PRIOR_KINDS[kind]})")
    try:
        a, b = float(parts[0]), float(parts[1])
    except ValueError:
        raise ParameterError(f"--prior {text!r}: {args!r} are not two numbers") from None
    try:
        return name, Prior(kind, a, b)
    except ParameterError as exc:
        raise ParameterError(f"--prior {text!r}: {exc}") from None


SIGMA_REL_PRIOR = Prior(PriorKind.LOGUNIFORM, 1e-5, 1.0)
DEFAULT_SPAN_DECADES = 3.0  # default log-uniform prior for unbounded parameters: LSQ value ×/÷ 10³


def coerce_priors(priors: Mapping[str, "Prior | str | tuple"] | None) -> dict[str, Prior]:
    """User priors by name as `Prior`: a `Prior`, a ``(kind, a, b)`` tuple or ``"kind:a,b"`` text."""
    out = {}
    for name, prior in (priors or {}).items():
        if isinstance(prior, str):
            _, prior = parse_prior(f"{name}={prior}")
        elif isinstance(prior, tuple) and len(prior) == 3:
            prior = Prior(*prior)
        elif not isinstance(prior, Prior):
            raise ParameterError(f"prior for {shown(name)}: expected a Prior, a (kind, a, b) tuple or 'kind:a,b' text, got {shown(prior)}")
        out[name] = prior
    return out


def default_prior(lower: float, upper: float, start: float) -> Prior:
    """The prior of a parameter the user gave none: log-uniform within finite positive bounds,
    uniform within finite bounds, else ``start`` ×/÷ 10^`DEFAULT_SPAN_DECADES` (log-uniform for
    non-negative parameters, uniform around ``start`` otherwise)."""
    if math.isfinite(upper) and lower > 0:
        return Prior(PriorKind.LOGUNIFORM, lower, upper)
    if math.isfinite(upper) and math.isfinite(lower):
        return Prior(PriorKind.UNIFORM, lower, upper)
    span = 10.0**DEFAULT_SPAN_DECADES
    if lower >= 0 and start > 0:
        return Prior(PriorKind.LOGUNIFORM, max(start / span, lower * (1 + 1e-12)) if lower > 0 else start / span, start * span)
    centre = start if math.isfinite(start) else 0.0
    half = span * max(abs(centre), 1.0)
    return Prior(PriorKind.UNIFORM, max(centre - half, lower), min(centre + half, upper))


def check_prior_inside(name: str, prior: Prior, lower: float, upper: float, inclusive: bool) -> None:
    """Raise `ParameterError` when a uniform or log-uniform prior reaches outside the
    parameter's bounds (lower, upper) (upper included when ``inclusive``)."""
    if prior.bounded:
        too_high = prior.b > upper or (prior.b == upper and not inclusive and math.isfinite(upper))
        if prior.a < lower or too_high:
            right = "]" if inclusive else ")"
            raise ParameterError(f"prior for {name}: {prior} reaches outside the parameter's bounds ({lower:g}, {upper:g}{right})")


def prior_log_density(x, code, a, b, lo, hi, log_norm):
    """ln p(x) for vectors of priors (JAX, elementwise). Outside (lo, hi] the density is −∞.

    ``code`` 0 uniform, 1 log-uniform, 2 normal, 3 log-normal (see the module docstring).
    """
    safe_x = jnp.where(x > 0, x, 1.0)
    safe_a = jnp.where(a > 0, a, 1.0)
    width = jnp.where(b > a, b - a, 1.0)
    log_ratio = jnp.where(b > safe_a, jnp.log(jnp.where(b > safe_a, b, 2.0) / safe_a), 1.0)
    sd = jnp.where(b > 0, b, 1.0)
    half_log_2pi = 0.5 * np.log(2 * np.pi)
    uniform = -jnp.log(width)
    loguniform = -jnp.log(safe_x) - jnp.log(log_ratio)
    normal = -0.5 * ((x - a) / sd) ** 2 - jnp.log(sd) - half_log_2pi - log_norm
    lognormal = -0.5 * ((jnp.log(safe_x) - jnp.log(safe_a)) / sd) ** 2 - jnp.log(safe_x * sd) - half_log_2pi - log_norm
    density = jnp.where(code == 0, uniform, jnp.where(code == 1, loguniform, jnp.where(code == 2, normal, lognormal)))
    inside = (x > lo) & (x <= hi)
    return jnp.where(inside, density, -jnp.inf)
