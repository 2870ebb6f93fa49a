"""The shipped SYNTHETIC Sirin-style example: reproducible from its seed, loadable into the
data model, realistic shape, and the paper's method recovers C_gap ≈ 413 pF, u ≈ 2.79 µm."""

import numpy as np
import pytest

import impedax as ix
from impedax.models import paper_gap_estimate, synthetic


@pytest.fixture(scope="module")
def shipped():
    return synthetic.load_example()


def test_regenerating_with_the_seed_reproduces_the_shipped_file(shipped):
    fresh = synthetic.generate_sirin_synthetic(shipped.attrs["seed"])
    for name in ("Z_total", "Z_skin", "Z_touchscreen"):
        np.testing.assert_array_equal(fresh[name].values, shipped[name].values)
    np.testing.assert_array_equal(fresh["frequency"].values, shipped["frequency"].values)
    assert shipped.attrs["truth"] == fresh.attrs["truth"]


def test_file_is_small_and_says_synthetic(shipped):
    assert synthetic.example_path().stat().st_size < 1_000_000
    assert "SYNTHETIC" in shipped.attrs["title"] and "generate_sirin_synthetic" in shipped.attrs["generator"]
    assert shipped.attrs["truth"]["remainder_sliding"]["C_gap"] == 413e-12
    assert shipped.sizes == {"contact": 2, "session": 3, "trial": 10, "frequency": 61}


def test_parts_load_into_the_data_model(shipped, tmp_path):
    parts = synthetic.example_spectra(shipped)
    assert set(parts) == {"total_sliding", "total_stationary", "skin", "touchscreen"}
    for ds in parts.values():
        ix.validate_spectrum(ds)
        assert ds["Z"].dims == ("session", "trial", "frequency")
    ix.save(parts["skin"], tmp_path / "skin.nc")
    np.testing.assert_array_equal(ix.load(tmp_path / "skin.nc")["Z"].values, parts["skin"]["Z"].values)


def test_paper_method_recovers_gap(shipped):
    parts = synthetic.example_spectra(shipped)
    est = paper_gap_estimate(parts["total_sliding"], parts["skin"], parts["touchscreen"], area=130e-6)
    assert est.c_gap == pytest.approx(413e-12, rel=0.02)
    assert est.gap == pytest.approx(2.79e-6, rel=0.02)
    assert est.gap_lower < est.gap < est.gap_upper


def _phase_peak(p):
    f = np.geomspace(1, 1e7, 4001)
    z = p["R_inf"] + p["R"] / (1 + p["R"] * p["Q"] * (2j * np.pi * f) ** p["alpha"])
    return f[np.argmin(np.angle(z))]


def test_skin_and_screen_phase_maxima(shipped):
    truth = shipped.attrs["truth"]
    assert _phase_peak(truth["skin"]) == pytest.approx(250.0, rel=0.05)
    assert _phase_peak(truth["touchscreen"]) == pytest.approx(1e5, rel=0.05)
    # and the measured means peak there too (within a grid step of 10^0.1)
    parts = synthetic.example_spectra(shipped)
    f = shipped["frequency"].values
    for name, where in (("skin", 250.0), ("touchscreen", 1e5)):
        phase = np.angle(parts[name]["Z"].mean(("session", "trial")).values)
        assert f[np.argmin(phase)] == pytest.approx(where, rel=0.6)


def test_realistic_scatter_and_stationary_contact(shipped):
    f = shipped["frequency"].values
    skin = shipped["Z_skin"]
    rel_sd = (np.abs(skin).std(("session", "trial")) / np.abs(skin).mean(("session", "trial"))).values
    assert rel_sd[0] > 2 * rel_sd[-1]  # larger scatter at low frequency
    total = shipped["Z_total"].mean(("session", "trial"))
    ratio = np.abs(total.sel(contact="sliding") / total.sel(contact="stationary")).values
    assert 5 < np.median(ratio[f <= 1e4]) < 20  # stationary ≈ 10x lower
    # the EP branch matters below ~30 Hz only: remaining phase near -90 deg above a few hundred Hz
    parts = synthetic.example_spectra(shipped)
    zr = ix.models.remaining_impedance(parts["total_sliding"], parts["skin"], parts["touchscreen"])
    phase = np.degrees(np.angle(zr["Z"].values))
    assert np.all(phase[(f >= 100) & (f <= 1e4)] < -75) and np.all(phase[(f >= 300) & (f <= 1e4)] < -80) and phase[0] > -45


def test_unknown_example():
    with pytest.raises(ix.DataError, match="unknown example"):
        synthetic.load_example("meyer")
