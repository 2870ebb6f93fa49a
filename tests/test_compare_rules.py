"""`impedax.compare`: nesting found whatever order the circuits are written in, two writings of
one impedance function marked as one fit, and F-tests it cannot make said so."""

import numpy as np
import pytest

import impedax as ix


def test_compare_finds_nesting_in_any_order_ties_and_tests_it_cannot_make():
    """SYNTHETIC two arcs (R0 = 10, 100 Ω ∥ 1 µF, 50 Ω ∥ 1 mF, 0.5 % noise), written here."""
    f = np.geomspace(0.01, 1e5, 50)
    s = 2j * np.pi * f
    rng = np.random.default_rng(5)
    z = 10 + 100 / (1 + s * 100e-6) + 50 / (1 + s * 50e-3)
    data = ix.make_spectrum(f, z * (1 + 0.005 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2)))
    one, series, ladder = (ix.fit(m, data) for m in ("R0 + R1 || C1", "R0 + R1 || C1 + R2 || C2", "R0 + (R1 + R2 || C2) || C1"))
    c = ix.compare([one, series, ladder])
    # nested whatever the order the circuits are written in
    assert {(t["simple"], t["complex"]) for t in c.f_tests} == {(one.model, series.model), (one.model, ladder.model)}
    assert all(t["valid"] and t["reason"] is None and t["at_bound"] == [] for t in c.f_tests)  # (a genuine nested pair)
    # two writings of one impedance function: one fit, marked as such
    rows = {r["model"]: r for r in c.rows}
    assert rows[series.model]["same_fit_as"] == ladder.model and rows[ladder.model]["same_fit_as"] == series.model
    assert "tied with" in c.table() and rows[one.model]["same_fit_as"] is None
    # a larger model stopped short of its optimum: no test
    far = {"R0": 1.0, "R1": 1.0, "C1": 1e-9, "R2": 1.0, "C2": 1e-9}
    short = ix.fit("R0 + R1 || C1 + R2 || C2", data, init=far, n_starts=1, max_steps=1)
    assert short.chi2 > one.chi2
    test = ix.compare([one, short]).f_tests[0]
    assert test["valid"] is False and "did not reach its optimum" in test["note"]
    assert "did not converge" in ix.compare([one, short]).table()
    assert ix.compare([one, short]).report().startswith(ix.compare([one, short]).table(warnings_below=True))


def test_compare_command_fixes_and_starts_each_model_that_has_the_parameter(tmp_path, capsys):
    from impedax.cli import main

    f = np.geomspace(1.0, 1e5, 40)
    z = 10 + 100 / (1 + (2j * np.pi * f * 1e-4) ** 0.9)
    path = tmp_path / "arc.csv"
    ix.save(ix.make_spectrum(f, z), path)
    argv = ["compare", str(path), "--model", "R0 + R1 || C1", "--model", "R0 + R1 || CPE1", "--fix", "R0=12", "--init", "CPE1.alpha=0.8"]
    assert main([*argv, "--json"]) == 0
    import json

    models = json.loads(capsys.readouterr().out)["models"]
    assert all(m["params"]["R0"]["value"] == 12 and m["params"]["R0"]["fixed"] for m in models)
    assert main([*argv, "--bound", "R1=50:1k"]) == 0
    out = capsys.readouterr().out.splitlines()  # (the held value and the bounds with their units, as typed: "R0 = 12" and "R1 within 50..1000" until 2026-12-06)
    assert "held fixed in R0 + R1 || CPE1: R0 = 12 Ω" in out and "bounded in R0 + R1 || CPE1: R1 within 50 Ω..1 kΩ" in out, out
    assert main(["compare", str(path), "--model", "R0 + R1 || C1", "--model", "R0 + R1 || CPE1", "--fix", "CPE1.a=1"]) == 2
    assert "no model has a parameter 'CPE1.a'; did you mean CPE1.alpha?" in capsys.readouterr().err


def test_no_f_test_where_the_larger_models_extra_parameter_sits_at_its_bound():
    """SYNTHETIC one arc (R0 = 10, 100 Ω ∥ 1 µF, 0.5 % noise), written here: the CPE's α runs
    to its bound 1 and a series L0 to 0, where the smaller model is the edge of the larger one's
    parameter space and F does not follow its distribution (Self & Liang 1987)."""
    f = np.geomspace(0.01, 1e5, 50)
    rng = np.random.default_rng(3)  # (a seed whose noise sends the CPE's α to 1)
    z = 10 + 100 / (1 + 2j * np.pi * f * 100e-6)
    data = ix.make_spectrum(f, z * (1 + 0.005 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2)))
    rc, cpe, inductive = (ix.fit(m, data) for m in ("R0 + R1 || C1", "R0 + R1 || CPE1", "L0 + R0 + R1 || C1"))
    assert "CPE1.alpha" in cpe.at_bound and cpe.values["CPE1.alpha"] > 0.999999 and "L0" in inductive.at_bound
    c = ix.compare([rc, cpe, inductive])
    tests = {t["complex"]: t for t in c.f_tests}
    assert set(tests) == {cpe.model, inductive.model}
    for larger, name in ((cpe, "CPE1.alpha"), (inductive, "L0")):
        t = tests[larger.model]
        assert t["valid"] is False and t["at_bound"] == [name] and "Self & Liang" in t["note"], t
        # the χ² did not fall by more than a hundredth of the reduced χ² (the bound rule's): the extra element does nothing
        assert rc.chi2 - larger.chi2 <= 1e-2 * larger.chi2_red
        assert t["reason"] == "reduces_to_simple" and t["note"].startswith(f"{larger.model} reduces to {rc.model}: {name} = ")
        assert f"F-test {rc.model}  ⊂  {larger.model}: no test: {larger.model} reduces to {rc.model}" in c.table()
    # without a valid test the misfit note's F-test evidence is not used (`_model_not_data`)
    assert not any("F-test p" in w for fit in c.fits for w in fit.warnings)


def test_a_parameter_run_open_reads_as_infinity_in_the_boundary_note():
    """An F-test not made because the larger model's R runs to its upper bound ∞ says "→ ∞",
    not the float the solver stopped at (a walkthrough read "R1 = 2.11e+167 is at its bound")."""
    from types import SimpleNamespace

    from impedax.fitting.comparison import _boundary_note  # noqa: PLC2701 (the rule under test)

    simple = SimpleNamespace(chi2=1.0, values={})
    complex_ = SimpleNamespace(chi2=0.5, chi2_red=0.01, values={"R1": 2.11e167, "CPE1.alpha": 1.0})
    note = _boundary_note(simple, complex_, "small", "large", ["R1", "CPE1.alpha"])["note"]
    assert note.startswith("R1 → ∞, CPE1.alpha = 1 are at their bounds") and "e+167" not in note


def test_a_held_parameter_that_the_reduction_needs_breaks_the_nesting():
    """SYNTHETIC one arc (R0 = 10, 100 Ω ∥ 1 µF, 0.5 % noise), written here. ``R0 + R1 || CPE1
    + L1`` contains ``R0 + R1 || C1`` only with L1 free to reach 0: held at 100 µH (or at any
    value) it does not, and no F-test is made between them (one was, F = 423, p = 3e-22 on REAL
    ZPlot data, 2026-12-03); a parameter both hold at the same value keeps the nesting, at
    different values breaks it; a parameter only the smaller model holds keeps it."""
    f = np.geomspace(1.0, 1e5, 40)
    rng = np.random.default_rng(7)
    z = 10 + 100 / (1 + 2j * np.pi * f * 100e-6)
    data = ix.make_spectrum(f, z * (1 + 0.005 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2)))
    rc = ix.fit("R0 + R1 || C1", data)
    pairs = lambda c: {(t["simple"], t["complex"]) for t in c.f_tests}  # noqa: E731
    held_l = ix.fit("R0 + R1 || CPE1 + L1", data, fixed={"L1": 1e-4})
    assert pairs(ix.compare([rc, held_l])) == set()
    assert "fits worse than" not in ix.compare([rc, held_l]).table(warnings_below=True)  # (no advice to start it from the R ∥ C fit: it cannot reach it)
    free_l = ix.fit("R0 + R1 || CPE1 + L1", data)
    (test,) = ix.compare([rc, free_l]).f_tests  # the same circuits with L1 free: nested, tested
    assert (test["simple"], test["complex"]) == (rc.model, free_l.model)
    # R0 held by both: at the same value nested (its F by hand), at another value not; on a
    # SYNTHETIC CPE arc (α = 0.85, written here), so that the CPE's α lies off its bound and the test is made
    arc = 10 + 100 / (1 + (2j * np.pi * f * 1e-4) ** 0.85)
    cpe_data = ix.make_spectrum(f, arc * (1 + 0.005 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2)))
    rc_12, cpe_12 = ix.fit("R0 + R1 || C1", cpe_data, fixed={"R0": 12.0}), ix.fit("R0 + R1 || CPE1", cpe_data, fixed={"R0": 12.0})
    (test,) = ix.compare([rc_12, cpe_12]).f_tests
    n = 2 * f.size
    assert test["df1"] == 1 and test["df2"] == n - 3 and test["valid"]
    assert np.isclose(test["f"], max(rc_12.chi2 - cpe_12.chi2, 0.0) / (cpe_12.chi2 / (n - 3)), rtol=1e-9)
    rc_12, cpe_13 = ix.fit("R0 + R1 || C1", data, fixed={"R0": 12.0}), ix.fit("R0 + R1 || CPE1", data, fixed={"R0": 13.0})
    assert pairs(ix.compare([rc_12, cpe_13])) == set()
    # held only in the smaller model: still a special case of the larger one
    assert pairs(ix.compare([rc_12, ix.fit("R0 + R1 || CPE1", data)])) == {(rc_12.model, "R0 + R1 || CPE1")}
    # a batch comparison follows the same rule (its not_at_optimum and reduction use it)
    from impedax.fitting.comparison import nested_as_held
    from impedax.circuits import parse

    small, big = parse("R0 + R1 || C1"), parse("R0 + R1 || CPE1 + L1")
    assert nested_as_held(small, {}, big, {}) and not nested_as_held(small, {}, big, {"L1": 1e-4})
    assert nested_as_held(small, {"R0": np.array([1.0, 2.0])}, big, {"R0": np.array([1.0, 2.0])})
    assert not nested_as_held(small, {"R0": np.array([1.0, 2.0])}, big, {"R0": np.array([1.0, 3.0])})


def test_the_compare_command_nests_its_models_with_the_held_parameters_as_the_comparison_does(tmp_path, capsys):
    """``impedax compare`` fits a model after the models it contains and starts it from their
    optimum (`nesting_order`, `largest_contained`); with ``--fix L1=100u`` the L model no longer
    contains R0 + R1 || C1 (`nested_as_held`: L1 held off 0), so it is fitted in the order given
    and not started from the R ∥ C optimum (until 2026-12-03 the command nested by circuit alone,
    the comparison by circuit and held values). SYNTHETIC one arc (R0 = 10, 100 Ω ∥ 1 µF, 0.5 %
    noise), written here."""
    import json

    from impedax.circuits import DEFAULT_REGISTRY, parse
    from impedax.cli import main
    from impedax.cli.compare import largest_contained, nesting_order

    big, small = "R0 + R1 || CPE1 + L1", "R0 + R1 || C1"
    circuits = [parse(big), parse(small)]
    assert nesting_order(circuits, DEFAULT_REGISTRY) == [1, 0] and largest_contained(0, circuits, [None, "fitted"], DEFAULT_REGISTRY) == 1
    held = [{"L1": 1e-4}, None]  # (as the command gives each model its --fix: None where it has none of them)
    assert nesting_order(circuits, DEFAULT_REGISTRY, held) == [0, 1] and largest_contained(0, circuits, [None, "fitted"], DEFAULT_REGISTRY, held) is None
    both_r0 = [{"R0": 12.0}, {"R0": 12.0}]  # (held alike in both: still nested)
    assert nesting_order(circuits, DEFAULT_REGISTRY, both_r0) == [1, 0] and largest_contained(0, circuits, [None, "fitted"], DEFAULT_REGISTRY, both_r0) == 1
    f = np.geomspace(1.0, 1e5, 40)
    rng = np.random.default_rng(7)
    z = 10 + 100 / (1 + 2j * np.pi * f * 100e-6)
    path = tmp_path / "arc.csv"
    ix.save(ix.make_spectrum(f, z * (1 + 0.005 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2))), path)
    argv = ["compare", str(path), "--model", big, "--model", small, "--json"]
    assert main(argv) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["started_from_contained"] == [{"model": big, "from": small}]
    # no --init: no message speaks of a start the user gave (a walkthrough read "the given start 8
    # times (every free parameter given ...)"); the one carried in is named by its model
    assert not any("given" in m["message"] for m in doc["models"]), [m["message"] for m in doc["models"]]
    assert main([*argv, "--fix", "L1=100u"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["started_from_contained"] == [] and out["f_tests"] == []


def test_a_pair_nested_by_a_limit_on_the_edge_of_the_space_takes_the_chi_bar_squared_p_value():
    """W ⊂ Wo (τ → ∞) and C ⊂ CPE (α = 1, α ≤ 1) put the smaller model on the boundary of the
    larger one's space, where F's reference is the 50:50 mixture of 0 and F(1, df2) (Self & Liang
    1987): p = ½ F.sf(F, 1, df2), half the plain F-test's. An element added (W1.sigma, interior
    here) keeps the plain p. SYNTHETIC spectra, written here."""
    from scipy import stats

    f = np.geomspace(0.05, 1e5, 60)
    s = 2j * np.pi * f
    rng = np.random.default_rng(11)
    noise = lambda: 1 + 0.01 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2)  # noqa: E731
    # a finite-length diffusion (Wo: R 200 Ω, τ 2 s) behind an arc, and an arc with α = 0.93
    x = np.sqrt(s * 2.0)
    wo_data = ix.make_spectrum(f, (10 + 100 / (1 + s * 1e-4) + 200 / np.tanh(x) / x) * noise())
    arc_data = ix.make_spectrum(f, (10 + 100 / (1 + (s * 1e-3) ** 0.93)) * noise())
    pairs = [(wo_data, "R0 + R1 || C1 + W1", "R0 + R1 || C1 + Wo1", ["Wo1: tau -> inf"]), (arc_data, "R0 + R1 || C1", "R0 + R1 || CPE1", ["CPE1: alpha = 1"])]
    for data, small, large, limits in pairs:
        simple, larger = ix.fit(small, data), ix.fit(large, data, init=ix.fit(small, data))
        (test,) = ix.compare([simple, larger]).f_tests
        assert test["valid"] and test["boundary_limits"] == limits, test
        n = 2 * data.sizes["frequency"]
        df2 = n - larger.n_params
        f_value = (simple.chi2 - larger.chi2) / (larger.n_params - simple.n_params) / (larger.chi2 / df2)
        assert test["f"] == pytest.approx(f_value, rel=1e-9)
        assert test["p_value"] == pytest.approx(0.5 * stats.f.sf(f_value, 1, df2), rel=1e-9)
        assert "50:50 chi-bar-squared mixture (Self & Liang 1987)" in test["note"]
        assert f"p = {test['p_value']:.3g} ({test['note']})" in ix.compare([simple, larger]).report()
    # an element added whose one parameter removes it at a bound (W1.sigma -> 0, W1.sigma > 0):
    # the smaller model is on the edge as well, the mixture too (test below)
    simple, larger = ix.fit("R0 + R1 || C1", wo_data), ix.fit("R0 + R1 || C1 + W1", wo_data)
    (test,) = ix.compare([simple, larger]).f_tests
    assert test["boundary_limits"] == ["W1 removed: sigma -> 0"]
    assert test["p_value"] == pytest.approx(0.5 * stats.f.sf(test["f"], test["df1"], test["df2"]), rel=1e-12)
    # a block of two elements removed (R2 -> 0 leaves C2 unidentified): no mixture, the plain
    # F-test, whose note says that is not p's reference there (Davies 1977, 1987)
    simple, larger = ix.fit("R0 + R1 || C1", wo_data), ix.fit("R0 + R1 || C1 + R2 || C2", wo_data)
    (test,) = ix.compare([simple, larger]).f_tests
    assert test["boundary_limits"] == [] and "R2 || C2 removed: C2 is not identified when R2 -> 0" in test["note"]
    assert test["p_value"] == pytest.approx(stats.f.sf(test["f"], test["df1"], test["df2"]), rel=1e-12)


def test_an_element_removed_at_the_bound_of_its_one_parameter_takes_the_chi_bar_squared_p_value():
    """R0 + R1 || CPE1 is R0 + R1 || CPE1 + W1 at W1.sigma = 0, and sigma > 0: the null lies on
    the edge of the larger model's space just as a capacitor does for a CPE at α = 1 (Self & Liang
    1987), so p = ½ F.sf(F, 1, df2), not the plain F-test's (REAL Autolab data printed p = 0.0716
    where the mixture gives 0.036). With both (C1 for CPE1 at α = 1 and W1 removed) the weights are
    ¼, ½, ¼ over 0, F(1, df2), F(2, df2)·2. The oracle is scipy's F distribution, written out here.
    SYNTHETIC spectrum: an arc with α = 0.9 and a Warburg tail of σ = 0.4 Ω s^-½ that
    1 % noise leaves in doubt (p ≈ 0.08, where the plain F-test said 0.16)."""
    from scipy import stats

    f = np.geomspace(0.05, 1e5, 60)
    s = 2j * np.pi * f
    rng = np.random.default_rng(5)
    z = 10 + 1 / (1 / 100 + 1e-4 * s**0.9) + 0.4 * (1 - 1j) / np.sqrt(2 * np.pi * f)
    data = ix.make_spectrum(f, z * (1 + 0.01 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2)))
    rc = ix.fit("R0 + R1 || C1", data)
    cpe = ix.fit("R0 + R1 || CPE1", data, init=rc)
    full = ix.fit("R0 + R1 || CPE1 + W1", data, init=cpe)
    comparison = ix.compare([rc, cpe, full])
    n = 2 * f.size
    tests = {(t["simple"], t["complex"]): t for t in comparison.f_tests}

    def f_stat(a, b):
        return (a.chi2 - b.chi2) / (b.n_params - a.n_params) / (b.chi2 / (n - b.n_params))

    one = tests[("R0 + R1 || CPE1", "R0 + R1 || CPE1 + W1")]
    assert one["valid"], one
    f1, df2 = f_stat(cpe, full), n - full.n_params
    assert one["f"] == pytest.approx(f1, rel=1e-9)
    assert 0.01 < one["p_value"] < 0.5  # (a p in doubt: the factor ½ is not lost to underflow)
    assert one["p_value"] == pytest.approx(0.5 * stats.f.sf(f1, 1, df2), rel=1e-9)
    assert "W1" in one["note"] and "50:50 chi-bar-squared mixture" in one["note"]
    two = tests[("R0 + R1 || C1", "R0 + R1 || CPE1 + W1")]
    assert two["valid"], two
    f2 = f_stat(rc, full)
    expected = 0.5 * stats.f.sf(2 * f2 / 1, 1, df2) + 0.25 * stats.f.sf(f2, 2, df2)
    assert two["p_value"] == pytest.approx(expected, rel=1e-9)
    assert "CPE1: alpha = 1" in two["note"] and "W1" in two["note"]


def test_the_f_test_p_values_are_scipy_stats_f_sf_exactly_and_compare_needs_no_scipy_stats(monkeypatch):
    """p of the F-test and of the chi-bar-squared mixture are those of scipy.stats.f.sf to the
    last bit (F below 0 and at ∞ included), while compare runs with scipy.stats unimportable:
    importing it took ~1 s of every ``impedax compare`` process. SYNTHETIC arc (α = 0.93, 1 %
    noise), written here."""
    import math
    import sys

    import scipy
    from scipy import stats

    from impedax.fitting.comparison import chi_bar_squared_p_value

    for f_value in (-1.0, 0.0, 1e-12, 0.37, 1.0, 3.9, 55.0, 1e8, math.inf):
        for df1, df2 in ((1, 5), (1, 113), (2, 40), (3, 1000)):
            assert chi_bar_squared_p_value(f_value, df1, df2) == float(stats.f.sf(f_value, df1, df2))
            if df1 == 1 and f_value > 0:  # (the 50:50 mixture: half the plain p)
                assert chi_bar_squared_p_value(f_value, df1, df2, 1) == 0.5 * float(stats.f.sf(f_value, df1, df2))
    f = np.geomspace(0.05, 1e5, 40)
    s = 2j * np.pi * f
    rng = np.random.default_rng(3)
    data = ix.make_spectrum(f, (10 + 100 / (1 + (s * 1e-3) ** 0.93)) * (1 + 0.01 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) / np.sqrt(2)))
    small = ix.fit("R0 + R1 || C1", data)
    large = ix.fit("R0 + R1 || CPE1", data, init=small)
    expected = 0.5 * float(stats.f.sf(ix.compare([small, large]).f_tests[0]["f"], 1, 2 * f.size - large.n_params))
    monkeypatch.setitem(sys.modules, "scipy.stats", None)  # (import scipy.stats now raises ImportError)
    monkeypatch.delattr(scipy, "stats", raising=False)
    (test,) = ix.compare([small, large]).f_tests
    assert test["valid"] and test["p_value"] == expected
