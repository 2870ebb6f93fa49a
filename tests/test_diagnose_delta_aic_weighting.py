"""A diagnosis's ΔAIC weighs each point by its noise, not by the fit's own weighting: its JSON
says so (`delta_aic_weighting`), and the value is recomputed here from the residuals and the
noise model with AIC = n ln(χ²/n) + 2k written out by hand (a walkthrough read a candidate's
`aic` 40 below the baseline's beside a `delta_aic` of −131 on REAL PowerSuite)."""

import json

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main


def test_delta_aic_is_the_noise_weighted_difference_and_the_json_says_so(tmp_path, capsys):
    f = np.geomspace(0.1, 1e5, 40)
    jw = 2j * np.pi * f
    z = 20 + 300 / (1 + 300 * 2e-6 * jw) + 800 / (1 + 800 * 1e-3 * jw)  # SYNTHETIC, two arcs
    z = z * (1 + 0.003 * (np.random.default_rng(4).standard_normal(f.size) + 1j * np.random.default_rng(5).standard_normal(f.size)))
    data = ix.make_spectrum(f, z)
    d = ix.diagnose(data, "R0 + R1 || C1")
    assert d.verdict == "missing_effect"

    def aic(fit):
        r = fit.residuals / d.noise
        chi2 = float(np.sum(r.real**2 + r.imag**2))
        n = 2 * r.size
        return n * np.log(chi2 / n) + 2 * fit.n_params

    best = d.suggestions[0]
    assert best.delta_aic == pytest.approx(aic(best.fit) - aic(d.baseline), rel=1e-9)
    assert best.delta_aic != pytest.approx(best.aic - d.baseline.aic, rel=0.05)  # (the fits' own AIC differ by another amount)

    path = tmp_path / "two_arcs.csv"
    path.write_text("f,re,im\n" + "".join(f"{a},{b.real},{b.imag}\n" for a, b in zip(f, z)))
    assert main(["diagnose", str(path), "--model", "R0 + R1 || C1", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["delta_aic_weighting"] == "noise"
