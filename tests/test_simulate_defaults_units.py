"""`impedax simulate`'s note of the parameters it took defaults for gives each value with its
unit in SI prefixes (`C_s = 1 µF`), as the other commands' text does; it read `C_s=1e-06`, a
bare number without a unit."""

from cli_run import run


def test_defaults_are_said_with_units_and_prefixes(capsys):
    code, _, err = run(["simulate", "R0 + Wo1 + R1 || CPE1 + L1", "--param", "R0=5", "--points", "2"], capsys)
    assert code == 0, err
    # the elements' defaults (docs/circuits.md): R 100 Ω, Wo R 100 Ω and τ 1 s, CPE Q 1e-6 F s^(α−1) and α 0.9, L 1 µH
    assert err == "impedax simulate: defaults used for Wo1.R = 100 Ω, Wo1.tau = 1 s, R1 = 100 Ω, CPE1.Q = 1 µF s^(α-1), CPE1.alpha = 0.9, L1 = 1 µH\n"


def test_meyer_circuit_defaults_name_farads_and_ohms(capsys):
    code, _, err = run(["simulate", "C_s + C_i + R_sc || C_sc + R_f", "--param", "C_s=140p", "--points", "2"], capsys)
    assert code == 0, err
    assert err == "impedax simulate: defaults used for C_i = 1 µF, R_sc = 100 Ω, C_sc = 1 µF, R_f = 100 Ω\n"
