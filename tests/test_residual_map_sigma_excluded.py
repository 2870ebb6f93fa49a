"""The residual map of a batch (`BatchFitResult.plot_residual_map`, `impedax fit --residual-map`)
shows what the fits weighed: in units of the data's σ for ``--weighting sigma`` (until
2026-12-06 it showed (Z − Z_model)/|Z| there too, where users judge residuals against σ), and
marks the frequencies ``--exclude`` left out as hatched grey rows named in a legend (until
2026-12-06 their neighbours' cells stretched over them without a word). Oracles: residuals
written by hand (Z_model = Z − σ (2 − 1j): −2 and 1 in σ, model minus data as a single fit's
figure, since 2026-12-06), cell edges halfway in log f."""

import math

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.cli import main
from impedax.fitting.least_squares import BatchFitResult

F = np.geomspace(0.1, 1e5, 25)
W = 2 * np.pi * F
N = 3


def arc(k: int) -> np.ndarray:
    """R0 + R1 ∥ C1 (closed form), R1 growing with k (SYNTHETIC)."""
    r1 = 1000.0 * (1 + 0.1 * k)
    return 20 + r1 / (1 + 1j * W * r1 * 1e-5)


def batch(weighting: str, keep=None) -> BatchFitResult:
    """N spectra of `arc` written by hand with σ = 0.2 % to 10 % of |Z| (rising with f) and
    Z_model = Z − σ (2 − 1j), at the frequencies ``keep`` (positions in F; all by default)."""
    keep = np.arange(F.size) if keep is None else np.asarray(keep)
    z = np.stack([arc(k) for k in range(N)])[:, keep]
    sigma = np.abs(z) * np.geomspace(0.002, 0.1, F.size)[keep]
    ds = xr.Dataset(
        {
            "value": (("param", "cycle"), np.tile([[20.0], [1000.0], [1e-5]], N)), "stderr": (("param", "cycle"), np.tile([[0.1], [1.0], [1e-8]], N)),
            "fixed": ("param", np.zeros(3, bool)), "at_bound": (("param", "cycle"), np.zeros((3, N), bool)),
            "rms_rel": ("cycle", np.full(N, 0.01)), "chi2_red": ("cycle", [0.9, 1.2, 4.0]), "converged": ("cycle", np.ones(N, bool)),
            "Z": (("cycle", "frequency"), z), "Z_model": (("cycle", "frequency"), z - sigma * (2 - 1j)), "sigma": (("cycle", "frequency"), sigma),
        },
        coords={"param": ["R0", "R1", "C1"], "cycle": np.arange(N), "frequency": F[keep]},
        attrs={"model": "R0 + R1 || C1", "weighting": weighting, "impedax_kind": "batch_fit", "warnings": {}},
    )
    return BatchFitResult.from_xarray(ds)


def maps_of(fig, rows: int = F.size):
    return [np.ma.filled(np.ma.asarray(ax.collections[0].get_array(), float), np.nan).reshape(rows, -1) for ax in fig.axes[:2]]


def closed(fig):
    import matplotlib.pyplot as plt

    plt.close(fig)


def test_a_sigma_weighted_batch_maps_its_residuals_in_sigma():
    fig = batch("sigma").plot_residual_map()
    try:
        re_map, im_map = maps_of(fig)
        np.testing.assert_allclose(re_map, -2.0, rtol=1e-12)  # (Z_model − Z)/σ = −σ(2 − j)/σ: model minus data, as FitResult.residuals
        np.testing.assert_allclose(im_map, 1.0, rtol=1e-12)
        label = fig.axes[-1].get_ylabel()
        assert label.startswith("(Z_model − Z)/σ [σ]\n(± 2 σ: the 99th percentile"), label
        assert "sigma weighting (map in σ)" in fig._suptitle.get_text()
        # (below: each fit's chi2_red, as written, and the line at 1 a fit at the noise lies on)
        lines = fig.axes[2].get_lines()
        assert fig.axes[2].get_ylabel() == "chi2_red" and lines[0].get_ydata().tolist() == [0.9, 1.2, 4.0]
        assert any(list(line.get_ydata()) == [1.0, 1.0] for line in lines[1:])
    finally:
        closed(fig)


def test_a_modulus_weighted_batch_still_maps_relative_residuals():
    fig = batch("modulus").plot_residual_map()
    try:
        re_map, im_map = maps_of(fig)
        relative = np.geomspace(0.002, 0.1, F.size) * 100  # σ/|Z| [%], by construction
        np.testing.assert_allclose(re_map, np.tile(-2 * relative[:, None], (1, N)), rtol=1e-9)
        np.testing.assert_allclose(im_map, np.tile(relative[:, None], (1, N)), rtol=1e-9)
        assert fig.axes[-1].get_ylabel().startswith("(Z_model − Z)/|Z| [%]")
        assert fig.axes[2].get_ylabel() == "rms_rel [%]" and fig.axes[2].get_lines()[0].get_ydata().tolist() == [1.0] * N
    finally:
        closed(fig)


def test_left_out_frequencies_are_hatched_rows_of_their_own_named_in_a_legend():
    left = [5, 12]
    keep = [i for i in range(F.size) if i not in left]
    fig = batch("modulus", keep).plot_residual_map(excluded=F[left])
    try:
        re_map, im_map = maps_of(fig)
        assert np.isnan(re_map[left]).all() and np.isfinite(np.delete(re_map, left, axis=0)).all()
        edges = np.asarray(fig.axes[0].collections[0].get_coordinates())[:, 0, 1]  # (the cells' frequency edges)
        np.testing.assert_allclose(edges[1:-1], np.sqrt(F[1:] * F[:-1]), rtol=1e-12)  # (halfway in log f between every pair, the left-out ones too)
        for ax in fig.axes[:2]:
            hatched = [p for p in ax.patches if p.get_hatch() == "///"]
            spans = sorted((p.get_path().transformed(p.get_patch_transform()).get_extents().y0, p.get_path().transformed(p.get_patch_transform()).get_extents().y1) for p in hatched)
            assert len(spans) == 2
            for (low, high), i in zip(spans, left):
                assert low == pytest.approx(math.sqrt(F[i - 1] * F[i])) and high == pytest.approx(math.sqrt(F[i] * F[i + 1]))
        legend = fig.axes[0].get_legend()
        assert legend is not None and legend.get_texts()[0].get_text() == "left out of the fits: 1.78 Hz, 100 Hz"  # (F[5] = 10^1.25 × 0.1 Hz, F[12] = 100 Hz)
    finally:
        closed(fig)


def test_no_legend_without_left_out_frequencies_nor_for_those_outside_the_band():
    fig = batch("modulus", np.arange(1, F.size)).plot_residual_map(excluded=[F[0]])  # (below the fitted band: no row)
    try:
        assert fig.axes[0].get_legend() is None and not [p for p in fig.axes[0].patches if p.get_hatch()]
    finally:
        closed(fig)


@pytest.mark.slow  # (~11 s: a batch fit, compilation included)
def test_the_command_passes_what_exclude_left_out(tmp_path, monkeypatch, capsys):
    data = ix.make_spectrum(F, np.stack([arc(k) for k in range(N)]), dims="cycle")
    path = str(tmp_path / "cycles.nc")
    ix.save(data, path)
    seen = {}
    original = BatchFitResult.plot_residual_map

    def recorded(self, **options):
        seen.update(options)
        return original(self, **options)

    monkeypatch.setattr(BatchFitResult, "plot_residual_map", recorded)
    assert main(["fit", path, "--model", "R0 + R1 || C1", "--exclude", f"{F[5]:.6g},{F[12]:.6g}", "--residual-map", str(tmp_path / "map.png"), "--quiet"]) == 0
    np.testing.assert_allclose(seen["excluded"], F[[5, 12]])
    assert (tmp_path / "map.png").exists()


@pytest.mark.parametrize("bad", ["abc", [1.0, "x"], [-5.0], [float("nan")], [[1.0, 2.0]]])
def test_bad_left_out_frequencies_are_one_clear_error(bad):
    with pytest.raises(ix.ParameterError, match=r"plot_residual_map\(excluded=\.\.\.\): frequencies \[Hz\] left out of the fits, positive and finite"):
        batch("modulus").plot_residual_map(excluded=bad)
