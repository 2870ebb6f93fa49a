"""What a notebook shows of a result as the last line of a cell without ``print``: its repr, one
line of fields with arrays and Datasets by their shape (`impedax.data.concise_repr`), as a fit's.
A gap analysis printed its four Datasets in full (8 kB, 31 lines on the embedded example), a
joint posterior every draw (215 lines after 20 steps), a circuit's DRT its τ grid (121 lines), a
comparison every row of its table. SYNTHETIC R0 + R1 ∥ CPE1 spectra; the hierarchical posterior
and the gap analysis are built by hand (tests/test_hierarchical_new_session.py,
tests/test_gap_outputs.py); a joint posterior's is in tests/test_netcdf_every_result_kind.py (slow)."""

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.drt import circuit_drt
from test_gap_outputs import _stub as gap_stub
from test_hierarchical_new_session import by_hand

F = np.geomspace(1.0, 1e5, 21)
Z = 10 + 100 / (1 + (2j * np.pi * F * 1e-3) ** 0.9)


@pytest.fixture(scope="module")
def results():
    one = ix.make_spectrum(F, Z)
    fit = ix.fit("R0 + R1 || CPE1", one, progress=False)
    return {"gap analysis": gap_stub(), "hierarchical posterior": by_hand(2), "circuit DRT": circuit_drt(fit),
            "comparison": ix.compare([fit, ix.fit("R0 + R1 || C1", one, progress=False)])}


# (the class, and one field as concise_repr shows it: an array or Dataset by its shape, a long text cut)
SHOWN = {
    "gap analysis": ("GapAnalysis(", "remaining=<Dataset {'frequency': 21}>"),
    "hierarchical posterior": ("HierarchicalPosterior(", "<float64 array ("),
    "circuit DRT": ("AnalyticDRT(", "tau=<float64 array ("),
    "comparison": ("Comparison(", "rows=("),
}


@pytest.mark.parametrize("kind", SHOWN)
def test_a_result_repr_is_one_short_line(results, kind):
    text = repr(results[kind])
    name, field = SHOWN[kind]
    assert text.startswith(name) and field in text, text
    assert "\n" not in text and len(text) < 2000, (len(text), text[:300])
