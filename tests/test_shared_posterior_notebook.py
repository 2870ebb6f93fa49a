"""A joint posterior in a notebook (`SharedPosterior._repr_html_`): a single spectrum's and a
hierarchical posterior had their report's content as HTML, a joint posterior showed the
dataclass's repr of its draws. SYNTHETIC data: two RC spectra written by formula, R0 shared."""

import html

import numpy as np

import impedax as ix
from test_shared_posterior_roundtrip import proportional  # noqa: F401  (a fixture)


def test_notebook_shows_the_report(proportional):  # noqa: F811
    post = proportional
    page = post._repr_html_()
    assert page.startswith('<div class="impedax-result">')
    assert "R0 + R1 || C1: joint posterior (R0 shared over trial, 2 spectra)" in page
    assert "sampler: emcee, 16 walkers, 30 steps (burn " in page and f"{16 * post.n_draws} draws, acceptance {post.mean_acceptance:.3f}" in page
    assert "noise: proportional: " in page
    # a row per sampled parameter, its median the median of its draws (numpy), its unit
    for name, unit in (("R0", "Ω"), ("R1[trial=3]", "Ω"), ("C1[trial=7]", "F"), ("sigma_rel", "")):
        cells = f"<td>{html.escape(name)}</td><td>{float(np.median(post.samples[name])):.5g}</td>"
        assert cells in page, name
        row = page[page.index(cells):].split("</tr>")[0]
        assert f"<td>{unit}</td>" in row, (name, row)
    for warning in post.warnings:
        assert html.escape(warning) in page
    assert post.warnings  # (30 steps: the chain-length warning at least)


def test_a_single_spectrum_posterior_gives_units_as_its_report(proportional):  # noqa: F811
    """`Posterior`'s notebook table wrote the unit as stored ("Ohm") where its report writes Ω."""
    data = ix.make_spectrum(proportional.frequency, proportional.z_data[0])
    post = ix.sample("R0 + R1 || C1", data, steps=30, walkers=16, seed=3, progress=False)
    page = post._repr_html_()
    for name, unit in (("R0", "Ω"), ("C1", "F")):
        row = page[page.index(f"<td>{name}</td>"):].split("</tr>")[0]
        assert f"<td>{unit}</td>" in row and "Ohm" not in row, (name, row)
