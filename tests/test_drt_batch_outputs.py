"""Batch DRT outputs say per spectrum what is per spectrum: the .nc's z_ref, λ choice, note and
band λ are variables over the batch (not the first spectrum's as global attributes), the text
says the floor once, the figure's title counts peaks without "3–3", and a negative L is noted
whatever its size. Spectra: numpy formulas (R0 + R‖C arcs), fixed noise seeds."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.cli import main
from impedax.fitting.drt import drt
from impedax.fitting.drt.result import format_lambda

F = np.geomspace(0.01, 1e5, 61)
W = 2 * np.pi * F


def arcs(scale: float) -> np.ndarray:
    """R0 + R1‖C1 + R2‖C2 (τ 1 ms and 1 s), all resistances times ``scale``."""
    return scale * (10.0 + 50.0 / (1 + 1j * W * 1e-3) + 100.0 / (1 + 1j * W * 1.0))


def noisy(z, level, seed):
    rng = np.random.default_rng(seed)
    return z + level * np.abs(z) * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size)) / math.sqrt(2)


@pytest.fixture(scope="module")
def cycles(tmp_path_factory):
    """Two cycles whose max|Z| differ by a factor 2 (160 Ω and 320 Ω at f → 0), 0.5 % noise."""
    spectra = np.stack([noisy(arcs(1.0), 0.005, 1), noisy(arcs(2.0), 0.005, 2)])
    path = tmp_path_factory.mktemp("drtbatch") / "cycles.nc"
    ix.save(ix.make_spectrum(F, spectra, dims=("cycle",), coords={"cycle": [1, 2]}), path)
    return str(path), spectra


def run(capsys, *argv):
    code = main(["drt", *argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_the_batch_netcdf_stores_each_spectrums_lambda_settings_as_variables(cycles, tmp_path, capsys):
    path, spectra = cycles
    out = tmp_path / "d.nc"
    assert run(capsys, path, "--out", str(out))[0] == 0
    payload = json.loads(run(capsys, path, "--json")[1])
    with xr.open_dataset(out) as ds:
        # z_ref = max|Z| of each spectrum, computed here from the numbers written
        assert ds["z_ref"].dims == ("cycle",)
        assert ds["z_ref"].values == pytest.approx(np.abs(spectra).max(axis=1), rel=1e-12)
        assert ds["lambda_choice"].values == pytest.approx([s["lambda_choice"] for s in payload["spectra"]], rel=1e-12)
        assert ds["band_lambda"].values == pytest.approx([s["band_lambda"] for s in payload["spectra"]], rel=1e-12)
        assert list(ds["lambda_note"].values) == [s["lambda_note"] or "" for s in payload["spectra"]]
        # no per-spectrum value left among the global attributes
        assert "band_lambda" not in ds.attrs and "lambda_note" not in ds.attrs
        assert "z_ref" in ds.attrs["lambda_scale"] and not any(ch.isdigit() for ch in ds.attrs["lambda_scale"].replace("z_ref^2", ""))
        assert ds.attrs["lambda_method"] == "gcv"
    # the JSON carries each spectrum's own z_ref
    assert [s["z_ref_ohm"] for s in payload["spectra"]] == pytest.approx(np.abs(spectra).max(axis=1), rel=1e-12)
    assert ix.load(str(out))["z_ref"].size == 2  # read back by the package


def test_the_batch_text_says_the_floor_once(cycles, capsys):
    path, _ = cycles
    batch = drt(ix.load(path))
    floored = [r for r in batch.results if r.lambda_note.startswith("raised to the floor")]
    lines = batch.report().splitlines()
    assert len(lines) == 3
    assert all("raised to the floor" not in line for line in lines[1:])
    if floored:
        assert f"λ raised to the floor 0.0001 on {len(floored)} of 2 spectra (gcv chose" in lines[0]
    else:
        assert "raised to the floor" not in lines[0]
    # a spectrum whose λ is its criterion's own gets it on its line when others were floored
    for line, one in zip(lines[1:], batch.results):
        assert (f"λ {one.lam:.2g}" in line) == (bool(floored) and one not in floored)


def test_many_floored_spectra_are_one_summary_with_the_range_of_choices():
    # clean arcs at 0.1 % noise: GCV chooses below 1e-4 for every one
    spectra = np.stack([noisy(arcs(s), 0.001, 10 + i) for i, s in enumerate((1.0, 1.5, 2.0, 2.5))])
    batch = drt(ix.make_spectrum(F, spectra, dims=("cycle",), coords={"cycle": [0, 1, 2, 3]}))
    choices = [r.lambda_choice for r in batch.results]
    assert all(c < 1e-4 for c in choices), choices
    first, *rest = batch.report().splitlines()
    assert "λ raised to the floor 0.0001 on 4 of 4 spectra (gcv chose " in first
    assert format_lambda(min(choices), 2) in first and format_lambda(max(choices), 2) in first
    assert len(rest) == 4 and all("λ" not in line for line in rest)


def test_the_batch_plot_title_says_n_peaks_when_all_spectra_have_n(cycles):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    batch = drt(ix.load(cycles[0]))
    assert set(batch.n_peaks.ravel()) == {2}
    fig = batch.plot()
    try:
        title = fig._suptitle.get_text()
        assert ": 2 peaks in the measured τ range" in title and "–" not in title  # resolved peaks inside the window (2026-12-01)
    finally:
        plt.close(fig)


def test_a_many_spectra_plot_draws_every_curve(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    spectra = np.stack([noisy(arcs(1.0 + 0.05 * i), 0.005, 20 + i) for i in range(12)])
    batch = drt(ix.make_spectrum(F, spectra, dims=("cycle",), coords={"cycle": list(range(12))}))
    fig = batch.plot()
    try:
        ax = fig.axes[0]
        curves = [seg for c in ax.collections for seg in getattr(c, "get_segments", lambda: [])()]
        assert len(curves) == 12 and np.array_equal(curves[3][:, 1], batch.results[3].gamma)
        assert ax.get_xscale() == "log"
    finally:
        plt.close(fig)


def test_a_negative_inductance_is_noted_below_the_warning_threshold(tmp_path, capsys):
    # R0 + R‖C + jωL with L = −1 µH: ω_max·|L| = 0.63 Ω, 3 % of |Z| ≈ 20 Ω at 100 kHz (under 5 %)
    l_h = -1e-6
    z = 20.0 + 100.0 / (1 + 1j * W * 1e-3) + 1j * W * l_h
    top = abs(z[-1])
    assert 2 * math.pi * F[-1] * abs(l_h) < 0.05 * top
    path = tmp_path / "negl.csv"
    ix.save(ix.make_spectrum(F, noisy(z, 0.002, 3)), path)
    result = drt(ix.load(str(path)))
    assert result.l_h == pytest.approx(l_h, rel=0.2)
    assert not any(w.startswith("L = ") for w in result.warnings)
    code, out, _ = run(capsys, str(path))
    assert code == 0
    note = [line for line in out.splitlines() if line.startswith("note: L = ")]
    assert len(note) == 1 and "negative" in note[0] and "artefact" in note[0]
    payload = json.loads(run(capsys, str(path), "--json")[1])
    assert len(payload["notes"]) == 1 and payload["warnings"] == []


def test_a_positive_inductance_has_no_note():
    z = 20.0 + 100.0 / (1 + 1j * W * 1e-3) + 1j * W * 1e-6
    result = drt((F, noisy(z, 0.002, 4)))
    assert result.l_h > 0 and result.notes == ()


def test_drt_residuals_are_data_minus_the_drt_model_and_the_names_are_the_datasets(cycles):
    """`DRTResult.residuals` = (Z_data − Z_fit)/|Z_data| (docs/drt.md; the KK test's sign, a
    circuit fit's is the opposite), Z_fit evaluated anew at the data's frequencies by
    `predict`; the long_name says the same. `drt.result.BATCH_RESULT_NAMES`, the names a batch
    dimension may not have, are exactly the batch Dataset's variables and dimensions."""
    from impedax.fitting.drt.result import BATCH_RESULT_NAMES

    path, spectra = cycles
    batch = drt(path)
    for k, one in enumerate(batch.results):
        by_hand = (spectra[k] - one.predict(F)) / np.abs(spectra[k])
        assert np.abs(by_hand).max() > 1e-3  # 0.5 % noise: the sign is measurable
        np.testing.assert_allclose(one.residuals, by_hand, atol=1e-9)
    assert batch[0].to_xarray()["residuals"].attrs["long_name"] == "(Z_data - Z_fit)/|Z_data|"
    ds = batch.to_xarray()
    assert (set(ds.variables) | set(ds.dims)) - {"cycle"} == BATCH_RESULT_NAMES


def test_the_json_names_the_file_read_as_kk_does(cycles, tmp_path, capsys):
    """``source`` (the file and any --select) at the top of the DRT JSON, of several spectra and
    of one, as `impedax kk --json` gives it; the --out .json too."""
    path, _ = cycles
    code, out, _ = run(capsys, path, "--json")
    assert code == 0 and json.loads(out)["source"] == path
    code, out, _ = run(capsys, path, "--select", "cycle=2", "--json")
    assert code == 0 and json.loads(out)["source"] == f"{path} [cycle=2]"
    assert main(["kk", path, "--select", "cycle=2", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["source"] == f"{path} [cycle=2]"  # (the same key and text)
    code, _, _ = run(capsys, path, "--out", str(tmp_path / "d.json"))
    assert code == 0 and json.loads((tmp_path / "d.json").read_text())["source"] == path


def test_the_batch_dataset_holds_what_each_spectrums_dataset_holds(cycles):
    """The batch .nc lacked the residuals, the peaks' standard deviations, C and the noise
    estimates of the single-spectrum .nc: each now equals the single DRT's of that cycle, and
    the residuals are (Z − Z_fit)/|Z| of the numbers written."""
    path, spectra = cycles
    data = ix.load(path)
    batch = drt(data).to_xarray()
    for i in range(2):
        one = drt(data.isel(cycle=i)).to_xarray()
        n = one.sizes["peak"]
        for name in ("residuals", "peak_r_sd", "peak_log10_tau_sd", "capacitance", "residual_sigma", "difference_noise"):
            got = batch[name].isel(cycle=i).values
            got = got[:n] if "peak" in batch[name].dims else got
            np.testing.assert_allclose(got, one[name].values, rtol=1e-9, err_msg=name)
        z, fit = batch["Z"].isel(cycle=i).values, batch["Z_fit"].isel(cycle=i).values
        np.testing.assert_allclose(batch["residuals"].isel(cycle=i).values, (z - fit) / np.abs(z), rtol=1e-12)


def test_a_drt_batch_repr_is_one_line(cycles):
    """The generated repr printed every spectrum's arrays; now one line: the count, the counted
    peaks (two arcs per cycle, τ 1 ms and 1 s: "2 counted peak(s) each", 2026-12-06; "2 counted
    peak(s)" of 2 spectra read as two in all) and the fits' rms_rel."""
    path, _ = cycles
    batch = drt(path)
    low, high = (f"{v * 100:.3g}" for v in sorted(r.rms_rel for r in batch.results))
    span = low if low == high else f"{low}–{high}"
    assert repr(batch) == f"DRTBatchResult(2 spectra over cycle: 2 counted peak(s) each, rms_rel {span} %)"


def test_the_batch_summary_reads_each_spectrum_s_suggestion_once(cycles, monkeypatch):
    """The batch JSON reads each spectrum's starting circuit once, for its row and for the one most
    spectra suggest (it read each twice: 0.15 s of 0.74 s on the 130 REAL battery cycles). Oracle:
    the calls of `suggest_circuit` counted, and the JSON's circuit the rows' most common."""
    from collections import Counter

    from impedax.fitting.drt import suggest

    path, _ = cycles
    result = drt(ix.load(path))
    calls = []
    original = suggest.suggest_circuit
    monkeypatch.setattr(suggest, "suggest_circuit", lambda one: calls.append(id(one)) or original(one))
    out = result.summary()
    assert sorted(calls) == sorted(id(one) for one in result.results)
    models = [row["suggested_model"] for row in out["spectra"]]
    assert out["suggested_model"] == Counter(models).most_common(1)[0][0] and out["n_suggesting"] == models.count(out["suggested_model"])


def test_the_many_spectra_colour_bar_reads_the_spectra_labels_not_positions():
    # SYNTHETIC 12 cycles labelled 100 … 111 (as `--select cycle=100:111` leaves them): the colour
    # bar read 0 … 10, the positions, so the colour of cycle 110 was ticked "10"
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cycles = list(range(100, 112))
    spectra = np.stack([noisy(arcs(1.0 + 0.05 * i), 0.005, 40 + i) for i in range(12)])
    batch = drt(ix.make_spectrum(F, spectra, dims=("cycle",), coords={"cycle": cycles}))
    fig = batch.plot()
    try:
        fig.canvas.draw()
        bar_axes = next(a for a in fig.axes if a.get_ylabel() == "cycle")  # the spectra's colour bar
        ticks = [(t, label.get_text()) for t, label in zip(bar_axes.get_yticks(), bar_axes.get_yticklabels()) if label.get_text() and 0 <= t <= 11]
        assert len(ticks) >= 3
        # each tick at position k reads the k-th cycle's label, taken from the file's own coordinate
        assert all(text == str(cycles[int(round(t))]) for t, text in ticks)
        assert bar_axes.get_ylabel() == "cycle"
    finally:
        plt.close(fig)


def test_the_batch_figure_maps_gamma_over_the_spectra_with_each_spectrums_peaks():
    # SYNTHETIC R0 + R1‖C1 + R2‖C2 over 3 cycles, τ1 = R1 C1 = 0.1 ms fixed and τ2 = R2 C2 moving
    # 10 ms → 30 ms → 100 ms (R2 = 100 Ω, C2 = τ2/R2), 0.2 % noise: the batch figure drew γ(τ) of
    # each cycle on one axes, without its peaks, so how a peak moves along a series was not shown
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PathCollection, QuadMesh

    taus = (0.01, 0.03, 0.1)
    spectra = np.stack([noisy(10.0 + 50.0 / (1 + 1j * W * 1e-4) + 100.0 / (1 + 1j * W * tau), 0.002, 60 + i) for i, tau in enumerate(taus)])
    batch = drt(ix.make_spectrum(F, spectra, dims=("cycle",), coords={"cycle": [5, 6, 7]}))
    fig = batch.plot()
    try:
        maps = [a for a in fig.axes if a.get_label() != "<colorbar>" and any(isinstance(c, QuadMesh) for c in a.collections)]
        assert len(maps) == 1
        ax = maps[0]
        assert ax.get_yscale() == "log" and ax.get_ylabel() == "τ [s]"
        # the mesh: one column per spectrum, its γ in Ω, on a colour bar named γ [Ω]
        mesh = next(c for c in ax.collections if isinstance(c, QuadMesh))
        assert np.asarray(mesh.get_array()).size == 3 * batch.results[0].gamma.size
        assert any(a.get_ylabel().startswith("γ [Ω]") for a in fig.axes if a is not ax)
        # the filled markers are each cycle's counted peaks: at 0.1 ms in every cycle and at the
        # generating τ2, within 0.15 decade (the formula's R C, not impedax's numbers)
        filled = next(c for c in ax.collections if isinstance(c, PathCollection) and c.get_label().startswith("peaks"))
        points = np.asarray(filled.get_offsets())
        for i, tau in enumerate(taus):
            at = np.log10(points[np.isclose(points[:, 0], i), 1])
            assert any(abs(t - np.log10(1e-4)) < 0.15 for t in at), (i, at)
            assert any(abs(t - np.log10(tau)) < 0.15 for t in at), (i, at)
        # the map shares the spectra's axis with the rms_rel panel below (labelled 5, 6, 7)
        assert ax.get_xlim() == pytest.approx((-0.5, 2.5))
    finally:
        plt.close(fig)


def test_the_batch_rms_panel_sets_each_fit_beside_the_noise_and_marks_the_misfits_red():
    # SYNTHETIC: three cycles of 10 Ω + 100 Ω/(1 + jω 1 ms) with 1 % relative noise on each part,
    # and a fourth whose Re Z drifts by 110 Ω × f_min/f (no Im part: not a relaxation γ can
    # reproduce): the rms_rel panel drew the four alike, with no noise level to read them against,
    # where the KK batch figure draws its noise estimate and the spectra not valid in red
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    f = np.logspace(-2, 5, 71)
    w = 2 * np.pi * f
    clean = 10.0 + 100.0 / (1 + 1j * w * 1e-3)

    def relative_noise(seed):
        rng = np.random.default_rng(seed)
        return clean * (1 + 0.01 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)))

    spectra = np.stack([relative_noise(70), relative_noise(71), relative_noise(72), relative_noise(73) + 110.0 * f.min() / f])
    batch = drt(ix.make_spectrum(f, spectra, dims=("cycle",), coords={"cycle": [1, 2, 3, 4]}))
    fig = batch.plot()
    try:
        ax = fig.axes[1]  # the rms_rel panel
        lines = {line.get_label(): line for line in ax.get_lines()}
        noise = next(line for label, line in lines.items() if label.startswith("rms_rel of the noise alone"))
        # 1 % per part gives rms_rel √2 × 1 % = 1.41 % of the complex residual; loose: the
        # first-difference estimate of 71 points scatters by some 10 %
        assert np.asarray(noise.get_ydata())[:3] == pytest.approx([math.sqrt(2)] * 3, rel=0.3)
        red = next(line for label, line in lines.items() if "beyond the noise" in label)
        assert list(np.asarray(red.get_xdata())) == [3]  # the drifting cycle, and only it
        assert list(np.asarray(lines["rms_rel"].get_xdata())) == [0, 1, 2]
        assert ax.get_yscale() == "log"
    finally:
        plt.close(fig)


def test_the_plot_option_says_what_a_file_of_several_spectra_gets(capsys):
    # `impedax kk --help` says what --plot draws for several spectra; `impedax drt --help` spoke of
    # one spectrum's figure (Nyquist/Bode), which a file of several does not get
    with pytest.raises(SystemExit):
        main(["drt", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    start = text.index("--plot FILE", text.index("options:"))
    plot_help = text[start:text.index("--dpi N", start)]
    assert "several spectra" in plot_help and "mapped over the spectra" in plot_help and "peaks" in plot_help


def test_the_batch_map_counts_gamma_in_the_overlay_panels_prefix():
    """The γ map's colour bar of `plot_drt_batch` (`impedax drt FILE.nc --plot`) counts γ in the
    SI prefix of the overlay panel above it: the overlay read γ [kΩ] up to 7.6 and the bar γ [Ω]
    up to 7000 in one figure (SYNTHETIC stack of three R0 + R1 ∥ CPE1 + R2 ∥ C2, kΩ arcs). Here
    the cycles' arcs times 100 (γ of tens of kΩ). Oracle: the label texts and the largest tick
    value against the bar's top γ from the result."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    spectra = np.stack([noisy(arcs(100.0), 0.005, 1), noisy(arcs(200.0), 0.005, 2)])
    batch = drt(ix.make_spectrum(F, spectra, dims=("cycle",), coords={"cycle": [1, 2]}))
    fig = batch.plot()
    try:
        fig.canvas.draw()
        overlay, bar_ax = fig.axes[0], fig.axes[-1]
        assert overlay.get_ylabel() == "γ [kΩ]"
        assert bar_ax.get_ylabel().startswith("γ [kΩ]")
        top = max(bar_ax.get_ylim())
        assert 1e3 <= top < 1e6  # (the map's γ in Ω: the prefix is k)
        ticks = [float(t.get_text().replace("\N{MINUS SIGN}", "-")) for t in bar_ax.get_yticklabels() if t.get_text() and t.get_position()[1] <= top]
        assert ticks and max(ticks) <= top / 1e3 + 1e-9 and max(ticks) >= 0.3 * top / 1e3
    finally:
        plt.close(fig)
