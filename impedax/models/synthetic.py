"""SYNTHETIC example measurements in the style of Sirin et al. (the default data of ``make demo``).

Nothing here is measured data. `generate_sirin_synthetic` draws spectra from closed-form
numpy formulas (written independently of impedax's circuit compiler) for the four measurement
groups of Sirin et al.: finger skin, touchscreen, and the total impedance of a finger sliding or
stationary on the screen. The shipped file ``impedax/data/sirin_synthetic.nc`` is its output for
the default seed; `load_example` reads it.

Model (true values in `SIRIN_SYNTHETIC_TRUTH`, also stored in the Dataset's attrs):

* skin:        800 Ω + 20 MΩ ∥ CPE(α = 0.90), phase maximum at 250 Hz;
* touchscreen: 90 Ω + 170 kΩ ∥ CPE(α = 0.92), phase maximum at 100 kHz (dispersion ≈ 10 kHz);
* remainder, sliding:    R_EP ∥ CPE_EP ∥ C_gap, C_gap = 413 pF; the EP branch (electrode
  polarization, R_EP = 100 MΩ, CPE_EP α = 0.30) carries more admittance than the gap below
  ≈ 10 Hz, its capacitance exceeds C_gap at 1 Hz, and it fades above ≈ 30 Hz. The CPE
  dominates R_EP above ≈ 2 Hz, so the data determine R_EP, CPE_EP and C_gap separately.
* remainder, stationary: sweat shorts the gap — R_EP 1000× smaller, the wet-gap capacitance
  20× C_gap — and hydrates the skin (skin R 10× smaller), giving ≈ 10× lower total impedance.
* total = skin + touchscreen + remainder (in series, Sirin eq 5), each total trial with its own
  skin and touchscreen draws (skin, screen and total are separate measurements).

Skin and screen are small against the gap capacitor up to ≈ 100 kHz (its impedance is 3.9 kΩ
there), so the remainder dominates the total up to ≈ 100 kHz as in the paper's Fig 4c. The
series resistance R_inf is what gives an R ∥ CPE a phase maximum (a bare R ∥ CPE tends
monotonically to −α·90°); the measured electrodes and tissue provide it.

Scatter: 3 sessions × 10 trials. Each parameter gets a session factor and a per-trial factor
(log-normal; skin R varies most, as electrodermal activity does). The contact of the sliding
finger varies from trial to trial as a whole: the gap thickness u is log-normal about 2.789 µm
(the population median; sd of ln u 1 % between sessions and 7 % between trials), R_EP (5 %,
15 %) and CPE_EP.Q (3 %, 8 %) likewise; each trial's true u, R_EP, CPE_EP.Q, α and C_gap are
stored in the ``trial_*`` variables, the spreads in ``attrs["trial_variation"]``. CPE exponents get small
additive jitter about each CPE's own characteristic frequency. Skin and screen keep their
session factors across the skin, screen and total measurements of a session (same finger and
screen on the same day); the trial factors are independent. Measurement noise is complex
Gaussian with relative standard deviation 0.4 % + 3 %·(1 Hz/f)^½, so it is larger at low
frequency. Fixed seed; deterministic.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import xarray as xr

from ..data import log_frequencies, make_spectrum
from ..constants import EPSILON_0
from ..errors import DataError

__all__ = [
    "SIRIN_SYNTHETIC_SEED",
    "SIRIN_SYNTHETIC_TRUTH",
    "generate_sirin_synthetic",
    "load_example",
    "example_spectra",
    "example_path",
    "r_cpe_series",
    "TWO_ARC_TRUTH",
    "TWO_ARC_SPREAD",
    "generate_two_arc_trials",
    "sirin_trial_remainders",
]

SIRIN_SYNTHETIC_SEED = 20230413
"""Seed of the shipped synthetic file."""

SIRIN_SYNTHETIC_TRUTH: dict[str, dict[str, float]] = {
    "skin": {"R_inf": 800.0, "R": 2.0e7, "Q": 1.049e-8, "alpha": 0.90},
    "touchscreen": {"R_inf": 90.0, "R": 1.7e5, "Q": 1.184e-9, "alpha": 0.92},
    "remainder_sliding": {"R_EP": 1.0e8, "CPE_EP.Q": 4.0e-9, "CPE_EP.alpha": 0.30, "C_gap": 413e-12},
    "remainder_stationary": {"R_EP": 1.0e5, "CPE_EP.Q": 2.0e-8, "CPE_EP.alpha": 0.30, "C_gap": 8.26e-9},
    "stationary_skin_r_factor": {"value": 0.1},
    "geometry": {"area_m2": 130e-6, "eps_gap": 1.00059},
}
"""True parameters [SI] of the synthetic example (Q in F·s^(α−1))."""

_SPREAD = {  # (session σ, trial σ) of log-normal factors, or additive σ for exponents
    "R_inf": (0.02, 0.03),
    "R_skin": (0.15, 0.25),
    "R_ts": (0.02, 0.06),
    "Q": (0.01, 0.04),
    "alpha": (0.002, 0.008),
    "R_EP": (0.05, 0.15),
    "Q_EP": (0.03, 0.08),
    "u": (0.01, 0.07),  # the contact varies with the normal force (1 ± 0.15 N) and finger placement
}
"""Log-normal spreads (sd of ln x between sessions, between trials of a session); exponents
(``alpha``) additive. The contact of the sliding finger (u, R_EP, CPE_EP.Q) varies most."""

_PIVOT_HZ = {"skin": 250.0, "touchscreen": 1e5, "EP": 10.0}  # where each CPE's α jitter pivots

_FILE = Path(__file__).resolve().parent.parent / "data" / "sirin_synthetic.nc"


def r_cpe_series(freq, r_inf, r, q, alpha):
    """Z = R_inf + R/(1 + R Q (jω)^α): an R ∥ CPE with a series resistance (numpy)."""
    jw = 1j * 2.0 * np.pi * np.asarray(freq, dtype=np.float64)
    return r_inf + r / (1.0 + r * q * jw**alpha)


def _remainder(freq, r_ep, q_ep, alpha_ep, c_gap):
    jw = 1j * 2.0 * np.pi * np.asarray(freq, dtype=np.float64)
    return 1.0 / (1.0 / r_ep + q_ep * jw**alpha_ep + jw * c_gap)


def generate_sirin_synthetic(seed: int = SIRIN_SYNTHETIC_SEED, *, sessions: int = 3, trials: int = 10, points: int = 61, fmin: float = 1.0, fmax: float = 1e6) -> xr.Dataset:
    """Generate the SYNTHETIC Sirin-style example (see the module docstring for the model).

    Returns one Dataset over ``frequency`` [Hz] (``points`` log-spaced, ``fmin``–``fmax``),
    ``session`` and ``trial`` with complex variables ``Z_total`` (extra dim ``contact`` =
    sliding, stationary), ``Z_skin`` and ``Z_touchscreen`` [Ω]; attrs hold the truth, the seed
    and the generator. `example_spectra` splits it into standard spectrum Datasets.
    """
    rng = np.random.default_rng(seed)
    freq = log_frequencies(fmin, fmax, points)
    shape = (sessions, trials)
    truth = SIRIN_SYNTHETIC_TRUTH

    def offsets(kind, day):
        # ``day``: session offsets shared by every measurement of one component in a session
        # (the same finger and screen on the same day); else drawn for this measurement
        s_sess, s_trial = _SPREAD[kind]
        sess = rng.normal(0.0, s_sess, (sessions, 1)) if day is None else day[kind]
        return (sess + rng.normal(0.0, s_trial, shape))[..., None]

    def factor(kind, day=None):
        return np.exp(offsets(kind, day))

    def cpe(q, alpha, pivot_hz, day=None, q_kind="Q"):
        # α scatters about the pivot frequency, where |Q (jω)^α| keeps Q's own scatter only;
        # jitter about ω = 1 rad/s would swing |Z_CPE| by ±15 % per trial at 1 MHz.
        a = alpha + offsets("alpha", day)
        return q * factor(q_kind, day) * (2.0 * np.pi * pivot_hz) ** (alpha - a), a

    def day_offsets(*kinds):
        return {kind: rng.normal(0.0, _SPREAD[kind][0], (sessions, 1)) for kind in kinds}

    skin_days = day_offsets("R_inf", "R_skin", "Q", "alpha")
    screen_days = day_offsets("R_inf", "R_ts", "Q", "alpha")

    def skin(r_factor=1.0):
        p = truth["skin"]
        return r_cpe_series(freq, p["R_inf"] * factor("R_inf", skin_days), r_factor * p["R"] * factor("R_skin", skin_days), *cpe(p["Q"], p["alpha"], _PIVOT_HZ["skin"], skin_days))

    def screen():
        p = truth["touchscreen"]
        return r_cpe_series(freq, p["R_inf"] * factor("R_inf", screen_days), p["R"] * factor("R_ts", screen_days), *cpe(p["Q"], p["alpha"], _PIVOT_HZ["touchscreen"], screen_days))

    def remainder(p):
        # the trial's own contact: u log-normal about the truth, so C_gap = ε0 ε A/u scales by 1/factor
        r_ep, (q_ep, alpha_ep), u_factor = p["R_EP"] * factor("R_EP"), cpe(p["CPE_EP.Q"], p["CPE_EP.alpha"], _PIVOT_HZ["EP"], q_kind="Q_EP"), factor("u")
        contact = {"R_EP": r_ep[..., 0], "CPE_EP.Q": q_ep[..., 0], "CPE_EP.alpha": alpha_ep[..., 0], "C_gap": p["C_gap"] / u_factor[..., 0]}
        return _remainder(freq, r_ep, q_ep, alpha_ep, p["C_gap"] / u_factor), contact

    def measured(z):
        rel = 0.004 + 0.03 / np.sqrt(freq)
        noise = rng.normal(0.0, 1.0, z.shape + (2,)) @ np.array([1.0, 1j])
        return z * (1.0 + rel * noise / np.sqrt(2.0))

    z_skin = measured(skin())
    z_ts = measured(screen())
    z_sliding, contact_sliding = remainder(truth["remainder_sliding"])
    sliding = measured(skin() + screen() + z_sliding)
    z_stationary, contact_stationary = remainder(truth["remainder_stationary"])
    stationary = measured(skin(truth["stationary_skin_r_factor"]["value"]) + screen() + z_stationary)
    geometry = truth["geometry"]
    trial_truth = {
        f"trial_{name.replace('.', '_')}": (("contact", "session", "trial"), np.stack([contact_sliding[name], contact_stationary[name]]), {"units": unit, "long_name": f"true {name} of each trial's contact (generator draw)"})
        for name, unit in (("R_EP", "ohm"), ("CPE_EP.Q", "F s^(alpha-1)"), ("CPE_EP.alpha", "1"), ("C_gap", "F"))
    }
    u_trial = EPSILON_0 * geometry["eps_gap"] * geometry["area_m2"] / np.stack([contact_sliding["C_gap"], contact_stationary["C_gap"]])
    trial_truth["trial_u"] = (("contact", "session", "trial"), u_trial, {"units": "m", "long_name": "true air-gap thickness of each trial (generator draw), u = eps0 eps_gap A / C_gap"})
    coords = {
        "frequency": ("frequency", freq, {"units": "Hz"}),
        "session": ("session", np.arange(1, sessions + 1)),
        "trial": ("trial", np.arange(1, trials + 1)),
        "contact": ("contact", np.array(["sliding", "stationary"])),
    }
    z_attrs = {"units": "ohm"}
    return xr.Dataset(
        {
            "Z_total": (("contact", "session", "trial", "frequency"), np.stack([sliding, stationary]), {**z_attrs, "long_name": "total impedance, finger on touchscreen"}),
            "Z_skin": (("session", "trial", "frequency"), z_skin, {**z_attrs, "long_name": "finger skin bioimpedance"}),
            "Z_touchscreen": (("session", "trial", "frequency"), z_ts, {**z_attrs, "long_name": "touchscreen impedance"}),
            **trial_truth,
        },
        coords=coords,
        attrs={
            "title": "SYNTHETIC finger-touchscreen impedance in the style of Sirin et al.",
            "synthetic": "yes: generated by impedax.models.synthetic.generate_sirin_synthetic, not measured",
            "generator": "impedax.models.synthetic.generate_sirin_synthetic",
            "seed": int(seed),
            "truth": json.loads(json.dumps(truth)),
            "trial_variation": json.loads(json.dumps({k: {"session_sd": v[0], "trial_sd": v[1]} for k, v in _SPREAD.items()})),
            "trial_variation_note": "ln of each parameter = ln(truth) + session offset + trial offset, both Gaussian with the sds in trial_variation (additive for alpha); the contact of the sliding finger: u 1 % between sessions and 7 % between trials, R_EP 5 %/15 %, CPE_EP.Q 3 %/8 %; the truth of each trial is stored in the trial_* variables; population median of u = eps0 eps_gap A / C_gap(truth) = 2.789 um",
            "noise": "per-session (shared by the skin, screen and total measurements of a session) and per-trial log-normal parameter factors; CPE exponent jitter pivots at 250 Hz (skin), 100 kHz (screen), 10 Hz (EP); complex Gaussian noise, relative sd 0.4 % + 3 % * (1 Hz/f)^0.5",
            "source": "impedax synthetic example (Sirin et al. style)",
        },
    )


def example_path(name: str = "sirin") -> Path:
    """Path of a shipped example file."""
    if name != "sirin":
        raise DataError(f"unknown example {name!r}; available: sirin")
    return _FILE


def load_example(name: str = "sirin") -> xr.Dataset:
    """Load the shipped SYNTHETIC example Dataset (see `generate_sirin_synthetic`)."""
    from ..io import read_netcdf

    return read_netcdf(example_path(name))


_PARTS = {
    "total_sliding": ("Z_total", {"contact": "sliding"}, "total impedance, finger sliding"),
    "total_stationary": ("Z_total", {"contact": "stationary"}, "total impedance, finger stationary"),
    "skin": ("Z_skin", {}, "finger skin"),
    "touchscreen": ("Z_touchscreen", {}, "touchscreen"),
}


def example_spectra(ds: xr.Dataset | None = None) -> dict[str, xr.Dataset]:
    """The example as standard spectrum Datasets (complex ``Z`` over ``frequency`` with dims
    ``session``, ``trial``): keys ``total_sliding``, ``total_stationary``, ``skin``,
    ``touchscreen``. ``ds`` defaults to `load_example`; another Dataset is a `DataError` saying
    what it lacks (not a KeyError from inside xarray; a spectrum's ``Z`` is no example)."""
    ds = load_example() if ds is None else ds
    _check_example(ds)
    out = {}
    for key, (var, sel, what) in _PARTS.items():
        z = ds[var].sel(sel).transpose("session", "trial", "frequency")
        out[key] = make_spectrum(
            ds["frequency"].values,
            z.values,
            dims=("session", "trial"),
            coords={"session": ds["session"].values, "trial": ds["trial"].values},
            attrs={"synthetic": ds.attrs.get("synthetic", "yes"), "seed": ds.attrs.get("seed"), "measurement": what},
            source=f"impedax synthetic example: {key}",
        )
    return out


def _check_example(ds) -> None:
    """``ds`` holds what `example_spectra` takes apart (`_PARTS`: Z_total over ``contact`` sliding
    and stationary, Z_skin, Z_touchscreen, each over session, trial and frequency), else one
    `DataError` naming the first thing missing."""
    if not isinstance(ds, xr.Dataset):
        raise DataError(f"example_spectra: ds must be the example Dataset (impedax.models.load_example() or generate_sirin_synthetic()), got {type(ds).__name__}")
    for var, sel, _ in _PARTS.values():
        missing = f"no variable {var!r}" if var not in ds.data_vars else next(
            (f"{var} has no dimension {d!r}" for d in ("session", "trial", "frequency", *sel) if d not in ds[var].dims), None)
        if missing is None:
            missing = next((f"{var} has no {d} {label!r} (its {d}s: {', '.join(map(str, ds[d].values))})" for d, label in sel.items()
                            if d not in ds.coords or label not in [str(v) for v in ds[d].values]), None)
        if missing and var not in ds.data_vars:
            held = ", ".join(map(str, ds.data_vars)) or "none"
            missing += f"; its variables: {held}" + (" (a spectrum: analyse its Z as it is)" if "Z" in ds.data_vars else "")
        if missing:
            raise DataError(f"example_spectra: ds is not the SYNTHETIC example (impedax.models.load_example() or generate_sirin_synthetic()): {missing}")


TWO_ARC_TRUTH: dict[str, float] = {"R0": 20.0, "R1": 100.0, "CPE1.Q": 1e-5, "CPE1.alpha": 0.85, "R2": 300.0, "CPE2.Q": 1e-3, "CPE2.alpha": 0.75}
"""Population medians [SI] of the two-arc coverage example (arcs near 550 Hz and 0.8 Hz)."""
TWO_ARC_SPREAD: dict[str, float] = {"R1": 0.10, "CPE1.Q": 0.05, "R2": 0.12, "CPE2.Q": 0.06}
"""sd of ln between trials of the per-trial parameters; R0 and the exponents are shared."""


def generate_two_arc_trials(seed: int, *, trials: int = 20, points: int = 41, fmin: float = 0.1, fmax: float = 1e5) -> xr.Dataset:
    """SYNTHETIC electrochemical spectra R0 + R1 ∥ CPE1 + R2 ∥ CPE2 over ``trials`` (numpy
    formula Z = R0 + Σ_i R_i/(1 + R_i Q_i (jω)^α_i), independent of impedax's compiler).

    R0 and the exponents are shared (`TWO_ARC_TRUTH`); R1, Q1, R2, Q2 are log-normal about
    their population medians with the spreads of `TWO_ARC_SPREAD`. Complex Gaussian noise of
    relative sd 0.5 % + 1 %·(1 Hz/f)^½ (larger at low frequency). The trials' true values are
    in ``trial_<name>`` variables."""
    rng = np.random.default_rng(seed)
    freq = log_frequencies(fmin, fmax, points)
    jw = 1j * 2.0 * np.pi * freq
    p = {k: np.full((trials, 1), v) for k, v in TWO_ARC_TRUTH.items()}
    for name, sd in TWO_ARC_SPREAD.items():
        p[name] = p[name] * np.exp(sd * rng.standard_normal((trials, 1)))
    z = p["R0"] + sum(p[f"R{i}"] / (1.0 + p[f"R{i}"] * p[f"CPE{i}.Q"] * jw ** p[f"CPE{i}.alpha"]) for i in (1, 2))
    rel = 0.005 + 0.01 / np.sqrt(freq)
    z = z * (1.0 + rel * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape)) / np.sqrt(2.0))
    ds = make_spectrum(freq, z, dims=("trial",), attrs={"synthetic": "yes", "generator": "impedax.models.synthetic.generate_two_arc_trials", "seed": int(seed)}, source="two-arc synthetic trials")
    for name in TWO_ARC_SPREAD:
        ds[f"trial_{name.replace('.', '_')}"] = ("trial", p[name][:, 0])
    return ds


def sirin_trial_remainders(ds: xr.Dataset, contact: str = "sliding") -> xr.Dataset:
    """Per-trial remaining impedance of the Sirin example: each total trial minus the trial
    means of skin and touchscreen (Sirin eq 5 per trial), a spectrum Dataset over
    (session, trial, frequency)."""
    from .sirin import trial_remainders

    if contact not in ("sliding", "stationary"):
        raise DataError(f"contact must be 'sliding' or 'stationary' (the example's two totals), got {contact!r}")
    parts = example_spectra(ds)
    return trial_remainders(parts[f"total_{contact}"], parts["skin"], parts["touchscreen"])
