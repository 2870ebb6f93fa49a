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
from impedax.data import format_quantity
from impedax.models.sirin import paper_gap_estimate, remaining_impedance
from spectra import sirin_scattered_measurements
from test_gap_outputs import POOLED_CHAIN

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
    fit = SimpleNamespace(frequency=f, z_model=z, rms_rel=0.02, chi2_red=0.1, weighting="sigma", model="R_EP || C_gap")
    u = 3.5e-6 * np.exp(0.01 * np.random.default_rng(0).standard_normal(200))
    post = SimpleNamespace(
        population_parameters=lambda: {"u": u, "C_gap": EPS0 * EPS_AIR * AREA / u, "R_EP": np.full(u.size, 5e7)},
        rhat=lambda: {"u": rhat_max, "R_EP": 1.001}, ess=lambda: {"u": 33.0, "R_EP": 400.0}, mixing=lambda: ({"u": rhat_max, "R_EP": 1.001}, {"u": 33.0, "R_EP": 400.0}), divergences=divergences, n_draws=400,
        mean_acceptance=0.85,
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
        ((941.0, 940.6, 941.3), "carries 941.0 V (90 % interval 940.6–941.3 V)"),  # 3 digits print 941–941: 4 do not
        ((940.8, 940.6, 941.0), "carries 940.8 V (90 % interval 940.6–941.0 V)"),  # the walkthrough's: trailing zero kept
        ((941.0, 941.01, 941.04), "carries 941.0 V (90 % interval ≈ 941.0 V)"),  # alike to 4 digits: once
        ((941.0, 900.0, 980.0), "carries 941 V (90 % interval 900–980 V)"),  # 3 digits suffice
    ],
)
def test_breakdown_interval_shows_its_ends_apart(band, shown):
    (note,) = _gap_breakdown_notes(_force_with_gap_voltage(*band), 3.5e-6, AREA, EPS_AIR)
    assert shown in note and "941–941" not in note


# --- 2026-12-03 walkthrough: a u that is no air gap, and the correlation advice's call ---------------

U_PRIOR = (EPS0 * EPS_AIR * AREA / 100e-6, EPS0 * EPS_AIR * AREA / 1e-15)  # u at C_gap = 100 µF and 1 fF (the prior's bounds)


def _pooled_stub(u):
    """A pooled `GapAnalysis` built by hand around the draws ``u`` [m] (no fit, no sampling): the
    SYNTHETIC remainder of `_stub_analysis` (u = 3.5 µm, so the paper's method gives an air gap)."""
    base = _stub_analysis(rhat_max=1.0)
    post = SimpleNamespace(parameter_draws=lambda: {"u": u, "C_gap": EPS0 * EPS_AIR * AREA / u, "R_EP": np.full(u.size, 5e7)}, **POOLED_CHAIN)
    force = base.force.assign({f"gap_voltage_{k}": base.force[k] * 0 + 75.0 for k in ("median", "q05", "q95")})
    return replace(base, method="pooled", hierarchical=None, posterior=post, force=force)


@pytest.mark.parametrize(("u_median", "verdict", "head"), [
    (3.5e-6, None, "gap thickness u = 3.4"),
    (2e-3, "lies outside the air gaps a contact can hold (1 nm–1 mm)", "sampled u (NO AIR GAP) = 2 mm"),
    (U_PRIOR[0] * 1.2, "piles up at the lower bound of its prior (C_gap = 100 µF: the prior sets it, not the data) and lies outside", "sampled u (prior-set) = "),
])
def test_a_u_that_is_no_air_gap_is_an_alarm_and_not_identified(u_median, verdict, head):
    """u outside 1 nm–1 mm, or piled up at a bound of its prior (C_gap at 100 µF or 1 fF: u =
    ε0 ε A/C written here), opens the report with "NO AIR GAP", is among the alarms and makes
    gap_identified (and force_determined) false; a u of 3.5 µm does none of this. The paper's
    u here is an air gap, so the advice is not the area's unit."""
    u = u_median * np.exp(0.01 * np.random.default_rng(1).standard_normal(400))
    gap = _pooled_stub(u)
    lines = gap.report().splitlines()
    assert next(x for x in lines if "u (" in x or x.startswith("gap thickness")).startswith(head)
    if verdict is None:
        assert gap.gap_identified and gap.alarms == () and gap.gap_implausible is None
        return
    assert not gap.gap_identified  # (the JSON's gap_identified and force_determined)
    assert verdict in gap.gap_implausible and gap.alarms == (f"NO AIR GAP: {gap.gap_implausible}; u, C_gap and the force are no measurement",)
    assert lines[0].startswith(f"NO AIR GAP: {gap.gap_implausible}") and "the area's unit is not the cause" in lines[0]
    assert " of a u that is no air gap, NO ESTIMATE of the force:" in gap.report() if verdict.startswith("lies outside") else " of the prior-set u, NO ESTIMATE" in gap.report()


def test_the_walkthrough_s_u_of_a_metre_is_no_air_gap_and_its_capacitances_have_their_prefix():
    """The walkthrough's run (`impedax gap FILE --area 130e-6 --pooled --steps 50`, a single
    BioLogic spectrum): u = 1.15 m piled up at the prior's upper bound (C_gap = 1 fF) was
    reported as "gap thickness u = 1150016.575 µm", "C_gap = 0.0 pF (90 %: 0.0–0.0 pF)", the
    paper's u as "0.000 µm", and the JSON said gap_identified true, alarms []. The paper's C_gap
    in numpy (Sirin §2.3: the mean |Y|/ω above 30 Hz) is 22.8 µF, its u 0.05 nm."""
    path = "tests/fixtures/real/exampleDataBioLogic.mpt"
    data = ix.load(path)
    f, z = data["frequency"].values, data["Z"].values.ravel()
    keep = f >= CUTOFF_HZ
    c_paper = np.mean(1.0 / (2 * np.pi * f[keep] * np.abs(z[keep])))
    u_paper = EPS0 * EPS_AIR * 130e-6 / c_paper
    assert 1e-11 < u_paper < 1e-10  # (the oracle: no air gap)
    gap = ix.models.gap_analysis(data, area=130e-6, method="pooled", steps=50, progress=False)
    s = gap.summary()
    u_upper = EPS0 * EPS_AIR * 130e-6 / 1e-15
    assert s["gap_um"]["value"] == pytest.approx(u_upper * 1e6, rel=0.02)  # (at the bound: the alarm's case)
    assert not s["gap_identified"] and not s["force_determined"] and s["gap_implausible"].startswith("u = 1.15 m (posterior median) piles up at the upper bound")
    assert s["paper_method"]["gap_implausible"].startswith(f"the paper method's u = {format_quantity(u_paper, 'm')} (C_gap = {format_quantity(c_paper, 'F')})")
    assert [a.split(":")[0] for a in s["alarms"]] == ["NO AIR GAP", "PAPER METHOD"]
    lines = gap.report().splitlines()
    assert lines[0].startswith("NO AIR GAP: u = 1.15 m") and "check the area's unit first" in lines[0] and lines[1].startswith("PAPER METHOD: NO AIR GAP")
    assert lines[2].startswith("sampled u (prior-set) = 1.15 m  (90 % interval of the draws: ")
    assert any(x.startswith(f"paper method    u = {format_quantity(u_paper, 'm')} (NO AIR GAP)") for x in lines)
    (c_line,) = [x for x in lines if x.startswith("C_gap")]
    assert c_line.startswith("C_gap (prior-set) = 1.00") and " fF (90 %: 1" in c_line and f"paper method {c_paper * 1e6:.4g} µF" in c_line and "pF" not in c_line


def test_the_correlation_advice_call_fits_with_the_weighting_its_sampling_needs():
    """The call the correlation advice prints (2026-12-03 walkthrough): run as printed on trial
    means with their SEM, its ``ix.fit`` was weighted by |Z| and the pooled sampling, whose
    likelihood is the SEM's χ² (noise ``sigma``), warned "init was fitted with weighting
    'modulus' …". The call now passes the analysis's weighting; its fit, run as printed (the
    ``…`` filled in), starts the sampling without that warning. SYNTHETIC draws for the advice;
    SYNTHETIC trials written in numpy for the run (`spectra.sirin_scattered_measurements`)."""
    import re

    from impedax.fitting.bayes.diagnostics import chain_warnings, strong_correlations
    from impedax.models.gap import _correlation_advice

    z = np.random.default_rng(5).standard_normal((3, 4000))
    ln_r, ln_u = 17.7 + 0.01 * z[0], np.log(3.5e-6) + 0.0015 * z[2]
    ln_q = -19.6 + 0.98 * (ln_r - 17.7) + 0.002 * z[1]
    chain = np.stack([ln_r, ln_q, ln_u], axis=-1).reshape(40, 100, 3)
    names = ["R_EP", "CPE_EP.Q", "u"]
    raw = [w for w in chain_warnings(names, [True] * 3, chain, dict.fromkeys(names, 1.0), 1, 0.3) if "strongly correlated" in w]
    draws = {"R_EP": np.exp(ln_r), "CPE_EP.Q": np.exp(ln_q), "u": np.exp(ln_u)}
    (said,) = _correlation_advice(raw, strong_correlations(names, [True] * 3, chain), draws, "R_EP || CPE_EP || C_gap", weighting="sigma")
    call = re.search(r"edl_fit=(ix\.fit\(.*\))\)$", said)[1]
    assert call.endswith("fixed={'R_EP': …}, weighting='sigma')")

    _, (total, skin, screen), spectra = _scattered(3)
    assert "sigma" in remaining_impedance(*spectra)  # (the trial means' SEM: the sampling's noise is "sigma")
    edl_fit = eval(call.replace("…", "5e7"), {"ix": ix, "total": spectra[0], "skin": spectra[1], "touchscreen": spectra[2]})
    assert edl_fit.weighting == "sigma"
    result = ix.models.gap_analysis(*spectra, area=AREA, method="pooled", edl_fit=edl_fit, steps=50, progress=False)
    assert not any("init was fitted with weighting" in w for w in result.warnings), result.warnings
