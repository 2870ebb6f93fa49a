"""Z-HIT of every spectrum of a file or Dataset of several (`zhit_batch`, `impedax kk --method
zhit`), against closed-form SYNTHETIC spectra: a modulus drift where it was put, nothing where
nothing was; until 2026-12-06 Z-HIT took one spectrum only, where the linear test and the DRT
took the file's every spectrum."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.errors import DataError

F = np.geomspace(0.01, 1e5, 71)
W = 2 * np.pi * F
CYCLES = [3, 17, 40]  # labels, not positions


def r_cpe(r1: float) -> np.ndarray:
    """R0 + R1 ∥ CPE (closed form)."""
    return 10 + 1 / (1 / r1 + 1e-4 * (1j * W) ** 0.8)


def stack() -> tuple[np.ndarray, np.ndarray]:
    """Three SYNTHETIC cycles with 0.5 % noise; the second's |Z| drifts up to 10 % below
    0.1 Hz while its phase does not (the signature of drift Z-HIT is for)."""
    rng = np.random.default_rng(11)
    rows = []
    for k, r1 in enumerate((1000.0, 1200.0, 1500.0)):
        z = r_cpe(r1) * (1 + 0.005 * (rng.standard_normal(F.size) + 1j * rng.standard_normal(F.size)) / math.sqrt(2))
        if k == 1:
            low = F < 0.1
            z[low] *= 1 + 0.1 * np.log10(0.1 / F[low])
        rows.append(z)
    return np.stack(rows), F < 0.1


def test_the_drifting_cycle_alone_is_flagged_where_it_drifts():
    z, drifted = stack()
    data = ix.make_spectrum(F, z, dims=("cycle",), coords={"cycle": CYCLES})
    batch = ix.zhit_batch(data)
    assert batch.dims == ("cycle",) and batch.shape == (3,)
    assert batch.valid.tolist() == [True, False, True]
    flagged = np.asarray(batch[1].flagged, bool)
    assert flagged.any() and np.all(F[flagged] < 0.1)  # only where the drift was put
    assert batch.labels()[1] == {"cycle": 17}
    text = batch.report("cycles.nc")
    assert text.splitlines()[0].startswith("Z-HIT of 3 spectra over cycle: 2 valid")
    assert any(line.split()[:3] == ["cycle=17", "NOT", "valid"] for line in text.splitlines()) and "--method zhit --select cycle=17" in text
    assert "ZHITBatchResult(3 spectra over cycle: 2 valid, 1 not)" == repr(batch)


def test_each_spectrum_of_the_batch_is_its_own_zhit():
    z, _ = stack()
    batch = ix.zhit_batch(ix.make_spectrum(F, z, dims=("cycle",), coords={"cycle": CYCLES}), noise_floor=0.02)
    for k in range(3):
        alone = ix.zhit((F, z[k]), noise_floor=0.02)
        np.testing.assert_allclose(batch[k].modulus, alone.modulus, rtol=1e-12)
        assert batch[k].bad_bands == alone.bad_bands and batch[k].threshold == alone.threshold
    ds = batch.to_xarray()
    assert ds["residuals"].dims == ("cycle", "frequency") and ds["cycle"].values.tolist() == CYCLES
    # residual = (|Z| − modulus)/|Z|, recomputed from the stored arrays
    np.testing.assert_allclose(ds["residuals"].values, (np.abs(z) - ds["modulus_zhit"].values) / np.abs(z), rtol=1e-9, atol=1e-15)
    assert ds["valid"].values.tolist() == [True, False, True] and ds.sizes["band"] == 1


def test_a_batch_dimension_named_as_a_result_variable_is_refused_before_any_test():
    z, _ = stack()
    with pytest.raises(DataError, match="'band'.*rename"):
        ix.zhit_batch(ix.make_spectrum(F, z, dims=("band",)))


def test_a_zero_modulus_names_its_spectrum():
    z, _ = stack()
    z[2, 5] = 0
    with pytest.raises(DataError, match="spectrum cycle=40: .*ln|Z| is undefined"):
        ix.zhit_batch(ix.make_spectrum(F, z, dims=("cycle",), coords={"cycle": CYCLES}))


def test_the_command_tests_every_spectrum_of_a_file(tmp_path, capsys):
    z, _ = stack()
    path = tmp_path / "cycles.nc"
    ix.save(ix.make_spectrum(F, z, dims=("cycle",), coords={"cycle": CYCLES}), path)
    assert main(["kk", str(path), "--method", "zhit", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["method"] == "zhit" and out["n_spectra"] == 3 and out["n_valid"] == 2 and out["dims"] == ["cycle"]
    assert [s["labels"] for s in out["spectra"]] == [{"cycle": c} for c in CYCLES]
    assert [s["valid"] for s in out["spectra"]] == [True, False, True]
    assert main(["kk", str(path), "--method", "zhit", "--out", str(tmp_path / "z.csv")]) == 0
    capsys.readouterr()
    lines = (tmp_path / "z.csv").read_text().splitlines()
    assert lines[0].startswith("cycle,frequency_hz,z_abs_ohm,modulus_zhit_ohm") and len(lines) == 1 + 3 * F.size
    # one spectrum picked: the single test's output, as before
    assert main(["kk", str(path), "--method", "zhit", "--select", "cycle=17", "--json"]) == 0
    one = json.loads(capsys.readouterr().out)
    assert one["valid"] is False and "spectra" not in one


@pytest.mark.parametrize("method", ["linear", "zhit"])
def test_the_plot_of_several_spectra_maps_each_residual_where_it_was_measured(method, tmp_path):
    """`impedax kk FILE --plot` on a file of several spectra (until 2026-12-06 "takes one
    spectrum"): a map of every spectrum's residual magnitude over the spectra and frequency,
    read back from the figure's mesh, and the flagged points of the drifting cycle circled."""
    import matplotlib.pyplot as plt

    z, _ = stack()
    data = ix.make_spectrum(F, z, dims=("cycle",), coords={"cycle": CYCLES})
    if method == "zhit":
        batch = ix.zhit_batch(data)
        magnitude = np.stack([np.abs(r.residuals) for r in batch.results])
    else:
        batch = ix.kk_test_batch(data)
        magnitude = np.stack([np.hypot(r.residuals_real, r.residuals_imag) for r in batch.results])
    fig = batch.plot()
    try:
        ax_map, ax_rms = fig.axes[0], fig.axes[1]
        mesh = ax_map.collections[0]
        cells = np.asarray(mesh.get_array()).reshape(F.size, 3)  # (frequency ascending) × spectra
        low, high = mesh.norm.vmin, mesh.norm.vmax
        np.testing.assert_allclose(cells, np.clip(magnitude.T * 100, low, high), rtol=1e-12)
        circled = ax_map.collections[1].get_offsets()
        flagged = np.nonzero(np.asarray(batch[1].flagged, bool))[0]
        assert set(np.asarray(circled)[:, 0]) == {1.0} and np.allclose(np.sort(circled[:, 1]), np.sort(F[flagged]))
        assert [t.get_text() for t in ax_rms.get_xticklabels() if t.get_text()] == ["3", "17", "40"]
        assert "2 " in fig._suptitle.get_text() and "1 not" in fig._suptitle.get_text()
    finally:
        plt.close(fig)
    path = tmp_path / "cycles.nc"
    ix.save(data, path)
    png = tmp_path / "map.png"
    assert main(["kk", str(path), "--method", method, "--plot", str(png)]) == 0
    assert png.read_bytes()[:4] == b"\x89PNG"


def _html_rows(html: str) -> list[list[str]]:
    """The cells of an HTML table's body, row by row (the test's own reading of the markup)."""
    import re

    body = html.split("<tbody>")[1].split("</tbody>")[0]
    return [re.findall(r"<td>(.*?)</td>", row) for row in body.split("</tr>") if "<td>" in row]


def test_a_notebook_shows_each_spectrum_of_a_batch_as_a_row():
    """KK, Z-HIT and DRT batches in a notebook showed their one-line repr only (added 2026-12-06)."""
    z, _ = stack()
    data = ix.make_spectrum(F, z, dims=("cycle",), coords={"cycle": CYCLES})
    for batch in (ix.zhit_batch(data), ix.kk_test_batch(data)):
        rows = _html_rows(batch._repr_html_())
        assert [row[0] for row in rows] == ["3", "17", "40"]
        assert [row[1] for row in rows] == ["valid" if bool(v) else "NOT valid" for v in batch.valid]
        assert [float(row[2]) for row in rows] == pytest.approx(batch.rms_rel * 100, rel=5e-3)
    # the DRT of R0 + R1 ∥ CPE(α = 0.8): R_pol = R1 (the DC limit minus R0); not for cycle 17,
    # whose |Z| was made to drift up to 10 % at the low end
    drt = ix.drt(data)
    rows = _html_rows(drt._repr_html_())
    assert [row[0] for row in rows] == ["3", "17", "40"]
    assert [float(rows[k][4]) for k in (0, 2)] == pytest.approx([1000.0, 1500.0], rel=0.03)
    one = ix.zhit((F, z[1]))._repr_html_()
    assert "<td>valid</td><td>no</td>" in one and "bad band" in one


@pytest.mark.parametrize("method", ["linear", "zhit"])
def test_a_batch_report_names_the_spectra_with_points_below_re_z_0(method):
    """R0 + R1 ∥ C1 whose two highest points were given Re Z < 0 (−5 % and −8 % of |Z|, an
    instrument's phase error at its top), in one of three cycles: the report names that cycle and
    those frequencies, as a single test's note does (the linear test's batch said nothing of
    them until 2026-12-06)."""
    rng = np.random.default_rng(3)
    z = np.stack([(10 + r1 / (1 + 1j * W * r1 * 1e-5)) * (1 + 0.002 * (rng.standard_normal(F.size) + 1j * rng.standard_normal(F.size)) / math.sqrt(2))
                  for r1 in (1000.0, 1100.0, 1200.0)])
    top = np.argsort(F)[-2:]
    z[1, top] = -np.array([0.05, 0.08]) * np.abs(z[1, top]) + 1j * z[1, top].imag
    data = ix.make_spectrum(F, z, dims=("cycle",), coords={"cycle": CYCLES})
    batch = ix.zhit_batch(data) if method == "zhit" else ix.kk_test_batch(data)
    notes = [line for line in batch.report().splitlines() if line.startswith("note: in ")]
    assert len(notes) == 1 and notes[0].startswith("note: in 1 of 3 spectra (cycle=17) points have Re Z < 0")
    assert "100 kHz" in notes[0]


@pytest.mark.parametrize("method", ["linear", "zhit"])
def test_a_batchs_json_names_its_method_as_one_spectrums_does(method, tmp_path, capsys):
    # (the Z-HIT batch's JSON had "method": "zhit" at its top, the linear test's none: a script
    # telling the two apart by that key got a KeyError on the linear one; SYNTHETIC stack)
    z, _ = stack()
    path = tmp_path / "cycles.nc"
    ix.save(ix.make_spectrum(F, z, dims=("cycle",), coords={"cycle": CYCLES}), path)
    assert main(["kk", str(path), "--method", method, "--select", "cycle=3", "--json"]) == 0
    single = json.loads(capsys.readouterr().out)
    assert main(["kk", str(path), "--method", method, "--json"]) == 0
    batch = json.loads(capsys.readouterr().out)
    assert batch["method"] == single["method"] == method
    assert {s["method"] for s in batch["spectra"]} == {method}


def test_the_maps_legend_hides_no_flagged_point():
    # (the legend stood in the map's upper right, over the REAL battery cycles' flags at
    # 6.2–9.9 kHz of cycles 92, 112 and 116; SYNTHETIC: the last four of twelve spectra with
    # their three highest frequencies 5 % off, flagged there)
    import matplotlib.pyplot as plt

    rng = np.random.default_rng(3)
    freq = F[::-1]
    z = np.stack([r_cpe_at(freq, 1000.0 + 20 * k) for k in range(12)]) * (1 + 0.003 * (rng.standard_normal((12, F.size)) + 1j * rng.standard_normal((12, F.size))) / math.sqrt(2))
    z[8:, :3] *= 1.05  # (the three highest frequencies of the last four)
    batch = ix.kk_test_batch(ix.make_spectrum(freq, z, dims=("cycle",), coords={"cycle": np.arange(12)}))
    flagged = np.array([np.asarray(r.flagged, bool) for r in batch.results])
    assert flagged[8:, :3].any()
    fig = batch.plot()
    try:
        fig.draw_without_rendering()
        ax_map = fig.axes[0]
        legend = ax_map.get_legend()
        box = legend.get_window_extent()
        circles = ax_map.collections[1]
        xy = circles.get_offset_transform().transform(np.asarray(circles.get_offsets(), float))
        inside = (xy[:, 0] >= box.x0) & (xy[:, 0] <= box.x1) & (xy[:, 1] >= box.y0) & (xy[:, 1] <= box.y1)
        assert not inside.any(), f"{inside.sum()} flagged points under the legend"
    finally:
        plt.close(fig)


def r_cpe_at(freq: np.ndarray, r1: float) -> np.ndarray:
    """R0 + R1 ∥ CPE (closed form) at ``freq``."""
    return 10 + 1 / (1 / r1 + 1e-4 * (2j * np.pi * freq) ** 0.8)


def test_a_batch_iterates_and_indexes_as_a_list_would():
    # (`for r in batch` ended in numpy's "invalid entry in coordinates array" after the last
    # spectrum, batch[-1] too, and batch[0] of a two-dimension batch read "parameter
    # multi_index must be a sequence of length 2"; SYNTHETIC stack, and 3 × 2 of it)
    z, _ = stack()
    data = ix.make_spectrum(F, z, dims=("cycle",), coords={"cycle": CYCLES})
    for batch in (ix.zhit_batch(data), ix.kk_test_batch(data)):
        assert [r.rms_rel for r in batch] == [r.rms_rel for r in batch.results]
        assert batch[-1] is batch.results[2] and batch[0] is batch.results[0]
        with pytest.raises(IndexError, match=r"beyond its spectra \(cycle 3\)"):
            batch[3]
    two = ix.make_spectrum(F, np.stack([z, z[::-1]], axis=1), dims=("cycle", "session"), coords={"cycle": CYCLES, "session": ["am", "pm"]})
    batch = ix.zhit_batch(two)
    assert len(list(batch)) == 6 and batch[2, 1] is batch.results[5] and batch[-1, -2] is batch.results[4]
    with pytest.raises(IndexError, match=r"one integer position per dimension \(cycle 3 × session 2\), e.g. \[0, 0\]"):
        batch[0]


def test_the_maps_legend_counts_one_flagged_point_in_the_singular():
    # (SYNTHETIC: one point of one of three spectra 30 % off; the legend read "flagged (1 points)")
    import matplotlib.pyplot as plt

    rng = np.random.default_rng(4)
    z = np.stack([r_cpe(1000.0 + 100 * k) for k in range(3)]) * (1 + 0.002 * (rng.standard_normal((3, F.size)) + 1j * rng.standard_normal((3, F.size))) / math.sqrt(2))
    z[1, 35] *= 1.3
    batch = ix.kk_test_batch(ix.make_spectrum(F, z, dims=("cycle",), coords={"cycle": CYCLES}))
    n_flagged = sum(int(np.sum(r.flagged)) for r in batch.results)
    fig = batch.plot()
    try:
        texts = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
        assert texts == [f"flagged ({n_flagged} point{'' if n_flagged == 1 else 's'})"] and n_flagged == 1
    finally:
        plt.close(fig)


@pytest.mark.parametrize("method", ["linear", "zhit"])
def test_a_batch_of_one_spectrum_marks_its_noise_estimate(method):
    # (SYNTHETIC: one cycle over a batch dimension; the noise estimate, a dashed line through
    # one point, drew nothing beside its legend entry)
    import matplotlib.pyplot as plt

    z, _ = stack()
    data = ix.make_spectrum(F, z[:1], dims=("cycle",), coords={"cycle": CYCLES[:1]})
    batch = ix.zhit_batch(data) if method == "zhit" else ix.kk_test_batch(data)
    fig = batch.plot()
    try:
        (line,) = [ln for ln in fig.axes[1].get_lines() if ln.get_label() == "noise estimate"]
        np.testing.assert_allclose(line.get_ydata(), [batch.results[0].noise_estimate * 100])
        assert line.get_marker() not in (None, "", "None", " ") and line.get_markersize() > 0
    finally:
        plt.close(fig)


def test_a_notebook_table_of_many_spectra_shows_those_that_fail():
    # (1,000 SYNTHETIC spectra filled a notebook with 1,000 rows; SYNTHETIC: the stack's three
    # cycles 24 times over, every third one drifting, 72 spectra)
    z, _ = stack()
    data = ix.make_spectrum(F, np.tile(z, (24, 1)), dims=("cycle",), coords={"cycle": np.arange(72)})
    drifting = [str(k) for k in range(1, 72, 3)]
    for batch in (ix.zhit_batch(data), ix.kk_test_batch(data)):
        html = batch._repr_html_()
        rows = _html_rows(html)
        assert [row[0] for row in rows] == drifting and {row[1] for row in rows} == {"NOT valid"}
        assert "72 spectra: the table shows the 24 not valid or inconclusive (48 valid not shown)" in html
    few = ix.make_spectrum(F, np.tile(z, (20, 1)), dims=("cycle",), coords={"cycle": np.arange(60)})
    assert len(_html_rows(ix.zhit_batch(few)._repr_html_())) == 60  # (up to 60: every spectrum)


def test_a_map_of_many_cells_is_one_image_in_a_vector_file(tmp_path):
    # (1,000 SYNTHETIC spectra × 40 frequencies made an SVG of 7.9 MB, a shape per cell;
    # SYNTHETIC: the stack's cycles 40 times over, 120 × 71 = 8,520 cells, more than the 5,000
    # kept as shapes)
    z, _ = stack()
    path = tmp_path / "many.nc"
    ix.save(ix.make_spectrum(F, np.tile(z, (40, 1)), dims=("cycle",), coords={"cycle": np.arange(120)}), path)
    svg = tmp_path / "map.svg"
    assert main(["kk", str(path), "--method", "zhit", "--plot", str(svg)]) == 0
    text = svg.read_text()
    assert text.count("<path") < 120 * F.size / 4  # (before: a path per cell, 8,617 in all)


def test_the_maps_write_float_labels_without_binary_noise():
    # (SYNTHETIC: soc = np.arange(6) * 0.1; the maps' ticks read "0.30000000000000004")
    import matplotlib.pyplot as plt

    z, _ = stack()
    data = ix.make_spectrum(F, np.tile(z, (2, 1)), dims=("soc",), coords={"soc": np.arange(6) * 0.1})
    assert str(float(data["soc"][3])) == "0.30000000000000004"
    fig = ix.zhit_batch(data).plot()
    try:
        fig.canvas.draw()
        assert [t.get_text() for t in fig.axes[1].get_xticklabels() if t.get_text()] == ["0.0", "0.1", "0.2", "0.3", "0.4", "0.5"]
    finally:
        plt.close(fig)
