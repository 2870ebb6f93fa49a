"""Data-driven starting values computed for a stack of spectra at once equal, row by row, the
per-spectrum rule they replace.

The oracle below is the per-spectrum code as it stood before the stack version (a Python pass
per spectrum), kept here verbatim with one change: its two ``np.argsort`` calls use
``kind="stable"``. numpy's default sort is not stable on machines with wide SIMD units (from
four equal keys on), so the old order among equal −Z'' peaks depended on the CPU; the stack
version takes equal peaks in the order the rule lists them, which is the stable order.
The spectra are numpy formulas written here, not impedax's compiled circuits.
"""

import numpy as np
import pytest

import impedax as ix
from impedax.circuits import DEFAULT_REGISTRY
from impedax.fitting.least_squares.starts import guess_start
from impedax.fitting.parameters import ParameterTable
from impedax.fitting.least_squares.starts import SpectrumFeatures, _clip_inside, _roles, data_driven_guess, data_driven_guesses, random_starts

RTOL = 1e-12  # the stack's vectorised pow may differ from the scalar pow in the last bit


# ---- oracle: the per-spectrum code (verbatim but for kind="stable") ------------------------


class OracleFeatures:
    def __init__(self, freq, z):
        order = np.argsort(freq)
        f, z = np.asarray(freq, float)[order], np.asarray(z, complex)[order]
        w = 2 * np.pi * f
        mag = np.abs(z)
        self.f_min, self.f_max = f[0], f[-1]
        self.z_min, self.z_max = max(mag.min(), 1e-300), mag.max()
        self.r_hf = max(z.real[-1], 1e-3 * self.z_min)
        self.r_lf = max(z.real[0], self.r_hf * 1.01)
        neg_im = -z.imag
        self.f_peak = f[np.argmax(neg_im)] if np.any(neg_im > 0) else np.sqrt(f[0] * f[-1])
        self.c_series = 1.0 / (w[0] * neg_im[0]) if neg_im[0] > 0 else 1.0 / (w[0] * mag[0])
        self.l_series = z.imag[-1] / w[-1] if z.imag[-1] > 0 else self.z_min / w[-1] * 1e-2
        k = min(3, len(f))
        if k >= 2 and np.all(neg_im[:k] > 0):
            lx, ly = np.log(f[:k]), np.log(neg_im[:k])
            slope = np.sum((lx - lx.mean()) * (ly - ly.mean())) / np.sum((lx - lx.mean()) ** 2)  # least-squares line
            self.alpha_lf = float(np.clip(-slope, 0.4, 1.0))
        else:
            self.alpha_lf = 0.85
        self.warburg = mag[0] * np.sqrt(w[0]) * 0.3
        self._f, self._neg_im = f, neg_im

    def arcs(self, n_arc):
        f, y = self._f, self._neg_im
        r_total = max(self.r_lf - self.r_hf, 0.05 * self.z_max)
        inner = np.flatnonzero((y[1:-1] > y[:-2]) & (y[1:-1] >= y[2:]) & (y[1:-1] > 0)) + 1
        ends = [i for i in (0, len(f) - 1) if len(f) > 1 and y[i] > 0 and y[i] > y[1 if i == 0 else -2]]
        peaks = np.concatenate([inner, np.asarray(ends, int)])
        peaks = peaks[np.argsort(-y[peaks], kind="stable")][:n_arc] if peaks.size else np.asarray([], int)
        f_peaks = list(f[peaks]) if peaks.size else [self.f_peak]
        heights = list(y[peaks]) if peaks.size else [r_total / 2]
        while len(f_peaks) < n_arc:
            f_peaks.append(f_peaks[0] / 10 ** len(f_peaks))
            heights.append(heights[0])
        order = np.argsort(f_peaks, kind="stable")[::-1]
        f_peaks = np.asarray(f_peaks)[order]
        r = np.asarray(heights, float)[order]
        r = r_total * r / r.sum()
        return r, 1.0 / (2 * np.pi * f_peaks)


def oracle_guess(circuit, table, features, registry=DEFAULT_REGISTRY):
    roles, n_blocks = _roles(circuit)
    elements = list(circuit.elements())
    n_series_r = max(1, sum(1 for e in elements if e.symbol == "R" and roles[e.name] < 0))
    n_res = np.ones(max(n_blocks, 1))
    for e in elements:
        if roles[e.name] >= 0 and registry[e.symbol].parameters[0].unit == "Ohm":
            n_res[roles[e.name]] += 1
    n_res = np.maximum(n_res - 1, 1)
    r_arcs, taus = features.arcs(max(n_blocks, 1))
    guess = {}
    for e in elements:
        block = roles[e.name]
        inside = block >= 0
        r_arc = r_arcs[block] / n_res[block] if inside else r_arcs.sum()
        tau = taus[block] if inside else 1.0 / (2 * np.pi * features.f_peak)
        f_arc = 1.0 / (2 * np.pi * tau)
        spec = registry[e.symbol]
        names = spec.parameter_names(e.name)
        sym = registry[e.symbol].symbol
        if sym == "R":
            guess[names[0]] = r_arc if inside else features.r_hf / n_series_r
        elif sym == "C":
            guess[names[0]] = tau / r_arc if inside else features.c_series
        elif sym == "L":
            guess[names[0]] = features.l_series
        elif sym == "CPE":
            alpha = 0.85 if inside else features.alpha_lf
            c = tau / r_arc if inside else features.c_series
            guess[names[0]] = c * (2 * np.pi * (f_arc if inside else features.f_min)) ** (1 - alpha)
            guess[names[1]] = alpha
        elif sym == "W":
            guess[names[0]] = features.warburg
        else:
            for p, n in zip(spec.parameters, names):
                if p.unit == "Ohm":
                    guess[n] = r_arc
                elif p.unit == "s":
                    guess[n] = tau
                elif p.unit == "1":
                    guess[n] = 0.85
                else:
                    guess[n] = p.default
    x = np.array([guess.get(n, np.nan) for n in table.names])
    given = ~np.isnan(table.values)
    x[given] = table.values[given]
    bad = ~np.isfinite(x)
    x[bad] = [circuit.parameter_specs(registry)[n].default for n in np.asarray(table.names)[bad]]
    return _clip_inside(x, table)


def oracle_random_starts(table, features, guess, n_starts, seed):
    """The per-spectrum random starts as they stood before the stack version (verbatim)."""

    def log_range(i):
        unit = table.units[i]
        w_lo, w_hi = 2 * np.pi * features.f_min, 2 * np.pi * features.f_max
        zlo, zhi = features.z_min, features.z_max
        ranges = {
            "Ohm": (zlo / 30, zhi * 3),
            "F": (1 / (w_hi * zhi) / 10, 1 / (w_lo * zlo) * 10),
            "H": (zlo / w_hi / 100, zhi / w_lo),
            "s": (1 / w_hi / 10, 1 / w_lo * 10),
            "Ohm s^-1/2": (zlo * np.sqrt(w_lo) / 30, zhi * np.sqrt(w_hi) * 3),
        }
        if unit.startswith("F s^"):
            lo, hi = 1 / (w_hi * zhi) / 100, 1 / (w_lo * zlo) * 100
        else:
            lo, hi = ranges.get(unit, (1e-3, 1e3))
        return np.log(max(lo, 1e-300)), np.log(max(hi, lo * 10, 1e-299))

    rng = np.random.default_rng(seed)
    starts = np.tile(guess, (n_starts, 1))
    n_jitter = (n_starts - 1) // 2
    for s in range(1, n_starts):
        for i in range(len(guess)):
            if table.fixed[i] or not np.isnan(table.values[i]) and s <= n_jitter:
                continue
            if table.units[i] == "1":
                starts[s, i] = rng.uniform(0.45, 1.0) if s > n_jitter else np.clip(guess[i] + rng.normal(0, 0.1), 0.3, 1.0)
            elif s <= n_jitter:
                starts[s, i] = guess[i] * 10 ** rng.normal(0, 0.7)
            else:
                lo, hi = log_range(i)
                starts[s, i] = np.exp(rng.uniform(lo, hi))
    starts[:, table.fixed] = table.values[table.fixed]
    return _clip_inside(starts, table)


# ---- synthetic spectra (numpy formulas) ----------------------------------------------------


def _arc(w, r, tau, alpha=1.0):
    """R || CPE written as a Cole element: R / (1 + (jωτ)^α)."""
    return r / (1 + (1j * w * tau) ** alpha)


def _family(w, kind, rng):
    u = lambda lo, hi: 10 ** rng.uniform(np.log10(lo), np.log10(hi))  # noqa: E731
    r0, r1, r2 = u(1, 100), u(100, 1e4), u(100, 1e4)
    t1 = u(1e-5, 1e-1)
    if kind == "rc":
        return r0 + _arc(w, r1, t1)
    if kind == "cpe":
        return r0 + _arc(w, r1, t1, rng.uniform(0.6, 0.95))
    if kind == "two_overlapping":
        return r0 + _arc(w, r1, t1, rng.uniform(0.8, 1.0)) + _arc(w, r2, t1 * rng.uniform(2, 5), rng.uniform(0.8, 1.0))
    if kind == "two_apart":
        return r0 + _arc(w, r1, t1, 0.9) + _arc(w, r2, t1 * u(100, 1e4), 0.75)
    if kind == "three":
        return r0 + _arc(w, r1, 1e-5) + _arc(w, r2, 1e-3) + _arc(w, u(100, 1e4), 1e-1, 0.8)
    if kind == "inductive":
        return r0 + 1j * w * u(1e-7, 1e-4) + _arc(w, r1, t1)
    if kind == "warburg":
        zw = u(10, 1e3) * (1 - 1j) / np.sqrt(w)
        return r0 + 1 / (1 / (r1 + zw) + 1j * w * t1 / r1)
    if kind == "open_warburg":
        td = u(0.1, 10)
        return r0 + _arc(w, r1, t1) + u(100, 1e3) / np.tanh(np.sqrt(1j * w * td)) / np.sqrt(1j * w * td)
    if kind == "series_capacitor":  # C_i + R_sc || C_sc + R_f: −Z'' rises to the lowest frequency
        return 1 / (1j * w * u(1e-10, 1e-8)) + _arc(w, u(1e4, 1e6), t1) + u(100, 1e3)
    if kind == "no_negative_imag":  # R + L: −Z'' < 0 everywhere
        return r0 + 1j * w * u(1e-7, 1e-4)
    if kind == "resistor":  # −Z'' = 0 everywhere
        return np.full(w.shape, r0, complex)
    if kind == "quantised":  # an instrument's 3 significant digits: plateaus and equal peaks
        z = r0 + _arc(w, r1, t1) + _arc(w, r1, t1 * 1e3)
        return _round_significant(z.real, 2) + 1j * _round_significant(z.imag, 2)
    if kind == "equal_peaks":  # many exactly equal local maxima (more than numpy's stable small sort)
        y = np.where(np.arange(w.size) % 3 == 1, 7.0, 1.0)
        return r0 - 1j * y
    if kind == "plateau":  # flat tops: only the rising edge of a plateau is a peak
        y = np.minimum(np.abs(_arc(w, r1, t1).imag) + np.abs(_arc(w, r1, t1 * 1e4).imag), 0.3 * r1)
        return r0 + r1 * 0.5 - 1j * y
    raise ValueError(kind)


def _round_significant(x, digits):
    scale = 10.0 ** (np.floor(np.log10(np.maximum(np.abs(x), 1e-300))) - digits)
    return np.round(x / scale) * scale


KINDS = ("rc", "cpe", "two_overlapping", "two_apart", "three", "inductive", "warburg", "open_warburg", "series_capacitor", "no_negative_imag", "resistor", "quantised", "equal_peaks", "plateau")


def _stack(freq, rng, per_kind=6, noise=0.01):
    """Rows of every family; every other row carries 1 % proportional complex noise."""
    w = 2 * np.pi * np.asarray(freq, float)
    rows = []
    for kind in KINDS:
        for i in range(per_kind):
            z = _family(w, kind, rng)
            if i % 2 and kind not in ("equal_peaks", "quantised", "resistor"):
                z = z + noise * np.abs(z) * (rng.normal(size=z.shape) + 1j * rng.normal(size=z.shape))
            rows.append(z)
    return np.stack(rows)


GRIDS = {
    "60 rising": np.geomspace(0.01, 1e6, 60),
    "41 falling (instrument order)": np.geomspace(1e6, 0.1, 41),
    "decade points": np.logspace(-2, 5, 8),
    "3 points": np.array([10.0, 1e3, 1e5]),
    "2 points": np.array([1e4, 10.0]),
    "1 point": np.array([100.0]),
}


@pytest.fixture(scope="module", params=list(GRIDS))
def stack(request):
    freq = GRIDS[request.param]
    return freq, _stack(freq, np.random.default_rng(7 + len(freq)))


# ---- features --------------------------------------------------------------------------------

SCALARS = ("f_min", "f_max", "z_min", "z_max", "r_hf", "r_lf", "f_peak", "c_series", "l_series", "alpha_lf", "warburg")


def test_stack_features_equal_per_spectrum_oracle(stack):
    freq, z = stack
    feats = SpectrumFeatures(freq, z)
    oracles = [OracleFeatures(freq, row) for row in z]
    for name in SCALARS:
        got = getattr(feats, name)
        want = np.array([getattr(o, name) for o in oracles])
        if name in ("f_min", "f_max"):  # shared frequencies: one value for the stack
            assert np.ndim(got) == 0 and got == want[0]
        else:
            assert np.shape(got) == (len(z),), name
            np.testing.assert_allclose(got, want, rtol=RTOL, err_msg=name)


@pytest.mark.parametrize("n_arc", [1, 2, 3, 5])
def test_stack_arcs_equal_per_spectrum_oracle(stack, n_arc):
    freq, z = stack
    r, tau = SpectrumFeatures(freq, z).arcs(n_arc)
    assert r.shape == tau.shape == (len(z), n_arc)
    for i, row in enumerate(z):
        r_i, tau_i = OracleFeatures(freq, row).arcs(n_arc)
        np.testing.assert_allclose(r[i], r_i, rtol=RTOL, err_msg=f"row {i}")
        np.testing.assert_allclose(tau[i], tau_i, rtol=RTOL, err_msg=f"row {i}")


def test_one_spectrum_keeps_scalar_features(stack):
    freq, z = stack
    for row in z[::5]:
        feats, oracle = SpectrumFeatures(freq, row), OracleFeatures(freq, row)
        for name in SCALARS:
            got, want = getattr(feats, name), getattr(oracle, name)
            assert type(got) is type(want), name
            assert got == pytest.approx(want, rel=RTOL, nan_ok=True), name
        for n_arc in (1, 3):
            r, tau = feats.arcs(n_arc)
            r_o, tau_o = oracle.arcs(n_arc)
            assert r.shape == tau.shape == (n_arc,)
            np.testing.assert_allclose(r, r_o, rtol=RTOL)
            np.testing.assert_allclose(tau, tau_o, rtol=RTOL)


def test_indexing_a_stack_gives_each_spectrum_own_features(stack):
    freq, z = stack
    feats = SpectrumFeatures(freq, z)
    assert len(feats) == len(z)
    for i in (0, 7, len(z) - 1, -1):
        one, ref = feats[i], SpectrumFeatures(freq, z[i])
        for name in SCALARS:
            assert type(getattr(one, name)) is type(getattr(ref, name)) and getattr(one, name) == getattr(ref, name)
        np.testing.assert_array_equal(one.arcs(2)[0], ref.arcs(2)[0])
    sub = feats[np.array([3, 1, 3])]
    assert len(sub) == 3
    np.testing.assert_array_equal(sub.r_hf, feats.r_hf[[3, 1, 3]])
    np.testing.assert_array_equal(sub.arcs(2)[1], feats.arcs(2)[1][[3, 1, 3]])
    with pytest.raises(TypeError):
        SpectrumFeatures(freq, z[0])[0]


def test_equal_peaks_are_taken_in_listed_order():
    """Hand-worked: equal interior peaks at 10 Hz and 1 kHz; the first listed (10 Hz) is the
    tallest, so one arc sits at 10 Hz, and a third arc is split from it two decades below."""
    f = np.array([1.0, 10.0, 100.0, 1e3, 1e4])
    z = 5.0 - 1j * np.array([0.0, 2.0, 0.0, 2.0, 0.0])
    r_total = max(5.0 * 1.01 - 5.0, 0.05 * np.sqrt(29.0))  # r_lf is lifted to 1.01 r_hf
    for feats in (SpectrumFeatures(f, z), SpectrumFeatures(f, np.stack([z, z]))[1]):
        r, tau = feats.arcs(1)
        np.testing.assert_allclose(1 / (2 * np.pi * tau), [10.0], rtol=1e-15)
        np.testing.assert_allclose(r, [r_total], rtol=1e-15)
        r, tau = feats.arcs(3)
        np.testing.assert_allclose(1 / (2 * np.pi * tau), [1e3, 10.0, 0.1], rtol=1e-15)
        np.testing.assert_allclose(r, [r_total / 3] * 3, rtol=1e-15)


# ---- guesses ---------------------------------------------------------------------------------

CIRCUITS = {
    "R0 + R1 || CPE1 + R2 || CPE2": ({"CPE1.alpha": 0.8}, {"R0": 12.0}),
    "R0 + R1 || C1": ({"C1": 1e-12}, {"R1": 2e3}),
    "R0 + (R1 + W1) || CPE1": ({"W1.sigma": 50.0}, {"CPE1.alpha": 0.9}),
    "C_i + R_sc || C_sc + R_f": ({"R_sc": 1e5}, {"C_i": 1.7e-9}),
    "R0 + L0 + R1 || CPE1": ({"L0": 1e-6}, {"R0": 20.0}),
    "R0 + Wo1 + R1 || CPE1 + R2 || C2 + R3 || C3": ({"Wo1.tau": 2.0, "C3": 1e-4}, {"R3": 100.0}),
    "R0 + (R1 + Ws1) || Q1 + G1": ({"Q1.alpha": 0.7}, {"G1.tau": 1e-3}),
    "R0 + R1 || HN1 + CC1": ({"HN1.beta": 0.6}, {"CC1.alpha": 0.8}),
    "R1 || (R2 + C2 || R3) + L1 + W1": ({}, {"L1": 1e-7}),
    "R0 + R1 || C1 + CPE2": ({"R1": 500.0}, {"R0": 5.0}),  # a CPE in the outer chain
    "R0 + R1 || C1 + R2 + C3": ({}, {"C3": 1e-3}),  # two resistors share the outer chain
}
TABLES = ("free", "init", "fixed", "init and fixed")


def _table(text, which):
    init, fixed = CIRCUITS[text]
    circuit = ix.parse(text)
    return circuit, ParameterTable.build(circuit, init=init if "init" in which else None, fixed=fixed if "fixed" in which else None)


@pytest.mark.parametrize("which", TABLES)
@pytest.mark.parametrize("text", list(CIRCUITS))
def test_stack_guesses_equal_per_spectrum_oracle(stack, text, which):
    freq, z = stack
    circuit, table = _table(text, which)
    got = data_driven_guesses(circuit, table, SpectrumFeatures(freq, z))
    want = np.stack([oracle_guess(circuit, table, OracleFeatures(freq, row)) for row in z])
    assert got.shape == (len(z), len(table.names))
    np.testing.assert_allclose(got, want, rtol=RTOL)
    assert np.all(np.isfinite(got))
    given = ~np.isnan(table.values)
    np.testing.assert_array_equal(got[:, given], np.broadcast_to(table.values[given], (len(z), given.sum())))


@pytest.mark.parametrize("text", list(CIRCUITS))
def test_one_spectrum_guess_equals_oracle(stack, text):
    freq, z = stack
    circuit, table = _table(text, "init and fixed")
    for row in z[::4]:
        got = data_driven_guess(circuit, table, SpectrumFeatures(freq, row))
        assert got.shape == (len(table.names),)
        np.testing.assert_allclose(got, oracle_guess(circuit, table, OracleFeatures(freq, row)), rtol=RTOL)


def test_guess_start_gives_one_start_per_spectrum():
    freq = GRIDS["60 rising"]
    z = _stack(freq, np.random.default_rng(3), per_kind=2)
    circuit, table = _table("R0 + R1 || CPE1 + R2 || CPE2", "fixed")
    stacked = guess_start(circuit, table, SpectrumFeatures(freq, z), DEFAULT_REGISTRY)
    one_by_one = np.concatenate([guess_start(circuit, table, SpectrumFeatures(freq, row), DEFAULT_REGISTRY) for row in z])
    assert stacked.shape == (len(z), int((~table.fixed).sum()))
    np.testing.assert_allclose(stacked, one_by_one, rtol=RTOL)


@pytest.mark.parametrize("which", TABLES)
@pytest.mark.parametrize("text", list(CIRCUITS))
def test_stack_random_starts_equal_per_spectrum_oracle(stack, text, which):
    """Starts for a stack (the multistart of a batch's poorly fitted spectra) are, row by
    row, those each spectrum draws alone: the same random numbers, its own ranges."""
    freq, z = stack
    circuit, table = _table(text, which)
    features = SpectrumFeatures(freq, z)
    guesses = data_driven_guesses(circuit, table, features)
    got = random_starts(table, features, guesses, 9, seed=4)
    assert got.shape == (len(z), 9, len(table.names))
    for row, guess, starts in zip(z, guesses, got):
        np.testing.assert_allclose(starts, oracle_random_starts(table, OracleFeatures(freq, row), guess, 9, 4), rtol=RTOL)
    one = random_starts(table, SpectrumFeatures(freq, z[0]), guesses[0], 9, seed=4)
    np.testing.assert_array_equal(one, got[0])
