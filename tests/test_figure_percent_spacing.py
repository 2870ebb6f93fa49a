"""Figures and examples write a percentage as the reports do, "90 %" (a space, or a no-break
space where a title is wrapped), never "90%": the legends "90% band", "68% band", "90%
predictive", "90% credible interval", the batch title's "100% converged" and the Sirin example's
"90% interval" and ``{:.0%}`` were the exceptions. Oracles: the text of every text artist of
figures drawn on SYNTHETIC data (numpy-made spectra and draws) and the source of the plotting
code and the examples."""

from __future__ import annotations

import functools
import io
import re
import tokenize
from pathlib import Path
from types import SimpleNamespace

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
import xarray as xr  # noqa: E402

import impedax as ix  # noqa: E402
from impedax.plotting.bayes import plot_posterior_bands  # noqa: E402
from impedax.plotting.models import plot_force_bands  # noqa: E402
from test_gap_walkthrough_fixes import _stub_analysis  # noqa: E402
from test_percent_spacing_all_commands import _glued  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
# a digit, or a replacement field's closing brace ("{x}%"), directly before "%"; a format spec
# ending in % ("{x:.0%}")
GLUED = re.compile(r"[\d}]%|%}")


def _texts(fig) -> list[str]:
    """The text of every text artist of ``fig`` once drawn; the figure is closed."""
    try:
        fig.canvas.draw()
        return [t.get_text() for t in fig.findobj(matplotlib.text.Text) if t.get_text()]
    finally:
        plt.close(fig)


def _spectrum(seed: int = 3, n: int = 31):
    """SYNTHETIC R0 + R1 || C1 (10 Ω, 100 Ω, 1 µF), 1 Hz–100 kHz, 0.5 % noise."""
    f = np.geomspace(1.0, 1e5, n)
    z = 10 + 100 / (1 + 2j * np.pi * f * 100 * 1e-6)
    rng = np.random.default_rng(seed)
    return f, z * (1 + 0.005 * (rng.standard_normal(n) + 1j * rng.standard_normal(n)))


def _draws(f, n_draws=60, seed=5):
    rng = np.random.default_rng(seed)
    r1 = 100 * (1 + 0.02 * rng.standard_normal((n_draws, 1)))
    return 10 + r1 / (1 + 2j * np.pi * f[None, :] * r1 * 1e-6)


def _force_stub():
    freq = np.geomspace(10.0, 1e5, 41)
    force = 0.06 + 0.39 * np.exp(-0.5 * ((np.log10(freq) - 3.0) / 0.8) ** 2)
    data = {k: (("branch", "frequency"), np.stack([force * s, 0.8 * force * s])) for k, s in (("median", 1.0), ("q05", 0.93), ("q95", 1.08))}
    return SimpleNamespace(force=xr.Dataset(data, coords={"branch": ["with_ep", "without_ep"], "frequency": freq}), v0=75.0)


def _posterior_bands():
    f, z = _spectrum()
    f_model = np.geomspace(1.0, 1e5, 80)
    zs = _draws(f_model)
    return plot_posterior_bands(f, z, f_model, zs, title="R0 + R1 || C1", z_predictive=zs * 1.01)


@functools.cache
def _gap_texts() -> tuple[str, ...]:
    """The texts of a stand-in gap analysis' figure (drawn once: its legends are placed in passes)."""
    return tuple(_texts(_stub_analysis(rhat_max=1.01).plot()))


def _fit_figure(kind: str):
    f, z = _spectrum()
    return ix.fit("R0 + R1 || C1", ix.make_spectrum(f, z)).plot() if kind == "fit" else ix.kk_test(ix.make_spectrum(f, z)).plot()


FIGURES = {
    "posterior bands": lambda: _texts(_posterior_bands()),
    "force bands": lambda: _texts(plot_force_bands(_force_stub())),
    "gap analysis": _gap_texts,
    "fit": lambda: _texts(_fit_figure("fit")),
    "kk": lambda: _texts(_fit_figure("kk")),
}


@pytest.mark.parametrize("name", FIGURES)
def test_no_figure_text_glues_a_number_to_its_percent_sign(name):
    texts = FIGURES[name]()
    assert texts, name
    glued = [piece for text in texts for piece in _glued(text)]
    assert not glued, f"{name}: {glued}"


def test_the_percent_legends_are_written_with_a_space():
    """The legends named in this file's docstring, read back whole."""
    assert {"90 % band", "68 % band", "90 % predictive (model + noise)"} <= set(_texts(_posterior_bands()))
    texts = _gap_texts()
    assert "90 % credible interval" in texts and any(t.endswith("median, 90 % band") for t in texts), texts


def test_the_batch_title_writes_the_converged_share_with_a_no_break_space():
    """The batch figure's title says "100 % converged" with a no-break space (the title is
    wrapped at spaces), and no text of the figure glues a number to its % sign."""
    f, _ = _spectrum()
    batch = ix.make_spectrum(f, np.stack([_spectrum(s)[1] for s in (3, 4)]), dims=("cycle",), coords={"cycle": [1, 2]})
    fig = ix.fit("R0 + R1 || C1", batch).plot()
    assert "100\u00a0% converged" in fig._suptitle.get_text()
    assert not [piece for text in _texts(fig) for piece in _glued(text)]


def _string_tokens(path: Path):
    source = path.read_text(encoding="utf-8")
    for token in tokenize.generate_tokens(io.StringIO(source).readline):
        if token.type == tokenize.STRING:
            yield token.start[0], token.string


@pytest.mark.parametrize("path", sorted([*(ROOT / "impedax" / "plotting").glob("*.py"), *(ROOT / "examples").glob("*.py")]), ids=lambda p: f"{p.parent.name}/{p.name}")
def test_no_string_of_the_plotting_code_or_the_examples_glues_a_percent_sign(path):
    """Every string literal (labels, titles, prints, docstrings): no "90%", "{x}%" or "{x:.0%}"."""
    glued = [(line, text) for line, text in _string_tokens(path) if GLUED.search(text.replace("\\u00a0", "\u00a0").replace("\\xa0", "\u00a0"))]
    assert not glued, glued
