"""`impedax.compare`: nesting found whatever order the circuits are written in, two writings of
one impedance function marked as one fit, and F-tests it cannot make said so."""

import numpy as np

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
    assert all(t["valid"] for t in c.f_tests)
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
    assert main(argv) == 0
    assert "held fixed in R0 + R1 || CPE1: R0 = 12" in capsys.readouterr().out
    assert main(["compare", str(path), "--model", "R0 + R1 || C1", "--model", "R0 + R1 || CPE1", "--fix", "CPE1.a=1"]) == 2
    assert "no model has a parameter 'CPE1.a'; did you mean CPE1.alpha?" in capsys.readouterr().err
