"""SYNTHETIC spectra with a hidden physical effect, from numpy formulas written independently
of impedax's compiler and of the effect catalog.

Each case: the user's circuit (lacking the effect), the effect id the diagnosis should name, a
numpy impedance formula of the true system, its parameters and the frequency range. `spectrum`
adds proportional complex Gaussian noise (tests.spectra.noisy).
"""

from __future__ import annotations

import numpy as np

from spectra import noisy


def _jw(f):
    return 1j * 2 * np.pi * np.asarray(f, float)


def _par(*zs):
    return 1.0 / sum(1.0 / z for z in zs)


def _cpe(f, q, a):
    return 1.0 / (q * _jw(f) ** a)


def _cap(f, c):
    return 1.0 / (_jw(f) * c)


def _warburg(f, s):
    w = 2 * np.pi * np.asarray(f, float)
    return s / np.sqrt(w) - 1j * s / np.sqrt(w)


def _wo(f, r, tau):  # R coth(√(jωτ))/√(jωτ)
    x = np.sqrt(_jw(f) * tau)
    return r / (np.tanh(x) * x)


def _ws(f, r, tau):  # R tanh(√(jωτ))/√(jωτ)
    x = np.sqrt(_jw(f) * tau)
    return r * np.tanh(x) / x


def _rc(f, r, c):
    return r / (1 + _jw(f) * r * c)


def _rq(f, r, q, a):
    return r / (1 + r * q * _jw(f) ** a)


# name: (user circuit, hidden effect id, formula(f, p), params, (f_min, f_max))
CASES = {
    # series resistance: an RC arc measured with an electrolyte/lead resistance the user left out
    "series_resistance/rc": ("R1 || C1", "series_resistance", lambda f, p: p["Rs"] + _rc(f, p["R1"], p["C1"]), {"Rs": 120.0, "R1": 2000.0, "C1": 1e-7}, (1.0, 1e6)),
    "series_resistance/rcpe": ("R1 || CPE1", "series_resistance", lambda f, p: p["Rs"] + _rq(f, p["R1"], p["Q"], p["a"]), {"Rs": 40.0, "R1": 5000.0, "Q": 3e-6, "a": 0.8}, (0.1, 1e5)),
    # series inductance: cable inductance above ~100 kHz
    "series_inductance/r_rc": ("R0 + R1 || C1", "series_inductance", lambda f, p: p["R0"] + _rc(f, p["R1"], p["C1"]) + _jw(f) * p["L"], {"R0": 20.0, "R1": 500.0, "C1": 1e-6, "L": 2e-6}, (1.0, 1e6)),
    "series_inductance/r_rcpe": ("R0 + R1 || CPE1", "series_inductance", lambda f, p: p["R0"] + _rq(f, p["R1"], p["Q"], p["a"]) + _jw(f) * p["L"], {"R0": 5.0, "R1": 200.0, "Q": 1e-5, "a": 0.85, "L": 1e-6}, (1.0, 1e6)),
    # stray capacitance across a high-impedance sample
    "stray_capacitance/r_rc": ("R0 + R1 || C1", "stray_capacitance", lambda f, p: _par(p["R0"] + _rc(f, p["R1"], p["C1"]), _cap(f, p["Cs"])), {"R0": 1e4, "R1": 1e6, "C1": 1e-9, "Cs": 2e-11}, (1.0, 1e6)),
    "stray_capacitance/r_rcpe": ("R0 + R1 || CPE1", "stray_capacitance", lambda f, p: _par(p["R0"] + _rq(f, p["R1"], p["Q"], p["a"]), _cap(f, p["Cs"])), {"R0": 5e3, "R1": 2e5, "Q": 1e-8, "a": 0.8, "Cs": 5e-11}, (1.0, 1e6)),
    # constant phase: a depressed arc fitted with an ideal C
    "constant_phase/r_rc": ("R0 + R1 || C1", "constant_phase", lambda f, p: p["R0"] + _rq(f, p["R1"], p["Q"], p["a"]), {"R0": 50.0, "R1": 3000.0, "Q": 2e-6, "a": 0.75}, (0.1, 1e5)),
    "constant_phase/meyer": ("C_i + R_sc || C_sc + R_f", "constant_phase", lambda f, p: _cap(f, p["Ci"]) + _rq(f, p["Rsc"], p["Q"], p["a"]) + p["Rf"], {"Ci": 1e-9, "Rsc": 1e6, "Q": 5e-9, "a": 0.7, "Rf": 1e4}, (10.0, 1e6)),
    # extra relaxation: a second arc
    "extra_relaxation/r_rc": ("R0 + R1 || C1", "extra_relaxation", lambda f, p: p["R0"] + _rc(f, p["R1"], p["C1"]) + _rc(f, p["R2"], p["C2"]), {"R0": 10.0, "R1": 400.0, "C1": 1e-7, "R2": 2000.0, "C2": 5e-5}, (0.01, 1e6)),
    "extra_relaxation/r_rcpe": ("R0 + R1 || CPE1", "extra_relaxation", lambda f, p: p["R0"] + _rq(f, p["R1"], p["Q1"], p["a1"]) + _rc(f, p["R2"], p["C2"]), {"R0": 30.0, "R1": 1000.0, "Q1": 1e-6, "a1": 0.85, "R2": 300.0, "C2": 1e-8}, (1.0, 1e6)),
    # diffusion: a Warburg tail behind the charge-transfer resistance (Randles)
    "diffusion/randles": ("R0 + R1 || C1", "diffusion", lambda f, p: p["R0"] + _par(p["R1"] + _warburg(f, p["sigma"]), _cap(f, p["C1"])), {"R0": 15.0, "R1": 300.0, "sigma": 150.0, "C1": 2e-5}, (0.01, 1e5)),
    "diffusion/finite": ("R0 + R1 || CPE1", "diffusion", lambda f, p: p["R0"] + _rq(f, p["R1"], p["Q"], p["a"]) + _wo(f, p["Rd"], p["tau"]), {"R0": 10.0, "R1": 200.0, "Q": 2e-5, "a": 0.9, "Rd": 500.0, "tau": 5.0}, (0.005, 1e5)),
    # electrode polarization: leakage across a blocking capacitance (the finger's air gap)
    "electrode_polarization/gap": ("C_gap", "electrode_polarization", lambda f, p: 1 / (1 / p["Rep"] + p["Q"] * _jw(f) ** p["a"] + _jw(f) * p["C"]), {"Rep": 2e7, "Q": 2e-9, "a": 0.25, "C": 413e-12}, (1.0, 1e6)),
    "electrode_polarization/series": ("R0 + C1", "electrode_polarization", lambda f, p: p["R0"] + _par(p["Rep"], _cap(f, p["C1"])), {"R0": 1e3, "Rep": 1e6, "C1": 1e-8}, (0.1, 1e5)),
}

# models that are right: verdict must be adequate
ADEQUATE = {
    "rc": ("R0 + R1 || C1", lambda f, p: p["R0"] + _rc(f, p["R1"], p["C1"]), {"R0": 50.0, "R1": 2000.0, "C1": 1e-7}, (1.0, 1e6)),
    "r_cpe": ("R0 + R1 || CPE1", lambda f, p: p["R0"] + _rq(f, p["R1"], p["Q"], p["a"]), {"R0": 20.0, "R1": 5000.0, "Q": 3e-6, "a": 0.8}, (0.1, 1e5)),
    "randles": ("R0 + (R1 + W1) || C1", lambda f, p: p["R0"] + _par(p["R1"] + _warburg(f, p["sigma"]), _cap(f, p["C1"])), {"R0": 15.0, "R1": 300.0, "sigma": 150.0, "C1": 2e-5}, (0.01, 1e5)),
    "two_arcs": ("R0 + R1 || CPE1 + R2 || CPE2", lambda f, p: p["R0"] + _rq(f, p["R1"], p["Q1"], p["a1"]) + _rq(f, p["R2"], p["Q2"], p["a2"]), {"R0": 10.0, "R1": 400.0, "Q1": 1e-7, "a1": 0.9, "R2": 3000.0, "Q2": 5e-5, "a2": 0.75}, (0.01, 1e6)),
    "gap_ep": ("R_EP || CPE_EP || C_gap", lambda f, p: 1 / (1 / p["Rep"] + p["Q"] * _jw(f) ** p["a"] + _jw(f) * p["C"]), {"Rep": 2e7, "Q": 2e-9, "a": 0.25, "C": 413e-12}, (1.0, 1e6)),
}


def frequencies(f_min, f_max, n=60):
    return np.logspace(np.log10(f_min), np.log10(f_max), n)


def spectrum(formula, params, frange, rel_noise, rng, n=60):
    """(frequency, noisy Z) of a case."""
    f = frequencies(*frange, n)
    return f, noisy(formula(f, params), rel_noise, rng)


def drifting(rng, rel_noise=0.005, n=60):
    """A non-stationary sweep: an RC arc whose resistance drifts by 40 % during the sweep (swept
    from high to low frequency, so the low-frequency end is measured last)."""
    f = frequencies(0.1, 1e5, n)
    t = np.linspace(1, 0, n)  # sweep time: 0 at the highest frequency (measured first), 1 at the lowest
    r1 = 2000.0 * (1 + 0.4 * t**2)
    c1 = 1e-6 * (1 - 0.3 * t)
    z = 50 + r1 / (1 + _jw(f) * r1 * c1)
    return f, noisy(z, rel_noise, rng)


EXPONENTS = {"a", "a1", "a2"}


def vary(params, rng, spread=0.2):
    """True parameters varied around a case's: scales ×10^U(−spread, spread), CPE exponents
    ±0.05 (kept in 0.5–0.98), so a study does not test one spectrum per effect only."""
    out = {}
    for k, v in params.items():
        if k in EXPONENTS:
            out[k] = float(np.clip(v + rng.uniform(-0.05, 0.05), 0.5, 0.98))
        else:
            out[k] = float(v * 10 ** rng.uniform(-spread, spread))
    return out
