"""``--keep-all-points`` (Python ``mask=False``) on ``diagnose`` and ``refine``: no point is left out
as not Kramers–Kronig consistent, and the KK test's flags are still reported on the ``data:``
line, apart from the verdict (docs/diagnosis.md, the CLI paragraph and section 1)."""

from pathlib import Path

import numpy as np
import pytest

import impedax as ix
import impedax.fitting
import impedax.fitting.diagnosis.refinement as refinement
from impedax.cli import main

import hidden_effects as he

REAL = Path(__file__).parent / "fixtures" / "real"


class _Called(Exception):
    """Raised by the stand-ins below once they have recorded their keyword arguments."""


@pytest.mark.parametrize("command", ["diagnose", "refine"])
@pytest.mark.parametrize("given, mask", [(["--keep-all-points"], False), ([], True)])
def test_the_cli_option_maps_to_mask(monkeypatch, capsys, command, given, mask):
    seen = {}

    def stand_in(*args, **kwargs):
        seen.update(kwargs)
        raise _Called

    monkeypatch.setattr(impedax.fitting, command, stand_in)
    with pytest.raises(_Called):
        main([command, str(REAL / "exampleDataGamry.DTA"), "--model", "R0 + R1 || CPE1", "--quiet", *given])
    assert seen["mask"] is mask
    with pytest.raises(SystemExit):
        main([command, "--help"])
    assert "--keep-all-points" in capsys.readouterr().out


def test_refine_passes_mask_to_its_first_diagnosis(monkeypatch):
    seen = {}

    def stand_in(*args, **kwargs):
        seen.update(kwargs)
        raise _Called

    monkeypatch.setattr(refinement, "diagnose", stand_in)
    f = np.logspace(-1, 5, 30)
    z = 10 + 100 / (1 + 2j * np.pi * f * 100 * 1e-6)  # SYNTHETIC R0 + R1 ∥ C1, exact
    with pytest.raises(_Called):
        ix.refine(ix.make_spectrum(f, z), "R0 + R1 || C1", mask=False)
    assert seen["mask"] is False


def test_diagnose_without_the_mask_keeps_every_point_and_reports_the_flags():
    """The SYNTHETIC spectrum of test_diagnose_noise's erratic points (three near the top, ×1.25,
    ×0.8 and ×1.3): by default they are left out; with ``mask=False`` every point is fitted and the
    report's ``data:`` line says why the flagged points stayed."""
    circuit, _, formula, params, frange = he.CASES["series_resistance/rc"]
    rng = np.random.default_rng(7)
    f, z = he.spectrum(formula, params, frange, 0.005, rng)
    z = z.copy()
    z[[55, 56, 57]] *= np.array([1.25 - 0.2j, 0.8 + 0.25j, 1.3 + 0.1j])
    data = ix.make_spectrum(f, z)
    d = ix.diagnose(data, circuit, mask=False, drt_evidence=False, n_starts=1)
    assert d.masked_points == () and d.baseline.n_points == f.size
    assert d.kk_flagged_kept is not None and "kept in every fit" in d.kk_flagged_kept
    line = next(x for x in d.report().splitlines() if x.startswith("data:"))
    assert "NOT Kramers–Kronig consistent" in line and d.kk_flagged_kept in line
    assert d.summary()["kk_flagged_kept"] == d.kk_flagged_kept and d.summary()["n_points_left_out"] == 0
