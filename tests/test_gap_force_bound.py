"""The force when the gap thickness u is not determined (docs/models.md, "The force when u is
not determined").

Eq 1, F = ½ ε0 ε_gap A |ΔV_gap|²/u², goes as 1/u²: where the data give only u ≥ u_b, they give
F ≤ F(u_b), an UPPER bound of the force, and the force of a u the priors set is no estimate; the
further u runs up its prior, the smaller that force. A 2026-12-01 walkthrough (ideal C_EP under
the default --ep CPE) got u from the prior's upper edge, 3.5 m, printed "force … max 1.4 pN"
for a true ~2 N and warned "the force is then an upper bound", with "check the area's unit
first" where the area was right. SYNTHETIC spectra written in numpy below."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.bayes.reparam import AREA_UNIT_ADVICE
from impedax.io.export import to_jsonable
from impedax.models.gap import _area_advice, _unidentified_note, gap_analysis, gap_bounds

EPS0 = 8.8541878128e-12
EPS_AIR = 1.00059
AREA = 130e-6
C_GAP = 413e-12
U_TRUE = EPS0 * EPS_AIR * AREA / C_GAP  # 2.787 µm
V0 = 75.0
F = np.geomspace(1.0, 1e6, 41)
W = 2 * np.pi * F
SKIN = 300.0 + 1.0 / (1.0 / 2e5 + 3e-8 * (1j * W) ** 0.8)
TS = 50.0 + 1.0 / (1.0 / 2e4 + 8e-11 * (1j * W) ** 0.9)


def _remainder(ep_admittance):
    return 1.0 / (1.0 / 5e7 + ep_admittance + 1j * W * C_GAP)


def _spectra(rng, remainder):
    """Total, skin and screen, one spectrum each with 0.3 % complex noise (SYNTHETIC)."""
    noisy = lambda z: ix.make_spectrum(F, z * (1 + 0.003 * (rng.normal(size=F.size) + 1j * rng.normal(size=F.size))))  # noqa: E731
    return noisy(SKIN + TS + remainder), noisy(SKIN), noisy(TS)


def _force_numpy(remainder, u):
    """Eq 1 in numpy: the PEAK force [N] at u [m], the remainder's voltage (all three of its
    branches are in parallel, so the voltage across C_gap) from the divider V0 Z_R/(Z_TS + Z_R + Z_skin)."""
    v_gap = V0 * remainder / (TS + remainder + SKIN)
    return 0.5 * EPS0 * EPS_AIR * AREA * np.abs(v_gap) ** 2 / u**2


@pytest.fixture(scope="module")
def ideal_ep():
    """An ideal C_EP = 100 pF beside C_gap, analysed with the default --ep CPE (pooled): u is
    not determined (only C_EP + C_gap is)."""
    remainder = _remainder(1j * W * 100e-12)
    return gap_analysis(*_spectra(np.random.default_rng(21), remainder), area=AREA, v0=V0, method="pooled", steps=300, progress=False), remainder


def test_undetermined_u_bounds_the_force_from_above(ideal_ep):
    """The force bound is eq 1 at u's lower bound (numpy, within 2 %: the voltage of the fitted
    remainder between the measured skin and screen, 0.3 % noise, against the true ones; 1.1 %
    at the worst point, near 400 kHz where the force is 300× below its peak) and lies above the
    true force, as an upper bound must."""
    result, remainder = ideal_ep
    assert result.gap_identified is False and result.gap_lower_bound < U_TRUE
    bound = result.force_upper_bound
    np.testing.assert_allclose(bound.values, _force_numpy(remainder, result.gap_lower_bound), rtol=0.02)
    true_force = _force_numpy(remainder, U_TRUE)
    assert np.all(bound.values >= true_force)
    assert bound.max() == pytest.approx(true_force.max() * (U_TRUE / result.gap_lower_bound) ** 2, rel=0.01)


def test_undetermined_u_says_the_force_is_not_determined(ideal_ep):
    result, _ = ideal_ep
    note = next(w for w in result.warnings if w.startswith("u is NOT determined by these data"))
    assert "the force is then an upper bound" not in note
    assert "The force is NOT determined either: eq 1 goes as 1/u², so u ≥ that bound gives only an upper bound of the force" in note
    lines = result.report().splitlines()
    force = next(line for line in lines if line.startswith("force (peak"))
    assert re.match(r"force \(peak, V0 = 75 V\) of the prior-set u, NO ESTIMATE of the force: with EP: (max |[0-9.]+ mN on a plateau over )", force)  # (a plateau named since 2026-12-05)
    bound_line = lines[lines.index(force) + 1]
    assert bound_line.startswith(f"force bound     F ≤ {ix.data.format_quantity(float(result.force_upper_bound.max()), 'N')} (peak, with EP")
    assert f"u's lower bound {result.gap_lower_bound * 1e6:.3f} µm" in bound_line
    assert next(line for line in lines if line.startswith("C_gap")).startswith("C_gap (prior-set) = ")
    s = json.loads(json.dumps(to_jsonable(result.summary()), allow_nan=False))
    assert s["force_determined"] is False and s["force_n"]["median"]  # (the sampled band's key stays: a contract)
    assert s["force_upper_bound_n"]["max"] == pytest.approx(float(result.force_upper_bound.max()))
    assert s["force_upper_bound_n"]["frequency_hz"] == list(F) and len(s["force_upper_bound_n"]["value"]) == F.size
    assert result.to_xarray().attrs["force_upper_bound_max_n"] == pytest.approx(s["force_upper_bound_n"]["max"])


def test_u_run_up_its_prior_gives_a_lower_bound_at_best():
    """The walkthrough's case, with draws of u spread up to the prior's upper edge (3.5 m at
    4 cm²): the note says the sampled force lies far BELOW what the data allow, a lower bound at
    best; draws at the bound itself say nothing of the kind."""
    low, high = gap_bounds(4e-4)
    bound = 1.589e-6
    runaway = np.geomspace(3.8e-6, high, 1000)
    note = _unidentified_note("the EP CPE's α is 0.994", bound, runaway, (low, high))
    median = float(np.median(runaway))
    assert f"lies {median / bound:.3g}× above the bound, which puts the force about {(median / bound) ** 2:.3g}× below the largest the data allow" in note
    assert f"its draws run to the upper edge of u's prior, {high:.3g} m, where the force is smallest" in note
    assert note.endswith("a force drawn from it is at best a lower bound, not an upper one")
    near = _unidentified_note("the EP CPE's α is 0.994", bound, np.linspace(1.0, 1.1, 100) * bound, (low, high))
    assert near.endswith("the sampled forces come from the prior-set u and are no estimate")


def test_area_unit_advice_only_where_the_area_can_be_the_cause(ideal_ep):
    """"check the area's unit first" stays when the paper's method gives no air gap at this
    area (a unit slip: mm² as m² gives u × 10⁶), and is replaced when it gives one."""
    result, _ = ideal_ep
    note = f"sampling: u = 0.00372 m (posterior median) is no air gap (1e-09–0.001 m is): {AREA_UNIT_ADVICE}, A = 0.0004 m², then the data"
    replaced = _area_advice([note, "other"], result.paper, identified=False)
    assert replaced[1] == "other" and AREA_UNIT_ADVICE not in replaced[0]
    assert replaced[0].endswith(f"the area's unit is not the cause: at A = {AREA:g} m² the paper's method gives u = {result.paper.gap * 1e6:.3f} µm, "
                                "within 1 nm–1 mm, which a unit slip of A (10⁶×) would not: u is not determined by these data (the warning 'u is NOT determined')")
    assert "an air gap" not in replaced[0]  # (beside the alarm NO AIR GAP it read as a contradiction)
    assert _area_advice([note], result.paper, identified=True)[0].endswith("check the three spectra and the model")
    from dataclasses import replace

    slipped = replace(result.paper, gap=result.paper.gap * 1e6)  # (the same capacitance at an area 10⁶ too large)
    assert _area_advice([note], slipped, identified=False) == [note]
    assert not any(AREA_UNIT_ADVICE in w for w in result.warnings)


def test_determined_u_keeps_its_force_report():
    """A CPE EP branch (α = 0.3) the data tell from C_gap: u determined, the force line as
    before, no bound line or key."""
    result = gap_analysis(*_spectra(np.random.default_rng(21), _remainder(4e-9 * (1j * W) ** 0.3)), area=AREA, v0=V0, method="pooled", steps=300, progress=False)
    assert result.gap_identified is True and result.force_upper_bound is None
    lines = result.report().splitlines()
    force = next(line for line in lines if line.startswith("force (peak"))
    assert re.match(r"force \(peak, V0 = 75 V\) with EP: (max |[0-9.]+ mN on a plateau over )", force)
    assert not any(line.startswith("force bound") for line in lines)
    assert next(line for line in lines if line.startswith("C_gap")).startswith("C_gap           = ")
    s = result.summary()
    assert s["force_determined"] is True and s["force_upper_bound_n"] is None
    assert np.isnan(result.to_xarray().attrs["force_upper_bound_max_n"])
    assert result.gap["value"] == pytest.approx(U_TRUE, rel=0.05)


def test_a_lower_bound_beyond_any_air_gap_prints_with_its_prefix():
    """u ≥ 18.8 mm (a resistive remainder's summed capacitance), not "u ≥ 18796.913 µm"; a bound
    within an air gap keeps µm to three decimals."""
    far = 0.0187969
    note = _unidentified_note("the remainder is resistive", far, np.linspace(1.0, 1.1, 100) * far, (1e-12, 10.0))
    assert "u ≥ 18.8 mm (" in note and "µm" not in note.split("(")[0]
    near = _unidentified_note("the remainder is resistive", 2.5e-6, np.linspace(1.0, 1.1, 100) * 2.5e-6, (1e-12, 10.0))
    assert "u ≥ 2.500 µm (" in near
