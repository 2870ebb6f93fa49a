"""The summary of posterior draws (mean, sd, quantiles, HDI) against Python's `statistics`,
which computes in exact fractions: draws of a parameter the data leave undetermined reach
1e220, whose squares lie beyond float64 (np.std overflowed to inf with a RuntimeWarning)."""

import statistics
import warnings

import numpy as np
import pytest

from impedax.fitting.bayes.diagnostics import draws_table
from impedax.fitting.derived import band_dataset, mean_and_sd


def huge_draws():
    rng = np.random.default_rng(0)  # an open branch's R: some walkers run off to 1e220
    return np.concatenate([np.full(30, 3.457025e220), 10 ** rng.uniform(11, 12, 270)])


def test_mean_and_sd_of_draws_beyond_float64s_squares_without_a_warning():
    x = huge_draws()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mean, sd = mean_and_sd(x)
    assert float(mean) == pytest.approx(statistics.fmean(x), rel=1e-12)
    assert float(sd) == pytest.approx(statistics.stdev(x), rel=1e-12)
    assert np.isfinite(sd)


def test_mean_and_sd_of_ordinary_draws_equal_numpys():
    x = np.random.default_rng(1).normal(50.0, 2.0, (400, 3))
    mean, sd = mean_and_sd(x)
    assert np.allclose(mean, x.mean(axis=0), rtol=1e-13) and np.allclose(sd, x.std(axis=0, ddof=1), rtol=1e-12)
    one_mean, one_sd = mean_and_sd(x[:1])
    assert np.array_equal(one_mean, x[0]) and np.array_equal(one_sd, np.zeros(3))  # (one draw: no spread)


def test_a_column_of_zeros_or_nan_keeps_its_value():
    x = np.zeros((10, 2))
    x[:, 1] = np.nan
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mean, sd = mean_and_sd(x)
    assert mean[0] == 0 and sd[0] == 0 and np.isnan(mean[1]) and np.isnan(sd[1])


def test_draws_table_and_band_dataset_agree_with_statistics():
    x = huge_draws()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        table = draws_table({"R2": x, "C1": np.linspace(1e-6, 2e-6, 300)})
        band = band_dataset(x[:, None])
    r2 = table.sel(param="R2")
    assert float(r2["sd"]) == pytest.approx(statistics.stdev(x), rel=1e-12)
    assert float(r2["median"]) == pytest.approx(statistics.median(x), rel=1e-12)
    assert float(band["sd"][0]) == pytest.approx(statistics.stdev(x), rel=1e-12)
    c1 = table.sel(param="C1")
    assert float(c1["mean"]) == pytest.approx(1.5e-6, rel=1e-12)
    assert float(c1["hdi90_high"]) - float(c1["hdi90_low"]) == pytest.approx(0.9e-6, rel=0.01)  # (uniform: any 90 % window)
    assert list(table["param"].values) == ["R2", "C1"]
