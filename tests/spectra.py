"""Synthetic test spectra from numpy formulas written independently of impedax's compiler."""

import numpy as np


def omega(f):
    return 2 * np.pi * np.asarray(f, float)


def z_cpe(f, q, alpha):
    return 1.0 / (q * (1j * omega(f)) ** alpha)


def z_parallel(*zs):
    return 1.0 / sum(1.0 / z for z in zs)


def rc(f, p):  # R0 + R1 || C1
    return p["R0"] + z_parallel(p["R1"], 1 / (1j * omega(f) * p["C1"]))


def r_cpe(f, p):  # R0 + R1 || CPE1
    return p["R0"] + z_parallel(p["R1"], z_cpe(f, p["CPE1.Q"], p["CPE1.alpha"]))


def randles(f, p):  # R0 + (R1 + W1) || C1
    w = omega(f)
    zw = p["W1.sigma"] * (1 - 1j) / np.sqrt(w)
    return p["R0"] + z_parallel(p["R1"] + zw, 1 / (1j * w * p["C1"]))


def two_arcs(f, p):  # R0 + R1 || CPE1 + R2 || CPE2
    return p["R0"] + z_parallel(p["R1"], z_cpe(f, p["CPE1.Q"], p["CPE1.alpha"])) + z_parallel(p["R2"], z_cpe(f, p["CPE2.Q"], p["CPE2.alpha"]))


def meyer(f, p):  # C_s + C_i + R_sc || C_sc + R_f
    s = 1j * omega(f)
    return 1 / (s * p["C_s"]) + 1 / (s * p["C_i"]) + p["R_sc"] / (1 + s * p["R_sc"] * p["C_sc"]) + p["R_f"]


CASES = {
    "rc": ("R0 + R1 || C1", rc, {"R0": 50.0, "R1": 2000.0, "C1": 1e-7}, (1.0, 1e6)),
    "r_cpe": ("R0 + R1 || CPE1", r_cpe, {"R0": 20.0, "R1": 5000.0, "CPE1.Q": 3e-6, "CPE1.alpha": 0.8}, (0.1, 1e5)),
    "randles": ("R0 + (R1 + W1) || C1", randles, {"R0": 15.0, "R1": 300.0, "W1.sigma": 150.0, "C1": 2e-5}, (0.01, 1e5)),
    "two_arcs": ("R0 + R1 || CPE1 + R2 || CPE2", two_arcs, {"R0": 10.0, "R1": 400.0, "CPE1.Q": 1e-7, "CPE1.alpha": 0.9, "R2": 3000.0, "CPE2.Q": 5e-5, "CPE2.alpha": 0.75}, (0.01, 1e6)),
}


def noisy(z, rel_noise, rng):
    """Proportional complex Gaussian noise: each of Re and Im gets N(0, rel_noise·|Z|)."""
    return z + rel_noise * np.abs(z) * (rng.normal(size=z.shape) + 1j * rng.normal(size=z.shape))


def perturb(params, rng, spread=0.5):
    """Random true parameters around ``params``: scales ×10^U(−spread, spread), exponents ±0.1."""
    out = {}
    for k, v in params.items():
        if k.endswith("alpha"):
            out[k] = float(np.clip(v + rng.uniform(-0.1, 0.1), 0.5, 0.98))
        else:
            out[k] = float(v * 10 ** rng.uniform(-spread, spread))
    return out


def r_cpe_series(w, r_inf, r, q, alpha):
    """R_inf + R ∥ CPE(Q, α) at angular frequencies w."""
    return r_inf + 1.0 / (1.0 / r + q * (1j * w) ** alpha)


def sirin_measurements(rng, n_trials, *, noise=0.005, trial_scatter=0.0, points=41, c_gap=413e-12):
    """SYNTHETIC Sirin-style trials written from formulas (not impedax's circuits): frequencies
    (1 Hz–1 MHz) and the total, skin and touchscreen spectra (n_trials, points). Skin and
    touchscreen R_inf + R ∥ CPE, remainder R_EP ∥ CPE_EP ∥ C_gap; complex noise of ``noise``·|Z|
    on Re and Im per point, times a per-trial factor 1 + ``trial_scatter``·N(0, 1) common to all
    frequencies (None: no such factor drawn)."""
    f = np.geomspace(1.0, 1e6, points)
    w = 2 * np.pi * f
    skin = r_cpe_series(w, 300.0, 2e5, 3e-8, 0.8)
    ts = r_cpe_series(w, 50.0, 2e4, 8e-11, 0.9)
    rem = 1.0 / (1.0 / 2e7 + 7.5e-10 * (1j * w) ** 0.3 + 1j * w * c_gap)

    def trials(z):
        scatter = 1.0 if trial_scatter is None else 1 + trial_scatter * rng.normal(size=(n_trials, 1))
        return z[None, :] * scatter + noise * np.abs(z) * (rng.normal(size=(n_trials, f.size)) + 1j * rng.normal(size=(n_trials, f.size)))

    return f, trials(skin + ts + rem), trials(skin), trials(ts)



def sirin_scattered_measurements(rng, n_trials, *, skin_scatter=0.2, screen_scatter=0.05, gap_scatter=0.05, noise=0.005, points=41, area=100e-6, gap=3.5e-6):
    """SYNTHETIC Sirin-style trials in which skin, screen and gap vary independently between
    trials (unlike `sirin_measurements`, whose one per-trial factor scales the whole sum): each
    trial draws its own skin factor exp(N(0, ``skin_scatter``)) on R_inf and R (and 1/factor
    on the CPE's Q), screen factor likewise, and gap u·exp(N(0, ``gap_scatter``)); the total's
    skin and screen are draws of their own, apart from the separately measured sets. Remainder
    R_EP ∥ CPE_EP ∥ C_gap with C_gap = ε0 ε_air A/u. Returns (f, total, skin, screen, trial u)."""
    eps0, eps_air = 8.8541878128e-12, 1.00059
    f = np.geomspace(1.0, 1e6, points)
    w = 2 * np.pi * f

    def skin(k):
        return r_cpe_series(w, 300.0 * k, 2e5 * k, 3e-8 / k, 0.8)

    def screen(k):
        return r_cpe_series(w, 50.0 * k, 2e4 * k, 8e-11 / k, 0.9)

    def remainder(u):
        return 1.0 / (1.0 / 2e7 + 7.5e-10 * (1j * w) ** 0.3 + 1j * w * eps0 * eps_air * area / u)

    def factor(scatter):
        return np.exp(scatter * rng.normal())

    gaps = gap * np.exp(gap_scatter * rng.normal(size=n_trials))
    total = np.array([skin(factor(skin_scatter)) + screen(factor(screen_scatter)) + remainder(u) for u in gaps])
    skins = np.array([skin(factor(skin_scatter)) for _ in range(n_trials)])
    screens = np.array([screen(factor(screen_scatter)) for _ in range(n_trials)])
    return f, noisy(total, noise, rng), noisy(skins, noise, rng), noisy(screens, noise, rng), gaps
