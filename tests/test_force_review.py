"""Review fixes of the force models and `impedax force`: input checks of meyer and vezzoli, the
plot's title and warnings, the overflow message naming the frequencies, Meyer's force at very low
frequency against a 50-digit mpmath evaluation of the circuit, and the Fig 9 numbers of the
Vezzoli example against eq 10 (each against an oracle written here or a paper's number)."""

import importlib
import math
import sys
import warnings
from pathlib import Path

import mpmath
import numpy as np
import pytest

from impedax.cli import main
from impedax.errors import ParameterError
from impedax.models import meyer, vezzoli

E0 = 8.8541878128e-12
THESIS = {"C_s": 140e-12, "C_i": 1.7e-9, "R_sc": 130e3, "C_sc": 2.2e-9, "R_f": 500.0}
AREA = math.pi * 0.004**2
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


# --- 1. input checks -------------------------------------------------------------------------------


@pytest.mark.parametrize("alpha", [1.5, 0.0, -0.2, float("nan")])
def test_meyer_model_refuses_a_cpe_exponent_outside_0_1(alpha):
    with pytest.raises(ParameterError, match=r"alpha must be in \(0, 1\]"):
        meyer.meyer_model("cpe", alpha=alpha)
    with pytest.raises(ParameterError, match=r"alpha must be in \(0, 1\]"):
        meyer.meyer_parameters(variant="cpe", alpha=alpha)


def test_meyer_model_cpe_exponent_one_is_accepted_and_q_is_c_sc():
    model = meyer.meyer_model("cpe", alpha=1.0)
    assert model.params["CPE_sc.Q"] == pytest.approx(2.2e-9, rel=1e-12)  # Q ω^(1−α) with α = 1: C_sc


@pytest.mark.parametrize("name, value", [("C_s", -1e-10), ("C_i", 0.0), ("R_sc", -130e3), ("R_f", 0.0), ("C_sc", -2.2e-9)])
@pytest.mark.parametrize("function", [meyer.force_time_average, meyer.force_peak])
def test_meyer_forces_refuse_nonpositive_element_values(function, name, value):
    with pytest.raises(ParameterError, match=rf"params\['{name}'\].* must be positive"):
        function({**THESIS, name: value}, 1e3)


@pytest.mark.parametrize("values, match", [({"CPE_sc.Q": -1e-9}, "CPE_sc.Q"), ({"CPE_sc.alpha": 1.5}, r"alpha'\] must be in \(0, 1\]"), ({"CPE_sc.alpha": 0.0}, "CPE_sc.alpha")])
def test_meyer_cpe_force_refuses_bad_cpe_values(values, match):
    params = {**meyer.meyer_model("cpe").params, **values}
    with pytest.raises(ParameterError, match=match):
        meyer.force_time_average(params, 1e3, variant="cpe")


def test_meyer_model_force_refuses_a_negative_capacitor_and_valid_values_still_match_the_chain():
    model = meyer.meyer_model()
    with pytest.raises(ParameterError, match="C_s"):
        model.with_params(C_s=-1e-10).force(1e3)
    # oracle: the chain by hand, K/2 (|V_F|² − |Q_f/C_i|²) at 1 kHz
    jw = 2j * np.pi * 1e3
    z_sc = 130e3 / (1 + jw * 130e3 * 2.2e-9)
    current = 140.0 / (1 / (jw * 140e-12) + 1 / (jw * 1.7e-9) + z_sc + 500.0)
    v_f, q_c = current * (1 / (jw * 1.7e-9) + z_sc), current * z_sc / (130e3 * jw) / 1.7e-9
    k = (1.7e-9 * 2.2e-9 / 3.9e-9) ** 2 / (2 * AREA * E0)
    assert float(model.force(1e3)) == pytest.approx(k / 2 * (abs(v_f) ** 2 - abs(q_c) ** 2), rel=1e-10)


@pytest.mark.parametrize("kwargs", [{"amplitude": np.array([1e-6, 2e-6])}, {"amplitude": 1e-6, "normal_force": np.array([0.2, 0.3])}, {"amplitude": [1e-6, 2e-6]}])
def test_squeeze_film_lift_asks_for_a_scalar(kwargs):
    with pytest.raises(ParameterError, match="must be a single number.*once per value"):
        vezzoli.squeeze_film_lift(**kwargs)


def test_squeeze_film_lift_takes_numpy_scalars():
    # flat plate (h_e = 0): time mean of P − 1 = √((1 + 1.5ε²)/(1 − ε²)) − 1, ε = h_v/(h_r + h_v)
    e = 1e-6 / 3e-6
    expected = 1e5 * 1e-4 * (np.sqrt((1 + 1.5 * e**2) / (1 - e**2)) - 1)
    for amplitude in (np.float64(1e-6), np.array(1e-6)):
        assert vezzoli.squeeze_film_lift(amplitude, h_r=2e-6, h_e=0.0).force == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("normal_force", [0.0, -0.2, np.array([0.2, 0.0])])
def test_friction_reduction_refuses_a_nonpositive_normal_force(normal_force):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no divide-by-zero RuntimeWarning on the way
        with pytest.raises(ParameterError, match="normal_force must be positive"):
            vezzoli.friction_reduction(0.1, normal_force)


def test_friction_reduction_is_the_clipped_ratio():
    lift = np.array([-0.01, 0.0, 0.1, 0.3])
    np.testing.assert_array_equal(vezzoli.friction_reduction(lift, 0.2), np.clip(lift / 0.2, 0, 1))
    assert vezzoli.friction_reduction(0.1, 0.4) == pytest.approx(0.25)


# --- 2. the plot's title, subtitle and warning -----------------------------------------------------


@pytest.fixture
def saved_figures(monkeypatch):
    """The matplotlib figures `impedax force --plot` would save (not written)."""
    import matplotlib.pyplot as plt

    import impedax.plotting

    figures = []

    def keep(fig, path):
        figures.append((fig.axes[0].get_title(), [t.get_text() for t in fig.texts]))
        plt.close(fig)

    monkeypatch.setattr(impedax.plotting, "save_figure", keep)
    return figures


def _plot(capsys, saved_figures, tmp_path, *args):
    assert main(["force", *args, "--points", "5", "--plot", str(tmp_path / "f.png"), "--out", str(tmp_path / "f.csv")]) == 0
    capsys.readouterr()
    (title, texts), = saved_figures[-1:]
    return title.replace("\n", " "), texts  # (the title is wrapped to the figure's width)


def test_meyer_plot_names_fig_3_4_only_for_its_time_average_with_thesis_values(capsys, saved_figures, tmp_path):
    title, texts = _plot(capsys, saved_figures, tmp_path, "meyer")
    assert "time-averaged force, thesis Fig 3.4" in title and "V_A = 140 V" in title and texts == []
    peak, _ = _plot(capsys, saved_figures, tmp_path, "meyer", "--convention", "peak")
    assert "peak force" in peak and "thesis Fig 3.4" not in peak and "Fig 3.4 shows their time average" in peak
    changed, _ = _plot(capsys, saved_figures, tmp_path, "meyer", "--param", "R_sc=1e5", "--param", "v_a=200")
    assert "Fig 3.4" not in changed and "R_sc = 1e+05 Ω" in changed and "V_A = 200 V (thesis 140 V)" in changed
    same, _ = _plot(capsys, saved_figures, tmp_path, "meyer", "--param", "R_f=500")  # the thesis value again
    assert "thesis Fig 3.4" in same


def test_vezzoli_plot_shows_the_eq8_warning_and_the_changed_values(capsys, saved_figures, tmp_path):
    title, texts = _plot(capsys, saved_figures, tmp_path, "vezzoli")
    assert "eq 10, time-averaged force" in title and "V_m = 2000 V; Table 2 values" in title and texts == []
    title, texts = _plot(capsys, saved_figures, tmp_path, "vezzoli", "--param", "h_i=1e-6", "--param", "eps_i=36", "--convention", "peak")
    ratio = 36 * 350e-6 / (2340 * 1e-6)  # C_i/C_s = ε_i h_s/(ε_s h_i)
    assert "peak force" in title and "h_i = 1e-06 m" in title and "eps_i = 36" in title
    assert len(texts) == 1 and f"{ratio:.3g}" in texts[0].replace("\n", " ") and "C_i ≪ C_s" in texts[0]
    fig8, _ = _plot(capsys, saved_figures, tmp_path, "vezzoli", "--param", "v_m=140", "--param", "h_i=1e-6", "--param", "eps_i=3.4")
    assert "Fig 8 conditions (h_s = 350 µm)" in fig8


@pytest.mark.parametrize("args", [["meyer", "--variant", "cpe"], ["meyer", "--param", "R_sc=1e5", "--param", "C_i=2e-9", "--param", "v_a=200", "--convention", "peak"], ["vezzoli", "--param", "h_i=1e-6"]])
def test_the_plot_title_and_warnings_lie_inside_the_figure(capsys, monkeypatch, tmp_path, args):
    """(walkthrough: ``meyer --variant cpe``'s second title line ran off the right edge, ending
    "...(C_sc of eq 3.13 at 1 kH"): wrapped to the figure's width. Oracle: the texts' boxes on
    an Agg canvas (matplotlib's `get_window_extent`) against the figure's."""
    import matplotlib.pyplot as plt

    import impedax.plotting

    figures = []
    monkeypatch.setattr(impedax.plotting, "save_figure", lambda fig, path: figures.append(fig))
    assert main(["force", *args, "--points", "5", "--plot", str(tmp_path / "f.png"), "--out", str(tmp_path / "f.csv")]) == 0
    capsys.readouterr()
    (fig,) = figures
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    for text in [fig.axes[0].title, *fig.texts]:
        box = text.get_window_extent(renderer)
        assert fig.bbox.x0 <= box.x0 and box.x1 <= fig.bbox.x1 and fig.bbox.y0 <= box.y0 and box.y1 <= fig.bbox.y1, text.get_text()
    plt.close(fig)


# --- 3. the overflow message names the frequencies when they are the cause -------------------------


@pytest.mark.parametrize(
    "args, says, not_says",
    [
        (["meyer", "--fmin", "1e-300", "--fmax", "1e300"], ["frequency range is the cause", "--fmin 1e-300 Hz", "raise --fmin"], "--param values"),
        (["vezzoli", "--fmin", "1e-300", "--fmax", "1e300"], ["frequency range is the cause", "lower --fmax"], "--param values"),
        (["vezzoli", "--param", "v_m=1e200"], ["check the --param values (v_m=1e+200)"], "frequency range"),
        (["vezzoli", "--param", "v_m=1e200", "--fmax", "1e300"], ["frequency range is the cause", "check the --param values too (v_m=1e+200)"], None),
    ],
)
def test_overflow_message_names_its_cause(capsys, args, says, not_says):
    assert main(["force", *args, "--points", "7"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    for text in says:
        assert text in err[0]
    assert not_says is None or not_says not in err[0]


# --- 4. Meyer's force at very low frequency --------------------------------------------------------


def _mp_force(params, f, variant="rc", v_a=140):
    """Eq 3.6 time average and peak with 50 digits: the chain by hand, I = V_A/Z_total,
    V_F = I (1/(jωC_i) + Z_sc), Q_f/C_i = I Z_sc/(R_sc jω C_i); F̄ = K/2 (|V_F|² − |Q_f/C_i|²),
    F_peak = F̄ + K/2 |V_F² − (Q_f/C_i)²| (the cancellation is harmless at this precision)."""
    with mpmath.workdps(50):
        p = {k: mpmath.mpf(v) for k, v in params.items()}
        w = 2 * mpmath.pi * mpmath.mpf(f)
        jw = mpmath.mpc(0, w)
        y_sc = jw * p["C_sc"] if variant == "rc" else p["CPE_sc.Q"] * jw ** p["CPE_sc.alpha"]
        c_sc = p["C_sc"] if variant == "rc" else p["CPE_sc.Q"] * w ** (p["CPE_sc.alpha"] - 1)
        z_sc = 1 / (1 / p["R_sc"] + y_sc)
        current = v_a / (1 / (jw * p["C_s"]) + 1 / (jw * p["C_i"]) + z_sc + p["R_f"])
        v_f = current * (1 / (jw * p["C_i"]) + z_sc)
        q_c = current * z_sc / (p["R_sc"] * jw) / p["C_i"]
        k = (p["C_i"] * c_sc / (p["C_i"] + c_sc)) ** 2 / (2 * mpmath.mpf(AREA) * mpmath.mpf(E0))
        mean = k / 2 * (abs(v_f) ** 2 - abs(q_c) ** 2)
        return float(mean), float(mean + k / 2 * abs(v_f**2 - q_c**2))


@pytest.mark.parametrize("f", [1e-6, 1e-5, 1e-4, 1e-2, 10.0, 37e3])
@pytest.mark.parametrize("variant", ["rc", "cpe"])
def test_meyer_force_at_very_low_frequency_against_mpmath(variant, f):
    model = meyer.meyer_model(variant)
    mean, peak = _mp_force(model.params, f, variant)
    assert float(meyer.force_time_average(model.params, f, variant=variant)) == pytest.approx(mean, rel=1e-6)
    assert float(meyer.force_peak(model.params, f, variant=variant)) == pytest.approx(peak, rel=1e-9)


def test_meyer_low_frequency_force_closed_form_by_hand():
    """With the divider of thesis A.1, V_F/V_A = C_s(1 + jωτ)/D and Q_f/(C_i V_A) = C_s/D, τ =
    R_sc(C_sc + C_i): V_F − Q_f/C_i = C_s V_A jωτ/D, V_F + Q_f/C_i = C_s V_A (2 + jωτ)/D, so
    F̄ = K/2 Re[jωτ (2 − jωτ)] |C_s V_A/D|² = K/2 (ωτ)² |C_s V_A/D|² — no subtraction left."""
    cs, ci, r, csc, rf = (THESIS[k] for k in ("C_s", "C_i", "R_sc", "C_sc", "R_f"))
    k = (ci * csc / (ci + csc)) ** 2 / (2 * AREA * E0)
    for f in (1e-6, 1e-5, 3e2):
        s = 2j * np.pi * f
        d = ci + cs + (csc * r * (ci + cs) + ci * cs * (rf + r)) * s + ci * cs * csc * rf * r * s**2
        expected = k / 2 * (2 * np.pi * f * r * (csc + ci)) ** 2 * abs(cs * 140.0 / d) ** 2
        assert float(meyer.force_time_average(THESIS, f)) == pytest.approx(expected, rel=1e-7)
    assert float(meyer.force_time_average(THESIS, 1e-6)) == pytest.approx(5.95e-19, rel=0.01)  # (was exactly 0)


# --- 5, 6. examples ---------------------------------------------------------------------------------


def _example(name):
    sys.path.insert(0, str(EXAMPLES))
    try:
        return importlib.import_module(name)
    finally:
        sys.path.remove(str(EXAMPLES))


def test_meyer_example_charge_bound_of_an_rc_circuit_bounds_its_force():
    """The example's bound, now also for an RC finger (α = 1): the RC force stays under its own
    circuit's bound and reaches it at high frequency (eq 3.6 with Q_f → 0)."""
    example = _example("meyer_rc_vs_cpe")
    f = np.geomspace(10.0, 1e9, 97)
    bound = example.charge_bound(f, THESIS, AREA)
    jw = 2j * np.pi * f  # Q_i = I/(jω), I = V_A/Z_total, written again here
    q_i = 140.0 / (1 / (jw * 140e-12) + 1 / (jw * 1.7e-9) + 130e3 / (1 + jw * 130e3 * 2.2e-9) + 500.0) / jw
    np.testing.assert_allclose(bound, np.abs(q_i) ** 2 / (4 * E0 * AREA), rtol=1e-12)
    force = np.asarray(meyer.force_time_average(THESIS, f))
    assert np.all(force <= bound * (1 + 1e-9)) and force[-1] == pytest.approx(bound[-1], rel=0.01)


def test_vezzoli_example_fig9_numbers_against_eq10():
    """The review's numbers (Table 2 fill-ins, 500 Hz, 140 V): 0.020 N at (ε_i 25, 8.5 µm) and 0.022 N
    at (8.5, 2.5 µm), not the paper's 0.03 N; each value the example says would give 0.03 N does,
    put back into impedax's eq 10."""
    example = _example("vezzoli_electrovibration")
    zro2, zno = example.fig9_requirements(25.0, 8.5e-6), example.fig9_requirements(8.5, 2.5e-6)
    assert zro2["force"] == pytest.approx(0.0196, abs=5e-4) and zno["force"] == pytest.approx(0.0220, abs=5e-4)
    assert zro2["eps_i"] == pytest.approx(50, rel=0.02) and zno["eps_i"] == pytest.approx(14.25, rel=0.02)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", vezzoli.Eq8ValidityWarning)  # (these points lie outside eq 8's condition)
        for eps, h, r in ((25.0, 8.5e-6, zro2), (8.5, 2.5e-6, zno)):
            force = lambda **kw: float(vezzoli.electrovibration_force(500.0, **{"h_i": h, "eps_i": eps, "v_m": 140.0, **kw}))
            assert force() == pytest.approx(r["force"], rel=1e-12)
            for kw in ({"h_i": r["h_i"]}, {"eps_i": r["eps_i"]}, {"h_s": r["h_s"]}, {"area": r["area"]}, {"v_m": r["v_m"]}):
                assert force(**kw) == pytest.approx(0.03, rel=1e-9)
            assert 2 * force(h_i=r["h_i_peak"]) == pytest.approx(0.03, rel=1e-9)
    sio2 = example.fig9_requirements(3.9, 1e-6)
    assert sio2["h_i"] < 1e-6  # the paper's "less than 1 µm of SiO2" holds


def test_the_force_spectrum_is_drawn_in_the_prefix_of_its_largest_value():
    """Vezzoli's model with a 1 µm layer drew 14,000 mN on a mN axis (walkthrough 2026-12-06): a
    force of 14 N is drawn in N, one of 0.16 N in mN, each point at force / the prefix's scale."""
    import matplotlib.pyplot as plt

    from impedax.plotting.models import plot_force_spectrum

    f = np.geomspace(10.0, 1e6, 5)
    for force, unit, scale in ((np.array([2.0, 6.0, 14.0, 9.0, 3.0]), "N", 1.0), (np.array([0.02, 0.08, 0.164, 0.1, 0.05]), "mN", 1e-3)):
        fig = plot_force_spectrum(f, force, title="t", convention="peak", peak={"frequency_hz": f[2], "force_n": force[2], "at_band_edge": False})
        ax = fig.axes[0]
        assert ax.get_ylabel() == f"peak force [{unit}]"
        np.testing.assert_allclose(ax.get_lines()[0].get_ydata(), force / scale)
        plt.close(fig)
