"""The diagnosis' evaluation set (tests/evaluation_set.py): its composition is what issue 18 asks
for, its formulas are right, and (slow) the diagnosis reaches its hit rates on it."""

import collections
import types

import numpy as np
import pytest

import impedax as ix

import evaluation_set as es

EFFECT_IDS = set(ix.DEFAULT_EFFECTS.ids())


@pytest.mark.parametrize("split", ["dev", "heldout"])
def test_composition(split):
    cases = es.cases(split)
    kinds = collections.Counter(c.kind for c in cases)
    assert len(cases) >= 100
    assert kinds["adequate"] >= 15 and kinds["invalid"] >= 5 and kinds["two"] >= 10
    # every effect id in at least three circuits
    circuits = collections.defaultdict(set)
    for c in cases:
        for e in c.expected:
            circuits[e].add(c.circuit)
    assert {e for e, cs in circuits.items() if len(cs) >= 3} >= EFFECT_IDS
    # circuits of 1 to 10 elements
    sizes = {len(ix.parse(c.circuit).element_names) for c in cases}
    assert min(sizes) == 1 and 8 <= max(sizes) <= 10
    # noise 0.3–3 %, flat and growing toward low frequency; barely visible to strong; edges; outliers
    assert min(c.noise for c in cases) == 0.003 and max(c.noise for c in cases) == 0.03
    assert {c.noise_profile for c in cases} == {"flat", "low_f"}
    assert {c.strength for c in cases if c.kind == "single"} == {es.WEAK, es.MEDIUM, es.STRONG}
    assert sum(c.tag == "edge" for c in cases) >= 2 and sum(c.outliers > 0 for c in cases) >= 4
    for c in cases:
        assert np.all(np.isfinite(c.z)) and np.all(np.diff(c.frequency) > 0)


def test_splits_differ_and_repeat():
    dev, held = es.cases("dev"), es.cases("heldout")
    assert [c.name for c in dev] == [c.name for c in held]
    assert all(not np.allclose(a.z, b.z) for a, b in zip(dev, held))
    assert all(np.array_equal(a.z, b.z) for a, b in zip(dev, es.cases("dev")))  # fixed seeds


TWO_EFFECT = [t for t in es.TEMPLATES if len(t.expected) == 2]


@pytest.mark.parametrize("template", TWO_EFFECT, ids=[t.name for t in TWO_EFFECT])
def test_generating_circuit_is_the_formula(template):
    """Each two-effect template names the circuit its numpy formula computes: fitted to the
    formula's noise-free spectrum, the circuit reaches it to rounding."""
    assert template.generating
    params = {**template.params, **template.strengths.get(es.MEDIUM, {})}
    f = np.logspace(np.log10(template.band[0]), np.log10(template.band[1]), template.n_points)
    fit = ix.fit(template.generating, ix.make_spectrum(f, template.impedance(f, params)))
    assert fit.rms_rel < 1e-9


def test_same_as_generating_needs_as_few_parameters_and_as_good_a_fit():
    def refined(k, rms):
        return types.SimpleNamespace(final=types.SimpleNamespace(n_params=k, rms_rel=rms))

    generating = types.SimpleNamespace(n_params=5, rms_rel=0.0060)
    assert es.same_as_generating(refined(5, 0.0061), generating)  # within 2 %
    assert es.same_as_generating(refined(4, 0.0050), generating)
    assert not es.same_as_generating(refined(6, 0.0050), generating)  # better, but with more parameters
    assert not es.same_as_generating(refined(5, 0.0062), generating)  # 3.3 % worse


def test_formulas_against_hand_values():
    f = np.array([1.0 / (2 * np.pi)])  # ω = 1 rad/s
    assert es.rc(f, 2.0, 0.5)[0] == pytest.approx(2.0 / (1 + 1j))  # R/(1 + jωRC), ωRC = 1
    assert es.cpe(f, 2.0, 0.5)[0] == pytest.approx(0.5 / np.sqrt(1j))
    assert es.warburg(f, 3.0)[0] == pytest.approx(3.0 - 3.0j)
    assert es.ind(f, 4.0)[0] == pytest.approx(4.0j)
    # finite diffusion: Wo → R/(jωτ)·... ≈ capacitive at low frequency (Z ≈ R/3 + 1/(jω R⁻¹ τ)), Ws → R
    lo = np.array([1e-6])
    assert es.ws(lo, 5.0, 1.0)[0].real == pytest.approx(5.0, rel=1e-4)
    assert es.wo(lo, 5.0, 1.0)[0].real == pytest.approx(5.0 / 3, rel=1e-3)
    # the low-f noise profile: geometric mean = level, ×LOW_F_GROWTH across the band
    fr = np.logspace(0, 6, 61)
    prof = es.noise_profile(fr, 0.01, "low_f")
    assert np.exp(np.mean(np.log(prof))) == pytest.approx(0.01) and prof[0] / prof[-1] == pytest.approx(es.LOW_F_GROWTH)


def test_relabelled_and_foster_circuits_fit_the_formula_to_rounding():
    """two/rc_rs_stray's truth, (R_s + R1 ∥ C1) ∥ C_s, is also R1 ∥ C1 with a relaxation nested in
    series with R1 (R1 the series resistance, C1 the stray capacitance), and, by Foster's
    theorem, two R ∥ C in series: fitted to the numpy formula's noise-free spectrum, each
    reaches it to rounding, and `equivalent_to_generating` says so; a circuit of another
    function (one R ∥ CPE) is not equivalent."""
    template = next(t for t in es.TEMPLATES if t.name == "two/rc_rs_stray")
    params = {**template.params, **template.strengths.get(es.MEDIUM, {})}
    f = np.logspace(np.log10(template.band[0]), np.log10(template.band[1]), template.n_points)
    exact = ix.make_spectrum(f, template.impedance(f, params))
    generating = ix.fit(template.generating, exact)
    for text in ("(R1 + R_relax || C_relax) || C1", "R1 || C1 + R2 || C2"):
        fit = ix.fit(text, exact)
        assert fit.rms_rel < 1e-9, text
        assert es.equivalent_to_generating(fit, generating), text
    assert not es.equivalent_to_generating(ix.fit("R1 || CPE1", exact), generating)


def test_two_recovered_needs_both_effects_or_the_generating_function():
    case = types.SimpleNamespace(expected=("series_resistance", "stray_capacitance"), kind="two")

    def outcome(effects, equivalent, structure):
        return es.Outcome(case, "adequate", (), effects, "adequate", 1.0, None, structure, equivalent)

    assert outcome(("series_resistance", "stray_capacitance"), False, False).two_recovered
    assert outcome(("extra_relaxation",), True, True).two_recovered
    assert not outcome(("extra_relaxation",), False, True).two_recovered  # as good on the noisy data, another function
    assert not outcome(("series_resistance",), None, None).two_recovered


@pytest.mark.slow
def test_the_diagnosis_meets_its_aims_on_the_tuning_split():
    """The whole dev2 split (107 SYNTHETIC cases, the split the rules are tuned on; ~10 min on 2
    cores): diagnose every case, refine the two-effect ones, and fit every best suggestion's
    model string from scratch. Measured at 96.1 % top-1, 0/16 false alarms, two-effect
    recovered 10/10 and 98.8 % reproduced (docs/diagnosis.md, evaluation table); the bounds
    leave room for at least two cases of drift on each rate, none for a false alarm."""
    outcomes = []
    for case in es.cases("dev2"):
        outcomes.append(es.run_case(case, reproduce=True))
        o = outcomes[-1]
        print(f"{'ok  ' if o.correct else 'MISS'} {case.name:40s} {o.verdict:16s} {list(o.ranked[:3])} reproduced {o.reproduced}")
    s = es.summarise(outcomes)
    print(s)
    assert s["top1"] >= 71 / 76
    assert s["false_alarm"] == 0
    assert s["invalid_found"] == 1
    assert s["two_recovered"] >= 0.8
    assert s["reproduced"] >= 0.95
