"""An F-test not made because a parameter of the larger model is at its bound names that
parameter as the fit's own notes do: "R0 = 0" where its note says "R0 is at its lower bound 0",
else its value with its unit (REAL exampleDataGamry.DTA, R0 + R1 || C1 against R0 + R1 || CPE1 +
R2 || CPE2, read "R0 = 1.27e-05 is at its bound" beside "R0 is at its lower bound 0")."""

from types import SimpleNamespace

import impedax as ix
from impedax.circuits import DEFAULT_REGISTRY
from impedax.fitting.comparison import _boundary_note  # noqa: PLC2701 (the rule under test)

SIMPLE = SimpleNamespace(chi2=1.0, values={})


def larger(value: float, warnings: tuple[str, ...]):
    return SimpleNamespace(chi2=0.5, chi2_red=0.01, values={"R0": value}, warnings=warnings, circuit=ix.parse("R0 + R1 || CPE1"), registry=DEFAULT_REGISTRY)


def test_a_parameter_on_its_bound_0_reads_0_and_one_near_it_its_value_with_its_unit():
    on = _boundary_note(SIMPLE, larger(1.2675e-05, ("R0 is at its lower bound 0",)), "small", "large", ["R0"])["note"]
    assert on.startswith("R0 = 0 is at its bound in large") and "e-05" not in on
    runs = "R0 = 87.4 µΩ runs to its lower bound 0 (fitted in log space, it approaches 0 without reaching it; to the data it is 0)"
    near = _boundary_note(SIMPLE, larger(8.74e-05, (runs,)), "small", "large", ["R0"])["note"]
    assert near.startswith("R0 = 87.4 µΩ is at its bound in large")  # (8.74e-05 Ω = 87.4e-6 Ω)
