"""The titles of the KK, Z-HIT and DRT figures give rms_rel as their reports do (3 significant
digits, no exponent): REAL PowerSuite's Z-HIT figure read "rms 1.2e+02 %" beside the report's
"rms_rel = 119 %", Gamry's KK figure "4.8 %" beside "4.79 %". Oracle: the number each report
prints, read back from its text, and the figure's title as matplotlib holds it."""

import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import pytest

import impedax as ix

REAL = Path(__file__).parent / "fixtures" / "real"


def _reported(report: str) -> str:
    return re.search(r"rms_rel = (\S+ %)", report).group(1)


@pytest.mark.parametrize("method, name", [
    ("zhit", "exampleDataPowersuite.txt"), ("zhit", "exampleDataGamry.DTA"), ("kk", "exampleDataGamry.DTA"), ("kk", "exampleDataPowersuite.txt"), ("drt", "exampleDataGamry.DTA"),
])
def test_the_figure_title_gives_rms_rel_as_the_report(method, name):
    data = ix.load(REAL / name)
    result = {"zhit": ix.zhit, "kk": ix.kk_test, "drt": ix.drt}[method](data)
    fig = result.plot()
    try:
        title = fig.get_suptitle()
    finally:
        plt.close(fig)
    assert f"rms_rel {_reported(result.report())}" in title, title
    assert "e+" not in title, title
