"""What a tour of the command line found, each with the case that showed it:

- the Ivium reader claimed any text that mentions its keys (a CSV whose comment says
  ``Technique=EIS, Solarcell=no``, or a page such as docs/io.md whose table of formats names
  them): it now wants its key lines at line starts;
- errors named Python arguments (``fixed:``, ``init:``, ``max_rc``, ``c``) where the command
  line has options (``--fix``, ``--init``, ``--max-rc``, ``--c``); ``--fix CPE1.a`` suggested
  CPE1.Q, ``--param r1`` nothing; ``--points`` said "at least 1" and refused 1; ``simulate``
  named its defaults before an error;
- ``draw -o NAME`` without an extension was refused where every other figure is a PNG;
- ``compare`` fitted one circuit twice (the same text, or the same circuit under other names)
  and split the Akaike weight 0.5/0.5;
- the batch figure of identical spectra repeated its tick labels (100.000000), wrote an offset
  (1e-9+1.767766953e3) and laid its legend over the data; the compare figure had no legend in
  its Nyquist panel and ran to 29 kΩ for data that end at 17 kΩ;
- ``fit``, ``kk``, ``compare``, ``diagnose`` wrote figures silently: every command now says
  ``wrote FILE`` on stderr for each file.

Spectra are written here as CSV text from the closed form of R0 + R1 ∥ C1, or are the real
files of tests/fixtures/real."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

REAL = Path(__file__).resolve().parent / "fixtures" / "real"
PNG = b"\x89PNG\r\n\x1a\n"

F = np.geomspace(1.0, 1e5, 21)


def rc_csv(path: Path) -> Path:
    """100 Ω + 1 kΩ ∥ 1 µF at 21 frequencies, as canonical CSV text."""
    z = 100.0 + 1000.0 / (1 + 1j * 2 * np.pi * F * 1000.0 * 1e-6)
    lines = ["frequency_hz,z_real_ohm,z_imag_ohm"] + [f"{float(f)!r},{float(v.real)!r},{float(v.imag)!r}" for f, v in zip(F, z)]
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.fixture
def spectrum(tmp_path):
    return rc_csv(tmp_path / "rc.csv")


def run(argv, capsys):
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


# --- 1. the Ivium reader looks at the file's structure ------------------------------------------

def test_csv_that_mentions_ivium_keys_is_read_as_a_table(tmp_path):
    path = tmp_path / "c.csv"
    path.write_text("# Technique=EIS, Solarcell=no\nfrequency_hz,z_real_ohm,z_imag_ohm\n1,10,-5\n10,8,-3\n100,6,-1\n")
    ds = ix.load(path)
    assert ds.attrs["format"] == "delimited text"
    np.testing.assert_array_equal(ds["frequency"].values, [1.0, 10.0, 100.0])
    np.testing.assert_array_equal(ds["Z"].values, [10 - 5j, 8 - 3j, 6 - 1j])


def test_text_that_names_ivium_keys_gets_the_generic_message(tmp_path, capsys):
    path = tmp_path / "notes.md"
    path.write_text("# notes\n\nIviumSoft files carry `Solarcell=`, `Technique=` keys and `primary_data` tables.\n")
    code, _, err = run(["inspect", path], capsys)
    assert code == 2 and "not a recognised spectrum file" in err and "no 'primary_data' table" not in err


def test_ivium_key_lines_at_line_starts_are_still_ivium(tmp_path):
    path = tmp_path / "tiny.idf"
    path.write_bytes(b"Peaks=false\r\nSolarcell=false\r\nTechnique=Constant E\r\nprimary_data\r\n3\r\n2\r\n10 -5 1\r\n8 -3 10\r\n")
    ds = ix.load(path)
    assert ds.attrs["format"] == "IviumSoft idf/ids"
    np.testing.assert_array_equal(ds["frequency"].values, [1.0, 10.0])
    np.testing.assert_array_equal(ds["Z"].values, [10 - 5j, 8 - 3j])


# --- 2. errors in the command line's words ----------------------------------------------------------

@pytest.mark.parametrize(
    "argv, expected",
    [
        (["fit", "{data}", "--model", "R0 + R1 || CPE1", "--fix", "R2=5"], "impedax fit: error: --fix: unknown parameter 'R2' for model 'R0 + R1 || CPE1' (parameters: R0, R1, CPE1.Q, CPE1.alpha)"),
        (["fit", "{data}", "--model", "R0 + R1 || CPE1", "--init", "R0=-5"], "impedax fit: error: --init: R0=-5 is outside its bounds"),
        (["fit", "{data}", "--model", "R0 + R1 || CPE1", "--fix", "CPE1.a=0.9"], "; did you mean CPE1.alpha? (parameters:"),
        (["fit", "{data}", "--model", "R0 + R1 || CPE1", "--init", "cpe1.q=1e-6"], "; did you mean CPE1.Q? (parameters:"),
        (["kk", "{data}", "--max-rc", "500"], "impedax kk: error: --max-rc must be an integer from 1 to"),
        (["kk", "{data}", "--c", "1.5"], "impedax kk: error: --c must be between 0 and 1 (exclusive), got 1.5"),
        (["simulate", "R0 + R1 || C1", "--param", "r1=5"], "--param: unknown parameter 'r1' for model 'R0 + R1 || C1'; did you mean R1?"),
        (["simulate", "R0 + R1 || C1", "--points", "0"], "impedax simulate: error: --points must be at least 2"),
        (["simulate", "R0 + R1 || C1", "--points", "1"], "impedax simulate: error: --points must be at least 2"),
        (["force", "meyer", "--points", "1"], "impedax force: error: --points must be at least 2"),
        # one frequency given more than once: simulate had called the copies duplicates (its own name twice), force printed each
        (["simulate", "R0 + R1 || C1", "--fmin", "10", "--fmax", "10", "--points", "3"], "impedax simulate: error: --points must be 1 when --fmin equals --fmax (one frequency, 10 Hz), got 3"),
        (["force", "vezzoli", "--fmin", "440", "--fmax", "440", "--points", "2"], "impedax force: error: --points must be 1 when --fmin equals --fmax (one frequency, 440 Hz), got 2"),
    ],
    ids=["fix-unknown", "init-out-of-bounds", "fix-attribute-prefix", "init-case", "kk-max-rc", "kk-c", "param-case", "points-0", "points-1", "force-points-1",
         "simulate-one-frequency-3", "force-one-frequency-2"],
)
def test_errors_name_the_option(argv, expected, spectrum, capsys):
    code, out, err = run([a.format(data=spectrum) for a in argv], capsys)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1, err
    assert expected in lines[0], lines[0]
    assert "fixed:" not in err and "max_rc" not in err and "defaults used" not in err


def test_one_point_of_one_frequency_is_still_allowed(capsys):
    code, out, err = run(["simulate", "R1", "--param", "R1=5", "--points", "1", "--fmin", "10", "--fmax", "10"], capsys)
    assert code == 0 and out.strip().splitlines()[1:] == ["10,5,0"]
    # without --points a one-frequency range is that one point (the default 61 or 161 would repeat it)
    code, out, err = run(["simulate", "R1", "--param", "R1=5", "--fmin", "10", "--fmax", "10"], capsys)
    assert code == 0 and out.strip().splitlines()[1:] == ["10,5,0"]
    code, out, err = run(["force", "vezzoli", "--fmin", "440", "--fmax", "440"], capsys)
    assert code == 0 and len(out.strip().splitlines()) == 2 and out.strip().splitlines()[1].startswith("440,")


def test_sample_noise_choices_are_named_as_typed(spectrum, capsys):
    """An unknown --noise lists the choices as the user types them (it listed Python enum reprs,
    ``<NoiseModel.PROPORTIONAL: 'proportional'>``)."""
    with pytest.raises(SystemExit) as info:
        main(["sample", str(spectrum), "--model", "R0 + R1 || CPE1", "--noise", "laplace"])
    err = capsys.readouterr().err
    assert info.value.code == 2 and "(choose from 'proportional', 'sigma')" in err and "NoiseModel" not in err
    # (fit's weighting names get their own message since 2026-12-06, the noise models named in words)
    with pytest.raises(SystemExit) as info:
        main(["sample", str(spectrum), "--model", "R0 + R1 || CPE1", "--noise", "unit"])
    err = capsys.readouterr().err
    assert info.value.code == 2 and "sample's noise models are proportional" in err and "NoiseModel" not in err


def test_a_noise_level_given_to_sample_and_a_noise_model_given_to_diagnose_say_where_they_belong(spectrum, capsys):
    """sample's --noise is a noise model, diagnose's and refine's a level: each refuses the
    other's kind with where it belongs (exit 2), in the CLI and in Python."""
    import impedax as ix

    with pytest.raises(SystemExit) as info:
        main(["sample", str(spectrum), "--model", "R0 + R1 || CPE1", "--noise", "1%"])
    err = capsys.readouterr().err
    assert info.value.code == 2 and "'1%' is a noise level" in err and "diagnose and refine" in err
    for command in ("diagnose", "refine"):
        code, out, err = run([command, spectrum, "--model", "R0 + R1 || C1", "--noise", "proportional"], capsys)
        assert code == 2 and out == "" and "sample's noise models" in err
    data = ix.load(spectrum)
    with pytest.raises(ix.ParameterError, match="a number is a noise level"):
        ix.sample("R0 + R1 || C1", data, noise=0.01, steps=10, progress=False)
    with pytest.raises(ix.ParameterError, match="sample's noise models"):
        ix.diagnose(data, "R0 + R1 || C1", noise="sigma")
    # (the names the level's check knows are the sampler's)
    from impedax.arguments import SAMPLE_NOISE_MODELS
    from impedax.fitting import NOISE_MODELS

    assert SAMPLE_NOISE_MODELS == tuple(str(m) for m in NOISE_MODELS)


def test_simulate_names_its_defaults_once_it_succeeded(capsys):
    code, out, err = run(["simulate", "R0 + C1", "--param", "R0=5", "--points", "2", "--fmin", "1", "--fmax", "10"], capsys)
    assert code == 0 and err == "impedax simulate: defaults used for C1 = 1 µF\n"
    assert out.splitlines()[0] == "frequency_hz,z_real_ohm,z_imag_ohm"


# --- 3. draw: a name without an extension is a PNG -------------------------------------------------

def test_draw_without_an_extension_writes_a_png(tmp_path, capsys):
    pytest.importorskip("schemdraw")
    out = tmp_path / "draw3"
    code, stdout, err = run(["draw", "R0 + R1 || CPE1", "-o", out], capsys)
    assert code == 0, err
    assert out.read_bytes().startswith(PNG) and err == f"wrote {out}\n" and stdout == ""
    assert [p.name for p in tmp_path.iterdir()] == ["draw3"]


# --- 4. compare refuses one circuit given twice ------------------------------------------------------

@pytest.mark.parametrize(
    "first, second, expected",
    [
        ("R0 + R1 || CPE1", "R0 + R1 || CPE1", "--model 'R0 + R1 || CPE1' is given twice; compare needs different circuits"),
        ("R0 + R1 || CPE1", "R0+R1||CPE1", "--model 'R0 + R1 || CPE1' is given twice (again as 'R0+R1||CPE1')"),
        ("R_s + R_ct || CPE_dl", "R0 + R1 || CPE1", "--model 'R_s + R_ct || CPE_dl' and --model 'R0 + R1 || CPE1' are the same circuit"),
        ("R_s + R_ct || Q_dl", "CPE1 || R1 + R0", "--model 'R_s + R_ct || Q_dl' and --model 'CPE1 || R1 + R0' are the same circuit"),
    ],
    ids=["same-text", "same-canonical-text", "other-names", "other-names-order-and-alias"],
)
def test_compare_refuses_one_circuit_twice_before_fitting(first, second, expected, spectrum, capsys, monkeypatch):
    def no_fit(*args, **kwargs):
        raise AssertionError("compare fitted a model before refusing")

    monkeypatch.setattr(ix, "fit", no_fit)
    code, out, err = run(["compare", spectrum, "--model", first, "--model", second], capsys)
    assert code == 2 and err.startswith("impedax compare: error: ") and expected in err, err
    assert len(err.strip().splitlines()) == 1 and out == ""


def test_compare_of_different_circuits_goes_on_to_fit(spectrum, capsys, monkeypatch):
    def reached(*args, **kwargs):
        raise ix.ParameterError("fit reached")

    monkeypatch.setattr(ix, "fit", reached)
    code, _, err = run(["compare", spectrum, "--model", "R0 + R1 || C1", "--model", "R0 + R1 || CPE1"], capsys)
    assert code == 2 and "fit reached" in err


# --- 7. every command says which files it wrote, on stderr --------------------------------------

@pytest.mark.parametrize(
    "argv, written",
    [
        (["fit", "{data}", "--model", "R0 + R1 || C1", "--plot", "{tmp}/fit", "--out", "{tmp}/fit.json"], ["fit", "fit.json"]),
        (["fit", "{data}", "--model", "R0 + R1 || C1", "--json", "--plot", "{tmp}/fit.png"], ["fit.png"]),
        (["kk", "{data}", "--plot", "{tmp}/kk.png"], ["kk.png"]),
        (["compare", "{data}", "--model", "R0 + R1 || C1", "--model", "R0 + R1 || CPE1", "--plot", "{tmp}/compare.png"], ["compare.png"]),
        (["diagnose", "{data}", "--model", "R0 + R1 || C1", "--effects", "series_resistance", "--plot", "{tmp}/diagnose.png"], ["diagnose.png"]),
        (["simulate", "R1", "--param", "R1=5", "--points", "3", "--out", "{tmp}/sim.csv"], ["sim.csv"]),
        (["inspect", "{data}", "--json", "--plot", "{tmp}/look.png", "--out", "{tmp}/look.nc"], ["look.nc", "look.png"]),
    ],
    ids=["fit", "fit-json", "kk", "compare", "diagnose", "simulate", "inspect-json"],
)
def test_every_written_file_is_announced_on_stderr(argv, written, spectrum, tmp_path, capsys):
    argv = [a.format(data=spectrum, tmp=tmp_path) for a in argv]
    code, out, err = run(argv, capsys)
    assert code == 0, err
    announced = [line[len("wrote "):] for line in err.splitlines() if line.startswith("wrote ")]
    assert sorted(announced) == sorted(str(tmp_path / name) for name in written), err
    assert all((tmp_path / name).stat().st_size > 0 for name in written)
    assert "wrote" not in out
    if "--json" in argv:
        json.loads(out)  # stdout holds the JSON alone


def test_output_to_stdout_is_not_announced(spectrum, capsys):
    code, out, err = run(["fit", spectrum, "--model", "R0 + R1 || C1", "--out", "-"], capsys)
    assert code == 0 and json.loads(out)["model"] == "R0 + R1 || C1"
    assert "wrote" not in err


# --- 5. and 6. figures --------------------------------------------------------------------------

@pytest.mark.parametrize(
    "ticks, labels",
    [
        ([1750.0, 1760.0, 1770.0, 1780.0], ["1750", "1760", "1770", "1780"]),
        ([99.0, 99.5, 100.0, 100.5, 101.0], ["99.0", "99.5", "100.0", "100.5", "101.0"]),
        ([1.0e-13, 1.1e-13, 1.2e-13], ["1e\N{MINUS SIGN}13", "1.1e\N{MINUS SIGN}13", "1.2e\N{MINUS SIGN}13"]),
        ([0.0, 2e6, 4e6], ["0", "2e+06", "4e+06"]),
    ],
)
def test_plain_ticks_tell_the_ticks_apart_without_an_offset(ticks, labels):
    from impedax.plotting import PlainTicks

    formatter = PlainTicks()
    formatter.set_locs(ticks)
    assert [formatter(t) for t in ticks] == labels


def _drawn(fig):
    fig.canvas.draw()
    return fig


def test_batch_figure_of_identical_spectra_reads_plainly():
    """data.ods holds four sheets of one spectrum: every parameter is the same to ~1e-12."""
    import matplotlib.pyplot as plt

    data = ix.load(REAL / "data.ods")
    batch = ix.fit("R0 + R1 || C1 + R2 || W1", data)
    fig = _drawn(batch.plot())
    try:
        panels = {ax.get_title(): ax for ax in fig.axes}
        r0 = next(ax for title, ax in panels.items() if title.startswith("R0 ["))
        value = float(batch.dataset["value"].sel(param="R0").median())
        low, high = r0.get_ylim()
        assert low == pytest.approx(value * 0.99) and high == pytest.approx(value * 1.01)
        for title, ax in panels.items():
            if title.startswith(("R0 [", "R1 [", "C1 [", "R2 [", "W1.sigma", "rms_rel")):
                texts = [t.get_text() for t in ax.get_yticklabels() if t.get_text()]
                assert len(texts) == len(set(texts)) >= 2, (title, texts)
                assert ax.yaxis.get_offset_text().get_text() == "", (title, ax.yaxis.get_offset_text().get_text())
        nyquist = next(ax for title, ax in panels.items() if title.startswith("data (○) and fits"))
        legend = nyquist.get_legend().get_window_extent()
        frame = nyquist.get_window_extent()
        assert legend.x0 >= frame.x1  # beside the panel, over none of its data
    finally:
        plt.close(fig)


@pytest.mark.slow  # (an end-to-end run of ~10 s: make test-all; the fast suite's 15-minute budget)
def test_compare_figure_has_a_nyquist_legend_and_follows_the_data():
    import matplotlib.pyplot as plt

    data = ix.load(REAL / "exampleDataGamry.DTA")
    models = ["R0 + R1 || CPE1 + CPE2", "R0 + R1 || CPE1 + R2 || CPE2"]
    fig = _drawn(ix.compare([ix.fit(m, data) for m in models]).plot())
    try:
        nyquist = next(ax for ax in fig.axes if ax.get_title() == "Nyquist")
        texts = [t.get_text() for t in nyquist.get_legend().get_texts()]
        assert texts[0] == "data" and [t.split(" (rms_rel")[0] for t in texts[1:]] == models
        z = data["Z"].values
        span = np.ptp(z.real)
        left, right = nyquist.get_xlim()
        assert z.real.max() <= right <= z.real.max() + 0.2 * span  # was 29 kΩ for data ending at 17 kΩ
        assert z.real.min() - 0.2 * span <= left <= z.real.min()
    finally:
        plt.close(fig)
