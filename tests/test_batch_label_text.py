"""Text outputs write a float label as figures do (`impedax.data.label_text`): a batch over
soc = np.arange(n) * 0.1 printed "soc=0.30000000000000004" in the fit report's headings, its
warning lines, its hint, `impedax kk`'s table and `--select`'s listing of labels, where its
figures said 0.3. JSON keeps the exact value. SYNTHETIC throughout (values written by hand or
from the formula of an RC arc)."""

import json

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.cli import main
from impedax.fitting.least_squares import BatchFitResult

NOISY = 0.30000000000000004  # (np.arange(6) * 0.1)[3], as numpy makes it
NOTE = "R1 has a relative standard error of 150 %: it is not determined by the data"
F = np.geomspace(1, 1e5, 40)
ARC = 10 + 100 / (1 + 2j * np.pi * F * 100 * 1e-6)  # R0 + R1 ∥ C1: 10 Ω, 100 Ω, 1 µF


def batch(n: int, warned=(3,), weighting: str = "unit", cells=None) -> BatchFitResult:
    """n spectra of R0 + R1 ∥ C1 over soc = np.arange(n) * 0.1 (and ``cells``, labels of a
    ``cell`` dimension before it), values written by hand (no fit), the data the arc with 0.05 %
    noise, the spectra at soc positions ``warned`` (of the first cell) with NOTE, filed under
    their exact keys."""
    soc = np.arange(n) * 0.1
    lead = () if cells is None else ("cell",)
    shape = (n,) if cells is None else (len(cells), n)
    rng = np.random.default_rng(1)
    noise = 1 + 0.0005 * (rng.standard_normal((*shape, F.size)) + 1j * rng.standard_normal((*shape, F.size))) / np.sqrt(2)
    first = "" if cells is None else f"cell={cells[0]}, "
    ds = xr.Dataset(
        {
            "value": (("param", *lead, "soc"), np.broadcast_to(np.array([10.0, 100.0, 1e-6]).reshape(3, *[1] * len(shape)), (3, *shape)).copy()),
            "stderr": (("param", *lead, "soc"), np.broadcast_to(np.array([0.1, 150.0, 1e-8]).reshape(3, *[1] * len(shape)), (3, *shape)).copy()),
            "fixed": ("param", np.zeros(3, bool)), "at_bound": (("param", *lead, "soc"), np.zeros((3, *shape), bool)),
            "rms_rel": ((*lead, "soc"), np.full(shape, 0.015)), "converged": ((*lead, "soc"), np.ones(shape, bool)),
            "Z": ((*lead, "soc", "frequency"), ARC * noise), "Z_model": ((*lead, "soc", "frequency"), np.broadcast_to(ARC, (*shape, F.size)).copy()),
        },
        coords={"param": ["R0", "R1", "C1"], "soc": soc, "frequency": F, **({} if cells is None else {"cell": cells})},
        attrs={"model": "R0 + R1 || C1", "weighting": weighting, "impedax_kind": "batch_fit", "warnings": {f"{first}soc={soc[k]}": [NOTE] for k in warned}},
    )
    return BatchFitResult.from_xarray(ds)


@pytest.mark.parametrize("n", [6, 10, 30])  # (a column per spectrum; a row per spectrum; quantiles only)
def test_a_batch_report_writes_float_labels_short_and_its_json_keeps_them_exact(n):
    fits = batch(n)
    report = fits.report()
    assert "0.30000000000000004" not in report
    assert "warning (1 of %d spectra: soc 0.3): %s" % (n, NOTE) in report
    if n <= 20:
        assert "soc=0.3 " in report
    summary = fits.summary()
    assert summary["spectra"][3]["soc"] == NOISY and summary["spectra"][3]["labels"] == {"soc": NOISY}
    assert summary["warning_kinds"][0]["spectra"] == ["soc=0.30000000000000004"]  # (the key warnings are filed under)
    assert fits.warnings["soc=0.30000000000000004"] == (NOTE,)


def test_a_batch_over_two_dimensions_names_its_spectra_short():
    two = batch(6, warned=(1, 3), cells=["a", "b"])
    assert set(two.warnings) == {"cell=a, soc=0.1", "cell=a, soc=0.30000000000000004"}
    report = two.report()
    assert "cell=a, soc=0.3" in report and "0.30000000000000004" not in report
    assert "warning (2 of 12 spectra: cell=a, soc=0.1; cell=a, soc=0.3): " in report


def test_the_misfit_hint_names_its_spectra_short():
    """|Z|-weighted fits at 1.5 % rms_rel of data an RC arc fits exactly (its KK chain reaches 0.19 %):
    the hint names them all, the worst by its short label too."""
    hints = batch(6, weighting="modulus").misfit_hints()
    assert hints is not None and "0.30000000000000004" not in hints["note"] and "soc 0.0, 0.1, 0.2, 0.3, 0.4, 0.5" in hints["note"]
    assert {"soc": NOISY} in hints["labels"]


def _soc_arcs(tmp_path, soc) -> str:
    """SYNTHETIC: the RC arc scaled by 1 + soc for each label of ``soc``, saved as soc.nc."""
    path = str(tmp_path / "soc.nc")
    ix.save(ix.make_spectrum(F, np.stack([ARC * (1 + s) for s in soc]), dims="soc", coords={"soc": soc}), path)
    return path


def test_kk_and_select_messages_write_float_labels_short(tmp_path, capsys):
    soc = np.arange(6) * 0.1
    path = _soc_arcs(tmp_path, soc)
    assert main(["kk", path, "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "soc=0.3 " in out and "0.30000000000000004" not in out
    assert main(["fit", path, "--model", "R0 + R1 || C1", "--select", "soc=0.35", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "its soc labels: 0.0, 0.1, 0.2, 0.3, 0.4, 0.5" in err
    assert main(["kk", path, "--select", "soc=0.3", "--json", "--quiet"]) == 0
    assert "soc.nc [soc=0.3]" in capsys.readouterr().out
    # a spectrum that fails the test (its Z'' × 1.6, not Kramers–Kronig-consistent): the next: line selects it short
    z = np.stack([ARC * (1 + s) for s in soc])
    z[3] = z[3].real + 1.6j * z[3].imag
    bad = str(tmp_path / "bad.nc")
    ix.save(ix.make_spectrum(F, z, dims="soc", coords={"soc": soc}), bad)
    assert main(["kk", bad, "--quiet"]) == 0
    out = capsys.readouterr().out
    assert f"next: impedax kk {bad} --select soc=0.3 tests soc=0.3 alone" in out and "0.30000000000000004" not in out


def test_the_series_of_a_plot_against_a_coordinate_are_named_short():
    """`plot(x="soc")` of a batch over cell × soc: one series per cell, cell labels
    np.arange(4) * 0.1 named in the legend as 0.3, not 0.30000000000000004."""
    import matplotlib.pyplot as plt

    fig = batch(3, warned=(), cells=np.arange(4) * 0.1).plot(x="soc")
    texts = [t.get_text() for legend in fig.legends for t in legend.get_texts()]
    plt.close(fig)
    assert texts == ["cell=0.0", "cell=0.1", "cell=0.2", "cell=0.3"]


@pytest.mark.slow  # (~13 s: six DRT fits)
def test_drt_names_float_labelled_spectra_short(tmp_path, capsys):
    """`impedax drt`'s per-spectrum lines, as the fit and kk reports."""
    soc = np.arange(6) * 0.1
    path = _soc_arcs(tmp_path, soc)
    assert main(["drt", path, "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "  soc=0.3: rms_rel" in out and "0.30000000000000004" not in out


@pytest.mark.slow  # (~25 s: a batch fit and a diagnosis)
def test_the_diagnose_command_a_fit_prints_names_the_label_short_and_runs(tmp_path, capsys):
    """SYNTHETIC: four RC arcs (numpy formula, 0.05 % noise) over soc = np.arange(4) * 0.1, the
    last with a second arc R0 + R1 ∥ C1 lacks: the fit's hint names soc=0.3 and its next: line
    selects it as --select soc=0.3 (was soc=0.30000000000000004), which picks that spectrum."""
    import shlex

    f = np.geomspace(1.0, 1e5, 40)
    rng = np.random.default_rng(7)
    arc = 20 + 1e3 / (1 + 2j * np.pi * f * 1e3 * 1e-6)
    second = 50 / (1 + 2j * np.pi * f * 50 * 3e-4)
    noise = 1 + 0.0005 * (rng.standard_normal((4, f.size)) + 1j * rng.standard_normal((4, f.size))) / np.sqrt(2)
    z = np.stack([arc + (second if k == 3 else 0.0) for k in range(4)]) * noise
    path = str(tmp_path / "soc.nc")
    ix.save(ix.make_spectrum(f, z, dims="soc", coords={"soc": np.arange(4) * 0.1}), path)
    assert main(["fit", path, "--model", "R0 + R1 || C1", "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "0.30000000000000004" not in out and "hint: the fit of soc=0.3 (1 of the 4)" in out
    command = next(line for line in out.splitlines() if line.startswith("next: impedax diagnose")).removeprefix("next: impedax ").split(" (where")[0]
    assert "--select soc=0.3 " in command
    assert main(shlex.split(command) + ["--json", "--quiet"]) == 0
    assert json.loads(capsys.readouterr().out)["source"].endswith("[soc=0.3]")
