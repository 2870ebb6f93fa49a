"""Two arcs at one τ are one arc to the data: the fit says so and advises dropping one (fixing
a parameter, as the group note advised, left the rest undetermined: --fix R2=10 sent C2 to
3e10 F on the REAL ZPlot file), and compare counts that model among those reducing to the best
instead of calling it the best's rival (a walkthrough, 2026-12-04)."""

from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import impedax as ix

REAL = Path(__file__).resolve().parent / "fixtures" / "real"
TWO_ARCS = "R0 + R1 || C1 + R2 || C2"


@pytest.fixture(scope="module")
def zplot():
    return ix.load(REAL / "exampleDataZPlot.z")


def _same_arc_notes(warnings):
    return [w for w in warnings if "relax at the same τ" in w]


def test_two_arcs_at_one_tau_are_named_with_the_advice_to_drop_one(zplot):
    fit = ix.fit(TWO_ARCS, zplot)
    v = fit.values
    tau1, tau2 = v["R1"] * v["C1"], v["R2"] * v["C2"]  # (the premise, from the fitted values alone)
    assert tau2 == pytest.approx(tau1, rel=0.01)
    [note] = _same_arc_notes(fit.warnings)
    assert note.startswith("R1 || C1 and R2 || C2 relax at the same τ = ") and "drop one of the two arcs" in note
    assert not any("fix one of them" in w for w in fit.warnings)
    # the claim, checked by fitting one arc: the same misfit
    one = ix.fit("R0 + R1 || C1", zplot)
    assert one.rms_rel == pytest.approx(fit.rms_rel, rel=1e-3)
    assert v["R1"] + v["R2"] == pytest.approx(one.values["R1"], rel=1e-3)  # (in series at one τ: R = R1 + R2)
    # a batch says the same of each spectrum
    batch = ix.fit(TWO_ARCS, xr.concat([zplot, zplot], dim="copy"), init=dict(v), n_starts=1)
    assert all(len(_same_arc_notes(ws)) == 1 for ws in batch.warnings.values()) and len(batch.warnings) == 2


def test_two_arcs_apart_get_no_such_note():
    f = np.geomspace(0.1, 1e5, 50)
    jw = 2j * np.pi * f
    z = 20 + 300 / (1 + 300 * 2e-6 * jw) + 800 / (1 + 800 * 1e-3 * jw)  # SYNTHETIC: τ 0.6 ms and 0.8 s
    z = z * (1 + 0.002 * np.random.default_rng(0).standard_normal(f.size))
    fit = ix.fit(TWO_ARCS, ix.make_spectrum(f, z))
    assert not _same_arc_notes(fit.warnings) and fit.rms_rel < 0.005


def test_compare_counts_the_two_arc_model_as_reducing_to_the_best(zplot):
    c = ix.compare([ix.fit(m, zplot) for m in ("R0 + R1 || CPE1", "R0 + R1 || CPE1 + W1", TWO_ARCS)])
    assert c.best == "R0 + R1 || CPE1"
    assert c.rows[2]["same_fit_as"] == "R0 + R1 || CPE1 + W1"
    assert c.reduces_to_best()["rivals"] == ["R0 + R1 || CPE1 + W1", TWO_ARCS]
    assert c.weak_evidence() is None  # (it was: "the data barely tell R0 + R1 || CPE1 from R0 + R1 || C1 + R2 || C2")
