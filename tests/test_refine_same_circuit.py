"""refine treats a circuit and a renamed copy of it as one model (`Circuit.structure_key`).

From C_gap on the SYNTHETIC Sirin remainder (examples/sirin_remaining_impedance.py) the greedy
path took R_EP ∥ CPE_EP across C_gap and ended adequate; the path of the cheaper C_gap → CPE_gap
then added R_EP ∥ C_EP and reached R_EP ∥ C_EP ∥ CPE_gap, the same network under other names.
It was diagnosed again and noted as "ends at R_EP || C_EP || CPE_gap (AIC -1408.9, 4
parameters) against R_EP || CPE_EP || C_gap (AIC -1408.9, 4 parameters) ... the data do not
tell the two apart". Now two ends of one network are not compared unless the later one is
kept (a better fit, or a tie that keeps more of the user's elements, whose names it keeps), and
no path starts from a renamed copy of a start already taken.
"""

from __future__ import annotations

from types import SimpleNamespace as NS

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.diagnosis import Verdict, refinement
from impedax.fitting.diagnosis.refinement import _distinct_networks


def key(text: str) -> str:
    return ix.parse(text).structure_key()


@pytest.mark.parametrize(
    "a, b",
    [
        ("R_a || C_a + R_b || C_b", "R_b || C_b + R_a || C_a"),  # the parts of a series node in another order
        ("R_a || C_a + R_b || C_b", "C_x || R_x + R_y || C_y"),  # and of each parallel node, under other names
        ("R_EP || CPE_EP || C_gap", "R_EP || C_EP || CPE_gap"),  # the Sirin case
        ("R1 + (R2 + C1)", "C9 + R8 + R7"),  # nested series groups flatten
        ("R1 || (C1 || R2)", "R5 || R6 || C7"),  # and parallel ones
        ("R0 + (R1 + W1) || CPE1", "CPE_dl || (W_d + R_ct) + R_s"),
        ("R0 + Q1 || R1", "R0 + CPE1 || R1"),  # an alias is the kind it stands for
    ],
)
def test_renamed_and_reordered_copies_have_one_structure_key(a, b):
    assert key(a) == key(b)
    assert str(ix.parse(a)) != str(ix.parse(b))  # (they are not one text)


@pytest.mark.parametrize(
    "a, b",
    [
        ("R1 + C1 || R2", "(R1 + C1) || R2"),  # series then parallel, or parallel of a series
        ("R1 + C1 || R2", "C1 + R1 || R2"),  # which element is in series
        ("R1 || C1", "R1 || CPE1"),  # an element of another kind
        ("R1 || C1", "R1 + C1"),
        ("R1 || C1 + R2 || C2", "R1 || C1 + R2 || CPE2"),
        ("R1 + R2", "R1 + R2 + R3"),  # another count
    ],
)
def test_different_networks_have_different_structure_keys(a, b):
    assert key(a) != key(b)


def _suggestion(effect, model, n_params, added, where="across C_gap", aic=-1400.0):
    fit = NS(circuit=ix.parse(model), model=model, aic=aic, chi2=1.0, n_params=n_params, converged=True, registry=ix.DEFAULT_REGISTRY)
    return NS(effect=effect, added=added, where=where, fit=fit, delta_aic=aic, removed=(), undetermined=())


def test_a_start_that_is_the_first_choice_under_other_names_starts_no_path():
    picked = _suggestion("electrode_polarization", "R_EP || CPE_EP || C_gap", 4, "R_EP || CPE_EP")
    renamed = _suggestion("extra_relaxation", "C_gap || R_relax || CPE_relax", 4, "R_relax || CPE_relax")
    other = _suggestion("constant_phase", "CPE_gap", 2, "CPE_gap")
    again = _suggestion("constant_phase", "CPE_x", 2, "CPE_x")
    assert _distinct_networks([renamed, other, again], picked) == [other]
    # the same network in the user's names (fewer of them left out) still starts a path
    picked_leaving = _suggestion("extra_relaxation", "C_i + R_sc + R_relax || C_relax", 5, "R_relax || C_relax", where="in series")
    picked_leaving.removed = ("C_sc",)
    keeping = _suggestion("series_resistance", "R_s + C_i + R_sc || C_sc", 5, "R_s", where="in series")
    assert _distinct_networks([keeping], picked_leaving) == [keeping]
    assert _distinct_networks([picked_leaving], keeping) == []


def _stand_in_refine(monkeypatch):
    """refine from C_gap with every diagnosis a stand-in of the Sirin case: the first diagnosis
    suggests R_EP ∥ CPE_EP (taken, then adequate) and the cheaper C_gap → CPE_gap, whose
    diagnosis suggests R_EP ∥ C_EP, reaching R_EP ∥ C_EP ∥ CPE_gap. Returns the refinement and
    the models diagnosed."""
    ep = _suggestion("electrode_polarization", "R_EP || CPE_EP || C_gap", 4, "R_EP || CPE_EP", aic=-1261.0)
    cpe = _suggestion("constant_phase", "CPE_gap", 2, "CPE_gap", where="in place of the ideal capacitor C_gap", aic=-300.0)
    renamed = _suggestion("electrode_polarization", "R_EP || C_EP || CPE_gap", 4, "R_EP || C_EP", aic=-1108.0)
    start = NS(circuit=ix.parse("C_gap"), model="C_gap", aic=-147.5, chi2=100.0, n_params=1, registry=ix.DEFAULT_REGISTRY, unidentified_groups=())

    def diagnosis(baseline, verdict, best=None, suggestions=()):
        return NS(baseline=baseline, verdict=verdict, best=best, suggestions=suggestions, candidates=suggestions, solver_shape=None, masked_points=(), drt_circuit=None, kk_of_kept=None, kk_as_tested=None, kk=None, same_fits=lambda s: ())

    canned = {
        "C_gap": diagnosis(start, Verdict.MISSING_EFFECT, ep, (ep, cpe)),
        "R_EP || CPE_EP || C_gap": diagnosis(ep.fit, Verdict.ADEQUATE),
        "CPE_gap": diagnosis(cpe.fit, Verdict.MISSING_EFFECT, renamed, (renamed,)),
        "R_EP || C_EP || CPE_gap": diagnosis(renamed.fit, Verdict.ADEQUATE),
    }
    diagnosed = []

    def diagnose(current, circuit=None, **options):
        model = str(circuit) if options.get("data") is None else current.model
        diagnosed.append(model)
        return canned[model]

    monkeypatch.setattr(refinement, "diagnose", diagnose)
    monkeypatch.setattr(refinement, "_reproduced", lambda used, fit, **options: (fit, None))
    monkeypatch.setattr(refinement, "undetermined_parameters", lambda fit: set())
    monkeypatch.setattr(refinement, "_simplified", lambda steps, used, **options: steps)
    monkeypatch.setattr(refinement, "_pruned", lambda steps, used, **options: steps)
    f = np.logspace(0, 6, 13)
    data = ix.make_spectrum(f, 1 / (2j * np.pi * f * 4e-10))
    return ix.refine(data, "C_gap"), diagnosed


def test_refine_does_not_compare_a_renamed_copy_of_its_model(monkeypatch):
    r, diagnosed = _stand_in_refine(monkeypatch)
    assert r.final_model == "R_EP || CPE_EP || C_gap" and [s.model for s in r.steps] == ["C_gap", "R_EP || CPE_EP || C_gap"]
    assert diagnosed == ["C_gap", "R_EP || CPE_EP || C_gap", "CPE_gap", "R_EP || C_EP || CPE_gap"]
    assert not any("R_EP || C_EP || CPE_gap" in n or " against " in n for n in r.notes), r.notes


@pytest.mark.slow
def test_refine_from_c_gap_on_the_sirin_remainder_compares_no_model_with_itself(monkeypatch):
    """The reproduced case itself (~25 s): the SYNTHETIC Sirin remainder, refine from C_gap."""
    from impedax.models import example_spectra, sirin

    spectra = example_spectra()
    z_r = sirin.remaining_impedance(spectra["total_sliding"], spectra["skin"], spectra["touchscreen"])
    diagnosed = []
    real = refinement.diagnose

    def counting(current, *args, **options):
        diagnosed.append(str(current.circuit) if hasattr(current, "circuit") else str(args[0]))
        return real(current, *args, **options)

    monkeypatch.setattr(refinement, "diagnose", counting)
    r = ix.refine(z_r, "C_gap")
    assert r.final_model == "R_EP || CPE_EP || C_gap" and r.verdict == "adequate", r.report()
    # no note compares two ends of one network (the path of CPE_gap had been noted as a tie)
    assert not [n for n in r.notes if "R_EP || C_EP || CPE_gap" in n], r.notes
    for note in r.notes:
        if " ends at " in note and " against " in note:
            other = note.split(" ends at ")[1].split(" (AIC ")[0]
            kept = note.split(" against ")[1].split(" (AIC ")[0].removeprefix("the first path's end ")  # (its words since 2026-11-30)
            assert key(other) != key(kept), note
