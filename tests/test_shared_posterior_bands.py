"""A joint posterior's model over its draws and its band figure (`SharedPosterior.predict`,
`SharedPosterior.plot`, `impedax sample --shared --plot`): each spectrum's curves are the RC
formula, written here, at that draw's shared and own values; the predictive noise has the
likelihood's scale; the figure draws the data of the spectra it names."""

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.fitting.derived import draw_indices
from test_shared_posterior_roundtrip import FREQ, MODEL, rc_impedance, stack, with_sigma  # noqa: F401  (with_sigma: a fixture)


@pytest.fixture(scope="module")
def eight():
    """Eight noisy RC spectra (1 % proportional), R0 common: more than `plot` draws by default."""
    data = ix.make_spectrum(FREQ, stack(5, (8,)), dims=("trial",), coords={"trial": np.arange(8) * 2})
    return ix.sample(MODEL, data, shared=["R0"], over="trial", steps=40, walkers=40, seed=1, progress=False)


def formula_draws(post, pick):
    """(spectrum, draw, frequency) from `rc_impedance` at the flat draws ``pick``: R0 shared (or
    fixed), R1 and C1 each spectrum's own, or shared where the posterior shares them."""
    samples = {n: v[pick] for n, v in post.samples.items()}

    def value(name, label):
        if name in post.fixed:
            return np.full(len(pick), post.fixed[name])
        return samples[name] if name in samples else samples[f"{name}[{label}]"]

    return np.stack([rc_impedance(FREQ[None, :], *(value(n, label)[:, None] for n in ("R0", "R1", "C1"))) for label in post.spectra])


def test_predict_is_each_spectrum_at_each_draw(eight, with_sigma):
    for post in (eight, with_sigma):  # (R0 shared; C1 shared over two dimensions with R0 fixed)
        pick = draw_indices(post.n_walkers * post.n_draws, 400)
        expected = formula_draws(post, pick)
        z = post.predict()
        assert z.shape == (len(post.spectra), pick.size, FREQ.size)
        np.testing.assert_allclose(z, expected, rtol=1e-10)
    # the spectra in their order: the median draw sits on its own data (1 % noise), not another's
    z_data = eight.z_data
    median = np.median(eight.predict().real, axis=1)
    misfit = np.abs(median[:, None, :] - z_data.real[None, :, :]).mean(axis=-1) / np.abs(z_data).mean(axis=-1)[None, :]
    assert np.array_equal(misfit.argmin(axis=1), np.arange(8)) and misfit.diagonal().max() < 0.02


def test_predictive_noise_has_the_likelihoods_scale(eight, with_sigma):
    # proportional: (Z_new − Z_model)/|Z_model| has σ = sigma_rel of the draw, on Re and Im alike;
    # 8 × 4,000 × 30 values: the sample's σ within 3 % of the draws' rms sigma_rel
    copies = 10
    pick = np.repeat(draw_indices(eight.n_walkers * eight.n_draws, 400), copies)
    z = np.repeat(eight.predict(), copies, axis=1)
    noisy = eight.predict(noise=True, copies=copies, seed=2)
    relative = (noisy - z) / np.abs(z)
    expected = np.sqrt(np.mean(eight.samples["sigma_rel"][pick] ** 2))
    for part in (relative.real, relative.imag):
        assert abs(part.std() / expected - 1) < 0.03 and abs(part.mean()) < 0.03 * expected
    # the data's σ: at the data's frequencies, (Z_new − Z_model)/σ is standard normal in each spectrum
    sigma = with_sigma.fit.dataset["Z"].copy(data=with_sigma.sigma).transpose("session", "trial", "frequency").values.reshape(2, 1, -1)
    scaled = (with_sigma.predict(noise=True, copies=copies, seed=2) - np.repeat(with_sigma.predict(), copies, axis=1)) / sigma
    for row in scaled:
        assert abs(row.real.std() - 1) < 0.05 and abs(row.imag.std() - 1) < 0.05
    with pytest.raises(ix.ParameterError, match="copies must be a positive integer"):
        eight.predict(noise=True, copies=0)


def panel_data(ax):
    """The data points (the open circles) a Bode panel draws: (frequency, value)."""
    (line,) = [ln for ln in ax.get_lines() if ln.get_marker() == "o"]
    return np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float)


def test_plot_draws_each_named_spectrum_with_its_data(eight, tmp_path):
    fig = eight.plot()
    rows = [0, 1, 3, 4, 6, 7]  # six of eight, spread from the first to the last
    assert "6 of 8 spectra" in fig._suptitle.get_text()
    axes = np.array(fig.axes).reshape(-1, 3)
    assert axes.shape == (6, 3)
    z_data = np.asarray(eight.fit.dataset["Z"].transpose("trial", "frequency").values)  # (the oracle: the data as stored)
    for (ax_nyq, ax_mod, ax_ph), row in zip(axes, rows):
        assert ax_nyq.get_title(loc="left") == f"trial={2 * row}"
        f, modulus = panel_data(ax_mod)
        np.testing.assert_array_equal(f, FREQ)
        np.testing.assert_allclose(modulus, np.abs(z_data[row]), rtol=1e-12)
        np.testing.assert_allclose(panel_data(ax_ph)[1], np.degrees(np.angle(z_data[row])), rtol=1e-12)
    fig = eight.plot(spectra=["trial=14", "trial=2"], title="two")
    assert fig._suptitle.get_text() == "two" and len(fig.axes) == 6
    assert [ax.get_title(loc="left") for ax in fig.axes[::3]] == ["trial=14", "trial=2"]
    np.testing.assert_allclose(panel_data(fig.axes[1])[1], np.abs(z_data[7]), rtol=1e-12)
    with pytest.raises(ix.ParameterError, match=r"spectra: 'trial=3'; this joint posterior's spectra are 'trial=0', 'trial=2'"):
        eight.plot(spectra=["trial=3"])


def test_plot_of_two_dimensions_and_from_the_file(with_sigma, tmp_path):
    fig = with_sigma.plot()
    assert [ax.get_title(loc="left") for ax in fig.axes[::3]] == list(with_sigma.spectra) == ["session=a, trial=0", "session=b, trial=0"]
    path = tmp_path / "joint.nc"
    ix.write_result(with_sigma, path)
    back = ix.SharedPosterior.from_xarray(ix.load(path))
    np.testing.assert_array_equal(back.predict(noise=True, seed=4), with_sigma.predict(noise=True, seed=4))


def test_cli_sample_shared_plot(tmp_path, capsys):
    path, png = tmp_path / "two.nc", tmp_path / "bands.png"
    ix.save(ix.make_spectrum(FREQ, stack(1, (2,)), dims=("trial",)), path)
    assert main(["sample", str(path), "--model", MODEL, "--shared", "R0", "--steps", "30", "--walkers", "16", "--quiet", "--plot", str(png)]) == 0
    assert png.stat().st_size > 1000 and "R0" in capsys.readouterr().out
