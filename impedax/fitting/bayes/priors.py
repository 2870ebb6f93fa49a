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

import math
from dataclasses import dataclass
from typing import Mapping

import jax.numpy as jnp
import numpy as np

from ...arguments import PRIOR_KINDS as PRIOR_KINDS, PriorKind as PriorKind, number_text, shown
from ...errors import ParameterError
from ..parameters import data_scales

__all__ = [
    "Prior",
    "PriorKind",
    "parse_prior",
    "PRIOR_KINDS",
    "SIGMA_REL_PRIOR",
    "DEFAULT_SPAN_DECADES",
    "UNDETERMINED_STDERRS",
    "STDERR_REACH",
    "coerce_priors",
    "data_scale_range",
    "undetermined",
    "default_prior",
    "check_prior_inside",
    "prior_log_density",
]


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
            raise ParameterError(f"prior {self}: lower {number_text(a)} must be below upper {number_text(b)}")
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

    def _standard_ends(self, lower: float, upper: float) -> tuple[float, float]:
        """The bounds (lower, upper) as standard scores of a normal or log-normal prior."""
        if self.kind is PriorKind.NORMAL:
            return (lower - self.a) / self.b, (upper - self.a) / self.b
        lo = math.log(lower) if lower > 0 else -math.inf
        hi = math.log(upper) if math.isfinite(upper) and upper > 0 else math.inf
        return (lo - math.log(self.a)) / self.b, (hi - math.log(self.a)) / self.b

    def log_normaliser(self, lower: float, upper: float) -> float:
        """ln of the probability mass the untruncated prior puts inside (lower, upper), in the
        tail where that mass lies (`_log_normal_mass`): exact however far the bounds sit from the
        prior's centre (a difference of two cdfs near 1 gave 0, and ln p = −∞ everywhere, once a
        lower bound sat 8.3 sd above a normal prior's mean)."""
        if self.bounded:
            return 0.0
        return _log_normal_mass(*self._standard_ends(lower, upper))

    def cdf(self, x, lower: float, upper: float) -> np.ndarray:
        """The prior's cumulative probability at ``x`` within the parameter bounds (lower,
        upper): the coordinate in which this prior is uniform on [0, 1] (linear for uniform,
        log for log-uniform; the prior's mass for normal and log-normal)."""
        x = np.asarray(x, float)
        lo, hi = self.support(lower, upper)
        with np.errstate(divide="ignore", invalid="ignore"):
            if self.kind is PriorKind.UNIFORM:
                t = (x - lo) / (hi - lo)
            elif self.kind is PriorKind.LOGUNIFORM:
                t = np.log(x / lo) / math.log(hi / lo)
            else:
                u = x if self.kind is PriorKind.NORMAL else np.log(np.where(x > 0, x, np.nan))
                centre = self.a if self.kind is PriorKind.NORMAL else math.log(self.a)
                z_lo, z_hi = self._standard_ends(lo, hi)
                t = _truncated_normal_cdf((u - centre) / self.b, z_lo, z_hi)
        return np.clip(t, 0.0, 1.0)

    def median(self, lower: float, upper: float) -> float:
        """A central value of the prior (used only when a start must come from the prior)."""
        if self.kind is PriorKind.UNIFORM:
            lo, hi = self.support(lower, upper)
            return 0.5 * (lo + hi)
        if self.kind is PriorKind.LOGUNIFORM:
            lo, hi = self.support(lower, upper)
            return math.sqrt(lo * hi)
        return self.a


def _log_normal_mass(z_lo: float, z_hi: float) -> float:
    """ln(Φ(z_hi) − Φ(z_lo)) of the standard normal, computed in the tail the interval lies in
    (mirrored into the lower tail, ln Φ by `scipy.special.log_ndtr`): finite wherever the mass is
    a positive double's logarithm, tens of sd from the centre included."""
    from scipy.special import log_ndtr

    if z_lo > -z_hi:  # (the interval lies more in the upper tail: mirror it)
        z_lo, z_hi = -z_hi, -z_lo
    if not z_lo < z_hi:
        return -math.inf
    upper, lower = float(log_ndtr(z_hi)), float(log_ndtr(z_lo))
    return upper + math.log1p(-math.exp(lower - upper)) if lower < upper else -math.inf


def _truncated_normal_cdf(z, z_lo: float, z_hi: float) -> np.ndarray:
    """The cdf at standard scores ``z`` of a standard normal truncated to (z_lo, z_hi),
    (Φ(z) − Φ(z_lo))/(Φ(z_hi) − Φ(z_lo)), in ratios of ln Φ of the tail the interval lies in."""
    from scipy.special import log_ndtr

    z = np.asarray(z, float)
    mirrored = z_lo > -z_hi
    if mirrored:
        z, z_lo, z_hi = -z, -z_hi, -z_lo
    top = float(log_ndtr(z_hi))
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        low = math.exp(float(log_ndtr(z_lo)) - top)
        t = (np.exp(log_ndtr(np.clip(z, z_lo, z_hi)) - top) - low) / (1.0 - low)
    t = np.where(np.isnan(z), np.nan, t)
    return 1.0 - t if mirrored else t


def parse_prior(text: str) -> tuple[str, Prior]:
    """``"R1=loguniform:1e2,1e5"`` (the command line's ``--prior``) → ``("R1", Prior("loguniform",
    100.0, 100000.0))``."""
    name, sep, spec = text.partition("=")
    name = name.strip()
    if not sep or not name:
        raise ParameterError(f"--prior {text!r}: expected NAME=KIND:ARGS, e.g. R1=loguniform:1e2,1e5")
    return name, prior_of_text(spec, f"--prior {text!r}")


def prior_of_text(spec: str, label: str) -> Prior:
    """``"loguniform:1e2,1e5"`` → ``Prior("loguniform", 100.0, 100000.0)``; errors begin with
    ``label``, where the text was given (``--prior 'R1=...'``, ``priors['R1']='...'``)."""
    kind, sep, args = spec.partition(":")
    kind = kind.strip().lower().replace("-", "").replace("_", "")
    if kind not in PRIOR_KINDS:
        raise ParameterError(f"{label}: unknown prior kind {kind!r}; choose one of {', '.join(PRIOR_KINDS)}")
    parts = [p.strip() for p in args.split(",")] if sep else []
    if len(parts) != 2:
        raise ParameterError(f"{label}: {kind} takes two numbers ({PRIOR_KINDS[kind]})")
    try:
        a, b = float(parts[0]), float(parts[1])
    except ValueError:
        raise ParameterError(f"{label}: {args!r} are not two numbers") from None
    try:
        return Prior(kind, a, b)
    except ParameterError as exc:
        raise ParameterError(f"{label}: {exc}") from None


SIGMA_REL_PRIOR = Prior(PriorKind.LOGUNIFORM, 1e-5, 1.0)
DEFAULT_SPAN_DECADES = 3.0  # default log-uniform prior for unbounded parameters: LSQ value ×/÷ 10³


def coerce_priors(priors: Mapping[str, "Prior | str | tuple"] | None) -> dict[str, Prior]:
    """User priors by name as `Prior`: a `Prior`, a ``(kind, a, b)`` tuple or ``"kind:a,b"`` text."""
    out = {}
    for name, prior in (priors or {}).items():
        label = f"priors[{shown(name)}]={shown(prior)}"
        if isinstance(prior, str):
            prior = prior_of_text(prior, label)
        elif isinstance(prior, tuple) and len(prior) == 3:
            try:
                prior = Prior(*prior)
            except ParameterError as exc:
                raise ParameterError(f"{label}: {exc}") from None
        elif not isinstance(prior, Prior):
            raise ParameterError(f"prior for {shown(name)}: expected a Prior, a (kind, a, b) tuple or 'kind:a,b' text, got {shown(prior)}")
        out[name] = prior
    return out


UNDETERMINED_STDERRS = 2.0  # a parameter is undetermined when value − 2·stderr reaches its lower bound
STDERR_REACH = 10.0  # ... and, without a data scale, its default prior reaches value + 10·stderr


def data_scale_range(unit: str, freq, z_abs) -> tuple[float, float] | None:
    """The values of a parameter of ``unit`` at which its element alone would have the
    measured |Z| at one of the measured frequencies (``freq`` [Hz], ``z_abs`` [Ω]), widened
    ×/÷ 10^`DEFAULT_SPAN_DECADES`; None for a unit impedax has no such scaling for (a user
    element's, a physical parameter's)."""
    omega = 2 * np.pi * np.asarray(freq, float)
    z_abs = np.asarray(z_abs, float)
    keep = np.isfinite(omega) & (omega > 0) & np.isfinite(z_abs) & (z_abs > 0)
    if not keep.any():
        return None
    x = data_scales(unit, np.asarray(freq, float)[keep], z_abs[keep])  # (`parameters.data_scales`)
    if x is None:
        return None
    span = 10.0**DEFAULT_SPAN_DECADES
    return float(x.min() / span), float(x.max() * span)


def undetermined(lower: float, start: float, stderr: float | None, at_bound: bool) -> bool:
    """Whether a least-squares value ``start`` leaves a non-negative parameter undetermined: at
    its lower bound, with a non-finite ``stderr``, or with start − `UNDETERMINED_STDERRS`·stderr
    at or below the lower bound (its approximate 95 % interval reaches the bound). ``stderr``
    None: not known (e.g. a physical parameter), which alone says nothing."""
    if at_bound:
        return True
    return stderr is not None and (not math.isfinite(stderr) or start - UNDETERMINED_STDERRS * stderr <= lower)


def default_prior(lower: float, upper: float, start: float, *, stderr: float | None = None, at_bound: bool = False, scale: tuple[float, float] | None = None, own: tuple[float, float] | None = None) -> Prior:
    """The prior of a parameter the user gave none within its bounds (lower, upper).

    ``own``: the element's own bounds, where the user narrowed them to (lower, upper)
    (``bounds=``, ``--bound``): the prior is then the default prior within the element's own
    bounds cut to the user's (`_cut_to`) — the same kind over the common range, so a
    non-binding bound leaves the prior as it was (an open lower side of a resistor's bound,
    ``R1=:10M``, keeps its log-uniform data-scaled prior, not uniform:0,1e7) and an exponent's
    stays uniform (docs/bayesian.md, "Priors").

    Without ``own``: log-uniform within finite positive bounds,
    uniform within finite bounds, else ``start`` ×/÷ 10^`DEFAULT_SPAN_DECADES` (log-uniform for
    non-negative parameters, uniform around ``start`` otherwise); a non-negative ``start`` of 0
    (a fit at that bound) with a ``scale``: log-uniform over the ``scale``.

    A non-negative parameter the least-squares fit leaves `undetermined` gets a range that does
    not exclude what the data allow: up to the larger of start·10³ and the top of the data's
    scale ``scale`` (`data_scale_range`: beyond it the element is a short or an open circuit to
    these data, whatever its value); down to the smaller of start/10³ and the bottom of
    ``scale``, or to the bottom of ``scale`` alone when the fit stopped at the bound (its value
    there says nothing about the scale). Without a ``scale`` (a unit impedax has no scaling
    for) the range reaches start + `STDERR_REACH`·stderr instead."""
    if own is not None and (float(own[0]), float(own[1])) != (float(lower), float(upper)):
        unbounded = default_prior(own[0], own[1], start, stderr=stderr, at_bound=at_bound, scale=scale)
        return _cut_to(unbounded, lower, upper)
    if math.isfinite(upper) and lower > 0:
        return Prior(PriorKind.LOGUNIFORM, lower, upper)
    if math.isfinite(upper) and math.isfinite(lower):
        return Prior(PriorKind.UNIFORM, lower, upper)
    span = 10.0**DEFAULT_SPAN_DECADES
    if lower >= 0 and start > 0:
        lo, hi = start / span, start * span
        if undetermined(lower, start, stderr, at_bound):
            if scale is not None:
                hi = max(hi, scale[1])
                lo = scale[0] if at_bound else min(lo, scale[0])
            elif stderr is not None and math.isfinite(stderr) and stderr > 0:
                hi = max(hi, start + STDERR_REACH * stderr)
        if lower > 0:
            lo = max(lo, lower * (1 + 1e-12))
        return Prior(PriorKind.LOGUNIFORM, lo, hi)
    if lower >= 0 and start == 0 and scale is not None:
        # a fit at the bound 0 says nothing of the scale: the data's own (`data_scale_range`), as
        # for a fit at a positive bound; the uniform around 0 below put C_gap within 0–1000 F
        # (REAL exampleData.csv's EDL fit ended at C_gap = 0, walkthrough 2026-12-06)
        return Prior(PriorKind.LOGUNIFORM, max(scale[0], lower), scale[1])
    centre = start if math.isfinite(start) else 0.0
    half = span * max(abs(centre), 1.0)
    if stderr is not None and math.isfinite(stderr):
        half = max(half, STDERR_REACH * stderr)
    return Prior(PriorKind.UNIFORM, max(centre - half, lower), min(centre + half, upper))


def _cut_to(prior: Prior, lower: float, upper: float) -> Prior:
    """A uniform or log-uniform ``prior`` cut to the bounds (lower, upper): the same kind over
    [max(a, lower), min(b, upper)] (the prior the sampler's support gives it anyway, `Prior.support`,
    now also what the report and ``post.priors`` show). The ends of a log-uniform prior stay
    positive (a user's lower bound 0 leaves its lower end)."""
    a, b = max(prior.a, lower), min(prior.b, upper)
    if not a < b:  # (the start lies within both, so only a degenerate range gets here)
        return prior
    return Prior(prior.kind, a, b)


def check_prior_inside(name: str, prior: Prior, lower: float, upper: float, inclusive: bool) -> None:
    """Raise `ParameterError` when a uniform or log-uniform prior reaches outside the
    parameter's bounds (lower, upper) (upper included when ``inclusive``)."""
    if prior.bounded:
        too_high = prior.b > upper or (prior.b == upper and not inclusive and math.isfinite(upper))
        if prior.a < lower or too_high:
            right = "]" if inclusive else ")"
            raise ParameterError(f"prior for {name}: {prior.kind}:{number_text(prior.a)},{number_text(prior.b)} reaches outside the parameter's bounds ({number_text(lower)}, {number_text(upper)}{right}")


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
