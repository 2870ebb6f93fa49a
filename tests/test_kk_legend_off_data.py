"""The KK figure's residual legend covers no data (docs/kk.md, "the legend goes where it covers
no label"): walkthrough 2026-12-06, `impedax kk exampleDataParstat.txt --plot`, whose legend's
least covering place inside the panel lay over Δ re and Δ im from 60 Hz to 10 kHz, the −40 %
point at 10 kHz among them. Oracles: the REAL Parstat and Gamry files, the figure as the command
line writes it (its title naming the file), geometry read back from matplotlib: each residual
point's display coordinates against the legend's window extent."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import impedax.plotting  # noqa: E402
from impedax.cli import main  # noqa: E402
from impedax.plotting import drawn_points  # noqa: E402

REAL = Path(__file__).parent / "fixtures" / "real"


@pytest.mark.parametrize("name", ["exampleDataParstat.txt", "exampleDataGamry.DTA"])
def test_no_residual_point_under_the_kk_legend(name, tmp_path, monkeypatch):
    written = []
    monkeypatch.setattr(impedax.plotting, "save_figure", lambda fig, path, **_: written.append(fig))
    assert main(["kk", str(REAL / name), "--plot", str(tmp_path / "kk.png"), "-q"]) == 0
    (fig,) = written
    fig.draw_without_rendering()
    ax = next(a for a in fig.axes if a.get_ylabel().startswith("KK residual"))
    box = ax.get_legend().get_window_extent()
    residuals = [line for line in ax.get_lines() if line.get_label() in ("Δ re", "Δ im")]
    assert len(residuals) == 2
    points = np.concatenate([line.get_transform().transform(line.get_xydata()) for line in residuals])
    under = (points[:, 0] >= box.x0) & (points[:, 0] <= box.x1) & (points[:, 1] >= box.y0) & (points[:, 1] <= box.y1)
    assert not under.any(), f"{under.sum()} residual points under the legend"
    drawn = drawn_points(ax)  # (and nothing else drawn: the lines between them, |Δ|, the rules' levels)
    assert not np.any((drawn[:, 0] >= box.x0) & (drawn[:, 0] <= box.x1) & (drawn[:, 1] >= box.y0) & (drawn[:, 1] <= box.y1))
