"""A haptics researcher's walkthrough of `impedax gap` (2026-12-02): the paper's bounds that are no
interval, the figure that hid "SAMPLING UNRELIABLE", the force command's --title help, and the
breakdown warning's "941–941 V". Oracles are numpy formulas and hand numbers written here; all
data are SYNTHETIC (numpy formulas in tests/spectra.py, or hand-built result stubs)."""

from __future__ import annotations

from dataclasses import replace
from types import SimpleNamespace

import matplotlib
import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.cli import main
from impedax.models.gap import GapAnalysis, _gap_breakdown_notes, _paper_interval_notes
from impedax.models.sirin import paper_gap_estimate, remaining_impedance
from spectra import sirin_scattered_measurements

EPS0 = 8.8541878128e-12  # vacuum permittivity [F/m], CODATA 2018
EPS_AIR = 1.00059  # air's relative permittivity (Sirin et al.)
AREA = 100e-6  # the walkthrough's apparent contact area [m²]
CUTOFF_HZ = 30.0  # Sirin §2.3: |Y_R| is capacitive above ≈ 30 Hz


def _scattered(seed):
    """SYNTHETIC: 12 trials, skin scatter 20 %, screen 5 %, u 5 % between trials (u = 3.5 µm,
    A = 100 mm²), as in the walkthrough's make_data.py."""
    f, total, skin, screen, _ = sirin_scattered_measurements(np.random.default_rng(seed), 12, skin_scatter=0.2, screen_scatter=0.05, gap_scatter=0.05, points=31)
    return f, (total, skin, screen), [ix.make_spectrum(f, z, dims=("trial",)) for z in (total, skin, screen)]


def _paper_numpy(f, total, skin, screen):
    """Sirin §2.3 in numpy: u of the trial means; u of the lowest and of the highest set (each
    measurement's trial of lowest/highest mean log|Z| above the cutoff), in that order; u of
    every total trial minus the mean skin and screen."""
    keep = f >= CUTOFF_HZ
    u_of = lambda z: EPS0 * EPS_AIR * AREA / np.mean(1.0 / (2 * np.pi * f[keep] * np.abs(z[keep])))  # noqa: E731
    pick = lambda z, choose: z[choose(np.mean(np.log(np.abs(z[:, keep])), axis=1))]  # noqa: E731
    u = u_of(total.mean(0) - skin.mean(0) - screen.mean(0))
    low_set, high_set = (u_of(pick(total, c) - pick(skin, c) - pick(screen, c)) for c in (np.argmin, np.argmax))
    trials = [u_of(z - skin.mean(0) - screen.mean(0)) for z in total]
    return u, low_set, high_set, np.array(trials)


def test_paper_bounds_that_are_no_interval_are_ordered_and_warned():
    """Seed 24: the extremes offset each other: bounds 3.331–3.366 µm, 4 % of the single trials'
    range, below u = 3.490 µm (as the walkthrough's 3.321–3.329 µm under 3.357 µm), and the
    lowest-impedance set gives the LARGER u."""
    f, arrays, parts = _scattered(24)
    u, low_set, high_set, trials = _paper_numpy(f, *arrays)
    assert low_set > high_set  # the oracle: reversed, so ordering is needed
    lower, upper = high_set, low_set
    assert u > upper and (upper - lower) < 0.05 * (trials.max() - trials.min())  # the oracle: the case

    paper = paper_gap_estimate(*parts, area=AREA)
    np.testing.assert_allclose([paper.gap, paper.gap_lower, paper.gap_upper], [u, lower, upper], rtol=1e-10)
    np.testing.assert_allclose([paper.gap_trial_min, paper.gap_trial_max], [trials.min(), trials.max()], rtol=1e-10)
    assert paper.gap_lower <= paper.gap_upper
    assert float(paper.to_xarray()["gap_trial_max"]) == paper.gap_trial_max

    (note,) = _paper_interval_notes(paper, remaining_impedance(*parts))
    assert note.startswith(f"the paper method's bounds {lower * 1e6:.4g}–{upper * 1e6:.4g} µm lie below its u = {u * 1e6:.4g} µm")
    assert f"give u = {trials.min() * 1e6:.4g}–{trials.max() * 1e6:.4g} µm" in note
    assert "no interval for u" in note and "offset each other" in note


def test_wide_bounds_around_u_give_no_warning():
    """Seed 1: u inside bounds as wide as 60 % of the single trials' range: no warning."""
    f, arrays, parts = _scattered(1)
    u, low_set, high_set, trials = _paper_numpy(f, *arrays)
    lower, upper = sorted((low_set, high_set))
    assert lower <= u <= upper and upper - lower > 0.25 * (trials.max() - trials.min())  # the oracle
    assert _paper_interval_notes(paper_gap_estimate(*parts, area=AREA), remaining_impedance(*parts)) == []


def test_narrow_bounds_are_warned_even_around_u():
    """Bounds that contain u but are far narrower than the trials' spread are no interval either;
    one spectrum per file has no bounds to warn of."""
    from impedax.models.sirin import PaperGapEstimate

    c = lambda x: EPS0 * EPS_AIR * AREA / x  # noqa: E731
    paper = PaperGapEstimate(c(3.5e-6), 3.5e-6, c(3.49e-6), c(3.51e-6), 3.49e-6, 3.51e-6, CUTOFF_HZ, AREA, EPS_AIR, 3.1e-6, 3.9e-6)
    trials = xr.Dataset(attrs={"n_trials_total": 12, "n_trials_skin": 12, "n_trials_touchscreen": 12})
    (note,) = _paper_interval_notes(paper, trials)
    assert note.startswith("the paper method's bounds 3.49–3.51 µm are 0.02 µm wide while single total trials") and "3.1–3.9 µm" in note
    one_each = xr.Dataset(attrs={"n_trials_total": 1, "n_trials_skin": 1, "n_trials_touchscreen": 1})
    assert _paper_interval_notes(paper, one_each) == []


def _stub_analysis(*, rhat_max, divergences=0, misfit=None):
    """A `GapAnalysis` built by hand (no fit, no sampling): SYNTHETIC remainder R_EP ∥ C_gap, fits
    and a hierarchical posterior as stubs with the diagnostics given."""
    f = np.geomspace(1.0, 1e6, 13)
    c_gap = EPS0 * EPS_AIR * AREA / 3.5e-6
    z = 1.0 / (1.0 / 5e7 + 2j * np.pi * f * c_gap)
    spectra = [ix.make_spectrum(f, np.stack([zz, zz * 1.01]), dims=("trial",)) for zz in (z + 2e3, np.full(f.size, 1e3 + 0j), np.full(f.size, 1e3 + 0j))]
    fit = SimpleNamespace(frequency=f, z_model=z, rms_rel=0.02, model="R_EP || C_gap")
    u = 3.5e-6 * np.exp(0.01 * np.random.default_rng(0).standard_normal(200))
    post = SimpleNamespace(
        population_parameters=lambda: {"u": u, "C_gap": EPS0 * EPS_AIR * AREA / u, "R_EP": np.full(u.size, 5e7)},
        rhat=lambda: {"u": rhat_max, "R_EP": 1.001}, ess=lambda: {"u": 33.0, "R_EP": 400.0}, divergences=divergences, n_draws=400,
    )
    band = np.geomspace(1e-3, 1e-2, f.size)
    force = xr.Dataset({k: (("branch", "frequency"), np.stack([band * s, band * s])) for k, s in (("median", 1.0), ("q05", 0.9), ("q95", 1.1))},
                       coords={"branch": ["with_ep", "without_ep"], "frequency": f})
    return GapAnalysis(remaining_impedance(*spectra), paper_gap_estimate(*spectra, area=AREA), fit, fit, None, force, AREA, 75.0, "CPE",
                       method="hierarchical", hierarchical=post, edl_misfit=misfit)


def _figure_texts(fig):
    return " | ".join(t.get_text() for t in fig.findobj(matplotlib.text.Text))


def test_gap_figure_marks_unreliable_sampling_and_a_misfit():
    """The walkthrough's R-hat 1.062: the figure heads with the report's "SAMPLING UNRELIABLE";
    R-hat 1.01 with no divergences does not; a misfit heads it with "MODEL DOES NOT FIT"."""
    import matplotlib.pyplot as plt

    flagged = _stub_analysis(rhat_max=1.062)
    assert flagged.alarms == ("SAMPLING UNRELIABLE: 0 divergent transitions of 400 draws, R-hat up to 1.062, ESS down to 33: the bands may be wrong",)
    fig = flagged.plot()
    assert "SAMPLING UNRELIABLE: 0 divergent transitions of 400 draws, R-hat up to 1.062" in _figure_texts(fig)
    plt.close(fig)

    clean = _stub_analysis(rhat_max=1.01)
    fig = clean.plot()
    assert clean.alarms == () and "UNRELIABLE" not in _figure_texts(fig)
    plt.close(fig)
    divergent = _stub_analysis(rhat_max=1.01, divergences=5)  # 5 of 400 > 1 %
    assert divergent.alarms and divergent.alarms[0].startswith("SAMPLING UNRELIABLE: 5 divergent")

    # the paper's bounds are labelled as no interval when a warning says so
    fig = replace(clean, warnings=("the paper method's bounds 3.49–3.51 µm lie below its u = 3.6 µm and …",)).plot()
    assert "paper bounds (extreme impedances); NO interval for u: see the warning" in _figure_texts(fig)
    plt.close(fig)
    fig = clean.plot()
    assert "NO interval" not in _figure_texts(fig)
    plt.close(fig)

    misfit = replace(clean, edl_misfit="the model misses the remainder (rms_rel 53%)")
    fig = misfit.plot()
    assert "MODEL DOES NOT FIT" in _figure_texts(fig) and "UNRELIABLE" not in _figure_texts(fig)
    plt.close(fig)


def _help(capsys, command):
    with pytest.raises(SystemExit):
        main([command, "--help"])
    return " ".join(capsys.readouterr().out.split())


def test_force_title_help_names_no_data_file(capsys):
    """`impedax force` reads no data file: its --title help says what its title names."""
    force = _help(capsys, "force")
    assert "names the data file" not in force and "(which names the paper, the equation and the force convention;" in force
    assert "(which names the data file)" in _help(capsys, "kk")


def _force_with_gap_voltage(median, q05, q95):
    """A hand-made force band (peak at 100 Hz) whose gap voltage at the peak is the numbers given."""
    f = np.array([10.0, 100.0, 1000.0])
    shape = np.array([0.5, 1.0, 0.5])
    data = {k: (("branch", "frequency"), np.stack([shape * s, shape * s])) for k, s in (("median", 1.0), ("q05", 0.9), ("q95", 1.1))}
    data |= {f"gap_voltage_{k}": (("branch", "frequency"), np.stack([shape * v, shape * v])) for k, v in (("median", median), ("q05", q05), ("q95", q95))}
    return xr.Dataset(data, coords={"branch": ["with_ep", "without_ep"], "frequency": f})


@pytest.mark.parametrize(
    "band, shown",
    [
        ((941.0, 940.6, 941.3), "carries 941.0 V (90% interval 940.6–941.3 V)"),  # 3 digits print 941–941: 4 do not
        ((940.8, 940.6, 941.0), "carries 940.8 V (90% interval 940.6–941.0 V)"),  # the walkthrough's: trailing zero kept
        ((941.0, 941.01, 941.04), "carries 941.0 V (90% interval ≈ 941.0 V)"),  # alike to 4 digits: once
        ((941.0, 900.0, 980.0), "carries 941 V (90% interval 900–980 V)"),  # 3 digits suffice
    ],
)
def test_breakdown_interval_shows_its_ends_apart(band, shown):
    (note,) = _gap_breakdown_notes(_force_with_gap_voltage(*band), 3.5e-6, AREA, EPS_AIR)
    assert shown in note and "941–941" not in note
