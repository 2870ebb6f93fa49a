"""Sirin et al.: air-gap thickness and electrostatic force from impedance spectra.

Measured separately: the finger skin Z_skin, the touchscreen Z_TS and the total Z_total of a
finger sliding on the screen. In series (paper Fig 3d), the remaining impedance of the
contact is Z_R = Z_total − Z_skin − Z_TS (eq 5), modeled as the EDL parallel model
R_EP ∥ C_EP ∥ C_gap (or R_EP ∥ CPE_EP ∥ C_gap): electrode polarization in parallel with the
air-gap capacitance.

A single contact (an electroadhesive gripper pad on its target: the measured impedance is the
contact's, R_EP ∥ CPE_EP ∥ C_gap) has no skin and no touchscreen to subtract: pass None for both
and the remainder is the total itself (`remaining_impedance`, `trial_remainders`,
`paper_gap_estimate`); the gap voltage and force take z_skin = z_ts = 0 (`gap_voltage`).

Force conventions: eq 1, F = ½ ε0 A ΔV_gap²/u², is evaluated at the voltage amplitude, so
`gap_force_peak` is the PEAK force over a drive period; `gap_force_time_average` is its
time average (½ of the peak for a sinusoid).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Mapping, Sequence

import jax
import jax.numpy as jnp
import numpy as np
import xarray as xr

from ..circuits import Circuit, compile_circuit, parse, voltage_across
from ..data import label_value, make_spectrum, validate_spectrum
from ..arguments import checked_arguments, drive_amplitude, numeric_array, relative_permittivity, require_parameters, shown, variants_named
from ..errors import DataError, ParameterError
from ..io.netcdf import result_dataset
from ..fitting.least_squares.result import SIGMA_FROM_NONE, SIGMA_FROM_OWN, SIGMA_FROM_TRIALS, SIGMA_SOURCES_ATTR
from ..io.table import SWEEP_RTOL
from ..constants import EPSILON_0, EPSILON_AIR

__all__ = [
    "SIRIN_AREA",
    "SIRIN_DRIVE_V",
    "SIRIN_C_GAP",
    "SIRIN_CUTOFF_HZ",
    "SINGLE_CONTACT_QUANTITY",
    "trial_mean",
    "remaining_impedance",
    "sigma_words",
    "trial_remainders",
    "admittance_spectrum",
    "gap_capacitance_paper",
    "gap_thickness",
    "PaperGapEstimate",
    "paper_gap_estimate",
    "EP_AUTO",
    "remainder_circuit",
    "remainder_impedance",
    "gap_voltage",
    "gap_force_peak",
    "gap_force_time_average",
    "magnitude_ratio",
    "phase_synchronization",
    "impedance_contributions",
    "force_from_friction_coefficients",
]

SIRIN_AREA = 130e-6
"""Apparent contact area A_app [m²] of the participant's index finger (paper §2.3)."""
SIRIN_DRIVE_V = 75.0
"""Drive amplitude V0 [V] (paper §2.4)."""
SIRIN_C_GAP = 413e-12
"""Reported air-gap capacitance [F] (paper §2.3)."""
SIRIN_CUTOFF_HZ = 30.0
"""The frequency [Hz] above which the paper reads C_gap = |Y_R|/ω (§2.3: the remainder's
conductance "almost vanishes" there): the default ``cutoff_hz``."""

_REMAINDERS = {
    "C": "R_EP || C_EP || C_gap",
    "CPE": "R_EP || CPE_EP || C_gap",
    None: "C_gap",
}


# --- remaining impedance -------------------------------------------------------------------


def _spectrum(ds, name: str) -> xr.Dataset:
    if not isinstance(ds, xr.Dataset):
        raise DataError(f"{name}: expected a spectrum Dataset with complex 'Z', got {type(ds).__name__}")
    return validate_spectrum(ds, source=str(ds.attrs.get("source", name)))


def trial_mean(ds: xr.Dataset, *, over: Sequence[str] | None = None) -> xr.Dataset:
    """Mean complex Z per frequency over the replicate dims ``over`` (default: every dim of Z
    but ``frequency``) with the standard error of the mean of Re and Im separately
    (``sigma_real``, ``sigma_imag`` = sample sd/√n, ddof 1); attrs ``n_trials`` and
    ``sigma_from``: "trial scatter" (n ≥ 2), "own sigma" (one spectrum that carries a ``sigma``,
    the sd of its Re and of its Im, taken as its error) or "none" (one spectrum without one:
    ``sigma_real`` = ``sigma_imag`` = 0)."""
    ds = _spectrum(ds, "spectrum")
    z = ds["Z"]
    dims = tuple(d for d in z.dims if d != "frequency") if over is None else tuple(over)
    missing = [d for d in dims if d not in z.dims or d == "frequency"]
    if missing:
        raise DataError(f"cannot average over {', '.join(missing)}: Z has dims {', '.join(z.dims)}")
    n = int(np.prod([z.sizes[d] for d in dims])) if dims else 1
    mean = z.mean(dims) if dims else z
    if n >= 2:
        sem_re = z.real.std(dims, ddof=1) / np.sqrt(n)
        sem_im = z.imag.std(dims, ddof=1) / np.sqrt(n)
        sigma_from = SIGMA_FROM_TRIALS
    elif "sigma" in ds:  # (one spectrum: its own σ, one sd for Re and Im, is its error)
        own = ds["sigma"].broadcast_like(z.real)
        sem_re = sem_im = own.mean(dims) if dims else own
        sigma_from = SIGMA_FROM_OWN
    else:
        sem_re = sem_im = xr.zeros_like(mean.real)
        sigma_from = SIGMA_FROM_NONE
    out = xr.Dataset({"Z": mean, "sigma_real": sem_re, "sigma_imag": sem_im})
    out.attrs = {"n_trials": n, "averaged_over": list(dims), "source": ds.attrs.get("source", "spectrum"), "sigma_from": sigma_from}
    return out


def _on_total_grid(total: xr.Dataset, part: xr.Dataset, name: str) -> xr.Dataset:
    """``part`` sorted by frequency and given the (sorted) total's frequencies, when the two
    grids agree within `SWEEP_RTOL` (the tolerance the readers merge sweeps with, and that of
    `impedax gap`'s checks: a descending sweep, or frequencies an instrument exported to a few
    digits, are the same grid); else a `DataError` naming ``name`` and the first point that
    differs."""
    part = part.sortby("frequency")
    ref = np.asarray(total["frequency"].values, float)
    own = np.asarray(part["frequency"].values, float)
    n = min(own.size, ref.size)
    bad = np.flatnonzero(np.abs(own[:n] / ref[:n] - 1.0) > SWEEP_RTOL)
    if own.size == ref.size and not bad.size:
        return part.assign_coords(frequency=total["frequency"])
    where = (f"first differing at point {bad[0] + 1}: {own[bad[0]]:.6g} Hz where the total has {ref[bad[0]]:.6g} Hz" if bad.size
             else f"the first {n} frequencies agree, then {'it goes' if own.size > ref.size else 'the total goes'} on")
    raise DataError(
        f"{name}: its frequencies differ from the total spectrum's ({name}: {own.size} points, {own[0]:.6g}–{own[-1]:.6g} Hz; "
        f"total: {ref.size} points, {ref[0]:.6g}–{ref[-1]:.6g} Hz; {where}); measure all three on one frequency grid "
        f"(within {SWEEP_RTOL:g} relative, the tolerance within which sweeps of one file merge)"
    )


SINGLE_CONTACT_QUANTITY = "impedance of a single contact Z_R = Z_total (no skin or touchscreen subtracted)"
"""The ``quantity`` attr of a remainder with nothing subtracted (skin and touchscreen None)."""


def _present_parts(total, skin, touchscreen) -> dict[str, xr.Dataset]:
    """The inputs given, checked as spectra, by name: skin and touchscreen both None are a
    single contact, nothing to subtract; exactly one None is a `ParameterError` (the chain has
    both in series; `gap_inputs.is_single_contact` says it for the gap analysis). Each is sorted
    by frequency, skin and screen on the total's frequencies (`_on_total_grid`)."""
    if (skin is None) != (touchscreen is None):
        raise ParameterError("give both skin and touchscreen spectra, or neither (None, None: a single contact, nothing subtracted)")
    given = {"total": total, "skin": skin, "touchscreen": touchscreen}
    parts = {name: _spectrum(ds, name) for name, ds in given.items() if ds is not None or name == "total"}
    parts["total"] = parts["total"].sortby("frequency")
    return {name: ds if name == "total" else _on_total_grid(parts["total"], ds, name) for name, ds in parts.items()}


def remaining_impedance(total: xr.Dataset, skin: xr.Dataset | None, touchscreen: xr.Dataset | None, *, over: Sequence[str] | None = None) -> xr.Dataset:
    """Remaining impedance Z_R = Z_total − Z_skin − Z_TS (Sirin eq 5), complex, from the
    trial means, with its standard error.

    Each input is a spectrum Dataset with replicate dims (e.g. ``session``, ``trial``;
    ``over`` names them, default all but ``frequency``). The three are independent
    measurements, so the SEMs of Re and Im add in quadrature:
    σ_Re(Z_R)² = Σ_k SEM_Re,k², likewise Im. Returns a spectrum Dataset with the mean ``Z``,
    ``sigma_real``, ``sigma_imag`` and ``sigma`` = √((σ_Re² + σ_Im²)/2) (one sd for Re and Im,
    as the data model's ``sigma``). An input of a single spectrum adds its own ``sigma`` (the
    sd of its Re and Im; a file's sigma column) in place of a SEM; no ``sigma`` when such an
    input carries none (its error is unknown) or the trials do not scatter (a zero standard
    error cannot weight a fit): attrs ``sigma_method`` then names the input and why.

    Dims of the total not in ``over`` (conditions: ``material``, ``voltage``) are kept: eq 5
    per condition, every variable over (*conditions, frequency) and attrs ``condition_dims``.
    Skin and screen are averaged over all their dims but those conditions; one they share with
    the total pairs label by label (the same labels, else a DataError), one they lack is
    subtracted from every condition alike. ``skin`` and ``touchscreen`` None: a single contact,
    nothing subtracted; Z_R is the total's trial mean with its SEM (attrs ``single_contact`` 1,
    no ``n_trials_skin``, ``n_trials_touchscreen``).
    """
    parts = _present_parts(total, skin, touchscreen)
    subtracted = [name for name in parts if name != "total"]
    freq = parts["total"]["frequency"].values
    means = {"total": trial_mean(parts["total"], over=over)}
    kept = tuple(d for d in means["total"]["Z"].dims if d != "frequency")
    for name in subtracted:
        shared = [d for d in kept if d in parts[name]["Z"].dims]
        _same_conditions(parts["total"], parts[name], shared, name)
        means[name] = trial_mean(parts[name], over=[d for d in parts[name]["Z"].dims if d != "frequency" and d not in shared])
    sizes = {**{d: means["total"].sizes[d] for d in kept}, "frequency": freq.size}

    def spread(mean: xr.Dataset, name: str) -> np.ndarray:  # (*kept, frequency)
        return _over_conditions(mean[name], sizes)

    z_r = spread(means["total"], "Z") - sum((spread(means[name], "Z") for name in subtracted), 0.0)
    var_re = sum(spread(m, "sigma_real") ** 2 for m in means.values())
    var_im = sum(spread(m, "sigma_imag") ** 2 for m in means.values())
    counts = {name: m.attrs["n_trials"] for name, m in means.items()}
    sigma = np.sqrt((var_re + var_im) / 2.0)
    method, have_sigma = _sigma_method({name: m.attrs["sigma_from"] for name, m in means.items()}, sigma)
    sigma = sigma if have_sigma else None
    single = not subtracted
    # (a mean over trials only when some input holds several: one sweep is no "trial means")
    averaged = ", trial means" if any(n > 1 for n in counts.values()) else ", one spectrum" if single else ", one spectrum each"
    attrs = {
        "quantity": (SINGLE_CONTACT_QUANTITY if single else "remaining impedance Z_R = Z_total - Z_skin - Z_TS (Sirin et al. eq 5)") + averaged,
        "sigma_method": method,
        **{f"n_trials_{name}": n for name, n in counts.items()},
    }
    if have_sigma:  # (what sigma is made of, as data: sigma_method's words for a reader)
        attrs[SIGMA_SOURCES_ATTR] = {name: str(m.attrs["sigma_from"]) for name, m in means.items()}
    if single:
        attrs["single_contact"] = 1
    if kept:
        attrs["condition_dims"] = ", ".join(kept)
    coords = {d: parts["total"][d].values for d in kept if d in parts["total"].coords}
    ds = make_spectrum(freq, z_r, sigma=sigma, dims=kept, coords=coords, attrs=attrs, source="remaining_impedance")
    if have_sigma:
        ds["sigma_real"] = ((*kept, "frequency"), np.sqrt(var_re), {"units": "ohm", "long_name": "standard error of Re Z_R"})
        ds["sigma_imag"] = ((*kept, "frequency"), np.sqrt(var_im), {"units": "ohm", "long_name": "standard error of Im Z_R"})
    return ds


def _sigma_method(sources: Mapping[str, str], sigma: np.ndarray) -> tuple[str, bool]:
    """How `remaining_impedance`'s sigma is made from each input's error (``sources``: its
    `trial_mean` ``sigma_from``), and whether it has one: the SEM of an input's trials, the own
    sigma of an input of one spectrum, added in quadrature; else why not, naming the inputs (a
    single spectrum without sigma, trials that do not scatter)."""
    unknown = [name for name, source in sources.items() if source == SIGMA_FROM_NONE]
    if unknown:
        return (f"not available: {joined_names(unknown)} {'is one spectrum' if len(unknown) == 1 else 'are one spectrum each'} without a sigma of "
                f"{'its' if len(unknown) == 1 else 'their'} own, so {'its' if len(unknown) == 1 else 'their'} error is unknown; a sigma column or variable "
                "gives it, or trials as an extra dimension their standard error", False)
    if not np.all(sigma > 0):
        return "not available: the trials do not scatter at some frequency (a zero standard error cannot weight a fit)", False
    return sigma_words(sources) + "; sigma = sqrt((sigma_real^2 + sigma_imag^2)/2)", True


def sigma_words(sources: Mapping[str, str]) -> str:
    """What a remainder's sigma is made of, in words, from its ``sigma_sources`` (input →
    `SIGMA_FROM_TRIALS` or `SIGMA_FROM_OWN`, as `remaining_impedance` records them): "SEM of Re
    and Im of each measurement over its trials, added in quadrature", or naming the inputs that
    gave their own stated sigma ("SEM of Re and Im over the trials of total; the stated sigma of
    skin and touchscreen (one spectrum each), added in quadrature"). The start of
    ``sigma_method``; `impedax remaining`'s line takes it from the sources, not from those words."""
    sem = [name for name, source in sources.items() if source == SIGMA_FROM_TRIALS]
    own = [name for name, source in sources.items() if source == SIGMA_FROM_OWN]
    if len(sources) == 1:
        return "SEM of Re and Im over the trials" if sem else "the stated sigma of the one spectrum"
    if not own:
        return "SEM of Re and Im of each measurement over its trials, added in quadrature"
    parts = ([f"SEM of Re and Im over the trials of {joined_names(sem)}"] if sem else []) + [f"the stated sigma of {joined_names(own)} (one spectrum{'' if len(own) == 1 else ' each'})"]
    return "; ".join(parts) + ", added in quadrature"


def joined_names(names: Sequence[str]) -> str:
    """``names`` as a sentence lists them: "total, skin and touchscreen"."""
    return names[0] if len(names) == 1 else f"{', '.join(names[:-1])} and {names[-1]}"


def _same_conditions(total: xr.Dataset, part: xr.Dataset, dims: Sequence[str], name: str) -> None:
    """A condition dim that ``part`` shares with the total has its size and labels (where both
    have labels): eq 5 subtracts the skin or screen of the same condition."""
    for d in dims:
        labelled = d in total.coords and d in part.coords
        if part.sizes[d] != total.sizes[d] or (labelled and not np.array_equal(np.asarray(part[d].values), np.asarray(total[d].values))):
            mine, theirs = (_labels_text(ds, d) for ds in (part, total))
            raise DataError(f"{name}: its {d} ({mine}) differs from the total's ({theirs}); a condition kept (not in `over`) pairs the spectra of one label")


SHOWN_LABELS = 6  # labels of a dim a message lists before "…"


def _labels_text(ds: xr.Dataset, dim: str) -> str:
    """``dim``'s labels as a message shows them (``[50, 100, 150]``), or its size."""
    if dim not in ds.coords:
        return f"{ds.sizes[dim]} positions"
    labels = [repr(label_value(v)) for v in ds[dim].values]
    return "[" + ", ".join(labels[:SHOWN_LABELS] + (["…"] if len(labels) > SHOWN_LABELS else [])) + "]"


def _over_conditions(values: xr.DataArray, sizes: Mapping[str, int]) -> np.ndarray:
    """``values`` as an array over the dims ``sizes`` (in order), repeated along those it lacks
    (a skin or screen mean measured once for every condition)."""
    return values.variable.set_dims(dict(sizes)).transpose(*sizes).values


def trial_remainders(total: xr.Dataset, skin: xr.Dataset | None, touchscreen: xr.Dataset | None) -> xr.Dataset:
    """Remaining impedance of every total trial: Z_R,t = Z_total,t − mean Z_skin − mean Z_TS
    (Sirin eq 5 per trial; skin and screen are separate measurements, so only their means pair
    with a total trial). A spectrum Dataset with the total's dims; the skin and screen trial
    scatter enters each trial's Z_R as noise (the hierarchical model's ν_k estimates it), and
    the error of the two subtracted means is one error shared by every trial, smooth in
    frequency: ``common_error_modes`` (common_mode, frequency) holds it as Σ_j ξ_j d_j with
    ξ_j ~ N(0, 1), d_t = (Z_t − mean)/√(n(n − 1)) for each skin and screen trial (so Σ d dᴴ is
    the covariance of the mean). Each total trial's own skin and screen deviate from the means
    by a whole smooth spectrum: ``trial_error_modes`` (trial_mode, frequency) holds that error
    as Σ_j ζ_tj m_j, m_j = (Z_j − mean)/√(n − 1), ζ_tj ~ N(0, 1) independent between trials.
    The hierarchical model marginalises the leading components of both (docs/bayesian.md,
    "Errors shared by every trial"). ``skin`` and ``touchscreen`` None: a single contact, each
    total trial as measured, without error modes."""
    parts = _present_parts(total, skin, touchscreen)
    freq = parts["total"]["frequency"].values
    means = {}
    for name in parts:
        if name != "total":
            means[name] = trial_mean(parts[name])
    z = parts["total"]["Z"] - sum((m["Z"].values for m in means.values()), 0.0)
    dims = tuple(d for d in z.dims if d != "frequency")
    if not dims:
        raise DataError("total: a single spectrum; per-trial remainders need trials as an extra dimension")
    z = z.transpose(*dims, "frequency")
    coords = {d: z[d].values for d in dims if d in z.coords}
    quantity = SINGLE_CONTACT_QUANTITY + ", each total trial" if not means else "remaining impedance of each total trial, Z_total,t - mean Z_skin - mean Z_TS (Sirin eq 5 per trial)"
    out = make_spectrum(freq, z.values, dims=dims, coords=coords, attrs={"quantity": quantity, **({"single_contact": 1} if not means else {})}, source="trial_remainders")
    modes, own = [], []
    for name in means:
        z_part = parts[name]["Z"].transpose(..., "frequency").values.reshape(-1, freq.size)
        n = z_part.shape[0]
        if n >= 2:  # Σ_t m_t m_tᴴ with m_t = (Z_t − mean)/√(n−1) is the sample covariance
            dev = (z_part - z_part.mean(axis=0)) / np.sqrt(n - 1.0)
            own.append(dev)
            modes.append(dev / np.sqrt(n))  # ... and divided by n, the covariance of the mean
    if modes:
        out["common_error_modes"] = (("common_mode", "frequency"), np.concatenate(modes), {"units": "ohm", "long_name": "error shared by every trial = sum_j xi_j * mode_j, xi_j ~ N(0, 1): the subtracted skin and screen means' deviations"})
        out["trial_error_modes"] = (("trial_mode", "frequency"), np.concatenate(own), {"units": "ohm", "long_name": "each trial's own error = sum_j zeta_tj * mode_j, zeta_tj ~ N(0, 1) independent between trials: its own skin and screen deviating from their means"})
    return out


def _complex_and_freq(z, freq=None):
    if isinstance(z, xr.Dataset):
        z = _spectrum(z, "remaining impedance")
        conditions = [d for d in str(z.attrs.get("condition_dims", "")).split(", ") if d in z["Z"].dims]
        if conditions:
            labelled = all(d in z.coords for d in conditions)
            example = ", ".join(f"{d}={shown(label_value(z[d].values[0])) if labelled else 0}" for d in conditions)
            raise DataError(f"the remaining impedance has the condition dims {', '.join(conditions)} (remaining_impedance kept them): take one condition at a time, e.g. z_r.{'sel' if labelled else 'isel'}({example})")
        if any(d != "frequency" for d in z["Z"].dims):
            z = trial_mean(z)
        return np.asarray(z["Z"].values), np.asarray(z["frequency"].values, dtype=np.float64)
    if freq is None:
        raise DataError("pass the frequencies [Hz] with a bare impedance array")
    return np.asarray(z, dtype=np.complex128), np.asarray(freq, dtype=np.float64)


def admittance_spectrum(z_r, freq=None) -> xr.Dataset:
    """Admittance Y = 1/Z, capacitance C(ω) = Im(Y)/ω and |Y|/ω [F] of a spectrum (a Dataset,
    trial-averaged if it has replicate dims, or a complex array with ``freq``) — Sirin Fig 4a/b."""
    z, f = _complex_and_freq(z_r, freq)
    omega = 2.0 * np.pi * f
    y = 1.0 / z
    return xr.Dataset(
        {
            "Y": ("frequency", y, {"units": "S", "long_name": "admittance 1/Z"}),
            "capacitance": ("frequency", y.imag / omega, {"units": "F", "long_name": "Im(Y)/omega"}),
            "abs_capacitance": ("frequency", np.abs(y) / omega, {"units": "F", "long_name": "|Y|/omega (Sirin's C_R above 30 Hz)"}),
        },
        coords={"frequency": ("frequency", f, {"units": "Hz"})},
    )


def gap_capacitance_paper(z_r, freq=None, *, cutoff_hz: float = SIRIN_CUTOFF_HZ, fmax_hz: float | None = None) -> float:
    """C_gap by Sirin's method (§2.3): the arithmetic mean, over the measured frequencies with
    ``cutoff_hz`` ≤ f (≤ ``fmax_hz`` if given), of |Y_R(f)|/ω = 1/(2πf |Z_R(f)|), where Z_R is
    the trial-mean remaining impedance. Equal weight per measured point (log-spaced grids weight
    every decade alike). Returns farads."""
    z, f = _complex_and_freq(z_r, freq)
    keep = f >= cutoff_hz
    if fmax_hz is not None:
        keep &= f <= fmax_hz
    if not np.any(keep):
        where = f"from the cutoff {cutoff_hz:g} Hz to fmax_hz {fmax_hz:g} Hz" if fmax_hz is not None else f"at or above the cutoff {cutoff_hz:g} Hz"
        raise DataError(
            f"no measured frequency {where}: the paper's C_gap is the mean of |Y_R|/ω above its cutoff (Sirin §2.3: "
            f"above ≈ 30 Hz the remainder is the gap's capacitance), and the data span {f.min():.6g}–{f.max():.6g} Hz"
            + ("; a lower cutoff_hz reads C_gap where electrode polarization may still add to it" if f.max() < cutoff_hz else "")
        )
    return float(np.mean(1.0 / (2.0 * np.pi * f[keep] * np.abs(z[keep]))))


@checked_arguments(c_gap=numeric_array(positive=True), area=numeric_array(positive=True), eps_gap=relative_permittivity)
def gap_thickness(c_gap, *, area: float = SIRIN_AREA, eps_gap: float = EPSILON_AIR):
    """Average air-gap thickness u = ε0 ε_gap A / C_gap [m] (Sirin §2.3); works on floats,
    numpy and JAX arrays (e.g. posterior draws of C_gap)."""
    return EPSILON_0 * eps_gap * area / c_gap


@dataclass(frozen=True)
class PaperGapEstimate:
    """Sirin's gap estimate: C_gap and u from the trial means, and the bounds from the lowest-
    and highest-impedance trials (§2.3). SI units (F, m)."""

    c_gap: float
    gap: float
    c_gap_low_impedance: float
    c_gap_high_impedance: float
    gap_lower: float
    gap_upper: float
    cutoff_hz: float
    area: float
    eps_gap: float
    # the smallest and largest u of single total trials (each minus the mean skin and screen),
    # NaN with one total spectrum: the trials' own spread the bounds can be set against
    gap_trial_min: float = float("nan")
    gap_trial_max: float = float("nan")

    def to_xarray(self) -> xr.Dataset:
        return result_dataset(xr.Dataset(
            {
                "c_gap": ((), self.c_gap, {"units": "F"}),
                "gap": ((), self.gap, {"units": "m"}),
                "c_gap_low_impedance": ((), self.c_gap_low_impedance, {"units": "F"}),
                "c_gap_high_impedance": ((), self.c_gap_high_impedance, {"units": "F"}),
                "gap_lower": ((), self.gap_lower, {"units": "m"}),
                "gap_upper": ((), self.gap_upper, {"units": "m"}),
                "gap_trial_min": ((), self.gap_trial_min, {"units": "m"}),
                "gap_trial_max": ((), self.gap_trial_max, {"units": "m"}),
            },
            attrs={"method": "Sirin et al. 2.3: mean |Y_R|/omega above the cutoff; bounds from extreme-impedance trials", "cutoff_hz": self.cutoff_hz, "area_m2": self.area, "eps_gap": self.eps_gap},
        ))


def _trial_rows(ds: xr.Dataset) -> np.ndarray:
    """Every spectrum of ``ds`` as a row (trials, frequency) of complex Z."""
    z = ds["Z"]
    dims = tuple(d for d in z.dims if d != "frequency")
    return z.transpose(*dims, "frequency").values.reshape(-1, z.sizes["frequency"])


def _extreme_trial(ds: xr.Dataset, keep: np.ndarray, pick: str) -> np.ndarray:
    """The trial of ``ds`` with the lowest or highest impedance (``pick``), ranked by the mean
    of log|Z| over the frequencies ``keep``."""
    flat = _trial_rows(ds)
    score = np.mean(np.log(np.abs(flat[:, keep])), axis=1)
    return flat[np.argmin(score) if pick == "lowest" else np.argmax(score)]


def paper_gap_estimate(total: xr.Dataset, skin: xr.Dataset | None, touchscreen: xr.Dataset | None, *, area: float = SIRIN_AREA, cutoff_hz: float = SIRIN_CUTOFF_HZ, fmax_hz: float | None = None, eps_gap: float = EPSILON_AIR) -> PaperGapEstimate:
    """Sirin §2.3 end to end: Z_R from the trial means (eq 5), C_gap = mean |Y_R|/ω above the
    cutoff (`gap_capacitance_paper`), u = ε0 ε_gap A/C_gap; and the paper's bounds "from the
    lowest and highest impedances measured for skin, touchscreen and the total": for each of the
    three measurements take the trial with the lowest (highest) impedance — ranked by the mean of
    log|Z| over the frequencies used — subtract, and convert as above. The bounds are the
    smaller and larger of the two resulting thicknesses (``gap_lower`` ≤ ``gap_upper``; the
    lowest-impedance set need not give the smaller u). They are no interval for u: the lowest
    skin and screen are subtracted from the lowest total, so the extremes offset each other and
    the two values can lie close together, even both on one side of u (docs/models.md, "The
    paper's bounds"). ``gap_trial_min``/``gap_trial_max``: u of each total trial minus the mean
    skin and screen (as `trial_remainders`), the trials' own spread, NaN with one total.
    ``skin`` and ``touchscreen`` None: a single contact, the total's trials as they are."""
    parts = _present_parts(total, skin, touchscreen)  # (sorted, on the total's grid: the extreme trials pair point by point)
    total, skin, touchscreen = parts["total"], parts.get("skin"), parts.get("touchscreen")
    z_r = remaining_impedance(total, skin, touchscreen)
    freq = z_r["frequency"].values
    c_gap = gap_capacitance_paper(z_r, cutoff_hz=cutoff_hz, fmax_hz=fmax_hz)
    keep = freq >= cutoff_hz
    if fmax_hz is not None:
        keep &= freq <= fmax_hz
    c_extreme = {}
    subtracted = [ds for ds in (skin, touchscreen) if ds is not None]
    for pick in ("lowest", "highest"):
        z = _extreme_trial(total, keep, pick) - sum((_extreme_trial(ds, keep, pick) for ds in subtracted), 0.0)
        c_extreme[pick] = gap_capacitance_paper(z, freq, cutoff_hz=cutoff_hz, fmax_hz=fmax_hz)
    gaps = sorted(float(gap_thickness(c, area=area, eps_gap=eps_gap)) for c in c_extreme.values())
    totals = _trial_rows(total)
    trial_min = trial_max = float("nan")
    if totals.shape[0] >= 2:
        others = sum((_trial_rows(ds).mean(axis=0) for ds in subtracted), 0.0)
        trial_gaps = [float(gap_thickness(gap_capacitance_paper(z - others, freq, cutoff_hz=cutoff_hz, fmax_hz=fmax_hz), area=area, eps_gap=eps_gap)) for z in totals]
        trial_min, trial_max = min(trial_gaps), max(trial_gaps)
    return PaperGapEstimate(
        c_gap, float(gap_thickness(c_gap, area=area, eps_gap=eps_gap)), c_extreme["lowest"], c_extreme["highest"], gaps[0], gaps[1], float(cutoff_hz), float(area), float(eps_gap),
        trial_min, trial_max,
    )


# --- gap voltage and force (pure JAX) ------------------------------------------------------


EP_AUTO = "auto"
"""``ep`` of the gap functions read from the parameter names: ``C_EP`` → ``"C"``,
``CPE_EP.*`` → ``"CPE"`` (the default, so draws of either analysis fit without naming it),
no name of an EP branch (no ``R_EP``, ``C_EP``, ``CPE_EP.*``) → None (C_gap alone)."""
_EP_NAMES = {"C": "R_EP, C_EP, C_gap", "CPE": "R_EP, CPE_EP.Q, CPE_EP.alpha, C_gap"}


def _canonical_ep(ep, *, auto: bool = True):
    """``ep`` in its canonical spelling: ``"C"``, ``"CPE"`` (any case), ``None`` or ``"none"``
    (C_gap alone) and, where the parameters are at hand, ``"auto"``."""
    if ep is None:
        return None
    if isinstance(ep, str):
        folded = ep.casefold()
        for option in ("C", "CPE"):
            if folded == option.casefold():
                return option
        if folded == "none":
            return None
        if auto and folded == EP_AUTO:
            return EP_AUTO
    listed = "'C', 'CPE', None" + (" or 'auto'" if auto else "")
    raise ParameterError(f"unknown electrode-polarization branch {shown(ep)}; use {listed}")


def remainder_circuit(ep: str | None = "CPE") -> Circuit:
    """The remainder model: ``"CPE"`` (default, as `gap_analysis` and ``impedax gap``) →
    R_EP || CPE_EP || C_gap, ``"C"`` → R_EP || C_EP || C_gap (Sirin Fig 2d), ``None`` (or
    ``"none"``) → C_gap alone (no electrode polarization). Case does not matter."""
    return parse(_REMAINDERS[_canonical_ep(ep, auto=False)])


@functools.lru_cache(maxsize=None)
def _compiled_remainder(text: str):
    return compile_circuit(text), voltage_across(text, "C_gap")


@functools.lru_cache(maxsize=None)
def _circuit_text(text: str) -> tuple[str, tuple[str, ...]]:
    circuit = parse(text)
    return str(circuit), tuple(circuit.parameter_names())


def _gap_thickness_hint(params) -> str:
    """What to say when ``params`` hold the gap thickness ``u`` but no C_gap."""
    if isinstance(params, Mapping) and "u" in params and "C_gap" not in params:
        return "; these hold u (draws of a posterior sampled in u, post.samples): pass post.circuit_samples(), which holds C_gap"
    return ""


def _infer_ep(params) -> str | None:
    """``"C"``, ``"CPE"`` or None (C_gap alone: no name of an EP branch) from the names in
    ``params`` (static dict keys: jittable)."""
    held = variants_named(params, {"C": "C_EP", "CPE": "CPE_EP."}, "ep")
    if any(held.values()):
        return "C" if held["C"] else "CPE"
    if isinstance(params, Mapping) and "R_EP" not in params and "C_gap" in params:
        return None  # {"C_gap": …}: the remainder without electrode polarization
    message = f"params lacks C_EP or CPE_EP.Q, CPE_EP.alpha; the model's parameters are {_EP_NAMES['CPE']} (ep='CPE') or {_EP_NAMES['C']} (ep='C')"
    raise ParameterError(message + (_gap_thickness_hint(params) or "; for C_gap alone pass ep=None"))


def _remainder(params, ep, remainder) -> str:
    """The remainder circuit's text for ``ep`` (``"auto"``: read from ``params``) or
    ``remainder``, once ``params`` hold its every parameter (else one ParameterError)."""
    if not isinstance(params, Mapping):
        require_parameters(params, ())
    if remainder is not None:
        text, names = _circuit_text(str(parse(remainder)))
    else:
        ep = _canonical_ep(ep)
        if ep == EP_AUTO:
            ep = _infer_ep(params)
        text, names = _circuit_text(_REMAINDERS[ep])
    missing = [n for n in names if n not in params]
    if missing:
        hint = _gap_thickness_hint(params) if "C_gap" in missing else ""
        raise ParameterError(f"params lacks {', '.join(missing)}; the model's parameters are {', '.join(names)}" + hint)
    require_parameters(params, names)
    return text


def _plain(rule):
    """``rule`` after an xarray DataArray is replaced by its values (``trial_mean(ds)["Z"]``)."""

    def check(value, name):
        if isinstance(value, xr.DataArray):
            value = value.values
        elif isinstance(value, xr.Dataset):
            raise ParameterError(f"{name} is a Dataset; pass its complex impedance, e.g. trial_mean(skin)['Z']")
        return rule(value, name)

    return check


def _keep_over_frequency(rule):
    """``rule`` for ``z_skin``/``z_ts``: an xarray DataArray over ``frequency`` is checked as its
    values and kept, for `_over_freq` to pair it with ``freq`` by frequency; else `_plain`'s."""
    plain = _plain(rule)

    def check(value, name):
        if isinstance(value, xr.DataArray) and "frequency" in value.dims:
            rule(value.values, name)
            return value
        return plain(value, name)

    return check


def _on_freq(value: xr.DataArray, freq, name: str):
    """The values of ``value`` (a DataArray over ``frequency``) at each frequency of ``freq``,
    matched within `SWEEP_RTOL` whatever their order (a descending sweep as read, `ix.load`), so
    that a skin or screen mean pairs with the frequencies it was measured at, not by position;
    a `ParameterError` when ``freq`` holds a frequency ``value`` lacks."""
    values = value.transpose(..., "frequency").values
    if isinstance(freq, jax.core.Tracer):  # (traced frequencies: no values to pair; by position as given)
        return values
    own = np.asarray(value["frequency"].values, float)
    target = np.asarray(freq, float)
    order = np.argsort(own)
    sorted_own = own[order]
    flat = target.reshape(-1)
    right = np.clip(np.searchsorted(sorted_own, flat), 0, own.size - 1)
    left = np.clip(right - 1, 0, own.size - 1)
    nearest = np.where(np.abs(sorted_own[left] - flat) <= np.abs(sorted_own[right] - flat), left, right)
    missing = np.flatnonzero(np.abs(sorted_own[nearest] / flat - 1.0) > SWEEP_RTOL)
    if missing.size:
        raise ParameterError(
            f"{name} is over frequencies that do not hold every frequency of freq ({name}: {own.size} points, {own.min():.6g}–{own.max():.6g} Hz; "
            f"freq: {flat.size} points, first missing {flat[missing[0]]:.6g} Hz): give {name} at the frequencies of freq "
            f"(e.g. the trial mean of a spectrum measured at them), or one value"
        )
    picked = values[..., order[nearest]]
    return picked.reshape(values.shape[:-1] + target.shape) if target.ndim else picked[..., 0]


def _over_freq(arguments) -> None:
    """``z_skin`` and ``z_ts`` give one value or one per frequency (a static shape check); a
    DataArray over ``frequency`` is first taken at the frequencies of ``freq`` (`_on_freq`)."""
    for name in ("z_skin", "z_ts"):
        if isinstance(arguments[name], xr.DataArray):
            arguments[name] = _on_freq(arguments[name], arguments["freq"], name)
    f_shape = np.shape(arguments["freq"])
    for name in ("z_skin", "z_ts"):
        shape = np.shape(arguments[name])
        try:
            np.broadcast_shapes(shape, f_shape)
        except ValueError:
            size = lambda s: f"{int(np.prod(s))} values" if len(s) <= 1 else f"shape {s}"  # noqa: E731
            raise ParameterError(f"{name} has {size(shape)}, freq has {size(f_shape)}: give {name} at every frequency of freq (or one value)") from None


_FREQ = _plain(numeric_array(positive=True))
_IMPEDANCE = _keep_over_frequency(numeric_array())


@checked_arguments(freq=_FREQ)
def remainder_impedance(params: Mapping[str, object], freq, *, ep: str | None = EP_AUTO, remainder: str | Circuit | None = None):
    """Z_R [Ω] of the remainder model (see `remainder_circuit`; ``ep="auto"``, the default,
    reads it from the parameter names: C_EP → ``"C"``, CPE_EP.* → ``"CPE"``; ``remainder``
    overrides it with any circuit holding a ``C_gap``). Pure JAX; extra entries in ``params``
    are ignored."""
    return _compiled_remainder(_remainder(params, ep, remainder))[0](params, freq)


@checked_arguments(_over_freq, freq=_FREQ, z_skin=_IMPEDANCE, z_ts=_IMPEDANCE, v0=drive_amplitude)
def gap_voltage(params: Mapping[str, object], freq, z_skin, z_ts, *, v0: float = SIRIN_DRIVE_V, ep: str | None = EP_AUTO, remainder: str | Circuit | None = None):
    """Complex amplitude [V] of the voltage across C_gap for a drive of amplitude ``v0`` (Sirin §2.4).

    The chain Z_TS + Z_R + Z_skin is driven by V0: I = V0/Z_total, V1 = V0 − Z_TS I,
    V2 = Z_skin I, ΔV = V1 − V2; the gap voltage is the voltage across the C_gap element of the
    solved remainder (with ``ep=None`` the remainder is C_gap alone: no charge leakage). The
    printed eq 2, ΔV_gap = ΔV − R_EP[I − (I_gap + I_EP)], is not used: for three elements in
    parallel I − I_gap − I_EP is the R_EP current, so it gives zero. ``z_skin``, ``z_ts``: complex
    arrays over ``freq`` (measured means or models; an xarray DataArray such as
    ``trial_mean(skin)["Z"]`` is taken as its values), one value or one per frequency; 0 and 0
    for a single contact with nothing in series (a gripper pad): I = V0/Z_R and ΔV = V0, so the
    voltage across C_gap, parallel to the EP branch, is the whole drive V0. ``ep``:
    ``"auto"`` (default) reads the remainder from the parameter names (C_EP → ``"C"``,
    CPE_EP.* → ``"CPE"``); ``"C"``, ``"CPE"`` (any case) or None name it. Pure JAX: vmap over
    posterior draws (the names and shapes are checked at trace time).
    """
    z_r, across_gap = _compiled_remainder(_remainder(params, ep, remainder))
    z_r = z_r(params, freq)
    current = v0 / (z_ts + z_r + z_skin)
    delta_v = (v0 - z_ts * current) - z_skin * current
    return delta_v * across_gap(params, freq)


@checked_arguments(_over_freq, freq=_FREQ, z_skin=_IMPEDANCE, z_ts=_IMPEDANCE, area=numeric_array(positive=True), v0=drive_amplitude, eps_gap=numeric_array(positive=True), gap=numeric_array(positive=True, optional=True))
def gap_force_peak(params: Mapping[str, object], freq, z_skin, z_ts, *, area: float = SIRIN_AREA, v0: float = SIRIN_DRIVE_V, ep: str | None = EP_AUTO, eps_gap: float = EPSILON_AIR, gap=None, remainder: str | Circuit | None = None):
    """PEAK electrostatic force [N] over a drive period, Sirin eq 1 at the voltage amplitude
    with the gap's permittivity: F = ½ ε0 ε_gap A |ΔV_gap|²/u² (= ½ C_gap |ΔV_gap|²/u, the
    parallel-plate force of the circuit's C_gap; eq 1 as printed, for air, leaves out ε_gap =
    1.00059, 0.06 %), with u = ε0 ε_gap A/C_gap from ``params["C_gap"]`` unless ``gap`` [m] is
    given. Arguments as `gap_voltage` (``ep="auto"``: the remainder from the parameter names).
    Pure JAX in ``params`` (vmap over draws)."""
    _remainder(params, ep, remainder)
    u = gap_thickness(params["C_gap"], area=area, eps_gap=eps_gap) if gap is None else gap
    v_gap = gap_voltage(params, freq, z_skin, z_ts, v0=v0, ep=ep, remainder=remainder)
    return 0.5 * EPSILON_0 * eps_gap * area * jnp.abs(v_gap) ** 2 / u**2


def gap_force_time_average(params: Mapping[str, object], freq, z_skin, z_ts, **kwargs):
    """TIME-AVERAGED electrostatic force [N] for a sinusoidal drive: ½ `gap_force_peak`
    (same arguments)."""
    return 0.5 * gap_force_peak(params, freq, z_skin, z_ts, **kwargs)


# --- contributions and friction ------------------------------------------------------------


def magnitude_ratio(z_i, z_total):
    """MR_i = |Z_i|/|Z_total| (Sirin eq 3, Fig 4c)."""
    return np.abs(_impedances(z_i, "z_i")) / np.abs(_impedances(z_total, "z_total"))


def _impedances(values, name: str) -> np.ndarray:
    """Impedances [Ω] as a NumPy array, else one `ParameterError` naming ``name`` (text: not NumPy's
    UFuncTypeError)."""
    array = np.asarray(values)
    if array.dtype == bool or not np.issubdtype(array.dtype, np.number):
        raise ParameterError(f"{name} must be impedances (complex numbers), got {shown(values)} (dtype {array.dtype})")
    return array


def phase_synchronization(z_i, z_total):
    """Percent phase synchronization PPS_i = [1 − |Φ_i − Φ_total|/|Φ_total|]·100 (Sirin eq 4,
    Fig 4d); phases Φ = arg Z. Eq 4 divides by |Φ_total|, so it is undefined where the total
    is purely resistive (Φ_total = 0): NaN there (no −inf, no warning), whatever Φ_i."""
    phi_i, phi_t = np.angle(_impedances(z_i, "z_i")), np.angle(_impedances(z_total, "z_total"))
    phi_i, phi_t = np.broadcast_arrays(phi_i, phi_t)
    scale = np.abs(phi_t)
    defined = scale > 0
    ratio = np.divide(np.abs(phi_i - phi_t), scale, out=np.full(scale.shape, np.nan), where=defined)
    out = (1.0 - ratio) * 100.0
    return out if out.ndim else out[()]


def impedance_contributions(total: xr.Dataset, skin: xr.Dataset, touchscreen: xr.Dataset) -> xr.Dataset:
    """MR and PPS of skin, touchscreen and remaining against the total (trial means), over
    ``component`` × ``frequency`` (Sirin Fig 4c, 4d)."""
    if skin is None or touchscreen is None:
        raise ParameterError("impedance_contributions compares skin, touchscreen and the remainder with the total (Sirin eqs 3, 4): give both skin and touchscreen spectra")
    parts = _present_parts(total, skin, touchscreen)  # (sorted, on the total's grid)
    total, skin, touchscreen = parts["total"], parts["skin"], parts["touchscreen"]
    z_r = remaining_impedance(total, skin, touchscreen)
    z_tot = trial_mean(total)["Z"].values
    comps = {"skin": trial_mean(skin)["Z"].values, "touchscreen": trial_mean(touchscreen)["Z"].values, "remaining": z_r["Z"].values}
    names = list(comps)
    return xr.Dataset(
        {
            "magnitude_ratio": (("component", "frequency"), np.stack([magnitude_ratio(comps[n], z_tot) for n in names])),
            "phase_synchronization": (("component", "frequency"), np.stack([phase_synchronization(comps[n], z_tot) for n in names]), {"units": "percent"}),
        },
        coords={"component": names, "frequency": ("frequency", z_r["frequency"].values, {"units": "Hz"})},
    )


def force_from_friction_coefficients(mu_off, mu_on, normal_force=1.0):
    """Sirin eq 6: F_e = (1 − µ_OFF/µ_ON) F_n [N] from the coefficients of friction without
    (µ_OFF) and with (µ_ON) voltage at normal force F_n (1 N in the paper)."""
    mu_off, mu_on = np.asarray(mu_off, dtype=np.float64), np.asarray(mu_on, dtype=np.float64)
    if not (np.all(mu_on > 0) and np.all(mu_off > 0)):
        raise ParameterError("friction coefficients must be positive")
    normal_force = np.asarray(normal_force, dtype=np.float64)
    if not np.all(np.isfinite(normal_force) & (normal_force > 0)):  # (F_n = -1 N would give a force of the opposite sign without a word)
        raise ParameterError(f"normal_force is the finger's normal force F_n [N] (1 N in the paper) and must be positive, got {shown(normal_force.tolist())}")
    return (1.0 - mu_off / mu_on) * normal_force
