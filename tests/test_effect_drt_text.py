"""Which DRT peak an ``extra_relaxation`` suggestion names (impedax.fitting.diagnosis.effects:
`drt_citation`, `cited_where`).

The words were made before the fit and named the peak the warm start came from, whatever the
fit ended at, even a peak outside the measured window: on AutoEIS's battery cycle 64 with
``R0 + R1 || CPE1`` the first suggestion read "(τ from the data's DRT peak at 25 s that the
model does not explain)" for an arc fitted at R·C = 43.6 ms (the DRT's 25 s peak lies beyond
the band's lowest frequency). A peak is now named only when it is one the baseline does not
explain, inside the measured window, and within half a decade of the fitted τ (R·C, or
(R·Q)^(1/α)), computed here in numpy from the fitted values.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.diagnosis.catalog import Proposal
from impedax.fitting.diagnosis.effects import cited_where, drt_citation
from impedax.fitting.drt import PeakEvidence, drt, unexplained_peaks
from impedax.fitting.drt.peaks import Peak

ROOT = Path(__file__).resolve().parents[1]
BATTERY = ROOT / "examples" / "data" / "autoeis_battery_cycles.nc"

_PREFIX = {"k": 1e3, "": 1.0, "m": 1e-3, "µ": 1e-6, "n": 1e-9}
_SECONDS = r"([\d.]+(?:e[+-]?\d+)?) (k|m|µ|n)?s"
_CITED = re.compile(r"\(fitted τ = " + _SECONDS + r", within half a decade of the data's DRT peak at " + _SECONDS + r" that the model does not explain\)")


def _seconds(number: str, prefix: str | None) -> float:
    return float(number) * _PREFIX[prefix or ""]


def _tau_numpy(values, added: str) -> float:
    """The new arc's τ from the fitted values: R·C, or (R·Q)^(1/α) for R ∥ CPE."""
    r_name, c_name = (x.strip() for x in added.split("||"))
    r = float(values[r_name])
    if c_name.startswith("CPE"):
        return float((r * values[f"{c_name}.Q"]) ** (1.0 / values[f"{c_name}.alpha"]))
    return r * float(values[c_name])


def _proposal(s) -> Proposal:
    return Proposal(s.effect, s.fit.circuit, s.added, s.where, ())


def _check_citations(text: str, values, added: str, evidence: PeakEvidence):
    """Each citation in ``text``: the fitted τ is the numpy one, and the peak is an unexplained,
    in-window peak of ``evidence`` within half a decade of it."""
    for m in _CITED.finditer(text):
        tau, peak_tau = _seconds(*m.group(1, 2)), _seconds(*m.group(3, 4))
        assert tau == pytest.approx(_tau_numpy(values, added), rel=0.006)
        peak = min(evidence.unexplained, key=lambda p: abs(math.log10(p.tau_s / peak_tau)))
        assert peak.tau_s == pytest.approx(peak_tau, rel=0.006) and peak.inside_window
        assert abs(math.log10(_tau_numpy(values, added) / peak.tau_s)) <= 0.5


# --- AutoEIS battery cycle 64 (REAL data) -------------------------------------------------------


@pytest.fixture(scope="module")
def cycle64():
    data = ix.load(BATTERY)
    data = data.isel(cycle=int(np.flatnonzero(data["cycle"].values == 64)[0]))
    return ix.diagnose(data, "R0 + R1 || CPE1")


def test_cycle64_does_not_cite_the_peak_outside_the_band(cycle64):
    d = cycle64
    ev = d.drt
    assert ev is not None
    far = [p for p in ev.unexplained if not p.inside_window]
    assert far and all(p.tau_s > 10 for p in far)  # the 25 s peak, beyond 1/(2π·21 mHz)
    best = d.best
    assert best.effect == "extra_relaxation" and best.added == "R_relax || C_relax"  # unchanged ranking
    tau = _tau_numpy(best.fit.values, best.added)
    assert tau == pytest.approx(43.6e-3, rel=0.01)
    # no unexplained in-window peak lies within half a decade of 43.6 ms (5.2 ms is 0.9 decade off)
    assert all(abs(math.log10(tau / p.tau_s)) > 0.5 for p in ev.unexplained if p.inside_window)
    assert cited_where(best.effect, _proposal(best), best.fit.values, best.fit.registry, ev) == "nested in series with R1 (a layer behind that arc)"
    for s in d.candidates:
        where = cited_where(s.effect, _proposal(s), s.fit.values, s.fit.registry, ev)
        assert "25 s" not in where and "τ from" not in where
        if s.effect == "extra_relaxation":
            _check_citations(where, s.fit.values, s.added, ev)
    assert "DRT peak at 25 s" not in d.report()
    assert "DRT peak" not in best.explanation and "DRT peak" not in best.where


# --- a SYNTHETIC missing arc inside the window ---------------------------------------------------


def _jw(f):
    return 1j * 2 * np.pi * f


@pytest.fixture(scope="module")
def missing_arc():
    """R0 + R1 ∥ C1 + R2 ∥ C2 (τ 1 ms and 1 s, inside 10 mHz–100 kHz), 0.5 % noise, fitted by
    R0 + R1 ∥ C1: the 1 s arc is missing."""
    rng = np.random.default_rng(7)
    f = np.logspace(-2, 5, 57)
    z = 10 + 100 / (1 + _jw(f) * 1e-3) + 40 / (1 + _jw(f) * 1.0)
    z = z * (1 + 0.005 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)))
    return ix.make_spectrum(f, z)


def test_a_fitted_arc_at_an_in_window_peak_cites_it(missing_arc):
    base = ix.fit("R0 + R1 || C1", missing_arc, n_starts=4)
    ev = unexplained_peaks(drt(missing_arc), base)
    (peak,) = [p for p in ev.unexplained if p.inside_window and abs(math.log10(p.tau_s)) < 0.3]
    cand = ix.fit("R0 + R1 || C1 + R_relax || C_relax", missing_arc, n_starts=4)
    tau = _tau_numpy(cand.values, "R_relax || C_relax")
    assert abs(math.log10(tau)) < 0.1  # the fit found the 1 s arc
    p = Proposal("extra_relaxation", cand.circuit, "R_relax || C_relax", "in series with the whole circuit", ())  # (as `_extra_relaxation` places it)
    where = cited_where("extra_relaxation", p, cand.values, cand.registry, ev)
    assert where.startswith("in series with the whole circuit (fitted τ = ") and where.count("DRT peak") == 1
    assert _CITED.search(where)
    _check_citations(where, cand.values, "R_relax || C_relax", ev)
    assert cited_where("extra_relaxation", Proposal(p.effect, p.circuit, p.added, where, ()), cand.values, cand.registry, ev) == where  # idempotent
    # derived placements keep the citation right after the placement
    derived = Proposal(p.effect, p.circuit, p.added, p.where + ", and R0 left out (why)", ())
    assert cited_where("extra_relaxation", derived, cand.values, cand.registry, ev) == where + ", and R0 left out (why)"
    # without DRT evidence, or for another effect, nothing is cited
    assert cited_where("extra_relaxation", p, cand.values, cand.registry, None) == "in series with the whole circuit"
    assert drt_citation("constant_phase", p, cand.values, cand.registry, ev) == ""


def test_the_diagnosis_cites_the_in_window_peak(missing_arc):
    d = ix.diagnose(missing_arc, "R0 + R1 || C1")
    best = d.best
    assert best.effect == "extra_relaxation" and best.added == "R_relax || C_relax"
    m = _CITED.search(best.explanation)
    assert m and best.where in best.explanation
    _check_citations(best.explanation, best.fit.values, best.added, d.drt)


# --- the rule, on peaks made by hand -------------------------------------------------------------


def _peak(tau, r, inside=True):
    return Peak(tau_s=tau, r_ohm=r, width_decades=1.0, gamma_max_ohm=r, inside_window=inside)


def _evidence(*peaks):
    return PeakEvidence(data_peaks=peaks, model_peaks=(), explained=(), unexplained=peaks, nearest_model_tau=tuple(math.nan for _ in peaks), distributed=(), text="")


ARC = Proposal("extra_relaxation", ix.parse("R0 + R_relax || C_relax"), "R_relax || C_relax", "in series with the whole circuit", ())


@pytest.mark.parametrize(
    "peaks, tau, cited",
    [
        ((_peak(25.0, 2.0, inside=False),), 25.0, None),  # outside the window: never
        ((_peak(0.1, 2.0),), 0.1 * 10**0.45, 0.1),  # within half a decade
        ((_peak(0.1, 2.0),), 0.1 * 10**0.55, None),  # beyond it
        ((_peak(0.1, 2.0), _peak(0.4, 1.0)), 0.2, 0.1),  # the warm start's (largest) peak when it qualifies
        ((_peak(0.01, 2.0), _peak(0.4, 1.0), _peak(0.05, 0.5)), 0.3, 0.4),  # else the nearest
        ((_peak(25.0, 2.0, inside=False), _peak(5e-3, 1.0)), 43.6e-3, None),  # cycle 64's case
    ],
)
def test_which_peak_is_cited(peaks, tau, cited):
    values = {"R0": 1.0, "R_relax": 2.0, "C_relax": tau / 2.0}
    text = drt_citation("extra_relaxation", ARC, values, ix.DEFAULT_REGISTRY, _evidence(*peaks))
    if cited is None:
        assert text == ""
    else:
        m = _CITED.search(text)
        assert m and _seconds(*m.group(3, 4)) == pytest.approx(cited, rel=0.006)
        assert _seconds(*m.group(1, 2)) == pytest.approx(tau, rel=0.006)


def test_a_peak_the_drt_does_not_tell_from_zero_is_never_cited():
    """REAL PowerSuite: the DRT line calls the 4.8 ms peak a ripple (R ≈ 99 ± 55 kΩ), and the
    top suggestion cited it in support two lines below; a resolved peak nearby is cited instead."""
    ripple, resolved = _peak(0.1, 2.0), _peak(0.3, 1.0)
    values = {"R0": 1.0, "R_relax": 2.0, "C_relax": 0.1 / 2.0}
    alone = PeakEvidence(data_peaks=(ripple,), model_peaks=(), explained=(), unexplained=(ripple,), nearest_model_tau=(math.nan,), distributed=(), text="", unresolved=(ripple,))
    assert drt_citation("extra_relaxation", ARC, values, ix.DEFAULT_REGISTRY, alone) == ""
    assert _CITED.search(drt_citation("extra_relaxation", ARC, values, ix.DEFAULT_REGISTRY, _evidence(ripple)))  # (the same peak, resolved)
    both = PeakEvidence(data_peaks=(ripple, resolved), model_peaks=(), explained=(), unexplained=(ripple, resolved), nearest_model_tau=(math.nan, math.nan),
                        distributed=(), text="", unresolved=(ripple,))
    m = _CITED.search(drt_citation("extra_relaxation", ARC, {**values, "C_relax": 0.2 / 2.0}, ix.DEFAULT_REGISTRY, both))
    assert m and _seconds(*m.group(3, 4)) == pytest.approx(0.3, rel=0.006)


def test_a_cpe_arc_uses_its_own_time_constant():
    tau, alpha = 0.1, 0.8
    values = {"R0": 1.0, "R_relax": 2.0, "CPE_relax.Q": tau**alpha / 2.0, "CPE_relax.alpha": alpha}
    p = Proposal("extra_relaxation", ix.parse("R0 + R_relax || CPE_relax"), "R_relax || CPE_relax", "in series with the whole circuit", ())
    text = drt_citation("extra_relaxation", p, values, ix.DEFAULT_REGISTRY, _evidence(_peak(0.25, 1.0)))
    m = _CITED.search(text)
    assert m and _seconds(*m.group(1, 2)) == pytest.approx(_tau_numpy(values, "R_relax || CPE_relax"), rel=0.006)
def test_plausibility_notes_write_frequencies_as_impedax_does_elsewhere():
    """The inductive loop's and the finite Warburg's plausibility notes gave ``{:.3g} Hz``
    ("1.59e+04–3.18e+04 Hz", "band (0.1–1e+03 Hz)"); they use `format_band`/`format_frequency`.
    Oracle: R_loop/(2πL) = 1e3/(2π·0.01) = 15.9 kHz, (R + R_loop)/(2πL) = 2e3/(2π·0.01) = 31.8 kHz;
    5/(2π·1e-6 s) = 796 kHz."""
    from impedax.circuits import parse
    from impedax.fitting.diagnosis.catalog import Proposal
    from impedax.fitting.diagnosis.effects import DEFAULT_EFFECTS

    effects = {e.id: e for e in DEFAULT_EFFECTS.effects}
    loop = Proposal("inductive_loop", parse("R0 + R1 || (R_loop + L_loop) || C1"), "R_loop + L_loop", "R1", ({},), band=(0.1, 1e3))
    note = effects["inductive_loop"].plausible({"R0": 10.0, "R1": 1e3, "C1": 1e-6, "R_loop": 1e3, "L_loop": 0.01}, loop)
    assert "put the loop at 15.9 kHz–31.8 kHz, outside the band (100 mHz–1 kHz)" in note, note
    warburg = Proposal("diffusion", parse("R0 + Ws_d"), "Ws_d", "end", ({},), band=(0.1, 1e3))
    note = effects["diffusion"].plausible({"R0": 10.0, "Ws_d.R": 100.0, "Ws_d.tau": 1e-6}, warburg)
    assert "(45°, from 796 kHz) lies above the band's top (1 kHz)" in note, note
