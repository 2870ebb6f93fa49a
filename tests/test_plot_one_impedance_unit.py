"""A figure's impedance panels count in one SI prefix: its |Z| panel in that of its Nyquist
panel. REAL exampleData.csv (|Z| from 15 to 54 mΩ, the file's numbers): `impedax compare`'s
figure drew the Nyquist panel in mΩ beside |Z| in Ω ticked 0.02, 0.03, 0.04 (2026-12-06).
Oracle: the labels' brackets and each tick label read back from the drawn figure against its
tick's position (the text times the prefix's power of ten is the value where it stands)."""

import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import impedax as ix  # noqa: E402
from tick_labels import labels_in_view  # noqa: E402

REAL = Path(__file__).parent / "fixtures" / "real"
SCALES = {"": 1.0, "k": 1e3, "M": 1e6, "m": 1e-3, "µ": 1e-6}


def _bracket(text: str) -> str:
    return re.search(r"\[(.*?)\]", text).group(1)


def _compared():
    data = ix.load(REAL / "exampleData.csv")
    return ix.compare([ix.fit("R0 + R1 || C1", data), ix.fit("R0 + R1 || CPE1", data)]).plot()


def _spectrum():
    from impedax.plotting import plot_spectrum

    return plot_spectrum(ix.load(REAL / "test_data.txt"))  # (|Z| 135 Ω to 5.68 MΩ: the Nyquist panel in MΩ)


@pytest.mark.parametrize("name, figure, unit", [("compare, exampleData.csv", _compared, "mΩ"), ("plot_spectrum, test_data.txt", _spectrum, "MΩ")])
def test_the_modulus_panel_counts_in_the_nyquist_panels_prefix(name, figure, unit):
    fig = figure()
    fig.canvas.draw()
    nyquist = next(ax for ax in fig.axes if ax.get_xlabel().startswith("Z'"))
    modulus = next(ax for ax in fig.axes if ax.get_ylabel().startswith("|Z| ["))
    assert _bracket(nyquist.get_xlabel()) == _bracket(nyquist.get_ylabel()) == _bracket(modulus.get_ylabel()) == unit, name
    scale = SCALES[unit[:-1]]
    renderer = fig.canvas.get_renderer()
    ticks = {round(float(t.get_loc()), 15): t.label1.get_text() for t in [*modulus.yaxis.get_major_ticks(), *modulus.yaxis.get_minor_ticks()]}
    shown = [(loc, text) for loc, text in ticks.items() if text]
    assert shown and [t for t, _ in labels_in_view(modulus.yaxis, renderer)], name
    for loc, text in shown:
        value = float(text.replace("\N{MINUS SIGN}", "-"))  # (no prefix of its own on a tick: a plain number)
        np.testing.assert_allclose(value * scale, loc, rtol=1e-9, err_msg=f"{name}: tick {text!r} at {loc}")
    plt.close(fig)
