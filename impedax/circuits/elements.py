"""The built-in elements: the one file to add an element.

Each element is one `ElementSpec` declaration in `DEFAULT_REGISTRY` below: symbol, name,
equation, parameters (unit, default, bounds, description, starting-guess role) and a pure JAX
impedance function ``impedance(omega, *params) -> complex``, plus its facts (DC path, drawing,
CDC letter, impedance.py symbol, program slots). A user's element needs no file here: build an
`ElementSpec` and ``DEFAULT_REGISTRY.register(spec)`` (docs/circuits.md, "Adding an element").
Formulas: docs/physics.md, section "Element formulas" (time dependence e^{jωt}). Each formula
imports ``jax.numpy`` when it is first evaluated, so that reading the registry (``impedax info``,
parsing, drawing) does not import JAX.
"""

from __future__ import annotations

import math

import numpy as np

from .spec import DCPath, ElementLimit, ElementSpec, ParameterSpec, Registry, StartRole

__all__ = ["DEFAULT_REGISTRY"]


# --- element formulas -----------------------------------------------------------------------
# Powers of jω are written in polar form, (jx)^a = x^a e^{jπa/2}, which is exact, never
# overflows for x>0 and keeps gradients finite.


def _j_power(x, a):
    """(j x)^a for real x > 0 and real a."""
    import jax.numpy as jnp

    return jnp.exp(a * jnp.log(x)) * jnp.exp(1j * (jnp.pi / 2) * a)


def _sqrt_j(y):
    """√(j y) for real y ≥ 0, as √(y/2)(1 + j): a real square root, where the complex one
    costs several times more (Wo and Ws evaluate it at every frequency of every solver step)."""
    import jax.numpy as jnp

    s = jnp.sqrt(0.5 * y)
    return s + 1j * s


def _coth_over_x(x):
    """coth(x)/x for complex x with Re x > 0, without overflow: with m = e^{-2x} − 1 (one
    complex expm1, accurate for small x; |m| ≤ 2), coth(x) = (2 + m)/(−m), so coth(x)/x =
    (2 + m)/(−m x). One transcendental evaluation, where e^{-2x} and expm1(−2x) apart cost
    twice as much, their derivatives included."""
    import jax.numpy as jnp

    m = jnp.expm1(-2.0 * x)
    return (2.0 + m) / (-m * x)


def _tanh_over_x(x):
    """tanh(x)/x for complex x with Re x > 0, without overflow: tanh(x) = −m/(2 + m) with
    m = e^{-2x} − 1 (see `_coth_over_x`)."""
    import jax.numpy as jnp

    m = jnp.expm1(-2.0 * x)
    return -m / ((2.0 + m) * x)


def _resistor(w, r):
    return r + 0j * w


def _resistor_admittance(w, r):
    return 1.0 / r + 0j * w


def _capacitor(w, c):
    return 1.0 / (1j * w * c)


def _capacitor_admittance(w, c):
    return 1j * w * c


def _inductor(w, l):  # noqa: E741 - L is the physics symbol
    return 1j * w * l


def _cpe(w, q, alpha):
    return 1.0 / (q * _j_power(w, alpha))


def _cpe_admittance(w, q, alpha):
    return q * _j_power(w, alpha)


def _warburg(w, sigma):
    import jax.numpy as jnp

    return sigma * (1.0 - 1j) / jnp.sqrt(w)


def _warburg_open(w, r, tau):
    return r * _coth_over_x(_sqrt_j(w * tau))


def _warburg_short(w, r, tau):
    return r * _tanh_over_x(_sqrt_j(w * tau))


def _gerischer(w, r, tau):
    import jax.numpy as jnp

    return r / jnp.sqrt(1.0 + 1j * w * tau)


def _cole_cole(w, r, tau, alpha):
    return r / (1.0 + _j_power(w * tau, alpha))


def _havriliak_negami(w, r, tau, alpha, beta):
    import jax.numpy as jnp

    base = 1.0 + _j_power(w * tau, alpha)
    return r * jnp.exp(-beta * jnp.log(base))


def _positive(suffix, unit, default, description, role):
    return ParameterSpec(suffix, unit, default, lower=0.0, upper=math.inf, description=description, role=role)


def _fraction(suffix, description, role=StartRole.EXPONENT):
    """An exponent in (0, 1], default 0.9."""
    return ParameterSpec(suffix, "1", 0.9, lower=0.0, upper=1.0, upper_inclusive=True, description=description, role=role)


def _resistance(description):
    """The resistance ``R`` of an element that makes its own arc (default 100 Ω)."""
    return _positive("R", "Ohm", 100.0, description, StartRole.ARC_RESISTANCE)


def _time_constant(default, description="time constant"):
    return _positive("tau", "s", default, description, StartRole.TIME_CONSTANT)


# --- limits: the simpler elements each one contains (`ElementLimit`) -------------------------
# Each returns the element's parameters that give the simpler one's impedance in the window
# ω_min..ω_max to ~1e-7 relative or better; params may be numpy arrays (one value per spectrum).

DEEP_DIFFUSION = 200.0
"""ω_min·τ of a finite Warburg standing for the semi-infinite one: Re √(jωτ) ≥ 10 over the
window, so coth and tanh differ from 1 by at most 2e^{-20} ≈ 4e-9."""
GERISCHER_DEEP = 1e7
"""ω_min·τ of a Gerischer standing for a Warburg: R/√(1 + jωτ) = R/√(jωτ)·(1 + 1/(jωτ))^{-1/2},
off by at most 1/(2ωτ) = 5e-8."""
FAST = 1e-7
"""ω_max·τ of an element whose time constant has vanished (a Ws, Gerischer or relaxation
standing for its resistance, a Wo for its capacitance): first-order terms ωτ/3 ≤ 3.3e-8."""


def _warburg_as_finite(params, omega_min, omega_max):
    """Wo or Ws as W (τ → ∞): Z → R/√(jωτ) = σ(1 − j)/√ω with R = σ√(2τ) (1/√j = (1 − j)/√2)."""
    (sigma,) = params
    tau = DEEP_DIFFUSION / omega_min
    return (sigma * np.sqrt(2.0 * tau), tau + 0.0 * sigma)


def _warburg_as_gerischer(params, omega_min, omega_max):
    """G as W (τ → ∞): Z → R/√(jωτ), R = σ√(2τ) as `_warburg_as_finite`."""
    (sigma,) = params
    tau = GERISCHER_DEEP / omega_min
    return (sigma * np.sqrt(2.0 * tau), tau + 0.0 * sigma)


def _finite_warburg_toward_infinite(params, omega_min, omega_max):
    """A Wo or Ws (R, τ) moved to its W limit with its Warburg coefficient σ = R/√(2τ) (its
    impedance R/√(jωτ) at ωτ ≫ 1) kept."""
    r, tau = params
    return _warburg_as_finite((r / np.sqrt(2.0 * tau),), omega_min, omega_max)


def _gerischer_toward_warburg(params, omega_min, omega_max):
    """A G (R, τ) moved to its W limit with σ = R/√(2τ) kept (R/√(1 + jωτ) → R/√(jωτ))."""
    r, tau = params
    return _warburg_as_gerischer((r / np.sqrt(2.0 * tau),), omega_min, omega_max)


WINDOW_EDGE = 3.0
"""ω_min·τ of a finite Warburg or Gerischer at the edge of its W limit: its knee just inside the
window, where a fit that sits at the limit finds an optimum of finite τ nearby (on 130 REAL
battery cycles the Ws model's batch fits stopped at the W limit on 16 cycles whose single fits
reach τ ≈ 45 s, ω_min·τ ≈ 6, 2026-12-02)."""


def _warburg_at_edge(params, omega_min, omega_max):
    """A Wo, Ws or G (R, τ) moved to τ = `WINDOW_EDGE`/ω_min with its Warburg coefficient
    σ = R/√(2τ) kept."""
    r, tau = params
    edge = WINDOW_EDGE / omega_min
    return (r / np.sqrt(2.0 * tau) * np.sqrt(2.0 * edge), edge + 0.0 * r)


def _capacitor_as_open_warburg(params, omega_min, omega_max):
    """Wo as C (τ → 0): coth(x)/x = 1/x² + 1/3 + O(x²), so Z → R/(jωτ) + R/3 = 1/(jωC) with
    R = τ/C (R/3 is ωτ/3 of |Z| at ω)."""
    (c,) = params
    tau = FAST / omega_max
    return (tau / c, tau + 0.0 * c)


def _resistor_as_fast(params, omega_min, omega_max):
    """Ws or G as R (τ → 0): R·f(jωτ) with f → 1. (Limits are module-level functions, not
    closures: a fit pickles with its registry, and an unpickled spec is the same spec.)"""
    (r,) = params
    return (r, FAST / omega_max + 0.0 * r)


def _resistor_as_cole_cole(params, omega_min, omega_max):
    """CC as R (τ → 0, α = 1)."""
    return (*_resistor_as_fast(params, omega_min, omega_max), 1.0 + 0.0 * params[0])


def _resistor_as_havriliak_negami(params, omega_min, omega_max):
    """HN as R (τ → 0, α = β = 1)."""
    return (*_resistor_as_cole_cole(params, omega_min, omega_max), 1.0 + 0.0 * params[0])


def _capacitor_as_cpe(params, omega_min, omega_max):
    """CPE as C (α = 1): Q = C."""
    (c,) = params
    return (c, 1.0 + 0.0 * c)


def _cole_cole_as_havriliak_negami(params, omega_min, omega_max):
    """HN as Cole–Cole (β = 1)."""
    r, tau, alpha = params
    return (r, tau, alpha, 1.0 + 0.0 * r)


_AS_WARBURG = ElementLimit("W", "tau -> inf", _warburg_as_finite, toward=_finite_warburg_toward_infinite, edge=_warburg_at_edge)
_AS_RESISTOR = ElementLimit("R", "tau -> 0", _resistor_as_fast)


# Boukamp's CDC letters: O is the finite-length Warburg with a transmissive boundary (tanh,
# impedax Ws) and T the one with a reflective boundary (coth, impedax Wo).
DEFAULT_REGISTRY = Registry(
    (
        ElementSpec(
            "R", "resistor", "Z = R",
            (_positive(None, "Ohm", 100.0, "resistance", StartRole.RESISTANCE),),
            _resistor, admittance=_resistor_admittance,
            dc=DCPath.CONDUCTS, draw="Resistor", cdc="R", impedance_py="R", program_capacity=6,
        ),
        ElementSpec(
            "C", "capacitor", "Z = 1/(jωC)",
            (_positive(None, "F", 1e-6, "capacitance", StartRole.CAPACITANCE),),
            _capacitor, admittance=_capacitor_admittance,
            dc=DCPath.BLOCKS, draw="Capacitor", cdc="C", impedance_py="C", program_capacity=4,
        ),
        ElementSpec(
            "L", "inductor", "Z = jωL",
            (_positive(None, "H", 1e-6, "inductance", StartRole.INDUCTANCE),),
            _inductor,
            dc=DCPath.SHORTS, draw="Inductor2", cdc="L", impedance_py="L",
        ),
        ElementSpec(
            "CPE", "constant phase element", "Z = 1/(Q (jω)^α)",
            (
                _positive("Q", "F s^(alpha-1)", 1e-6, "CPE coefficient", StartRole.CPE_Q),
                _fraction("alpha", "CPE exponent (1 = capacitor)", StartRole.CPE_EXPONENT),
            ),
            _cpe, aliases=("Q",), admittance=_cpe_admittance,
            dc=DCPath.BLOCKS, draw="CPE", cdc="Q", impedance_py="CPE", program_capacity=4,
            limits=(ElementLimit("C", "alpha = 1", _capacitor_as_cpe),),
        ),
        ElementSpec(
            "W", "semi-infinite Warburg", "Z = σ(1 − j)/√ω",
            (_positive("sigma", "Ohm s^-1/2", 100.0, "Warburg coefficient", StartRole.WARBURG),),
            _warburg,
            dc=DCPath.BLOCKS, cdc="W", impedance_py="W",
        ),
        ElementSpec(
            "Wo", "finite Warburg, open (reflective)", "Z = R coth(√(jωτ))/√(jωτ)",
            (_resistance("diffusion resistance"), _time_constant(1.0, "diffusion time constant")),
            _warburg_open,
            dc=DCPath.BLOCKS, cdc="T", impedance_py="Wo",
            limits=(_AS_WARBURG, ElementLimit("C", "tau -> 0 at tau/R = C", _capacitor_as_open_warburg)),
        ),
        ElementSpec(
            "Ws", "finite Warburg, short (transmissive)", "Z = R tanh(√(jωτ))/√(jωτ)",
            (_resistance("diffusion resistance"), _time_constant(1.0, "diffusion time constant")),
            _warburg_short,
            dc=DCPath.CONDUCTS, cdc="O", impedance_py="Ws",
            limits=(_AS_WARBURG, _AS_RESISTOR),
        ),
        ElementSpec(
            "G", "Gerischer", "Z = R/√(1 + jωτ)",
            (_resistance("Gerischer resistance"), _time_constant(1e-3)),
            _gerischer,
            dc=DCPath.CONDUCTS, cdc="G", impedance_py="G",
            limits=(ElementLimit("W", "tau -> inf", _warburg_as_gerischer, toward=_gerischer_toward_warburg, edge=_warburg_at_edge), _AS_RESISTOR),
        ),
        ElementSpec(
            "CC", "Cole–Cole relaxation", "Z = R/(1 + (jωτ)^α)",
            (_resistance("relaxation strength"), _time_constant(1e-3), _fraction("alpha", "broadening exponent")),
            _cole_cole,
            dc=DCPath.CONDUCTS, impedance_py="Zarc",
            limits=(ElementLimit("R", "tau -> 0", _resistor_as_cole_cole),),
        ),
        ElementSpec(
            "HN", "Havriliak–Negami relaxation", "Z = R/(1 + (jωτ)^α)^β",
            (
                _resistance("relaxation strength"), _time_constant(1e-3),
                _fraction("alpha", "symmetric broadening"), _fraction("beta", "asymmetric broadening"),
            ),
            _havriliak_negami,
            dc=DCPath.CONDUCTS,
            limits=(ElementLimit("CC", "beta = 1", _cole_cole_as_havriliak_negami), ElementLimit("R", "tau -> 0", _resistor_as_havriliak_negami)),
        ),
    )
)
