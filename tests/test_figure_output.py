"""Figures and tables for a thesis: font sizes that follow matplotlib's rcParams, ``figsize``,
``--dpi``, vector ``--plot`` formats, ``--title``, and parameters as value ± standard error
rounded to the error's digits (text and LaTeX, ``impedax fit --out FILE.tex``)."""

from __future__ import annotations

import dataclasses

import matplotlib

matplotlib.use("Agg")

import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import impedax as ix  # noqa: E402
from impedax.cli import main  # noqa: E402
from impedax.data import exact_number, format_value_error, latex_unit, latex_value_error, round_to_error  # noqa: E402
from impedax.plotting import plot_spectrum  # noqa: E402

R0, R1, C1 = 20.0, 500.0, 1e-6  # SYNTHETIC: R0 + R1 || C1, 1 % complex noise, seed 7
FREQ = np.geomspace(0.1, 1e5, 40)


def _z_true(f):
    return R0 + R1 / (1 + 2j * np.pi * f * R1 * C1)


def _z_noisy(seed=7):
    rng = np.random.default_rng(seed)
    z = _z_true(FREQ)
    return z * (1 + 0.01 * (rng.standard_normal(FREQ.size) + 1j * rng.standard_normal(FREQ.size)))


@pytest.fixture(scope="module")
def spectrum_csv(tmp_path_factory):
    """A canonical CSV of the SYNTHETIC spectrum."""
    path = tmp_path_factory.mktemp("fig") / "spec.csv"
    z = _z_noisy()
    path.write_text("frequency_hz,z_real_ohm,z_imag_ohm\n" + "".join(f"{float(f)!r},{float(v.real)!r},{float(v.imag)!r}\n" for f, v in zip(FREQ, z)))
    return path


@pytest.fixture(scope="module")
def fit_result():
    return ix.fit("R0 + R1 || C1", ix.make_spectrum(FREQ, _z_noisy()))


def _legend_sizes(fig):
    return [t.get_fontsize() for ax in fig.axes if ax.get_legend() is not None for t in ax.get_legend().get_texts()]


def _spectrum_figure(**kw):
    return plot_spectrum((FREQ, _z_noisy()), (FREQ, _z_true(FREQ)), title="SYNTHETIC", **kw)


# --- fonts follow rcParams ---------------------------------------------------------------------

def test_legend_keeps_its_default_size_under_default_rcparams():
    fig = _spectrum_figure()
    sizes = _legend_sizes(fig)
    plt.close(fig)
    assert sizes and all(s == pytest.approx(8.0) for s in sizes)  # (as before: legend(fontsize=8))


def test_legend_fontsize_set_in_rcparams_is_honoured():
    with plt.rc_context({"legend.fontsize": 14}):
        fig = _spectrum_figure()
    sizes = _legend_sizes(fig)
    plt.close(fig)
    assert sizes and all(s == pytest.approx(14.0) for s in sizes)


def test_fit_result_plot_follows_a_larger_base_font(fit_result):
    # font.size 15 instead of matplotlib's 10: impedax's compact 8 pt legends scale by 1.5
    with plt.rc_context({"font.size": 15}):
        fig = fit_result.plot()
    sizes = _legend_sizes(fig)
    plt.close(fig)
    assert sizes and all(s == pytest.approx(12.0) for s in sizes)


def test_long_residual_label_is_shortened_where_it_would_run_past_its_panel():
    # chosen when the layout places the panels: at every draw
    with plt.rc_context({"font.size": 14}):
        small = _spectrum_figure(figsize=(6.3, 5.0))
        small.canvas.draw()
        shortened = small.axes[3].get_ylabel()
        small.set_size_inches(6.3, 12.0)  # (tall enough again: the label as given)
        small.canvas.draw()
        restored = small.axes[3].get_ylabel()
    large = _spectrum_figure()
    large.canvas.draw()
    default = large.axes[3].get_ylabel()
    plt.close(small), plt.close(large)
    assert (shortened, restored, default) == ("residual [%]", "residual (Z_model − Z)/|Z| [%]", "residual (Z_model − Z)/|Z| [%]")


# --- figsize -----------------------------------------------------------------------------------

def test_figsize_is_honoured(fit_result):
    fig = fit_result.plot(figsize=(6.3, 4.5))
    size = tuple(fig.get_size_inches())
    plt.close(fig)
    assert size == pytest.approx((6.3, 4.5))


# --- CLI: --dpi, vector formats, --title, .tex ---------------------------------------------------

def test_dpi_sets_the_png_pixel_size(spectrum_csv, tmp_path):
    from impedax.cli.common import FIGURE_DPI
    from impedax.plotting import FIGURE_DPI as PLOTTING_DPI

    assert FIGURE_DPI == PLOTTING_DPI == 120  # (the --help text repeats the plotting default)
    paths = {dpi: tmp_path / f"fit{dpi}.png" for dpi in (None, 60)}
    for dpi, path in paths.items():
        assert main(["fit", str(spectrum_csv), "--model", "R0 + R1 || C1", "--plot", str(path), *(["--dpi", str(dpi)] if dpi else [])]) == 0
    default, low = (mpimg.imread(paths[d]).shape for d in (None, 60))
    # the fit figure is 11 in wide (`spectrum_layout`): 11 × dpi pixels
    assert default[1] == 11 * 120 and low[1] == 11 * 60
    assert low[0] == pytest.approx(default[0] / 2, abs=1)


def test_compare_takes_the_figure_options(spectrum_csv, tmp_path):
    """compare's --plot has --dpi and --title as every other command's (11 in wide at 40 dpi)."""
    path = tmp_path / "compare.png"
    assert main(["compare", str(spectrum_csv), "--model", "R0 + R1 || C1", "--model", "R0 + R1 || CPE1", "--plot", str(path), "--dpi", "40", "--title", ""]) == 0
    assert mpimg.imread(path).shape[1] == 11 * 40


@pytest.mark.parametrize("ext, head", [(".pdf", (b"%PDF",)), (".svg", (b"<?xml", b"<svg")), (".eps", (b"%!PS",))])
def test_plot_writes_vector_formats_by_extension(spectrum_csv, tmp_path, ext, head):
    path = tmp_path / f"fit{ext}"
    assert main(["fit", str(spectrum_csv), "--model", "R0 + R1 || C1", "--plot", str(path)]) == 0
    assert path.read_bytes().startswith(head)


def test_dpi_must_be_positive(spectrum_csv, tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["fit", str(spectrum_csv), "--model", "R0", "--plot", str(tmp_path / "x.png"), "--dpi", "0"])
    assert exc.value.code == 2
    assert "--dpi: expected a positive number of dots per inch, got '0'" in capsys.readouterr().err
    assert not (tmp_path / "x.png").exists()


def test_title_option_replaces_or_removes_the_figure_title(tmp_path):
    from impedax.cli.common import figure_writer

    figures = {}
    for key, title in (("default", None), ("text", "Fig. 3.2"), ("none", "")):
        fig = _spectrum_figure()
        figure_writer(lambda fig=fig: fig, "/data/run 1/spec.csv", title=title, dpi=20)(tmp_path / f"{key}.png")
        figures[key] = fig
    suptitle = {k: (f._suptitle.get_text() if f._suptitle is not None else None) for k, f in figures.items()}
    assert suptitle["default"] == "SYNTHETIC\nspec.csv"  # (the file's name added, as before)
    assert suptitle["text"] == "Fig. 3.2"
    assert suptitle["none"] is None


# --- value ± error rounded to the error's digits ----------------------------------------------

# (value, error) → (value, error, power of ten), rounded by hand: the error to two significant
# digits, the value to the error's last digit, half up on the decimal number as written
ROUNDING_ORACLE = [
    (533.3168, 13.0249, ("533", "13", 0)),
    (0.012345, 0.00067, ("0.01235", "0.00067", 0)),
    (20.014, 0.0624, ("20.014", "0.062", 0)),
    (499.01, 0.885, ("499.01", "0.89", 0)),  # (0.885 → 0.89: half up)
    (9.96, 9.96, ("10", "10", 0)),  # (the error rounds to the next decade: still two digits)
    (5.0, 120.0, ("5.0", "120", 0)),  # (a value below its error: each to two significant digits)
    (0.95, 1.0, ("0.95", "1.0", 0)),
    (-3.0, 0.96, ("-3.00", "0.96", 0)),
    (-0.0001, 0.5, ("-1.0e-04", "0.50", 0)),  # (not "0.00": each with its own power of ten)
    (0.0, 0.5, ("0.00", "0.50", 0)),  # (a value of zero: at the error's digit)
    (2.18e7, 2.8e15, ("2.2e+07", "2.8e+15", 0)),  # (not "(0.0 ± 2.8)×10^15", which reads R = 0)
    (1e5, 1e12, ("1.0e+05", "1.0e+12", 0)),
    (1.0002e-6, 2.82e-9, ("1.0002", "0.0028", -6)),
    (1.5e7, 2.5e5, ("1.500", "0.025", 7)),
    (123456.0, 7.0, ("1.234560", "0.000070", 5)),  # (10^5: outside 0.01 ≤ |value| < 10^4)
    (1234.5, 0.12, ("1234.50", "0.12", 0)),
    (0.0099, 0.001, ("9.9", "1.0", -3)),
    (9.996e-4, 9.96e-6, ("1.000", "0.010", -3)),  # (the carry 9.996 → 10.00 moves the exponent)
    (9999.6, 50.0, ("1.0000", "0.0050", 4)),  # (9999.6 → 10000 at the tens: now 10^4)
    (1.0003e-3, 1.7e-6, ("1.0003", "0.0017", -3)),  # (CC1.tau and HN1.tau: one rule, both scaled)
    (9.96e-4, 2.2e-5, ("9.96", "0.22", -4)),
    (2.5e-4, 1.5e-5, ("2.50", "0.15", -4)),
    (1.0, 0.0, ("1", "", 0)),  # (no error: the value to 5 significant digits)
    (1.234567, float("nan"), ("1.2346", "", 0)),
]


@pytest.mark.parametrize("value, error, expected", ROUNDING_ORACLE)
def test_round_to_error_matches_hand_rounding(value, error, expected):
    assert round_to_error(value, error) == expected


def test_format_value_error_reads_as_written_by_hand():
    assert format_value_error(533.3168, 13.0249, "Ohm") == "533 ± 13 Ω"
    assert format_value_error(0.012345, 0.00067) == "0.01235 ± 0.00067"
    assert format_value_error(1.0002e-6, 2.82e-9, "F") == "(1.0002 ± 0.0028)e-06 F"
    assert format_value_error(0.5, float("nan"), "1") == "0.5"
    assert format_value_error(2.18e7, 2.8e15, "Ohm") == "2.2e+07 ± 2.8e+15 Ω"


# (value, error) → the LaTeX cell, written by hand
LATEX_ORACLE = [
    (533.3168, 13.0249, r"$533 \pm 13$"),
    (1.0002e-6, 2.82e-9, r"$(1.0002 \pm 0.0028) \times 10^{-6}$"),
    (9.996e-4, 9.96e-6, r"$(1.000 \pm 0.010) \times 10^{-3}$"),
    (2.18e7, 2.8e15, r"$2.2 \times 10^{7} \pm 2.8 \times 10^{15}$"),
    (-0.0001, 0.5, r"$-1.0 \times 10^{-4} \pm 0.50$"),
    (5.0, 120.0, r"$5.0 \pm 120$"),
    (1.234567e7, float("nan"), r"$1.2346 \times 10^{7}$"),
]


@pytest.mark.parametrize("value, error, expected", LATEX_ORACLE)
def test_latex_value_error_matches_hand_text(value, error, expected):
    assert latex_value_error(value, error) == expected


def test_a_fixed_value_is_written_as_given():
    assert [exact_number(v) for v in (12.3456, 2000.0, 1e-6, 0.1 + 0.2)] == ["12.3456", "2000", "1e-06", "0.30000000000000004"]
    assert latex_value_error(12.3456, float("nan"), exact=True) == "$12.3456$"
    assert latex_value_error(1e-6, float("nan"), exact=True) == r"$1 \times 10^{-6}$"


def test_latex_units_need_no_package():
    assert latex_unit("Ohm") == r"$\Omega$"
    assert latex_unit("Ohm s^-1/2") == r"$\Omega\,\mathrm{s}^{-1/2}$"
    assert latex_unit("F s^(alpha-1)") == r"$\mathrm{F}\,\mathrm{s}^{\alpha-1}$"
    assert latex_unit("1") == ""


def test_to_latex_holds_the_rounded_pairs(fit_result):
    # the fit's own numbers replaced by the hand-rounded cases above (a frozen dataclass)
    result = dataclasses.replace(
        fit_result,
        values={"R0": 533.3168, "R1": 0.012345, "C1": 1.0002e-6},
        stderr={"R0": 13.0249, "R1": 0.00067, "C1": 2.82e-9},
    )
    text = result.to_latex()
    lines = text.splitlines()
    assert lines[1] == r"\begin{tabular}{lll}" and lines[-1] == r"\end{tabular}"
    assert r"R0 & $533 \pm 13$ & $\Omega$ \\" in lines
    assert r"R1 & $0.01235 \pm 0.00067$ & $\Omega$ \\" in lines
    assert r"C1 & $(1.0002 \pm 0.0028) \times 10^{-6}$ & $\mathrm{F}$ \\" in lines


def test_to_latex_writes_a_fixed_value_as_given_and_marks_the_undetermined(fit_result):
    fixed = ix.fit("R0 + R1 || C1", ix.make_spectrum(FREQ, _z_noisy()), fixed={"R0": 12.3456}).to_latex()
    assert r"R0 & $12.3456$ (fixed) & $\Omega$ \\" in fixed.splitlines()
    # the walkthrough's R1 = 2.18e7 ± 2.8e15 Ω in place of the fit's own R1 (a frozen dataclass)
    loose = dataclasses.replace(fit_result, values={**fit_result.values, "R1": 2.18e7}, stderr={**fit_result.stderr, "R1": 2.8e15})
    assert r"R1 & $2.2 \times 10^{7} \pm 2.8 \times 10^{15}$ (undetermined) & $\Omega$ \\" in loose.to_latex().splitlines()
    assert "(undetermined)" not in fit_result.to_latex()


def test_fit_out_tex_writes_the_latex_table(spectrum_csv, tmp_path, fit_result):
    path = tmp_path / "fit.tex"
    assert main(["fit", str(spectrum_csv), "--model", "R0 + R1 || C1", "--out", str(path)]) == 0
    text = path.read_text(encoding="utf-8")
    assert text.startswith("% impedax fit: R0 + R1 || C1") and r"\end{tabular}" in text
    value, error, _ = round_to_error(fit_result.values["R1"], fit_result.stderr["R1"])
    assert f"R1 & ${value} \\pm {error}$ & $\\Omega$ \\\\" in text


@pytest.mark.slow  # (~10 s: a batch fit, compilation included)
def test_fit_out_tex_of_several_spectra_writes_a_row_each(tmp_path, capsys):
    # SYNTHETIC: two trials of the spectrum; refused until 2026-12-06 ("a LaTeX table holds the
    # fit of one spectrum"), now a row per trial (`BatchFitResult.to_latex`, tests/test_batch_latex.py)
    data = ix.make_spectrum(FREQ, np.stack([_z_noisy(1), _z_noisy(2)]), dims="trial")
    ix.io.save(data, tmp_path / "two.nc")
    code = main(["fit", str(tmp_path / "two.nc"), "--model", "R0 + R1 || C1", "--out", str(tmp_path / "fit.tex")])
    assert code == 0
    lines = (tmp_path / "fit.tex").read_text(encoding="utf-8").splitlines()
    assert lines[0].startswith("% impedax fit: R0 + R1 || C1, 2 spectra over trial (2)") and lines[-1] == r"\end{tabular}"
    assert lines[3] == r"trial & R0 [$\Omega$] & R1 [$\Omega$] & C1 [$\mathrm{F}$] & rms\_rel [\%] \\"
    assert [line.split(" & ")[0] for line in lines[5:7]] == ["0", "1"]


def test_the_drt_figure_names_its_file_as_the_other_commands_do(spectrum_csv, tmp_path, monkeypatch):
    """impedax drt --plot passed no source to its figure: its title named no file."""
    import impedax.plotting

    saved = []
    monkeypatch.setattr(impedax.plotting, "save_figure", lambda fig, path, **kw: saved.append(fig))
    assert main(["drt", str(spectrum_csv), "--plot", str(tmp_path / "drt.png")]) == 0
    assert len(saved) == 1 and saved[0]._suptitle is not None
    assert spectrum_csv.name in saved[0]._suptitle.get_text()


def test_dpi_above_the_cap_is_refused_before_any_work(spectrum_csv, tmp_path, capsys):
    """--dpi 3000 drew for 38 s in 3.9 GB (walkthrough 2026-12-05): above 1200 it is refused, exit 2, nothing written."""
    with pytest.raises(SystemExit) as exc:
        main(["fit", str(spectrum_csv), "--model", "R0", "--plot", str(tmp_path / "x.png"), "--dpi", "3000"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "--dpi: 3000 dots per inch is more than the 1200 print needs" in err and "vector format" in err
    assert not (tmp_path / "x.png").exists()
