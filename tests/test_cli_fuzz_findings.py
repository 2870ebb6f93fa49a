"""Bad input the command-line matrix (tests/cli_fuzz_matrix.py) found ending in a traceback:
each case exits 2 with one message naming the file or the option, and an existing --out file
keeps its bytes.

The matrix's first run (2026-12-07, 2994 command lines) found: `impedax diagnose` and `refine`
on a spectrum whose Z is exactly zero at some frequency (ZeroDivisionError, or ValueError with
--weighting unit); `--dpi` below what FreeType draws text at (RuntimeError from matplotlib's
savefig, or "cannot write empty image"); `impedax fit --shared` naming every free parameter
(JAX's ValueError "Need at least one array to stack")."""

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

EXISTING = b"an existing output file: a failing run must leave these bytes\n"
RC = "R0 + R1 || C1"


def _csv(path, f, z):
    path.write_text("frequency_hz,z_real_ohm,z_imag_ohm\n" + "".join(f"{x:.8g},{v.real:.8g},{v.imag:.8g}\n" for x, v in zip(f, z)))
    return str(path)


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """SYNTHETIC spectra (numpy formula of R0 + R1 || C1, 21 points from 1 Hz to 100 kHz): good,
    all Z zero, one Z zero (at 17.8 Hz), and a series of two along ``day``."""
    folder = tmp_path_factory.mktemp("fuzz")
    f = np.geomspace(1, 1e5, 21)
    z = 10 + 100 / (1 + 2j * np.pi * f * 1e-4)
    one_zero = z.copy()
    one_zero[5] = 0
    ix.save(ix.make_spectrum(f, np.stack([z, 1.01 * z]), dims=("day",), coords={"day": [1, 2]}), folder / "series.nc")
    return {
        "good": _csv(folder / "good.csv", f, z),
        "zero": _csv(folder / "zero.csv", f, np.zeros_like(z)),
        "one-zero": _csv(folder / "one_zero.csv", f, one_zero),
        "series": str(folder / "series.nc"),
    }


def _refused(argv, out, capsys):
    """Run ``impedax *argv`` with an existing ``out`` file named by --out: exit 2, one error line,
    no traceback, ``out`` unchanged; returns the message."""
    out.write_bytes(EXISTING)
    try:
        code = main([*argv, "--out", str(out)])
    except SystemExit as exc:  # (argparse's own refusals)
        code = exc.code
    _, err = capsys.readouterr()
    assert code == 2, err
    assert "Traceback" not in err
    assert len([line for line in err.splitlines() if ": error: " in line]) == 1, err
    assert out.read_bytes() == EXISTING
    return err


@pytest.mark.parametrize("command", ["diagnose", "refine"])
@pytest.mark.parametrize("name, weighting, where", [
    ("zero", "modulus", "Z is exactly zero at 1 Hz, 1.78 Hz, 3.16 Hz and 18 more"),
    ("zero", "unit", "Z is exactly zero at 1 Hz, 1.78 Hz, 3.16 Hz and 18 more"),
    ("one-zero", "modulus", "Z is exactly zero at 17.8 Hz;"),
    ("one-zero", "unit", "Z is exactly zero at 17.8 Hz;"),
])
def test_diagnosis_of_zero_impedance_is_refused(files, tmp_path, capsys, command, name, weighting, where):
    err = _refused([command, files[name], "--model", RC, "--weighting", weighting], tmp_path / "d.json", capsys)
    assert where in err and files[name] in err and "needs |Z| > 0" in err


def test_diagnosis_of_a_fit_to_zero_impedance_is_refused_in_python(files):
    fitted = ix.fit(RC, files["one-zero"], weighting="unit")  # (fit takes the point: unit weights need no |Z|)
    with pytest.raises(ix.DataError, match=r"Z is exactly zero at 17.8 Hz; a diagnosis judges"):
        ix.diagnose(fitted)


@pytest.mark.parametrize("dpi", ["1", "5", "1e-300", "19.9"])
@pytest.mark.parametrize("argv", [
    lambda p, fig: ["fit", p["good"], "--model", RC, "--plot", fig],
    lambda p, fig: ["kk", p["good"], "--plot", fig],
    lambda p, fig: ["inspect", p["good"], "--plot", fig],
], ids=["fit", "kk", "inspect"])
def test_dpi_too_small_to_draw_text_is_refused(files, tmp_path, capsys, argv, dpi):
    figure = tmp_path / "figure.png"
    err = _refused([*argv(files, str(figure)), "--dpi", dpi], tmp_path / "out.json" if argv(files, "")[0] != "inspect" else tmp_path / "out.csv", capsys)
    assert "--dpi" in err and "at least 20" in err
    assert not figure.exists()


@pytest.mark.parametrize("dpi", ["20", "40"])
def test_dpi_at_the_least_draws(files, tmp_path, capsys, dpi):
    figure = tmp_path / "figure.png"
    assert main(["kk", files["good"], "--plot", str(figure), "--dpi", dpi]) == 0
    assert figure.read_bytes().startswith(b"\x89PNG")


@pytest.mark.parametrize("shared, fixed", [("R0,R1,C1", []), ("R1,C1", ["--fix", "R0=10"])])
def test_sharing_every_free_parameter_fits_one_set_of_values(files, tmp_path, capsys, shared, fixed):
    out = tmp_path / "fit.json"
    assert main(["fit", files["series"], "--model", RC, "--shared", shared, "--over", "day", *fixed, "--out", str(out)]) == 0
    assert "Traceback" not in capsys.readouterr().err and out.stat().st_size > 0


def test_sharing_every_free_parameter_in_python_lies_between_the_spectra(files):
    """The series holds Z and 1.01·Z of R0 = 10 Ω, R1 = 100 Ω: under relative (modulus) weights the
    best single circuit is c·Z with 1 ≤ c ≤ 1.01, so R0 lies in [10, 10.1] and R1 in [100, 101]."""
    r = ix.fit(RC, ix.load(files["series"]), shared=["R0", "R1", "C1"], over="day")
    assert 10 * (1 - 1e-6) <= float(r.values("R0")) <= 10.1 * (1 + 1e-6)
    assert 100 * (1 - 1e-6) <= float(r.values("R1")) <= 101 * (1 + 1e-6)


@pytest.mark.parametrize("title", [r"$\undefinedcmd$", r"$\frac{1}$", "a $x^$ b"])
def test_a_title_that_is_no_math_text_is_refused(files, tmp_path, capsys, title):
    figure = tmp_path / "figure.png"
    err = _refused(["kk", files["good"], "--plot", str(figure), "--title", title], tmp_path / "kk.json", capsys)
    assert "argument --title" in err and "math text" in err and "\\$" in err
    assert not figure.exists()


@pytest.mark.parametrize("title", [r"Z at $\omega = 2\pi f$", r"costs \$5", "$x", "a $ b", ""])
def test_titles_that_draw_are_drawn(files, tmp_path, title):
    figure = tmp_path / "figure.png"
    assert main(["kk", files["good"], "--plot", str(figure), "--title", title]) == 0
    assert figure.read_bytes().startswith(b"\x89PNG")


@pytest.mark.parametrize("name", [r"x$\bad$.csv", "price $5 and $6.csv"])
def test_a_file_name_with_dollar_signs_is_the_title_as_written(files, tmp_path, monkeypatch, name):
    """The data file's name in a figure's title is text, not matplotlib math: a name with a
    backslash between dollar signs ended in a ParseFatalException, and one with two dollar signs
    drew the words between them in italics, without the signs."""
    import impedax.plotting

    titles = []
    save = impedax.plotting.save_figure
    monkeypatch.setattr(impedax.plotting, "save_figure", lambda fig, path, **kw: (titles.append(fig._suptitle._preprocess_math(fig._suptitle.get_text())), save(fig, path, **kw)))
    data = tmp_path / name
    data.write_bytes(open(files["good"], "rb").read())
    figure = tmp_path / "figure.png"
    assert main(["kk", str(data), "--plot", str(figure)]) == 0
    shown, is_math = titles[0]
    assert not is_math and name in shown
    assert figure.read_bytes().startswith(b"\x89PNG")


HUGE = 10**400  # a Python int beyond every float
API_HUGE_INT = [  # (id, call, message fragment naming the argument)
    ("fit-fmin", lambda ds: ix.fit(RC, ds, fmin=HUGE), "fmin must be finite"),
    ("kk-c", lambda ds: ix.kk_test(ds, c=HUGE), "c must be between 0 and 1"),
    ("drt-lam", lambda ds: ix.drt(ds, lam=HUGE), "lam must be a positive finite number"),
    ("diagnose-noise", lambda ds: ix.diagnose(ds, RC, noise=HUGE), "noise must be finite"),
    ("log-frequencies", lambda ds: ix.log_frequencies(HUGE, 1e3, 5), "must be finite"),
]


@pytest.mark.parametrize("call, fragment", [c[1:] for c in API_HUGE_INT], ids=[c[0] for c in API_HUGE_INT])
def test_an_integer_beyond_floating_point_is_a_parameter_error(files, call, fragment):
    """The Python matrix (wrong types in every argument of the public functions) found 10**400
    ending in OverflowError "int too large to convert to float"."""
    with pytest.raises(ix.ParameterError, match=fragment) as caught:
        call(ix.load(files["good"]))
    assert len(str(caught.value)) < 300


API_WRONG_TYPES = [  # (id, call, error type, message fragment naming the argument)
    ("validate-spectrum-list", lambda: ix.validate_spectrum([1.0, 2.0]), ix.DataError, "expected an xarray.Dataset, got list"),
    ("validate-spectrum-none", lambda: ix.validate_spectrum(None), ix.DataError, "expected an xarray.Dataset, got NoneType"),
    ("draw-circuit-list", lambda: ix.draw_circuit([1.0, 2.0]), ix.ParameterError, "circuit must be circuit text or a Circuit, got"),
    ("draw-circuit-none", lambda: ix.draw_circuit(None), ix.ParameterError, "circuit must be circuit text or a Circuit, got None"),
    ("stack-files-numbers", lambda: ix.stack_files([1.0, 2.0]), ix.ParameterError, "paths: item 1 of 2 is not a file name"),
    ("stack-files-arrays", lambda: ix.stack_files([np.ones(3), np.ones(3)]), ix.ParameterError, "paths: item 1 of 2 is not a file name"),
]


@pytest.mark.parametrize("call, error, fragment", [c[1:] for c in API_WRONG_TYPES], ids=[c[0] for c in API_WRONG_TYPES])
def test_wrong_types_in_python_are_impedax_errors(call, error, fragment):
    """The Python matrix found these ending in AttributeError ('list' object has no attribute
    'attrs' / 'parameter_names') and TypeError (expected str, bytes or os.PathLike object)."""
    with pytest.raises(error, match=fragment.replace("(", r"\(")) as caught:
        call()
    assert len(str(caught.value)) < 300


@pytest.mark.parametrize("call", [
    lambda ds: ix.drt(ds, lam=list(np.arange(40) + 1j)),
    lambda ds: ix.fit(RC, ds, shared=list(np.arange(40) + 1j)),
], ids=["drt-lam", "fit-shared"])
def test_a_long_wrong_value_is_shortened_in_the_message(files, call):
    """A list of 40 complex numbers was quoted whole (about 1,200 characters)."""
    with pytest.raises(ix.ParameterError) as caught:
        call(ix.load(files["good"]))
    assert len(str(caught.value)) < 300


@pytest.fixture(scope="module")
def dollar_labels(tmp_path_factory):
    """SYNTHETIC two spectra (numpy formula of R0 + R1 ‖ CPE1) along ``sheet``, labelled ``$\\bad$``
    (no math text) and ``price $5 and $6`` (math text that would italicise "5 and ")."""
    import xarray as xr

    f = np.geomspace(1e5, 1.0, 25)
    s = 2j * np.pi * f
    z = np.array([10 + 100 / (1 + 100 * 1e-5 * s**a) for a in (0.9, 0.8)])
    path = tmp_path_factory.mktemp("dollars") / "sheets.nc"
    ix.save(xr.Dataset({"Z": (("sheet", "frequency"), z)}, coords={"sheet": [r"$\bad$", "price $5 and $6"], "frequency": f}), path)
    return str(path)


@pytest.mark.parametrize("argv", [["fit", "--model", "R0 + R1 || CPE1", "--residual-map", "map.png"], ["compare", "--model", "R0 + R1 || CPE1", "--model", RC], ["kk"], ["drt"]], ids=["fit", "compare", "kk", "drt"])
def test_spectrum_labels_with_dollar_signs_are_drawn_as_written(dollar_labels, tmp_path, monkeypatch, argv):
    """A batch figure draws each spectrum's label (a sheet's name, a `stack --coords` label) as
    text: `$\\bad$` ended fit, compare, kk and drt --plot in matplotlib's ParseFatalException. Every
    text of the saved figure that holds a label is drawn without math (matplotlib's own parse)."""
    import matplotlib.text
    import impedax.plotting

    drawn = []
    save = impedax.plotting.save_figure

    def saving(fig, path, **kw):
        fig.canvas.draw()
        drawn.extend(t._preprocess_math(t.get_text()) for t in fig.findobj(matplotlib.text.Text) if "bad" in t.get_text() or "price" in t.get_text())
        return save(fig, path, **kw)

    monkeypatch.setattr(impedax.plotting, "save_figure", saving)
    monkeypatch.chdir(tmp_path)
    command, *rest = argv
    assert main([command, dollar_labels, *rest, "--plot", "figure.png", "-q"]) == 0
    assert (tmp_path / "figure.png").read_bytes().startswith(b"\x89PNG")
    assert drawn and all(not is_math for _, is_math in drawn), drawn
    assert any(r"$\bad$" in text for text, _ in drawn) and any("price $5 and $6" in text for text, _ in drawn), drawn


# --- a newcomer's walkthrough and the matrix's "accepted" list (2026-12-07) ---------------------

REAL_CSV = __import__("pathlib").Path(__file__).parent / "fixtures" / "real" / "exampleData.csv"


@pytest.fixture
def two_real(tmp_path):
    """REAL: impedance.py's exampleData.csv (tests/fixtures/real, MIT) as a.csv, and as b.csv with
    Z × 1.01, one grid: a stack of the two (two identical copies are refused as one file copied,
    `stack_files`)."""
    rows = [line.split(",") for line in REAL_CSV.read_text().splitlines() if line.strip()]
    (tmp_path / "a.csv").write_bytes(REAL_CSV.read_bytes())
    (tmp_path / "b.csv").write_text("".join(f"{f},{float(re) * 1.01!r},{float(im) * 1.01!r}\n" for f, re, im in rows))
    return [str(tmp_path / "a.csv"), str(tmp_path / "b.csv")]


@pytest.mark.parametrize("coords, where", [
    (["nan", "1"], "label 1 of 2, 'nan'"),
    (["1", "NaN"], "label 2 of 2, 'NaN'"),
    (["inf", "1"], "label 1 of 2, 'inf'"),
    (["", "b"], "label 1 of 2 is empty"),
    (["a", "  "], "label 2 of 2 is empty"),
    (["a", " b"], "label 2 of 2, ' b'"),
])
def test_stack_refuses_a_label_select_cannot_name(two_real, tmp_path, capsys, coords, where):
    err = _refused(["stack", *two_real, "--coords", *coords], tmp_path / "s.nc", capsys)
    assert "--coords" in err and where in err, err


def test_stack_refuses_a_repeated_label(two_real, tmp_path, capsys):
    err = _refused(["stack", *two_real, "--coords", "1", "1.0"], tmp_path / "s.nc", capsys)
    assert "--coords: the label 1 is given twice (files 1 and 2)" in err


def test_stack_labels_in_python_refuse_nan(two_real):
    with pytest.raises(ix.ParameterError, match=r"coords: label 1 of 2, 'nan', is not a finite number"):
        ix.stack_files(two_real, coords=[float("nan"), 1.0])
@pytest.mark.parametrize("dim, named", [("a b", "' '"), ("a=b", "'='"), ("a,b", "','"), (" day", "' '"), ("a/b", "'/'"), ("-x", "'-' cannot lead")])
def test_stack_refuses_a_dimension_select_cannot_name(two_real, tmp_path, capsys, dim, named):
    err = _refused(["stack", *two_real, f"--dim={dim}"], tmp_path / "s.nc", capsys)
    assert f"--dim: {dim!r} cannot name a dimension" in err and named in err, err


@pytest.mark.parametrize("dim", ["frequency", "Z", "sigma"])
def test_stack_refuses_a_dimension_named_as_a_variable_of_the_spectrum(two_real, tmp_path, capsys, dim):
    err = _refused(["stack", *two_real, "--dim", dim], tmp_path / "s.nc", capsys)
    assert f"'{dim}'" in err and "--dim" in err, err


@pytest.mark.parametrize("dim, coords", [("day", ["1", "2"]), ("temperature", ["a,b", "x=y"]), ("cell_2.v-1", ["0.5", "1.5"])])
def test_stack_names_that_select_reads_are_kept(two_real, tmp_path, capsys, dim, coords):
    out = tmp_path / "s.nc"
    assert main(["stack", *two_real, "--dim", dim, "--coords", *coords, "--out", str(out), "-q"]) == 0
    capsys.readouterr()
    assert main(["inspect", str(out), "--select", f"{dim}={coords[1]}", "--json"]) == 0
    assert "Traceback" not in capsys.readouterr().err


@pytest.mark.parametrize("option", [["--dpi", "200"], ["--title", "day 3"], ["--title", ""]], ids=["dpi", "title", "empty-title"])
@pytest.mark.parametrize("argv", [
    lambda out: ["inspect", str(REAL_CSV), "--out", out],
    lambda out: ["kk", str(REAL_CSV), "--out", out, "-q"],
    lambda out: ["simulate", "--model", RC, "--param", "R0=10", "R1=100", "C1=1u", "--out", out],
], ids=["inspect", "kk", "simulate"])
def test_a_figure_option_without_a_figure_is_noted(tmp_path, capsys, argv, option):
    """REAL (impedance.py's exampleData.csv) for inspect and kk. --dpi and --title without --plot
    change nothing: one note on stderr, the exit code and the outputs as without them."""
    plain, noted = tmp_path / "plain.csv", tmp_path / "noted.csv"
    assert main(argv(str(plain))) == 0
    capsys.readouterr()
    assert main([*argv(str(noted)), *option]) == 0
    out, err = capsys.readouterr()
    command = argv("")[0]
    assert [line for line in err.splitlines() if "no effect" in line] == [f"impedax {command}: note: {option[0]} has no effect without --plot"], err
    assert list(tmp_path.glob("*.png")) == []


def test_figure_options_with_a_figure_are_not_noted(tmp_path, capsys):
    figure = tmp_path / "preview.png"
    assert main(["inspect", str(REAL_CSV), "--plot", str(figure), "--dpi", "50", "--title", "REAL"]) == 0
    assert "no effect" not in capsys.readouterr().err
    assert figure.read_bytes().startswith(b"\x89PNG")


def test_sample_notes_each_of_its_figures():
    """sample draws three figures (--plot, --corner, --trace): the note names them all, in the order of --help; fit's
    --residual-map is a figure too, so --dpi with it alone is not noted."""
    from impedax.cli import _subparser, build_parser
    from impedax.cli.common import unused_figure_options

    sample = _subparser(build_parser("sample"), "sample")
    args = sample.parse_args(["d.csv", "--model", RC, "--dpi", "300"])
    assert unused_figure_options(sample, args) == ["--dpi has no effect without --corner, --trace or --plot"]
    assert unused_figure_options(sample, sample.parse_args(["d.csv", "--model", RC, "--dpi", "300", "--trace", "t.png"])) == []
    fit = _subparser(build_parser("fit"), "fit")
    assert unused_figure_options(fit, fit.parse_args(["d.csv", "--model", RC, "--dpi", "300", "--residual-map", "m.png"])) == []
    assert unused_figure_options(fit, fit.parse_args(["d.csv", "--model", RC, "--title", "x"])) == ["--title has no effect without --plot or --residual-map"]


@pytest.mark.parametrize("argv", [
    ["kk", str(REAL_CSV), "-q"],
    ["drt", str(REAL_CSV), "-q"],
    ["fit", str(REAL_CSV), "--model", RC],
    ["diagnose", str(REAL_CSV), "--model", RC],
    ["stack", str(REAL_CSV), str(REAL_CSV.with_name("exampleDataAutolab.txt"))],
    ["force", "meyer"],
    ["draw", RC],
], ids=["kk", "drt", "fit", "diagnose", "stack", "force", "draw"])
def test_out_txt_of_a_result_is_refused_before_any_work(tmp_path, capsys, argv):
    """REAL input (impedance.py's example files). A result, DRT, stack, force table or diagram has
    no .txt form: refused naming the extensions it has, before any file is read or fit is run."""
    err = _refused(argv, tmp_path / "out.txt", capsys)
    assert "--out" in err and ("'.txt'" in err or "written as netCDF" in err)
    assert ".csv" in err or ".nc" in err or ".png" in err


@pytest.mark.parametrize("name, written_as", [("out.txt", "CSV"), ("out", "CSV"), ("out.tsv", "tab-separated"), ("out.csv", None), ("out.nc", None)])
def test_a_spectrum_written_under_another_extension_says_its_format(tmp_path, capsys, name, written_as):
    """REAL (impedance.py's exampleData.csv). A spectrum's --out takes .txt, .tsv and no
    extension (docs/io.md, "Writing spectra"); the "wrote" line says what such a file holds."""
    out = tmp_path / name
    assert main(["inspect", str(REAL_CSV), "--out", str(out)]) == 0
    err = capsys.readouterr().err
    if written_as is None:
        assert f"wrote {out}\n" in err
        return
    separator = "\t" if written_as == "tab-separated" else ","
    assert out.read_text().startswith(separator.join(["frequency_hz", "z_real_ohm", "z_imag_ohm"]) + separator)
    assert f"wrote {out} (the spectrum as {written_as} text, as impedax load reads it)\n" in err, err


@pytest.fixture
def progress_at_once(monkeypatch):
    """Progress lines printed from the first (not after `PROGRESS_AFTER_S`)."""
    import impedax.cli.common as common

    monkeypatch.setattr(common, "PROGRESS_AFTER_S", 0.0)


@pytest.mark.parametrize("command", ["diagnose", "refine"])
@pytest.mark.parametrize("quiet", [False, True])
def test_diagnose_says_what_it_begins_before_the_fitting_code(capsys, monkeypatch, progress_at_once, command, quiet):
    """REAL (impedance.py's exampleData.csv). `impedax diagnose` was silent for 17–21 s on a
    loaded machine while it imported the fitting code (JAX) and compiled and ran its baseline fit:
    its first line is on stderr by the time the analysis is called (a stand-in here, which
    stops the run), in the style of the others ([  t s] text); --quiet drops it."""
    import impedax.fitting

    seen = []

    def stand_in(*args, **kwargs):
        seen.append(capsys.readouterr())
        raise ix.ParameterError("stopped by the test")

    monkeypatch.setattr(impedax.fitting, command, stand_in)
    assert main([command, str(REAL_CSV), "--model", RC, "--json", *(["--quiet"] if quiet else [])]) == 2
    (before,) = seen
    first = f"{'diagnosing' if command == 'diagnose' else 'refining'} {RC} on {REAL_CSV}: loading the fitting code, then the baseline fit (a circuit's first fit compiles its solvers)"
    assert before.out == ""
    assert before.err.splitlines() == ([] if quiet else [f"[  0.0 s] {first}"])


def test_diagnose_json_stays_on_stdout_beneath_its_first_line(capsys, progress_at_once):
    """REAL (impedance.py's exampleData.csv), the whole run: the first line, then the baseline's,
    on stderr; stdout holds the JSON alone."""
    import json
    import re

    assert main(["diagnose", str(REAL_CSV), "--model", RC, "--effects", "series_inductance", "--json"]) == 0
    out, err = capsys.readouterr()
    assert json.loads(out)["verdict"]
    lines = err.splitlines()
    assert re.fullmatch(r"\[  0\.\d s\] diagnosing " + re.escape(f"{RC} on {REAL_CSV}: loading the fitting code, then the baseline fit ") + r"\(.*\)", lines[0]), lines[:2]
    assert lines[1].endswith(f"] fitting the baseline {RC}"), lines[:2]
