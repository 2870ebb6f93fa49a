"""The DRT figure's legend says at which λ its credible band is, as the report does: on the REAL
exampleDataZPlot.z (impedance.py, MIT) γ is drawn at the floor λ = 10⁻⁴ and the band at the
evidence's 1.8×10⁻⁷, which rises to 0.4 kΩ near 0.1 ms where γ is 0, under a legend that said
only "90 % band". Oracles: the report's own line ("credible band at λ = …") and the JSON's
``lambda`` and ``band_lambda``."""

from __future__ import annotations

import json
import re

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402

import impedax as ix  # noqa: E402
from impedax.cli import main  # noqa: E402

ZPLOT = "tests/fixtures/real/exampleDataZPlot.z"


def test_the_band_legend_names_the_band_lambda_the_report_gives(capsys):
    assert main(["drt", ZPLOT, "--json", "-q"]) == 0
    payload = json.loads(capsys.readouterr().out)
    assert payload["band_lambda"] < payload["lambda"] / 10  # the case: the band's λ is not γ's
    result = ix.drt(ix.load(ZPLOT))
    band_words = re.search(r"credible band at λ = (\S+) ", result.report()).group(1)  # "1.8×10⁻⁷"
    fig = result.plot()
    try:
        legend = [t.get_text() for ax in fig.axes if ax.get_legend() for t in ax.get_legend().get_texts()]
        band = [t for t in legend if t.startswith("90 % band")]
        assert len(band) == 1
        assert f"at λ = {band_words}" in band[0] and "noise only" in band[0]
    finally:
        plt.close(fig)

