"""Exchangeable arcs put in order from the parameters alone, as after a candidate fit (whose
solver returns no peak frequencies): the arc whose −Z'' peaks at the higher frequency is
reported first. Oracle: the closed form of an R ∥ C arc, −Z'' = ωR²C / (1 + (ωRC)²), evaluated
with NumPy on the same frequency grid."""

from __future__ import annotations

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.least_squares import order
from impedax.fitting.least_squares.order import canonical_order
from impedax.fitting.least_squares.solvers import SolverOutput
from impedax.fitting.parameters import ParameterTable

FREQ = np.geomspace(1e-2, 1e5, 57)


def _grid_peak(r: float, c: float) -> float:
    """The grid frequency at which an R ∥ C arc's −Z'' is largest (closed form)."""
    omega = 2 * np.pi * FREQ
    return float(FREQ[np.argmax(omega * r**2 * c / (1 + (omega * r * c) ** 2))])


@pytest.mark.parametrize("arcs", [("R1", "C1", "R2", "C2"), ("R_relax", "C_relax", "R_relax2", "C_relax2")])
def test_the_slower_arc_written_first_is_moved_second(arcs):
    r_a, c_a, r_b, c_b = arcs
    circuit = ix.parse(f"R0 + {r_a} || {c_a} + {r_b} || {c_b}")
    table = ParameterTable.build(circuit)
    values = {"R0": 2.0, r_a: 30.0, c_a: 1e-2, r_b: 10.0, c_b: 1e-6}  # the first arc relaxes at 0.53 Hz, the second at 16 kHz
    assert _grid_peak(values[r_a], values[c_a]) < _grid_peak(values[r_b], values[c_b])
    x = np.array([values[n] for n in table.names])
    jacobian = np.tile(np.arange(x.size, dtype=float), (4, 1))  # column i holds i: where each column went
    out = canonical_order(circuit, table, FREQ, SolverOutput(x=x, chi2=0.0, jacobian=jacobian, z_model=None), ix.DEFAULT_REGISTRY)
    at = {n: i for i, n in enumerate(table.names)}
    assert out.x[at[r_a]] == values[r_b] and out.x[at[c_a]] == values[c_b]
    assert out.x[at[r_b]] == values[r_a] and out.x[at[c_b]] == values[c_a]
    assert list(out.jacobian[0]) == [at[n] for n in ("R0", r_b, c_b, r_a, c_a)]


def test_one_peak_function_serves_every_name_of_one_structure():
    """Two circuits of one structure under other names (a refine's candidates) order their arcs
    with one traced peak function, not one each."""
    before = set(order._PEAK_PROGRAMS)
    for names in (("R1", "C1", "R2", "C2"), ("R_relax", "C_relax", "R_relax2", "C_relax2"), ("R_a", "C_a", "R_b", "C_b")):
        test_the_slower_arc_written_first_is_moved_second(names)
    assert len(set(order._PEAK_PROGRAMS) - before) <= 1
