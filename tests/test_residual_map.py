"""`BatchFitResult.plot_residual_map` and `impedax fit FILE --residual-map`: the relative
residuals of every fit of a batch as maps over the spectra and frequency (added 2026-12-06).
Oracles: the residuals recomputed from the fitted values with a numpy closed form of the model,
and, on SYNTHETIC series, a missing arc showing as one pattern in every spectrum where a
complete model leaves uncorrelated noise."""

from __future__ import annotations

import math
from pathlib import Path
import warnings

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

REAL = Path(__file__).parent / "fixtures" / "real"

F = np.geomspace(0.1, 1e5, 45)
W = 2 * np.pi * F
MODEL = "R0 + R1 || C1"


def r_rc(r0, r1, c1):
    """R0 + R1 ∥ C1 (closed form)."""
    return r0 + r1 / (1 + 1j * W * r1 * c1)


def series(with_second_arc: bool, n: int = 6):
    """n SYNTHETIC spectra, R1 growing along the series, 0.3 % noise; with a second arc
    (50 Ω ∥ 1 µF, τ = 50 µs) that MODEL lacks, or without."""
    rng = np.random.default_rng(5)
    rows = []
    for k in range(n):
        z = r_rc(20.0, 1000.0 * (1 + 0.1 * k), 1e-5)
        if with_second_arc:
            z = z + 50.0 / (1 + 1j * W * 50.0 * 1e-6)
        rows.append(z * (1 + 0.003 * (rng.standard_normal(F.size) + 1j * rng.standard_normal(F.size)) / math.sqrt(2)))
    return ix.make_spectrum(F, np.stack(rows), dims=("cycle",), coords={"cycle": np.arange(10, 10 + n)})


def fitted(data):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return ix.fit(MODEL, data, progress=False)


def maps_of(fig):
    """The two meshes' cells, (frequency ascending) × spectra, read back from the figure."""
    meshes = [ax.collections[0] for ax in fig.axes[:2]]
    return [np.asarray(m.get_array()).reshape(F.size, -1) for m in meshes]


def test_the_maps_hold_each_fits_relative_residuals():
    data = series(True)
    batch = fitted(data)
    fig = batch.plot_residual_map()
    try:
        re_map, im_map = maps_of(fig)
        for k in range(6):
            z_model = r_rc(*(float(batch.values(name).isel(cycle=k)) for name in ("R0", "R1", "C1")))
            z = data["Z"].isel(cycle=k).values
            expected = (z_model - z) / np.abs(z) * 100  # F is ascending already; model minus data, as FitResult.residuals (data minus model until 2026-12-06)
            np.testing.assert_allclose(re_map[:, k], expected.real, atol=1e-6)
            np.testing.assert_allclose(im_map[:, k], expected.imag, atol=1e-6)
        assert "modulus weighting" in fig._suptitle.get_text()
        assert [t.get_text() for t in fig.axes[2].get_xticklabels() if t.get_text()] == [str(c) for c in range(10, 16)]
    finally:
        import matplotlib.pyplot as plt

        plt.close(fig)


@pytest.mark.parametrize("with_second_arc, systematic", [(True, True), (False, False)])
def test_a_missing_arc_is_one_pattern_across_the_spectra_and_noise_is_not(with_second_arc, systematic):
    """The imaginary map's columns: correlated spectrum to spectrum (median r > 0.8) when the
    fitted model lacks the second arc; |median r| < 0.3 when nothing is missing (the case
    where the map must not suggest an effect)."""
    import matplotlib.pyplot as plt

    fig = fitted(series(with_second_arc)).plot_residual_map()
    try:
        _, im_map = maps_of(fig)
    finally:
        plt.close(fig)
    r = np.corrcoef(im_map.T)
    median = float(np.median(r[np.triu_indices_from(r, 1)]))
    assert (median > 0.8) if systematic else (abs(median) < 0.3)


def test_the_command_writes_the_map_and_refuses_it_for_one_spectrum(tmp_path, capsys):
    path = tmp_path / "cycles.nc"
    ix.save(series(True, 3), path)
    png = tmp_path / "map.png"
    assert main(["fit", str(path), "--model", MODEL, "--residual-map", str(png), "--quiet"]) == 0
    assert png.read_bytes()[:4] == b"\x89PNG"
    capsys.readouterr()
    one = tmp_path / "one.png"
    assert main(["fit", str(path), "--model", MODEL, "--select", "cycle=11", "--residual-map", str(one)]) == 2
    err = capsys.readouterr().err
    assert err.count("error:") == 1 and "--residual-map maps the residuals of several spectra" in err and "--plot" in err
    assert not one.exists()



def test_a_batch_whose_fits_miss_structure_points_at_the_map(tmp_path, capsys):
    """The batch's misfit hint (rms_rel 0.2–2 % and over 5× the KK chain's) ends with diagnose of
    the worst spectrum and, until the map is asked for, the option that maps all of them."""
    rng = np.random.default_rng(5)
    # a small second arc (1 Ω ∥ τ = 50 µs beside R0 = 20 Ω) and 0.05 % noise: rms_rel ≈ 1.3 %, ≫ the chain's
    z = [(r_rc(20.0, 1000.0 * (1 + 0.1 * k), 1e-5) + 1.0 / (1 + 1j * W * 5e-5)) * (1 + 0.0005 * (rng.standard_normal(F.size) + 1j * rng.standard_normal(F.size)) / math.sqrt(2))
         for k in range(3)]
    path = tmp_path / "cycles.nc"
    ix.save(ix.make_spectrum(F, np.stack(z), dims=("cycle",), coords={"cycle": [10, 11, 12]}), path)
    assert main(["fit", str(path), "--model", MODEL, "--quiet"]) == 0
    said = [line for line in capsys.readouterr().out.splitlines() if line.startswith("next: impedax diagnose")]
    assert len(said) == 1 and said[0].endswith("; --residual-map FIG.png on this command maps where it fails across all of them)")
    assert main(["fit", str(path), "--model", MODEL, "--quiet", "--residual-map", str(tmp_path / "m.png")]) == 0
    said = [line for line in capsys.readouterr().out.splitlines() if line.startswith("next: impedax diagnose")]
    assert len(said) == 1 and "--residual-map" not in said[0]


def _tick_texts(ax):
    ax.get_figure().canvas.draw()
    return [t.get_text() for t in ax.get_yticklabels() if t.get_text()], ax.yaxis.get_offset_text().get_text()


@pytest.mark.slow
def test_the_rms_panel_of_equal_fits_reads_plain_numbers_around_their_value():
    # (the four sheets of the REAL data.ods hold one spectrum: four fits equal to a few ulp,
    # 11.08 %, were ticked 4 and 5 under the offset "1e-11+1.107680505e1")
    data = ix.load(REAL / "data.ods")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        batch = ix.fit("R0 + R1 || CPE1", data, progress=False)
    z, w = data["Z"].values, 2 * np.pi * data["frequency"].values
    r0, r1, q, alpha = (float(batch.values(p).isel(sheet=0)) for p in ("R0", "R1", "CPE1.Q", "CPE1.alpha"))
    z_model = r0 + 1 / (1 / r1 + q * (1j * w) ** alpha)  # (closed form: R0 + R1 ∥ CPE1)
    fig = batch.plot_residual_map()
    try:
        ax_rms = fig.axes[2]
        rms = float(np.sqrt(np.mean(np.abs((z[0] - z_model) / np.abs(z[0])) ** 2))) * 100
        texts, offset = _tick_texts(ax_rms)
        assert offset == ""
        low, high = ax_rms.get_ylim()
        assert low < rms < high and high - low < 0.2 * rms  # (a window about the value, not ±1e-11)
        ticks = ax_rms.get_yticks()
        values = [float(t.get_text().replace("−", "-")) for t, at in zip(ax_rms.get_yticklabels(), ticks) if low <= at <= high]
        np.testing.assert_allclose(values, [at for at in ticks if low <= at <= high], rtol=1e-3)  # (each label its own place)
        assert len(set(values)) == len(values) >= 2
    finally:
        import matplotlib.pyplot as plt

        plt.close(fig)


def outlier_series():
    """SYNTHETIC: `series` without the second arc, one point of cycle 3 ×11 (a 1000 % outlier),
    and its batch fit: (Z, batch)."""
    z = series(False)["Z"].values.copy()
    z[3, 20] *= 11
    return z, fitted(ix.make_spectrum(F, z, dims=("cycle",), coords={"cycle": np.arange(6)}))


def test_the_rms_panel_goes_log_when_one_fit_is_decades_off():
    # (the outlier puts cycle 3's rms_rel ~100× the others')
    _, batch = outlier_series()
    fig = batch.plot_residual_map()
    try:
        ax_rms = fig.axes[2]
        assert ax_rms.get_yscale() == "log"
        texts, offset = _tick_texts(ax_rms)
        assert offset == "" and texts
    finally:
        import matplotlib.pyplot as plt

        plt.close(fig)


def test_the_colour_bar_says_where_the_colour_saturates():
    # (SYNTHETIC: one point of one spectrum ×11, a 1000 % outlier far beyond the 99th percentile;
    # the bar's ends are arrows and its label names the largest |residual|, from numpy)
    z, batch = outlier_series()
    fig = batch.plot_residual_map()
    try:
        bar = fig.axes[-1]
        z_model = r_rc(*(float(batch.values(p).isel(cycle=3)) for p in ("R0", "R1", "C1")))
        relative = (z[3] - z_model) / np.abs(z[3]) * 100
        largest = max(np.abs(relative.real).max(), np.abs(relative.imag).max())
        assert largest > 50  # (relative to the ×11 point itself: (11 − 1)/11 of it)
        label = bar.get_ylabel()
        assert f"up to {largest:.3g} %" in label, label
        mesh = fig.axes[1].collections[0]  # (the bar is made from the second map)
        assert mesh.colorbar.extend in ("min", "both")  # (the ×11 point lies above its model: model minus data, far below 0)
        fig.draw_without_rendering()  # (the label, on two lines, stays inside the figure: on one it ran past the top)
        text, box = bar.yaxis.label, fig.bbox
        extent = text.get_window_extent()
        assert box.y0 <= extent.y0 and extent.y1 <= box.y1 and extent.x1 <= box.x1
    finally:
        import matplotlib.pyplot as plt

        plt.close(fig)


def test_a_global_fits_figures_name_what_it_shares():
    # (SYNTHETIC: R0 shared over cycle; the map and the parameter figure of a global fit read as
    # those of independent fits of the same series, nothing naming R0 shared)
    import matplotlib.pyplot as plt

    data = series(False, n=3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        shared = ix.fit(MODEL, data, shared=["R0"], over="cycle", progress=False)
        independent = ix.fit(MODEL, data, progress=False)
    for figure in (shared.plot_residual_map(), shared.plot()):
        assert "R0 shared over cycle" in figure.get_suptitle()
        plt.close(figure)
    for figure in (independent.plot_residual_map(), independent.plot()):
        assert "shared" not in figure.get_suptitle()
        plt.close(figure)


def test_maps_of_more_cells_than_the_vector_limit_are_rasterised(monkeypatch):
    # (the limit lowered to 6 spectra × 45 frequencies − 1 cells: both maps are drawn as images in
    # a vector file, as 1,000 spectra are at the limit of 5,000)
    import matplotlib.pyplot as plt

    import impedax.plotting.fit as plotting_fit

    batch = fitted(series(False))
    for limit, rasterised in ((6 * F.size - 1, True), (6 * F.size, False)):
        monkeypatch.setattr(plotting_fit, "MAP_VECTOR_CELLS", limit)
        fig = batch.plot_residual_map()
        try:
            assert [ax.collections[0].get_rasterized() for ax in fig.axes[:2]] == [rasterised, rasterised]
        finally:
            plt.close(fig)


def test_the_map_writes_float_labels_without_binary_noise():
    # (SYNTHETIC: soc = np.arange(6) * 0.1; the ticks read "0.30000000000000004", "0.6000000000000001")
    import matplotlib.pyplot as plt

    data = series(False).assign_coords(cycle=np.arange(6) * 0.1)
    fig = fitted(data).plot_residual_map()
    try:
        fig.canvas.draw()
        assert [t.get_text() for t in fig.axes[2].get_xticklabels() if t.get_text()] == ["0.0", "0.1", "0.2", "0.3", "0.4", "0.5"]
    finally:
        plt.close(fig)
