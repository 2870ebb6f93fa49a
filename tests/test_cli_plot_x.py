"""`impedax fit FILE --plot FIG.png --plot-x DIM`: the parameters of a batch drawn against a
numeric coordinate (`BatchFitResult.plot(x=DIM)`), its arguments checked before the fit."""

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.fitting.least_squares.batch import BatchFitResult

F = np.geomspace(1.0, 1e5, 30)
VOLTAGES = [0.0, 100.0, 200.0]


@pytest.fixture(scope="module")
def pad(tmp_path_factory):
    """SYNTHETIC R0 + R1 ∥ C1 over voltage × repeat, C1 growing with the voltage, 0.5 % noise;
    and a copy whose voltage labels are text."""
    rng = np.random.default_rng(7)
    c1 = 1e-6 * (1 + 0.002 * np.asarray(VOLTAGES))[:, None, None]
    z = 20.0 + 500.0 / (1 + 2j * np.pi * F * 500.0 * c1) * np.ones((1, 2, 1))
    z = z * (1 + 0.005 * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape)))
    folder = tmp_path_factory.mktemp("pad")
    numeric = ix.make_spectrum(F, z, dims=("voltage", "repeat"), coords={"voltage": VOLTAGES, "repeat": [0, 1]})
    text = numeric.assign_coords(voltage=["0 V", "100 V", "200 V"])
    ix.save(numeric, folder / "pad.nc")
    ix.save(text, folder / "pad_text.nc")
    return folder


def test_plot_x_draws_against_the_coordinate(pad, monkeypatch, capsys):
    asked = []
    drawn = BatchFitResult.plot

    def recorded(self, **options):
        asked.append(options)
        return drawn(self, **options)

    monkeypatch.setattr(BatchFitResult, "plot", recorded)
    figure = pad / "q.png"
    assert main(["fit", str(pad / "pad.nc"), "--model", "R0 + R1 || C1", "--plot", str(figure), "--plot-x", "voltage", "--quiet"]) == 0
    assert asked == [{"params": None, "x": "voltage"}] and figure.stat().st_size > 10_000
    # the figure's C1 panel: an error-bar series per repeat, at the voltages (shifted apart by
    # a few % of the 100 V step) and at the fitted values
    fitted = ix.fit("R0 + R1 || C1", ix.load(pad / "pad.nc"))
    figure = fitted.plot(x="voltage")
    panel = next(a for a in figure.axes if a.get_title().startswith("C1"))
    assert len(panel.containers) == 2 and panel.get_xlabel() == "voltage"
    c1 = fitted.values("C1")
    np.testing.assert_allclose(c1.transpose("voltage", "repeat").values, 1e-6 * (1 + 0.002 * np.array(VOLTAGES))[:, None] * np.ones((1, 2)), rtol=0.02)  # (the generating C1)
    for repeat, bars in enumerate(panel.containers):
        line = bars.lines[0]
        np.testing.assert_allclose(line.get_xdata(), VOLTAGES, atol=10.0)  # (the repeats a few V apart)
        np.testing.assert_allclose(line.get_ydata(), c1.sel(repeat=repeat).values, rtol=1e-12)


@pytest.mark.parametrize("extra, fragment", [
    (["--plot-x", "voltage"], "give --plot too"),
    (["--plot", "FIG", "--plot-x", "volt"], "--plot-x volt: not a dimension of the spectra of"),
    (["--plot", "FIG", "--plot-x", "repeat", "--select", "repeat=0"], "--plot-x repeat: not a dimension"),
])
def test_bad_plot_x_is_refused_before_the_fit(pad, capsys, monkeypatch, extra, fragment):
    monkeypatch.setattr(ix, "fit", lambda *a, **k: pytest.fail("fitted before the check"))
    extra = [str(pad / "f.png") if e == "FIG" else e for e in extra]
    assert main(["fit", str(pad / "pad.nc"), "--model", "R0 + R1 || C1", *extra]) == 2
    assert fragment in capsys.readouterr().err


def test_plot_x_needs_a_numeric_coordinate(pad, capsys, monkeypatch):
    monkeypatch.setattr(ix, "fit", lambda *a, **k: pytest.fail("fitted before the check"))
    assert main(["fit", str(pad / "pad_text.nc"), "--model", "R0 + R1 || C1", "--plot", str(pad / "g.png"), "--plot-x", "voltage"]) == 2
    assert "voltage has no numeric coordinate" in capsys.readouterr().err
