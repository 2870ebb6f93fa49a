"""Vezzoli et al.: electrovibration force, ultrasonic squeeze film, and their coupling.

Electrovibration: the stratum corneum (thickness h_s, permittivity ε_s, resistivity ρ_s) in
series with the insulator (h_i, ε_i) under the applied voltage v(t) = V_m cos ωt. The skin acts as
a high-pass (eq 8) with τ = ε0 ε_s ρ_s, which the paper states is valid for C_i ≪ C_s, i.e.
C_i/C_s = ε_i h_s/(ε_s h_i) small (`insulator_capacitance_ratio`); the force functions warn
(`Eq8ValidityWarning`) above `EQ8_RATIO_LIMIT`. `electrovibration_force` (eq 10) is the
TIME-AVERAGED force, `electrovibration_force_peak` the largest force over a period (twice it),
`instantaneous_force` (eq 7) the force at one instant.

Squeeze film (eqs 2–6, Table 1, after Biet et al. 2007) in the σ → ∞ limit; its assumptions are
listed in `squeeze_film_lift`.
"""

from __future__ import annotations

import contextlib
import math
import warnings
from dataclasses import dataclass

import jax
import jax.numpy as jnp
import numpy as np
import xarray as xr

from ..arguments import checked_arguments, drive_amplitude, numeric_array, relative_permittivity, shown
from ..errors import ParameterError
from ..io.netcdf import result_dataset
from ..constants import EPSILON_0

__all__ = [
    "TABLE2",
    "TABLE1",
    "MEYER_CONDITIONS",
    "skin_time_constant",
    "effective_voltage",
    "instantaneous_force",
    "electrovibration_force",
    "electrovibration_force_peak",
    "voltage_for_force",
    "EQ8_RATIO_LIMIT",
    "Eq8ValidityWarning",
    "insulator_capacitance_ratio",
    "eq8_validity_message",
    "insulator_sweep",
    "voltage_sweep",
    "stratum_corneum_sweep",
    "friction_coupling",
    "SQUEEZE_NUMBER_MIN",
    "SqueezeNumberWarning",
    "SqueezeFilm",
    "squeeze_film_lift",
    "squeeze_number",
    "friction_reduction",
]

TABLE2 = {"h_i": 90e-6, "h_s": 350e-6, "area": 1e-4, "eps_i": 3.35, "eps_s": 2340.0, "rho_s": 3.0e4, "v_m": 2000.0, "frequency": 440.0}
"""Vezzoli Table 2 [SI]: plastic film 90 µm (ε_i 3.35), stratum corneum 350 µm (ε_s 2340,
ρ_s 3.0e4 Ω·m at 440 Hz), A = 1 cm², V_m = 2000 V, f = 440 Hz."""

MEYER_CONDITIONS = {"v_m": 140.0, "h_i": 1e-6, "eps_i": 3.4}
"""Fig 8 conditions taken from Meyer et al.: 140 V, 1 µm insulator with ε_i = 3.4 (other
parameters from Table 2)."""

TABLE1 = {"h_r": 1.8e-6, "h_e": 50e-6, "l_e": 350e-6, "f_r": 38220.0, "wavelength": 0.8e-2, "normal_force": (0.2, 0.4), "eta": 1.85e-5, "p0": 1e5}
"""Vezzoli Table 1 [SI]: plate roughness h_r, fingerprint amplitude h_e and period L_e, mode
frequency f_r and wavelength, finger force range, air viscosity η, atmospheric pressure p0."""


@checked_arguments(eps_s=relative_permittivity, rho_s=numeric_array(positive=True))
def skin_time_constant(eps_s=TABLE2["eps_s"], rho_s=TABLE2["rho_s"]):
    """τ = ε0 ε_s ρ_s [s] of the stratum corneum (eq 8). Its arguments, and those of
    `effective_voltage`, `instantaneous_force` and `insulator_capacitance_ratio`, are checked as
    `electrovibration_force`'s (unchecked, ``rho_s=-1`` would give τ < 0, ``area=-1e-4`` a
    negative force, ``h_i=-1e-6`` a ratio of −0.5, without a word)."""
    return EPSILON_0 * eps_s * rho_s


@checked_arguments(freq=numeric_array(positive=True), eps_s=relative_permittivity, rho_s=numeric_array(positive=True))
def effective_voltage(freq, *, eps_s=TABLE2["eps_s"], rho_s=TABLE2["rho_s"]):
    """Eq 8 transfer v_e/v = jωτ/(1 + jωτ) (complex; eq 9 is its time-domain form)."""
    jwt = 1j * 2.0 * jnp.pi * jnp.asarray(freq) * skin_time_constant(eps_s, rho_s)
    return jwt / (1.0 + jwt)


def _geometry(h_i, h_s, eps_i, eps_s):
    return (h_i + h_s) * (h_i / eps_i + h_s / eps_s)


@checked_arguments(v_e=numeric_array(), h_i=numeric_array(positive=True), h_s=numeric_array(positive=True), area=numeric_array(positive=True), eps_i=relative_permittivity, eps_s=relative_permittivity)
def instantaneous_force(v_e, *, h_i=TABLE2["h_i"], h_s=TABLE2["h_s"], area=TABLE2["area"], eps_i=TABLE2["eps_i"], eps_s=TABLE2["eps_s"]):
    """Eq 7: f_e(t) = ε0 A v_e(t)² / (2 (h_i + h_s)(h_i/ε_i + h_s/ε_s)) [N] for the voltage
    v_e(t) [V] across the stratum corneum at one instant."""
    return EPSILON_0 * area * jnp.asarray(v_e) ** 2 / (2.0 * _geometry(h_i, h_s, eps_i, eps_s))


EQ8_RATIO_LIMIT = 0.1
"""Largest C_i/C_s = ε_i h_s/(ε_s h_i) taken as "C_i ≪ C_s", the condition the paper states for
eq 8 (an order of magnitude below 1; the paper gives no number: impedax's choice, docs/physics.md,
"impedax's own choices and derived values"). Table 2 (90 µm film): 0.0056.
The paper's own Figs 8–10 use 1 µm insulators and lie above it: Fig 8 (ε_i = 3.4) 0.15–0.73 for
h_s = 100–500 µm, Fig 10 (ε_i 1–36, h_s = 350 µm) 0.15–5.4."""


class Eq8ValidityWarning(UserWarning):
    """The parameters leave the condition C_i ≪ C_s under which the paper states eq 8 (and so
    eqs 9 and 10) holds: C_i/C_s above `EQ8_RATIO_LIMIT`."""


@checked_arguments(h_i=numeric_array(positive=True), h_s=numeric_array(positive=True), eps_i=relative_permittivity, eps_s=relative_permittivity)
def insulator_capacitance_ratio(*, h_i=TABLE2["h_i"], h_s=TABLE2["h_s"], eps_i=TABLE2["eps_i"], eps_s=TABLE2["eps_s"]):
    """C_i/C_s = (ε0 ε_i A/h_i)/(ε0 ε_s A/h_s) = ε_i h_s/(ε_s h_i): insulator over stratum corneum
    capacitance (the area cancels). Eq 8 assumes it is ≪ 1. Broadcasts."""
    return eps_i * h_s / (eps_s * h_i)


def eq8_validity_message(*, h_i=TABLE2["h_i"], h_s=TABLE2["h_s"], eps_i=TABLE2["eps_i"], eps_s=TABLE2["eps_s"]) -> str | None:
    """The text of the `Eq8ValidityWarning` for these values (the largest ratio of an array),
    or None when C_i/C_s ≤ `EQ8_RATIO_LIMIT` everywhere or a value is a JAX tracer (under
    ``jit``/``vmap``/``grad`` the values are unknown, and nothing is said)."""
    if any(isinstance(v, jax.core.Tracer) for v in (h_i, h_s, eps_i, eps_s)):
        return None
    ratio = np.asarray(insulator_capacitance_ratio(h_i=np.asarray(h_i, float), h_s=np.asarray(h_s, float), eps_i=np.asarray(eps_i, float), eps_s=np.asarray(eps_s, float)))
    worst = float(np.max(ratio))
    if not worst > EQ8_RATIO_LIMIT:
        return None
    return (
        f"Vezzoli eq 8 assumes C_i ≪ C_s, but C_i/C_s = ε_i h_s/(ε_s h_i) = {worst:.3g}"
        + (" (the largest of the values given)" if ratio.size > 1 else "")
        + f", above {EQ8_RATIO_LIMIT:g}: the high-pass v_e/v = jωτ/(1 + jωτ) and the force of eq 10 are outside the paper's stated validity"
    )


def _warn_outside_eq8(h_i, h_s, eps_i, eps_s) -> None:
    message = eq8_validity_message(h_i=h_i, h_s=h_s, eps_i=eps_i, eps_s=eps_s)
    if message is not None:
        # (this function ← the force function ← its argument checks ← the caller)
        warnings.warn(message, Eq8ValidityWarning, stacklevel=4)


def _mean_force(freq, h_i, h_s, area, eps_i, eps_s, rho_s, v_m):
    wt = 2.0 * jnp.pi * jnp.asarray(freq) * skin_time_constant(eps_s, rho_s)
    return EPSILON_0 * area * v_m**2 / (4.0 * _geometry(h_i, h_s, eps_i, eps_s)) * wt**2 / (1.0 + wt**2)


@checked_arguments(freq=numeric_array(positive=True), h_i=numeric_array(positive=True), h_s=numeric_array(positive=True), area=numeric_array(positive=True), eps_i=relative_permittivity, eps_s=relative_permittivity, rho_s=numeric_array(positive=True), v_m=drive_amplitude)
def electrovibration_force(freq, *, h_i=TABLE2["h_i"], h_s=TABLE2["h_s"], area=TABLE2["area"], eps_i=TABLE2["eps_i"], eps_s=TABLE2["eps_s"], rho_s=TABLE2["rho_s"], v_m=TABLE2["v_m"]):
    """Eq 10, TIME-AVERAGED force [N] for v(t) = V_m cos ωt:
    F_e = ε0 A V_m² / (4 (h_i + h_s)(h_i/ε_i + h_s/ε_s)) · (ωτ)²/(1 + (ωτ)²), τ = ε0 ε_s ρ_s.
    Broadcasts over every argument (sweeps; vmap/grad safe). Table 2 → 0.0556 N at 440 Hz.
    Warns (`Eq8ValidityWarning`) when C_i/C_s > `EQ8_RATIO_LIMIT` (`eq8_validity_message`)."""
    _warn_outside_eq8(h_i, h_s, eps_i, eps_s)
    return _mean_force(freq, h_i, h_s, area, eps_i, eps_s, rho_s, v_m)


@checked_arguments(freq=numeric_array(positive=True), h_i=numeric_array(positive=True), h_s=numeric_array(positive=True), area=numeric_array(positive=True), eps_i=relative_permittivity, eps_s=relative_permittivity, rho_s=numeric_array(positive=True), v_m=drive_amplitude)
def electrovibration_force_peak(freq, *, h_i=TABLE2["h_i"], h_s=TABLE2["h_s"], area=TABLE2["area"], eps_i=TABLE2["eps_i"], eps_s=TABLE2["eps_s"], rho_s=TABLE2["rho_s"], v_m=TABLE2["v_m"]):
    """PEAK force [N]: the largest instantaneous force of eq 7 over a period, = 2 × eq 10.

    With eq 9, v_e(t) = V_e cos(ωt + φ), V_e = V_m ωτ/√(1 + (ωτ)²), φ = π/2 − arctan ωτ, eq 7
    gives f_e(t) = K V_e² cos²(ωt + φ) = (K V_e²/2)(1 + cos(2ωt + 2φ)), K = ε0 A/(2 (h_i + h_s)
    (h_i/ε_i + h_s/ε_s)): a DC part equal to eq 10's F_e and a 2ω part of the same amplitude (no
    ω part), between 0 and K V_e² = 2 F_e, reached at the crest of v_e. (At the crest of the
    applied v, t = 0, it is 2 F_e (ωτ)²/(1 + (ωτ)²).) Arguments and warning as
    `electrovibration_force`."""
    _warn_outside_eq8(h_i, h_s, eps_i, eps_s)
    return 2.0 * _mean_force(freq, h_i, h_s, area, eps_i, eps_s, rho_s, v_m)


def _force_target(value, name):
    """A time-averaged force to reach [N]: numbers ≥ 0 (eq 10 is a square, ≥ 0; a negative
    target has no voltage, and √ of it would be NaN without a word)."""
    value = numeric_array()(value, name)
    if not isinstance(value, jax.core.Tracer) and not (np.isrealobj(np.asarray(value)) and np.all(np.asarray(value) >= 0)):
        raise ParameterError(f"{name} must be ≥ 0 N (eq 10's time-averaged force is a square: no voltage gives a negative one), got {shown(value)}")
    return value


@checked_arguments(force=_force_target, freq=numeric_array(positive=True), h_i=numeric_array(positive=True), h_s=numeric_array(positive=True), area=numeric_array(positive=True), eps_i=relative_permittivity, eps_s=relative_permittivity, rho_s=numeric_array(positive=True))
def voltage_for_force(force, freq, *, h_i=TABLE2["h_i"], h_s=TABLE2["h_s"], area=TABLE2["area"], eps_i=TABLE2["eps_i"], eps_s=TABLE2["eps_s"], rho_s=TABLE2["rho_s"]):
    """Eq 10 solved for the amplitude [V] giving a time-averaged ``force`` [N] (Fig 10):
    V_m = √(4 F (h_i + h_s)(h_i/ε_i + h_s/ε_s)(1 + (ωτ)²) / (ε0 A (ωτ)²)). Warns as
    `electrovibration_force` (`Eq8ValidityWarning`)."""
    _warn_outside_eq8(h_i, h_s, eps_i, eps_s)
    wt = 2.0 * jnp.pi * jnp.asarray(freq) * skin_time_constant(eps_s, rho_s)
    return jnp.sqrt(4.0 * jnp.asarray(force) * _geometry(h_i, h_s, eps_i, eps_s) * (1.0 + wt**2) / (EPSILON_0 * area * wt**2))


@contextlib.contextmanager
def _warned_at_caller():
    """The `Eq8ValidityWarning` of the calls inside a sweep said once, pointing at the sweep's
    caller (the sweeps are `checked_arguments` functions: one frame more); other warnings passed on as they were."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        yield
    eq8 = [w for w in caught if issubclass(w.category, Eq8ValidityWarning)]
    if eq8:  # (this generator ← contextlib's __exit__ ← the sweep ← its argument checks ← its caller)
        warnings.warn(eq8[0].message, Eq8ValidityWarning, stacklevel=5)
    for w in caught:
        if not issubclass(w.category, Eq8ValidityWarning):
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)


@checked_arguments(h_i=numeric_array(positive=True), eps_i=numeric_array(positive=True))
def insulator_sweep(h_i, eps_i, *, freq=500.0, v_m=140.0, **params) -> xr.DataArray:
    """Fig 9: time-averaged force [N] over insulator thickness ``h_i`` [m] × permittivity
    ``eps_i`` (paper: ε_i 1–36, 500 Hz, 140 V; other parameters from Table 2 unless given)."""
    h_i, eps_i = np.atleast_1d(np.asarray(h_i, float)), np.atleast_1d(np.asarray(eps_i, float))
    with _warned_at_caller():
        force = electrovibration_force(freq, h_i=h_i[None, :], eps_i=eps_i[:, None], v_m=v_m, **params)
    return xr.DataArray(np.asarray(force), dims=("eps_i", "h_i"), coords={"eps_i": eps_i, "h_i": ("h_i", h_i, {"units": "m"})}, name="force", attrs={"units": "N", "convention": "time-average", "figure": "Vezzoli Fig 9", "frequency_hz": float(freq), "v_m": float(v_m)})


@checked_arguments(eps_i=numeric_array(positive=True))
def voltage_sweep(eps_i, *, force=0.01, h_i=1e-6, freq=500.0, **params) -> xr.DataArray:
    """Fig 10: voltage amplitude [V] needed for a time-averaged ``force`` (0.01 N) over
    ``eps_i`` with a 1 µm insulator at 500 Hz (other parameters from Table 2 unless given)."""
    eps_i = np.atleast_1d(np.asarray(eps_i, float))
    with _warned_at_caller():
        v = voltage_for_force(force, freq, h_i=h_i, eps_i=eps_i, **params)
    return xr.DataArray(np.asarray(v), dims=("eps_i",), coords={"eps_i": eps_i}, name="voltage", attrs={"units": "V", "figure": "Vezzoli Fig 10", "force_n": float(force), "h_i_m": float(h_i), "frequency_hz": float(freq)})


@checked_arguments(freq=numeric_array(positive=True), h_s=numeric_array(positive=True))
def stratum_corneum_sweep(freq, h_s, **params) -> xr.DataArray:
    """Fig 8: time-averaged force [N] over frequency × stratum corneum thickness ``h_s`` [m]
    under Meyer's conditions (`MEYER_CONDITIONS`: 140 V, 1 µm, ε_i 3.4; the rest Table 2)."""
    freq, h_s = np.atleast_1d(np.asarray(freq, float)), np.atleast_1d(np.asarray(h_s, float))
    kwargs = {**MEYER_CONDITIONS, **params}
    with _warned_at_caller():
        force = electrovibration_force(freq[None, :], h_s=h_s[:, None], **kwargs)
    return xr.DataArray(np.asarray(force), dims=("h_s", "frequency"), coords={"h_s": ("h_s", h_s, {"units": "m"}), "frequency": ("frequency", freq, {"units": "Hz"})}, name="force", attrs={"units": "N", "convention": "time-average", "figure": "Vezzoli Fig 8"})


@checked_arguments(mu=numeric_array(positive=True), delta_mu=numeric_array(), normal_force=numeric_array(), electrostatic_force=numeric_array())
def friction_coupling(mu, delta_mu, normal_force, electrostatic_force):
    """Eq 11: tangential force F_t = (µ − Δµ)(F_n + F_e) [N] — ultrasound lowers µ by Δµ,
    electrovibration adds F_e to the normal force F_n. Refused (`ParameterError`, naming the
    argument): µ ≤ 0, Δµ outside [0, µ] (ultrasound lowers friction at most to none: µ − Δµ < 0
    gives a tangential force against the motion's sense, F_t = −0.22 N for µ = 0.5,
    Δµ = 0.7), and F_n or F_e below 0 (eq 10's force is a square, attracting the finger)."""
    values = (mu, delta_mu, normal_force, electrostatic_force)
    if not any(isinstance(v, jax.core.Tracer) for v in values):
        mu_a, delta_a = np.asarray(mu, float), np.asarray(delta_mu, float)
        if np.any(delta_a < 0) or np.any(delta_a > mu_a):
            raise ParameterError(f"delta_mu is the friction coefficient's reduction Δµ, in [0, µ] (µ − Δµ ≥ 0: no friction at the most), got Δµ = {shown(delta_mu)} for µ = {shown(mu)}")
        for name, value in (("normal_force", normal_force), ("electrostatic_force", electrostatic_force)):
            if np.any(np.asarray(value, float) < 0):
                raise ParameterError(f"{name} [N] must be ≥ 0 (a finger pressing; eq 10's force attracts it), got {shown(value)}")
    return (mu - delta_mu) * (normal_force + electrostatic_force)


# --- squeeze film --------------------------------------------------------------------------


SQUEEZE_NUMBER_MIN = 10.0
"""The squeeze number σ above which the paper takes the σ → ∞ limit of eq 6 as justified ("if
σ > 10", citing Biet et al. 2007 and Winter et al. 2013)."""


class SqueezeNumberWarning(UserWarning):
    """σ (eq 5) at or below `SQUEEZE_NUMBER_MIN`: the film is compressible (it acts like a spring),
    and the σ → ∞ pressure of eq 6 that `squeeze_film_lift` uses overstates the lift."""


@dataclass(frozen=True)
class SqueezeFilm:
    """Squeeze-film lift at one vibration amplitude: lift ``force`` F_s [N], ``squeeze_number``
    σ (eq 5, the σ → ∞ limit needs σ ≳ 10), ``friction_reduction`` Δµ/µ in [0, 1]."""

    amplitude: float
    force: float
    squeeze_number: float
    friction_reduction: float
    normal_force: float

    def to_xarray(self) -> xr.Dataset:
        return result_dataset(xr.Dataset(
            {"force": ((), self.force, {"units": "N"}), "squeeze_number": self.squeeze_number, "friction_reduction": self.friction_reduction},
            attrs={"amplitude_m": self.amplitude, "normal_force_n": self.normal_force, "model": "Vezzoli eqs 2-6 (sigma -> inf)"},
        ))


def squeeze_number(amplitude, *, area=TABLE2["area"], length=None, freq=TABLE1["f_r"], h_r=TABLE1["h_r"], h_e=TABLE1["h_e"], eta=TABLE1["eta"], p0=TABLE1["p0"]):
    """Eq 5 with the characteristic area read as l0² (dimensionless σ needs an area there):
    σ = 12 η ω l0² / (p0 h0²), h0 = h_r + h_v + h_e, l0 = √A unless ``length`` is given.
    Refuses what `squeeze_film_lift` refuses (a `ParameterError` naming the argument): an
    amplitude below 0, a geometry or air value that is not positive (h_e ≥ 0)."""
    amplitudes = numeric_array()(amplitude, "amplitude")
    if not isinstance(amplitudes, jax.core.Tracer) and not (np.isrealobj(amplitudes) and np.all(np.asarray(amplitudes) >= 0)):  # (unchecked, -1e-6 m would give σ = 20.7, area=-1e-4 "math domain error")
        raise ParameterError(f"squeeze_number: amplitude is the vibration amplitude h_v and must be ≥ 0 m, got {shown(amplitude)}")
    _check_film_inputs(area=area, length=length, h_r=h_r, h_e=h_e, freq=freq, eta=eta, p0=p0, points=2, caller="squeeze_number")
    l0 = math.sqrt(area) if length is None else length
    h0 = h_r + np.asarray(amplitude, float) + h_e
    return 12.0 * eta * 2.0 * math.pi * freq * l0**2 / (p0 * h0**2)


def _require_scalars(**values) -> None:
    """Each of ``values`` a single real number (or None): `squeeze_film_lift` computes one lift."""
    for name, value in values.items():
        if value is None or (isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))):
            continue
        if np.ndim(value) == 0 and np.asarray(value).dtype.kind in "iuf":  # a 0-d array
            continue
        if np.ndim(value):
            raise ParameterError(
                f"squeeze_film_lift: {name} must be a single number, got an array of shape {np.shape(value)}; "
                "call it once per value, e.g. [squeeze_film_lift(a) for a in amplitudes]"
            )
        raise ParameterError(f"squeeze_film_lift: {name} must be a number, got {shown(value)} ({type(value).__name__})")


_FILM_UNITS = {"area": "m²", "length": "m", "h_r": "m", "h_e": "m", "l_e": "m", "freq": "Hz", "eta": "Pa·s", "p0": "Pa"}


def _check_film_inputs(*, points, caller: str = "squeeze_film_lift", **values) -> None:
    """`squeeze_film_lift`'s geometry and air: each finite and positive (``h_e`` ≥ 0: no
    fingerprints is a flat finger), ``length`` None or positive, ``points`` an integer ≥ 2. The
    plate's roughness h_r > 0 keeps the film open: at h_r = 0 a fingerprint ridge touches the plate
    at the bottom of the stroke and eq 6's pressure diverges. A `ParameterError` naming the
    argument and its unit (unchecked, ``area=0`` would say "lift must be finite", ``area<0`` raise
    "math domain error", ``l_e=0`` ZeroDivisionError, ``freq<0`` give σ < 0 without a word)."""
    for name, value in values.items():
        if value is None and name == "length":
            continue
        low_ok = value >= 0 if name == "h_e" else value > 0
        if not (math.isfinite(value) and low_ok):
            what = "≥ 0" if name == "h_e" else "positive"
            why = ": at h_r = 0 the film closes where a fingerprint ridge meets the plate and eq 6 diverges" if name == "h_r" else ""
            raise ParameterError(f"{caller}: {name} must be {what} [{_FILM_UNITS[name]}], got {value}{why}")
    if isinstance(points, (bool, np.bool_)) or not isinstance(points, (int, np.integer)) or points < 2:
        raise ParameterError(f"squeeze_film_lift: points must be an integer ≥ 2 (the trapezoid rule over the contact length), got {shown(points)}")


def squeeze_film_lift(amplitude, *, normal_force=0.2, area=TABLE2["area"], length=None, h_r=TABLE1["h_r"], h_e=TABLE1["h_e"], l_e=TABLE1["l_e"], freq=TABLE1["f_r"], eta=TABLE1["eta"], p0=TABLE1["p0"], points: int = 20001) -> SqueezeFilm:
    """Squeeze-film lift F_s [N] for vibration amplitude h_v = ``amplitude`` [m] (eqs 2–6).

    Film: h = h_r + h_v(1 + cos ωt) + h_e(1 + cos kx), k = 2π/L_e (eq 3). In the σ → ∞ limit the
    pressure is eq 6; eq 2 averages P − 1 over a period and over x ∈ [−l0/2, l0/2], times p0 A.
    The time average is exact: ⟨1/(a + ε cos ωt)⟩ = 1/√(a² − ε²); x is integrated by the
    trapezoid rule on ``points`` points. Assumptions (Table 1 omits A and l0; eq 1 as printed
    is inconsistent):

    * contact area A = 1 cm² (Table 2's apparent area) and contact length l0 = √A = 1 cm;
    * eq 5's "A" read as l0², so σ is dimensionless;
    * the friction law of eq 1 read as Δµ/µ = F_s/F_n (friction µ(F_n − F_s)), capped at 1:
      levitation when F_s ≥ F_n. The paper prints (µ − Δµ)/µ = F_s/F_n, cleanly, but that is
      inconsistent with its own words: read literally, the remaining friction µ − Δµ grows with
      the lift F_s and vanishes without it (F_s = 0), while Fig 7 shows the reduction Δµ/µ
      growing with amplitude to levitation. Coulomb friction on the load the film does not
      carry, µ (F_n − F_s), gives (µ − Δµ)/µ = 1 − F_s/F_n, i.e. Δµ/µ = F_s/F_n: the printed
      equation lacks its "1 −".

    The squeeze-film theory curves are those of Fig 7 (its caption: "the predicted friction
    reduction by the squeeze film effect"); the paper's text says "Figure 8", which is the
    electrovibration force (Fig 8's caption).

    With these, h_v ≈ 2 µm lifts ≈ 0.17 N, so just above 2 µm levitates a 0.2 N finger, as the
    paper says (σ = 18.4 there). Where σ ≤ `SQUEEZE_NUMBER_MIN` (10, the paper's bound for the
    σ → ∞ limit) the lift is still that limit's, with a `SqueezeNumberWarning`.

    One amplitude and one finger force per call (numbers, not arrays: a `SqueezeFilm` holds
    one lift); for a curve, ``[squeeze_film_lift(a) for a in amplitudes]``.
    """
    _require_scalars(amplitude=amplitude, normal_force=normal_force, area=area, length=length, h_r=h_r, h_e=h_e, l_e=l_e, freq=freq, eta=eta, p0=p0)
    if amplitude < 0 or not math.isfinite(amplitude):
        raise ParameterError(f"vibration amplitude must be ≥ 0 m, got {amplitude}")
    if not (normal_force > 0 and math.isfinite(normal_force)):
        raise ParameterError(f"normal force must be positive, got {normal_force}")
    _check_film_inputs(area=area, length=length, h_r=h_r, h_e=h_e, l_e=l_e, freq=freq, eta=eta, p0=p0, points=points)
    l0 = math.sqrt(area) if length is None else length
    h0 = h_r + amplitude + h_e
    delta, eps = h_e / h0, amplitude / h0
    k = 2.0 * math.pi / l_e
    x = np.linspace(-l0 / 2.0, l0 / 2.0, points)
    a = 1.0 + delta * np.cos(k * x)
    b = 1.0 + delta * math.cos(k * l0 / 2.0)
    mean_pressure = a * math.sqrt(b**2 + 1.5 * eps**2) / (b * np.sqrt(a**2 - eps**2))
    lift = p0 * area * np.trapezoid(mean_pressure - 1.0, x) / l0
    sigma = float(squeeze_number(amplitude, area=area, length=l0, freq=freq, h_r=h_r, h_e=h_e, eta=eta, p0=p0))
    if not sigma > SQUEEZE_NUMBER_MIN:
        warnings.warn(
            f"squeeze number σ = {sigma:.3g} (eq 5) is not above {SQUEEZE_NUMBER_MIN:g}, where the paper takes eq 6's σ → ∞ pressure as justified: "
            f"the film is compressible here and the lift of {lift:.3g} N is an overestimate (σ ∝ f l0²/h0²: a higher mode frequency, a longer contact or a thinner film raise it)",
            SqueezeNumberWarning, stacklevel=2,
        )
    return SqueezeFilm(float(amplitude), float(lift), sigma, float(friction_reduction(lift, normal_force)), float(normal_force))


@checked_arguments(lift=numeric_array(), normal_force=numeric_array(positive=True))
def friction_reduction(lift, normal_force):
    """Δµ/µ = F_s/F_n clipped to [0, 1] (our reading of eq 1, whose printed (µ − Δµ)/µ = F_s/F_n
    is inconsistent: see `squeeze_film_lift`; 1 means levitation) for the lift
    F_s [N] and the finger's normal force F_n [N] (positive: with no finger force the ratio is
    undefined, and a `ParameterError` is raised). Broadcasts."""
    return np.clip(np.asarray(lift, float) / np.asarray(normal_force, float), 0.0, 1.0)
