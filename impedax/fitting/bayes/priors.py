"""Prior distributions for Bayesian fits, by parameter name.

Four kinds, each with two numbers (SI units of the parameter):

* ``uniform:lo,hi``      p(x) = 1/(hi − lo) on [lo, hi]
* ``loguniform:lo,hi``   p(x) = 1/(x ln(hi/lo)) on [lo, hi], 0 < lo (flat in log x; the default)
* ``normal:mu,sd``       Gaussian, truncated to the parameter's bounds and renormalised
* ``lognormal:median,s`` ln x ~ N(ln median, s²) (s is the standard deviation of ln x), truncated
  to the parameter's bounds and renormalised

Every density is normalised (evidence values need that).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import jax.numpy as jnp
import numpy as np

from ...errors import ParameterError

__all__ = ["Prior", "parse_prior", "PRIOR_KINDS"]

PRIOR_KINDS = {
    "uniform": "uniform:LO,HI — flat on [LO, HI]",
    "loguniform": "loguniform:LO,HI — flat in log x on [LO, HI], 0 < LO (the default)",
    "normal": "normal:MU,SD — Gaussian (truncated to the parameter's bounds)",
    "lognormal": "lognormal:MEDIAN,S — ln x Gaussian with standard deviation S (truncated to the bounds)",
}
_CODES = {"uniform": 0, "loguniform": 1, "normal": 2, "lognormal": 3}


@dataclass(frozen=True)
class Prior:
    """One prior: ``Prior("loguniform", 1e2, 1e5)``; see the module docstring for the kinds."""

    kind: str
    a: float
    b: float

    def __post_init__(self):
        if self.kind not in PRIOR_KINDS:
            raise ParameterError(f"unknown prior kind {self.kind!r}; choose one of {', '.join(PRIOR_KINDS)}")
        a, b = float(self.a), float(self.b)
        if not (math.isfinite(a) and math.isfinite(b)):
            raise ParameterError(f"prior {self}: both numbers must be finite")
        if self.kind in ("uniform", "loguniform") and not a < b:
            raise ParameterError(f"prior {self}: lower {a:g} must be below upper {b:g}")
        if self.kind == "loguniform" and a <= 0:
            raise ParameterError(f"prior {self}: a log-uniform prior needs a positive lower end")
        if self.kind == "normal" and b <= 0:
            raise ParameterError(f"prior {self}: the standard deviation must be positive")
        if self.kind == "lognormal" and (a <= 0 or b <= 0):
            raise ParameterError(f"prior {self}: the median and S must be positive")
        object.__setattr__(self, "a", a)
        object.__setattr__(self, "b", b)

    def __str__(self) -> str:
        return f"{self.kind}:{self.a:g},{self.b:g}"

    @property
    def code(self) -> int:
        return _CODES[self.kind]

    def support(self, lower: float, upper: float) -> tuple[float, float]:
        """The prior's support within the parameter bounds (lower, upper)."""
        if self.kind in ("uniform", "loguniform"):
            return max(self.a, lower), min(self.b, upper)
        return lower, upper

    def log_normaliser(self, lower: float, upper: float) -> float:
        """ln of the probability mass the untruncated prior puts inside (lower, upper)."""
        from scipy import stats

        if self.kind == "normal":
            mass = stats.norm.cdf(upper, self.a, self.b) - stats.norm.cdf(lower, self.a, self.b)
        elif self.kind == "lognormal":
            lo = math.log(lower) if lower > 0 else -math.inf
            hi = math.log(upper) if math.isfinite(upper) and upper > 0 else math.inf
            mass = stats.norm.cdf(hi, math.log(self.a), self.b) - stats.norm.cdf(lo, math.log(self.a), self.b)
        else:
            return 0.0
        return math.log(mass) if mass > 0 else -math.inf

    def median(self, lower: float, upper: float) -> float:
        """A central value of the prior (used only when a start must come from the prior)."""
        if self.kind == "uniform":
            lo, hi = self.support(lower, upper)
            return 0.5 * (lo + hi)
        if self.kind == "loguniform":
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
