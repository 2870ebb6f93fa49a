"""``--select`` of numeric labels computed with rounding error: a state of charge written as
``np.arange(8) * 0.1`` holds 0.30000000000000004 and 0.7000000000000001, which users read and type
as 0.3 and 0.7; until 2026-12-06 ``--select soc=0.3`` was refused ("no spectrum has that label")
and ``soc=0.5:0.7`` left 0.7 out."""

from __future__ import annotations

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.cli.common import load_selected
from impedax.errors import ParameterError

F = np.geomspace(1.0, 1e5, 30)
SOC = np.arange(8) * 0.1  # (0.30000000000000004, 0.6000000000000001, 0.7000000000000001 among them)


@pytest.fixture(scope="module")
def soc_file(tmp_path_factory):
    w = 2 * np.pi * F
    z = np.stack([10 + (100 + 10 * k) / (1 + 1j * w * (100 + 10 * k) * 1e-6) for k in range(SOC.size)])  # R0 + R1 ∥ C1, R1 = 100 Ω + 10 Ω × position
    path = tmp_path_factory.mktemp("soc") / "soc.nc"
    ix.save(ix.make_spectrum(F, z, dims=("soc",), coords={"soc": SOC}), path)
    return str(path), z


def test_a_label_typed_as_read_picks_its_spectrum(soc_file):
    path, z = soc_file
    assert SOC[3] != 0.3  # (the premise: the stored label is not the typed number)
    one = load_selected(path, ["soc=0.3"], single="impedax diagnose")
    np.testing.assert_array_equal(one["Z"].values, z[3])


def test_a_range_keeps_an_end_written_with_rounding_error(soc_file):
    path, z = soc_file
    assert SOC[7] > 0.7
    several = load_selected(path, ["soc=0.5:0.7"])
    np.testing.assert_array_equal(several["Z"].values, z[5:8])


def test_a_nearby_number_that_is_no_label_is_still_refused(soc_file):
    path, _ = soc_file
    with pytest.raises(ParameterError, match="no spectrum of .* has that label"):
        load_selected(path, ["soc=0.31"])


def test_the_command_tests_the_picked_spectrum(soc_file, capsys):
    path, _ = soc_file
    assert main(["kk", path, "--select", "soc=0.3", "--json"]) == 0
    assert '"valid": true' in capsys.readouterr().out


def test_the_drt_batch_figure_writes_the_labels_as_read(soc_file):
    """The DRT batch figure's spectrum axis read "0.30000000000000004" where the maps and the
    fit figure write 0.3 (`data.label_text`); the legend (8 spectra) likewise."""
    import matplotlib.pyplot as plt

    path, _ = soc_file
    fig = ix.drt(ix.load(path)).plot()
    try:
        ticks = [t.get_text() for t in fig.axes[1].get_xticklabels() if t.get_text()]
        legend = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    finally:
        plt.close(fig)
    assert "0.3" in ticks and not any("0000000" in t for t in ticks)
    assert any(t.startswith("soc=0.3:") for t in legend) and not any("0000000" in t for t in legend)
