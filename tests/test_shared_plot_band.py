"""A global fit's figure draws a shared parameter as one band of value ± standard error, titled
"(shared)", not the same error bar at every spectrum (REAL 130 battery cycles with --shared
CPE1.alpha: a wall of 130 identical bars)."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
import xarray as xr  # noqa: E402

import impedax as ix  # noqa: E402


@pytest.mark.slow  # (~8 s: a global fit of three spectra and its figure)
def test_a_shared_parameter_is_a_band_and_the_others_keep_their_bars():
    """SYNTHETIC: three cells of R0 + R1 || C1 (numpy formula, C1 = 10 µF in each, 0.5 % noise),
    C1 shared."""
    f = np.logspace(-1, 5, 30)
    rng = np.random.default_rng(5)
    r1 = np.array([100.0, 200.0, 400.0])
    z = 10 + r1[:, None] / (1 + 2j * np.pi * f[None, :] * r1[:, None] * 1e-5)
    z = z * (1 + 0.005 * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape)) / np.sqrt(2))
    data = xr.Dataset({"Z": (("cell", "frequency"), z)}, coords={"cell": ["a", "b", "c"], "frequency": f})
    fit = ix.fit("R0 + R1 || C1", data, shared="C1", progress=False)
    value, error = float(fit.values("C1")), float(fit.stderr("C1"))
    assert np.isfinite(error) and error > 0
    fig = fit.plot()
    try:
        panels = {ax.get_title(): ax for ax in fig.axes}
        shared = next(ax for title, ax in panels.items() if title.startswith("C1 ") and title.endswith("(shared)"))
        assert not shared.containers  # (no error bars)
        (band,) = [p for p in shared.patches]
        low, high = band.get_y(), band.get_y() + band.get_height()  # (axhspan: a rectangle in data y)
        assert np.isclose(low, value - error, rtol=1e-9) and np.isclose(high, value + error, rtol=1e-9)
        r1_panel = next(ax for title, ax in panels.items() if title.startswith("R1 "))
        assert r1_panel.containers and "(shared)" not in r1_panel.get_title()
    finally:
        plt.close(fig)
