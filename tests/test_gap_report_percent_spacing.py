"""The gap, force and sample reports write a percentage as diagnose and refine write theirs: the
number, a space, % ("90 % credible interval", "rms_rel 77.5 %"). The gap report wrote "90%" beside
its own "77.5 %" (the shipped SYNTHETIC example, pooled). Each report is searched for a digit
directly followed by %."""

from __future__ import annotations

import re

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

_GLUED = re.compile(r"\d%")


def _glued(text: str) -> list[str]:
    return [text[max(0, m.start() - 30): m.end() + 10] for m in _GLUED.finditer(text)]


@pytest.fixture(scope="module")
def pooled_report():
    from impedax.models import example_spectra
    from impedax.models.gap import gap_analysis

    s = example_spectra()
    return gap_analysis(s["total_sliding"], s["skin"], s["touchscreen"], area=130e-6, method="pooled", steps=20, progress=False).report()


def test_the_gap_report_spaces_its_percentages(pooled_report):
    assert "90 % credible interval" in pooled_report and "(90 %: " in pooled_report and "\nforce 90 %      " in pooled_report, pooled_report
    assert not _glued(pooled_report), _glued(pooled_report)


def test_gap_report_helpers_space_their_percentages():
    """The lines a pooled run on the example does not reach: the voltage's interval, the force
    plateau and the sampling verdict's rule."""
    import xarray as xr

    from impedax.models.gap import _volts_with_interval, force_maximum_text

    assert _volts_with_interval({"value": 71.0, "q05": 50.2, "q95": 90.4}) == "71 V (90 %: 50.2–90.4 V)"
    f = np.logspace(0, 5, 51)
    force = 0.407 / (1.0 + (f / 3e4) ** 2)  # (within 1 % of its maximum up to ≈ 3 kHz: a plateau at the band's lower end)
    text = force_maximum_text(xr.DataArray(force, coords={"frequency": f}, dims="frequency"))
    assert text.endswith("(within 1 %; largest at 1 Hz, the band's lower end)") and not _glued(text), text


def test_force_and_sample_reports_space_their_percentages(capsys, tmp_path):
    """``impedax force`` on a plateau (its stderr note) and ``impedax sample``'s report."""
    assert main(["force", "vezzoli", "--fmin", "1e6", "--fmax", "1e9"]) == 0
    out = capsys.readouterr()
    assert "within 1 % of it over" in out.err and not _glued(out.out + out.err), _glued(out.out + out.err)
    f = np.logspace(0, 5, 25)
    z = 10 + 1e3 / (1 + 2j * np.pi * f * 1e3 * 1e-6)
    ix.save(ix.make_spectrum(f, z * (1 + 0.01 * np.random.default_rng(4).standard_normal(25))), tmp_path / "rc.csv")
    assert main(["sample", str(tmp_path / "rc.csv"), "--model", "R0 + R1 || C1", "--steps", "20", "--quiet"]) == 0
    report = capsys.readouterr().out
    assert "sampler" in report and not _glued(report), _glued(report)
