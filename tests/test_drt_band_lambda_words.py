"""The report's second line says when the credible band is not at γ's λ, and what that means. On
the REAL exampleDataParstat.txt (impedance.py, MIT) γ is at the floor λ = 10⁻⁴ and the band at
the evidence's λ ≈ 12, 5 decades above: the band of a much smoother γ, widened to contain the
γ shown, whose width then says nothing about that γ; the line said only "credible band at λ =
29 (evidence; …)". Oracles: the JSON's ``lambda`` and ``band_lambda`` (which λ is larger decides
"smoother" or "rougher")."""

from __future__ import annotations

import json
import re

import pytest

import impedax as ix
from impedax.cli import main
from impedax.data import format_lambda

REAL = "tests/fixtures/real/"


def _second_line(path):
    result = ix.drt(ix.load(path))
    return result, result.report().splitlines()[1]


@pytest.mark.parametrize("name, word", [("exampleDataParstat.txt", "smoother"), ("exampleDataZPlot.z", "rougher")])
def test_the_report_names_gammas_lambda_beside_the_bands_and_what_the_band_is(name, word, capsys):
    assert main(["drt", REAL + name, "--json", "-q"]) == 0
    payload = json.loads(capsys.readouterr().out)
    lam, band = payload["lambda"], payload["band_lambda"]
    assert (band > 10 * lam) if word == "smoother" else (band < lam / 10)  # the case: the band's λ is not γ's
    _, line = _second_line(REAL + name)
    assert f"credible band at λ = {format_lambda(band, 2)} " in line
    assert f"not at γ's λ = {format_lambda(lam, 2)}" in line
    assert f"the band of a {word} γ" in line
    assert "widened to contain the γ shown" in line and "its width is not the uncertainty of the γ shown" in line
    assert re.search(r"credible band at λ = (\S+) ", line).group(1) == format_lambda(band, 2)  # (the legend test's reading)


def test_a_band_at_gammas_lambda_is_said_plainly():
    """A band whose λ is γ's (within 1 %, the figure legend's rule) gets no such words: the same
    result with band_lambda set to lam."""
    import dataclasses

    result, _ = _second_line(REAL + "exampleDataParstat.txt")
    same = dataclasses.replace(result, band_lambda=result.lam)
    line = same.report().splitlines()[1]
    assert f"credible band at λ = {format_lambda(result.lam, 2)} (γ's λ" in line
    assert "widened" not in line and "smoother" not in line
