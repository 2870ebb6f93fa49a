"""Vezzoli et al.: electrovibration force, ultrasonic squeeze film, and their coupling.

Electrovibration: the stratum corneum (thickness h_s, permittivity ε_s, resistivity ρ_s) in
series with the insulator (h_i, ε_i) under the applied voltage v(t) = V_m cos ωt. The skin acts as
a high-pass (eq 8) with τ = ε0 ε_s ρ_s, valid for C_i ≪ C_s. `electrovibration_force` (eq 10) is
the TIME-AVERAGED force; `instantaneous_force` (eq 7) the force at one instant.

Squeeze film (eqs 2–6, Table 1, after Biet et al. 2007) in the σ → ∞ limit; its assumptions are
listed in `squeeze_film_lift`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import jax.numpy as jnp
import numpy as np
import xarray as xr

from ..arguments import checked_arguments, numeric_array
from ..errors import ParameterError
from ..constants import EPSILON_0

__all__ = [
    "TABLE2",
    "TABLE1",
    "MEYER_CONDITIONS",
    "skin_time_constant",
    "effective_voltage",
    "instantaneous_force",
    "electrovibration_force",
    "voltage_for_force",
    "insulator_sweep",
    "voltage_sweep",
    "stratum_corneum_sweep",
    "friction_coupling",
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


def skin_time_constant(eps_s=TABLE2["eps_s"], rho_s=TABLE2["rho_s"]):
    """τ = ε0 ε_s ρ_s [s] of the stratum corneum (eq 8)."""
    return EPSILON_0 * eps_s * rho_s


def effective_voltage(freq, *, eps_s=TABLE2["eps_s"], rho_s=TABLE2["rho_s"]):
    """Eq 8 transfer v_e/v = jωτ/(1 + jωτ) (complex; eq 9 is its time-domain form)."""
    jwt = 1j * 2.0 * jnp.pi * jnp.asarray(freq) * skin_time_constant(eps_s, rho_s)
    return jwt / (1.0 + jwt)


def _geometry(h_i, h_s, eps_i, eps_s):
    return (h_i + h_s) * (h_i / eps_i + h_s / eps_s)


def instantaneous_force(v_e, *, h_i=TABLE2["h_i"], h_s=TABLE2["h_s"], area=TABLE2["area"], eps_i=TABLE2["eps_i"], eps_s=TABLE2["eps_s"]):
    """Eq 7: f_e(t) = ε0 A v_e(t)² / (2 (h_i + h_s)(h_i/ε_i + h_s/ε_s)) [N] for the voltage
    v_e(t) [V] across the stratum corneum at one instant."""
    return EPSILON_0 * area * jnp.asarray(v_e) ** 2 / (2.0 * _geometry(h_i, h_s, eps_i, eps_s))


@checked_arguments(freq=numeric_array(positive=True), h_i=numeric_array(positive=True), h_s=numeric_array(positive=True), area=numeric_array(positive=True), eps_i=numeric_array(positive=True), eps_s=numeric_array(positive=True), rho_s=numeric_array(positive=True), v_m=numeric_array())
def electrovibration_force(freq, *, h_i=TABLE2["h_i"], h_s=TABLE2["h_s"], area=TABLE2["area"], eps_i=TABLE2["eps_i"], eps_s=TABLE2["eps_s"], rho_s=TABLE2["rho_s"], v_m=TABLE2["v_m"]):
    """Eq 10, TIME-AVERAGED force [N] for v(t) = V_m cos ωt:
    F_e = ε0 A V_m² / (4 (h_i + h_s)(h_i/ε_i + h_s/ε_s)) · (ωτ)²/(1 + (ωτ)²), τ = ε0 ε_s ρ_s.
    Broadcasts over every argument (sweeps; vmap/grad safe). Table 2 → 0.0556 N at 440 Hz."""
    wt = 2.0 * jnp.pi * jnp.asarray(freq) * skin_time_constant(eps_s, rho_s)
    return EPSILON_0 * area * v_m**2 / (4.0 * _geometry(h_i, h_s, eps_i, eps_s)) * wt**2 / (1.0 + wt**2)


@checked_arguments(force=numeric_array(), freq=numeric_array(positive=True), h_i=numeric_array(positive=True), h_s=numeric_array(positive=True), area=numeric_array(positive=True), eps_i=numeric_array(positive=True), eps_s=numeric_array(positive=True), rho_s=numeric_array(positive=True))
def voltage_for_force(force, freq, *, h_i=TABLE2["h_i"], h_s=TABLE2["h_s"], area=TABLE2["area"], eps_i=TABLE2["eps_i"], eps_s=TABLE2["eps_s"], rho_s=TABLE2["rho_s"]):
    """Eq 10 solved for the amplitude [V] giving a time-averaged ``force`` [N] (Fig 10):
    V_m = √(4 F (h_i + h_s)(h_i/ε_i + h_s/ε_s)(1 + (ωτ)²) / (ε0 A (ωτ)²))."""
    wt = 2.0 * jnp.pi * jnp.asarray(freq) * skin_time_constant(eps_s, rho_s)
    return jnp.sqrt(4.0 * jnp.asarray(force) * _geometry(h_i, h_s, eps_i, eps_s) * (1.0 + wt**2) / (EPSILON_0 * area * wt**2))


def insulator_sweep(h_i, eps_i, *, freq=500.0, v_m=140.0, **params) -> xr.DataArray:
    """Fig 9: time-averaged force [N] over insulator thickness ``h_i`` [m] × permittivity
    ``eps_i`` (paper: ε_i 1–36, 500 Hz, 140 V; other parameters from Table 2 unless given)."""
    h_i, eps_i = np.atleast_1d(np.asarray(h_i, float)), np.atleast_1d(np.asarray(eps_i, float))
    force = electrovibration_force(freq, h_i=h_i[None, :], eps_i=eps_i[:, None], v_m=v_m, **params)
    return xr.DataArray(np.asarray(force), dims=("eps_i", "h_i"), coords={"eps_i": eps_i, "h_i": ("h_i", h_i, {"units": "m"})}, name="force", attrs={"units": "N", "convention": "time-average", "figure": "Vezzoli Fig 9", "frequency_hz": float(freq), "v_m": float(v_m)})


def voltage_sweep(eps_i, *, force=0.01, h_i=1e-6, freq=500.0, **params) -> xr.DataArray:
    """Fig 10: voltage amplitude [V] needed for a time-averaged ``force`` (0.01 N) over
    ``eps_i`` with a 1 µm insulator at 500 Hz (other parameters from Table 2 unless given)."""
    eps_i = np.atleast_1d(np.asarray(eps_i, float))
    v = voltage_for_force(force, freq, h_i=h_i, eps_i=eps_i, **params)
    return xr.DataArray(np.asarray(v), dims=("eps_i",), coords={"eps_i": eps_i}, name="voltage", attrs={"units": "V", "figure": "Vezzoli Fig 10", "force_n": float(force), "h_i_m": float(h_i), "frequency_hz": float(freq)})


def stratum_corneum_sweep(freq, h_s, **params) -> xr.DataArray:
    """Fig 8: time-averaged force [N] over frequency × stratum corneum thickness ``h_s`` [m]
    under Meyer's conditions (`MEYER_CONDITIONS`: 140 V, 1 µm, ε_i 3.4; the rest Table 2)."""
    freq, h_s = np.atleast_1d(np.asarray(freq, float)), np.atleast_1d(np.asarray(h_s, float))
    kwargs = {**MEYER_CONDITIONS, **params}
    force = electrovibration_force(freq[None, :], h_s=h_s[:, None], **kwargs)
    return xr.DataArray(np.asarray(force), dims=("h_s", "frequency"), coords={"h_s": ("h_s", h_s, {"units": "m"}), "frequency": ("frequency", freq, {"units": "Hz"})}, name="force", attrs={"units": "N", "convention": "time-average", "figure": "Vezzoli Fig 8"})


def friction_coupling(mu, delta_mu, normal_force, electrostatic_force):
    """Eq 11: tangential force F_t = (µ − Δµ)(F_n + F_e) [N] — ultrasound lowers µ by Δµ,
    electrovibration adds F_e to the normal force F_n."""
    return (mu - delta_mu) * (normal_force + electrostatic_force)


# --- squeeze film --------------------------------------------------------------------------


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
        return xr.Dataset(
            {"force": ((), self.force, {"units": "N"}), "squeeze_number": self.squeeze_number, "friction_reduction": self.friction_reduction},
            attrs={"amplitude_m": self.amplitude, "normal_force_n": self.normal_force, "model": "Vezzoli eqs 2-6 (sigma -> inf)"},
        )


def squeeze_number(amplitude, *, area=TABLE2["area"], length=None, freq=TABLE1["f_r"], h_r=TABLE1["h_r"], h_e=TABLE1["h_e"], eta=TABLE1["eta"], p0=TABLE1["p0"]):
    """Eq 5 with the characteristic area read as l0² (dimensionless σ needs an area there):
    σ = 12 η ω l0² / (p0 h0²), h0 = h_r + h_v + h_e, l0 = √A unless ``length`` is given."""
    l0 = math.sqrt(area) if length is None else length
    h0 = h_r + np.asarray(amplitude, float) + h_e
    return 12.0 * eta * 2.0 * math.pi * freq * l0**2 / (p0 * h0**2)


def squeeze_film_lift(amplitude, *, normal_force=0.2, area=TABLE2["area"], length=None, h_r=TABLE1["h_r"], h_e=TABLE1["h_e"], l_e=TABLE1["l_e"], freq=TABLE1["f_r"], eta=TABLE1["eta"], p0=TABLE1["p0"], points: int = 20001) -> SqueezeFilm:
    """Squeeze-film lift F_s [N] for vibration amplitude h_v = ``amplitude`` [m] (eqs 2–6).

    Film: h = h_r + h_v(1 + cos ωt) + h_e(1 + cos kx), k = 2π/L_e (eq 3). In the σ → ∞ limit the
    pressure is eq 6; eq 2 averages P − 1 over a period and over x ∈ [−l0/2, l0/2], times p0 A.
    The time average is exact: ⟨1/(a + ε cos ωt)⟩ = 1/√(a² − ε²); x is integrated by the
    trapezoid rule on ``points`` points. Assumptions (Table 1 omits them; eq 1 is garbled in
    the paper's text):

    * contact area A = 1 cm² (Table 2's apparent area) and contact length l0 = √A = 1 cm;
    * eq 5's "A" read as l0², so σ is dimensionless;
    * the friction law of eq 1 read as Δµ/µ = F_s/F_n (friction µ(F_n − F_s)), capped at 1:
      levitation when F_s ≥ F_n.

    With these, h_v ≈ 2 µm lifts ≈ 0.17 N, so just above 2 µm levitates a 0.2 N finger, as the
    paper says.
    """
    if amplitude < 0 or not math.isfinite(amplitude):
        raise ParameterError(f"vibration amplitude must be ≥ 0 m, got {amplitude}")
    if normal_force <= 0:
        raise ParameterError(f"normal force must be positive, got {normal_force}")
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
    return SqueezeFilm(float(amplitude), float(lift), sigma, float(friction_reduction(lift, normal_force)), float(normal_force))


def friction_reduction(lift, normal_force):
    """Δµ/µ = F_s/F_n clipped to [0, 1] (our reading of eq 1; 1 means levitation)."""
    return np.clip(np.asarray(lift, float) / normal_force, 0.0, 1.0)
