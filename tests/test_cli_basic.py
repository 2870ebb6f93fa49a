"""`impedax simulate` and `impedax info`: outputs, JSON, and bad input → exit 2."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

import impedax as ix
from impedax.cli import GC_THRESHOLDS, main


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "impedax", *args], capture_output=True, text=True, timeout=300)


def test_simulate_to_stdout_matches_formula(capsys):
    code = main(["simulate", "R0 + R1 || C1", "--param", "R0=10", "--param", "R1=1000", "--param", "C1=1e-6", "--fmin", "1", "--fmax", "1e5", "--points", "11"])
    assert code == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert lines[0] == "frequency_hz,z_real_ohm,z_imag_ohm" and len(lines) == 12
    rows = np.array([[float(v) for v in ln.split(",")] for ln in lines[1:]])
    f = rows[:, 0]
    assert f[0] == 1.0 and f[-1] == pytest.approx(1e5, rel=1e-15)
    z = 10 + 1000 / (1 + 1j * 2 * np.pi * f * 1e-3)
    np.testing.assert_allclose(rows[:, 1] + 1j * rows[:, 2], z, rtol=1e-14)


def test_simulate_to_file_and_plot(tmp_path):
    out, png = tmp_path / "s.csv", tmp_path / "s.png"
    assert main(["simulate", "R_EP || C_EP || C_gap", "--out", str(out), "--plot", str(png)]) == 0
    ds = ix.load(out)
    assert ds.sizes["frequency"] == 61 and png.stat().st_size > 1000


def test_simulate_at_the_frequencies_of_a_real_file(tmp_path, capsys):
    """--frequencies FILE: the model at the REAL Gamry file's own frequencies, in its order
    (200015.6 Hz down to 0.0158898 Hz), each as the file writes it, read back with numpy; Z by
    the closed form R0 + R1/(1 + jωR1C1). Walkthrough 2026-12-06: a model could be simulated
    on a log grid only, never on a measurement's frequencies."""
    from pathlib import Path

    gamry = Path(__file__).parent / "fixtures" / "real" / "exampleDataGamry.DTA"
    lines = gamry.read_text(encoding="latin-1").splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("ZCURVE")) + 3  # (the table, its column and units rows, then the points)
    measured = np.array([float(line.split("\t")[3]) for line in lines[start:] if line.strip()])  # the Freq column
    out = tmp_path / "sim.csv"
    code = main(["simulate", "R0 + R1 || C1", "--param", "R0=10", "R1=1000", "C1=1e-6", "--frequencies", str(gamry), "--out", str(out), "-q"])
    assert code == 0
    rows = np.loadtxt(out, delimiter=",", skiprows=1, usecols=(0, 1, 2))
    assert measured.size == 72 and rows[:, 0].tolist() == measured.tolist()
    z = 10 + 1000 / (1 + 2j * np.pi * measured * 1000 * 1e-6)
    np.testing.assert_allclose(rows[:, 1] + 1j * rows[:, 2], z, rtol=1e-13)
    capsys.readouterr()
    assert main(["simulate", "R1", "--frequencies", str(gamry), "--points", "5"]) == 2
    assert "--points: give either --frequencies FILE (its frequencies) or --fmin/--fmax/--points (a log-spaced band), not both" in capsys.readouterr().err


LONG_CIRCUIT = "R0 + L1 + R1 || (C1 + R2 || CPE2) + R3 || (W3 + C3) || (R4 + Wo4) + Ws5 || CC5 + HN6 + G7"  # (89 characters)


def _saved_simulate_figure(tmp_path, monkeypatch, *options, model=LONG_CIRCUIT):
    """The figure `impedax simulate MODEL --plot` saves with ``options``, drawn (Agg)."""
    import matplotlib.figure
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    saved = []
    original = matplotlib.figure.Figure.savefig

    def keep(self, *args, **kwargs):
        saved.append(self)
        return original(self, *args, **kwargs)

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", keep)
    assert main(["simulate", model, "--plot", str(tmp_path / "s.png"), "--out", str(tmp_path / "s.csv"), "-q", *options]) == 0
    (figure,) = saved
    renderer = FigureCanvasAgg(figure).get_renderer()
    figure.draw(renderer)
    return figure, renderer


@pytest.mark.parametrize("model", ["R0 + R1 || C1", "R0 + R1 || C1 + R2 || C2 + R_ab || CPE_3", "R0 + L1 + R1 || (C1 + R2 || CPE2) + R3 || (W3 + C3) || (R4 + Wo4) + Ws5 || CC5 + HN6 + G7"])
def test_simulate_plot_legends_stay_inside_their_panels(tmp_path, monkeypatch, model):
    """Every legend of `impedax simulate --plot` lies inside its panel and clear of the axis
    labels (read back from matplotlib's geometry): a circuit of 72 characters, written whole in
    the |Z| panel's legend, ran 130 px past the panel's left side, over the '|Z| [Ω]' label."""
    figure, renderer = _saved_simulate_figure(tmp_path, monkeypatch, model=model)
    legends = [ax for ax in figure.axes if ax.get_legend() is not None]
    assert legends
    for ax in legends:
        box, panel = ax.get_legend().get_window_extent(renderer), ax.get_window_extent(renderer)
        assert panel.x0 <= box.x0 and box.x1 <= panel.x1 and panel.y0 <= box.y0 and box.y1 <= panel.y1
        assert not box.overlaps(ax.yaxis.label.get_window_extent(renderer))
    assert model in figure.texts[0].get_text()  # the title names the circuit


def test_info_json(capsys):
    assert main(["info", "R_f + R_sc || CPE_sc", "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    names = [p["name"] for p in info["parameters"]]
    assert names == ["R_f", "R_sc", "CPE_sc.Q", "CPE_sc.alpha"]
    alpha = info["parameters"][3]
    assert alpha["lower"] == 0 and alpha["upper"] == 1 and alpha["upper_inclusive"] is True


@pytest.mark.parametrize(
    "args, fragment",
    [
        (["simulate", "Csc + R1"], "did you mean C_sc?"),
        (["simulate", "R1", "--param", "R2=3"], "unknown parameter 'R2'"),
        (["simulate", "R1", "--param", "R1=-3"], "outside its bounds"),
        (["simulate", "R1", "--param", "R1=abc"], "is not a number"),
        (["simulate", "R1", "--param", "R1"], "expected NAME=VALUE"),
        (["simulate", "R1", "--fmin", "0"], "positive"),
        # the option named, as the commands that fit name it (they read "frequencies must be
        # positive and finite, got fmin=0.0, fmax=1000000.0": no option, a default fmax never given)
        (["simulate", "R1", "--fmin", "0"], "--fmin must be positive, got 0"),
        (["simulate", "R1", "--fmin", "1", "--fmax", "-2"], "--fmax must be positive, got -2"),
        (["force", "meyer", "--fmin", "0"], "--fmin must be positive, got 0"),
        (["force", "vezzoli", "--fmin", "-3", "--fmax", "5"], "--fmin must be positive, got -3"),
        (["simulate", "R1", "--fmin", "10", "--fmax", "1"], "--fmax (1 Hz) is below --fmin (10 Hz)"),
        (["simulate", "R1", "--out", "/nonexistent/dir/x.csv"], "does not exist"),
        (["info", "R1 + + C1"], "expected an element"),
    ],
)
def test_bad_input_exit_2_one_message(args, fragment, capsys):
    assert main(args) == 2
    err = capsys.readouterr().err
    assert fragment in err and "Traceback" not in err


def test_console_entry_point_runs_as_module():
    result = run_cli("simulate", "R1", "--param", "R1=5", "--points", "2")
    assert result.returncode == 0 and result.stdout.splitlines()[1].startswith("1,5,0")
    bad = run_cli("simulate", "X1")
    assert bad.returncode == 2 and "Traceback" not in bad.stderr


def test_program_end_keeps_outputs_exit_handlers_and_code(tmp_path):
    """The program ends without the interpreter's teardown (`impedax.cli._end_program`): what
    a command printed (more than a pipe buffer) and wrote is complete, exit handlers still run,
    and the exit code is the command's. The program runs with `GC_THRESHOLDS`."""
    marker, out = tmp_path / "exit-handler-ran", tmp_path / "s.csv"
    driver = (
        "import atexit, gc, pathlib, sys\n"
        f"atexit.register(lambda: pathlib.Path({str(marker)!r}).write_text(repr(gc.get_threshold())))\n"
        "sys.argv = ['impedax', *sys.argv[1:]]\n"
        "from impedax.cli import main\nraise SystemExit(main())\n"
    )
    env = {k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}  # standard output block-buffered
    args = ["simulate", "R0 + R1 || C1", "--points", "4000", "--fmin", "1", "--fmax", "1e6"]
    result = subprocess.run([sys.executable, "-c", driver, *args], capture_output=True, text=True, timeout=300, env=env)
    lines = result.stdout.splitlines()
    assert result.returncode == 0 and len(lines) == 4001 and lines[-1].startswith("1000000")
    assert marker.read_text() == repr(GC_THRESHOLDS) != repr((700, 10, 10))  # the program's collector thresholds
    info = subprocess.run([sys.executable, "-c", driver, "info", "R0 + R1 || C1", "--json"], capture_output=True, text=True, timeout=300, env=env)
    assert info.returncode == 0 and len(json.loads(info.stdout)["parameters"]) == 3
    assert run_cli(*args, "--out", str(out)).returncode == 0 and ix.load(out).sizes["frequency"] == 4000
    marker.unlink()
    bad = subprocess.run([sys.executable, "-c", driver, "simulate", "X1"], capture_output=True, text=True, timeout=300, env=env)
    assert bad.returncode == 2 and "X1" in bad.stderr and marker.read_text() == repr(GC_THRESHOLDS)


def test_refine_starts_from_the_library_s_default_circuit_when_no_model_is_given():
    # `impedax refine DATA` without --model starts where ix.refine does; diagnose still asks
    # for the model it is to diagnose
    import inspect

    from impedax.cli import build_parser
    from impedax.fitting.diagnosis.refinement import REFINE_START

    assert build_parser("refine").parse_args(["refine", "data.csv"]).model == REFINE_START == "R0 + R1 || C1"
    assert inspect.signature(ix.refine).parameters["circuit"].default == REFINE_START
    assert build_parser("refine").parse_args(["refine", "data.csv", "--model", "R0 + C1"]).model == "R0 + C1"
    with pytest.raises(SystemExit):
        build_parser("diagnose").parse_args(["diagnose", "data.csv"])


def test_numbers_on_the_command_line_take_si_prefixes(capsys):
    # R1=1k, C1=1u, --fmin 1, --fmax 100k: the spectrum of the plain numbers (the formula
    # above); m is milli and M mega; a prefix the list does not have is an error naming the forms
    from impedax.cli.common import prefixed_number

    assert [prefixed_number(t) for t in ("1k", "2.2u", "2.2µ", "10n", "5m", "1M", "-3p", ".5G", "1e3", "7")] == pytest.approx(
        [1e3, 2.2e-6, 2.2e-6, 1e-8, 5e-3, 1e6, -3e-12, 5e8, 1e3, 7.0], rel=1e-15
    )
    # the float nearest the decimal written, as float() reads it: no 1.7000000000000001e-09 in JSON
    assert [prefixed_number(t) for t in ("1.7n", "2.2u", "0.1f", "4.7p", "3.3k")] == [float("1.7e-9"), float("2.2e-6"), float("1e-16"), float("4.7e-12"), 3300.0]
    code = main(["simulate", "R0 + R1 || C1", "--param", "R0=10", "--param", "R1=1k", "--param", "C1=1u", "--fmin", "1", "--fmax", "100k", "--points", "11"])
    assert code == 0
    rows = np.array([[float(v) for v in ln.split(",")] for ln in capsys.readouterr().out.strip().splitlines()[1:]])
    assert rows[-1, 0] == pytest.approx(1e5, rel=1e-15)
    z = 10 + 1000 / (1 + 1j * 2 * np.pi * rows[:, 0] * 1e-3)
    np.testing.assert_allclose(rows[:, 1] + 1j * rows[:, 2], z, rtol=1e-14)
    assert main(["simulate", "R0 + R1 || C1", "--param", "R1=1x"]) == 2
    assert "'1x' is not a number (write 1000, 1e3 or 1k; SI prefixes f p n u µ m k M G T)" in capsys.readouterr().err
    with pytest.raises(SystemExit) as stop:
        main(["simulate", "R0", "--fmax", "1kHz"])
    assert stop.value.code == 2 and "'1kHz' is not a number" in capsys.readouterr().err


def test_info_table_writes_units_as_symbols(capsys):
    # the text table read "Ohm", "F s^(alpha-1)" and "1"; JSON keeps the specs' spelling
    assert main(["info", "R0 + CPE1 + W1"]) == 0
    rows = {ln.split()[0]: ln for ln in capsys.readouterr().out.splitlines()[2:]}
    assert rows["R0"].split()[1] == "Ω" and "F s^(α-1)" in rows["CPE1.Q"] and "Ω s^-1/2" in rows["W1.sigma"]
    assert rows["CPE1.alpha"].split()[1] == "0.9"  # no unit column text for a dimensionless exponent
    assert main(["info", "R0", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["parameters"][0]["unit"] == "Ohm"


@pytest.mark.parametrize("argv", [
    ["simulate", "R0 + R1 || C1", "--param", "R0=10", "R1=1k", "C1=1u", "--points", "5"],
    ["simulate", "--param", "R0=10", "R1=1k", "C1=1u", "R0 + R1 || C1", "--points", "5"],  # MODEL after the values stays MODEL
    ["simulate", "R0 + R1 || C1", "--param=R0=10", "R1=1k", "--param", "C1=1u", "--points", "5"],
])
def test_several_name_value_after_one_param(capsys, argv):
    """docs/cli.md's `--param NAME=VALUE ...`: several values after one --param, as repeated
    --param. Oracle: R0 + R1/(1 + jωR1C1) written out."""
    assert main(argv) == 0
    rows = np.array([[float(v) for v in ln.split(",")] for ln in capsys.readouterr().out.strip().splitlines()[1:]])
    z = 10 + 1e3 / (1 + 1j * 2 * np.pi * rows[:, 0] * 1e3 * 1e-6)
    np.testing.assert_allclose(rows[:, 1] + 1j * rows[:, 2], z, rtol=1e-12)


def test_force_takes_several_name_value_after_one_param_and_a_stray_value_names_param(capsys):
    """force: one --param with two values gives the force of both (Vezzoli eq 10 by hand, Fig 8's
    1 µm insulator at 140 V, Table 2's rest); a NAME=VALUE without --param says to give it one."""
    assert main(["force", "--param", "h_i=1u", "v_m=140", "vezzoli", "--fmin", "440", "--fmax", "440", "--points", "1"]) == 0
    force = float(capsys.readouterr().out.splitlines()[1].split(",")[1])
    e0, wt = 8.8541878128e-12, 2 * np.pi * 440 * 8.8541878128e-12 * 2340 * 3e4
    assert force == pytest.approx(e0 * 1e-4 * 140**2 / (4 * (1e-6 + 350e-6) * (1e-6 / 3.35 + 350e-6 / 2340)) * wt**2 / (1 + wt**2), rel=1e-9)
    with pytest.raises(SystemExit) as info:
        main(["simulate", "R0 + C1", "R0=5", "C1=1u"])
    err = capsys.readouterr().err
    assert info.value.code == 2 and "unrecognized arguments: R0=5 C1=1u; a parameter value follows --param: --param R0=5 C1=1u" in err


def test_commands_with_a_positional_model_take_the_model_option_too(capsys, tmp_path):
    """`simulate`, `info` and `draw` take MODEL as their first argument; `--model X` and
    `--model=X` (as `fit`, `diagnose` and the others take it) mean the same."""
    outputs = []
    for argv in (["simulate", "R0 + R1 || C1", "--points", "4"], ["simulate", "--model", "R0 + R1 || C1", "--points", "4"],
                 ["simulate", "--points", "4", "--model=R0 + R1 || C1"]):
        assert main(argv) == 0
        outputs.append(capsys.readouterr().out)
    assert outputs[0] == outputs[1] == outputs[2] and outputs[0].count("\n") == 5
    assert main(["info", "--json", "--model", "R0 + CPE1"]) == 0
    assert [p["name"] for p in json.loads(capsys.readouterr().out)["parameters"]] == ["R0", "CPE1.Q", "CPE1.alpha"]
    assert main(["draw", "--model", "R0 + R1 || C1", "-o", str(tmp_path / "d.png")]) == 0
    assert (tmp_path / "d.png").stat().st_size > 0
    # a model given both ways is one too many
    with pytest.raises(SystemExit) as info:
        main(["simulate", "R0 + R1 || C1", "--model", "R0"])
    assert info.value.code == 2 and "MODEL given twice: 'R0 + R1 || C1' and --model 'R0'" in capsys.readouterr().err
    # neither way is none, and --help lists --model
    with pytest.raises(SystemExit) as info:
        main(["simulate", "--points", "4"])
    assert info.value.code == 2 and "required: MODEL (or --model MODEL)" in capsys.readouterr().err
    for command in ("simulate", "info", "draw", "force"):
        with pytest.raises(SystemExit):
            main([command, "--help"])
        assert "--model MODEL" in capsys.readouterr().out
    # force's model keeps its choices either way
    assert main(["force", "--model", "meyer", "--points", "3"]) == 0
    assert capsys.readouterr().out.count("\n") == 4
    with pytest.raises(SystemExit) as info:
        main(["force", "--model", "nope"])
    assert info.value.code == 2 and "invalid choice: 'nope'" in capsys.readouterr().err


@pytest.mark.parametrize("title", ["My title", ("A much longer title of the user's own, " * 2).strip()])
def test_simulate_with_a_title_still_names_a_long_circuit(tmp_path, monkeypatch, title):
    """An 89-character circuit is "model" in the legends (longer than 40 characters): with
    ``--title`` the figure's only text was the user's title and named the circuit nowhere. Now the
    circuit follows the title on lines of its own, every line inside the figure's width."""
    figure, renderer = _saved_simulate_figure(tmp_path, monkeypatch, "--title", title)
    legends = [t.get_text() for ax in figure.axes if ax.get_legend() is not None for t in ax.get_legend().get_texts()]
    assert legends and set(legends) == {"model"}
    (text,) = figure.texts
    assert text.get_text().startswith(title)
    assert " ".join(text.get_text()[len(title):].split()) == LONG_CIRCUIT  # (the circuit whole, however wrapped)
    box = text.get_window_extent(renderer)
    assert 0 <= box.x0 and box.x1 <= figure.bbox.width and box.y1 <= figure.bbox.height


def test_simulate_with_an_empty_title_has_none(tmp_path, monkeypatch):
    """``--title ''`` leaves the title out, the circuit's line with it (as for every figure)."""
    figure, _ = _saved_simulate_figure(tmp_path, monkeypatch, "--title", "")
    assert not any(t.get_text() for t in figure.texts)


def test_info_lists_each_element_kind_with_its_equation(capsys):
    """Walkthrough 2026-12-06: `impedax info` named a Gerischer or a Havriliak–Negami element
    but not its formula; each kind in the circuit is now listed once, in order, with its
    equation (the textbook forms: Gerischer Z = R/√(1 + jωτ), Havriliak–Negami
    Z = R/(1 + (jωτ)^α)^β), and JSON holds them under the added key "elements"."""
    assert main(["info", "R0 + G1 + R1 || HN1"]) == 0
    lines = capsys.readouterr().out.splitlines()
    table = lines[lines.index(next(line for line in lines if line.startswith("element "))):]
    assert [line.split()[0] for line in table[1:]] == ["R", "G", "HN"]
    assert table[2].endswith("Z = R/√(1 + jωτ)") and table[3].endswith("Z = R/(1 + (jωτ)^α)^β")
    assert main(["info", "R0 + G1 + R1 || HN1", "--json"]) == 0
    shown = json.loads(capsys.readouterr().out)
    assert shown["elements"][1] == {"symbol": "G", "element_kind": "Gerischer", "equation": "Z = R/√(1 + jωτ)"}
    assert [r["name"] for r in shown["parameters"]] == ["R0", "G1.R", "G1.tau", "R1", "HN1.R", "HN1.tau", "HN1.alpha", "HN1.beta"]
    assert main(["info", "Q1 + CPE2", "--json"]) == 0  # (Q is the CPE's alias: one kind)
    assert [k["symbol"] for k in json.loads(capsys.readouterr().out)["elements"]] == ["CPE"]


def test_simulate_at_the_frequencies_of_one_sweep_of_a_file_of_two_grids(tmp_path, capsys):
    """SYNTHETIC table of two sweeps on grids 2.3 % apart: --frequencies alone is refused with
    the advice to pick one with --select, which simulate now takes (it named an option simulate
    did not have); --select sweep=1 gives the second sweep's 30 frequencies as written."""
    first, second = np.geomspace(1e5, 1e-2, 30), np.geomspace(10**5.01, 10**-1.99, 30)
    path = tmp_path / "two.csv"
    path.write_text("freq,Zreal,Zimag\n" + "".join(f"{float(f)!r},100.0,-1.0\n" for f in [*first, *second]))
    assert main(["simulate", "R1", "--frequencies", str(path), "-q"]) == 2
    assert "read one alone with --select sweep=0" in capsys.readouterr().err
    assert main(["simulate", "R1", "--param", "R1=5", "--frequencies", str(path), "--select", "sweep=1", "-q"]) == 0
    rows = np.array([[float(v) for v in line.split(",")] for line in capsys.readouterr().out.splitlines()[1:]])
    assert rows[:, 0].tolist() == [float(f) for f in second] and (rows[:, 1] == 5).all() and (rows[:, 2] == 0).all()
    assert main(["simulate", "R1", "--select", "sweep=1"]) == 2
    assert "--select picks spectra of the --frequencies FILE" in capsys.readouterr().err


def test_simulate_plot_draws_the_model_as_a_smooth_curve(tmp_path, monkeypatch):
    """`impedax simulate --plot` draws the model on `MODEL_POINTS_PER_DECADE` points a decade
    (`model_curve`), as `fit --plot` does, while the CSV keeps its 61 frequencies: 61 points over
    7 decades drew a SYNTHETIC R0 + R1 ∥ CPE1 + R2 ∥ C2's arcs as visible chords. Oracle: every
    point of the Nyquist curve lies on the closed form R0 + R1/(1 + jωR1C1) of its frequency."""
    from impedax.plotting import MODEL_POINTS_PER_DECADE

    figure, _ = _saved_simulate_figure(tmp_path, monkeypatch, "--param", "R0=20", "R1=1k", "C1=1u", "--fmin", "0.01", "--fmax", "1e5", model="R0 + R1 || C1")
    assert len((tmp_path / "s.csv").read_text().splitlines()) == 62  # (header + the 61 frequencies written)
    (curve,) = [line for line in figure.axes[0].get_lines() if len(line.get_xdata()) > 1]
    x, y = np.asarray(curve.get_xdata()), np.asarray(curve.get_ydata())
    assert x.size >= MODEL_POINTS_PER_DECADE * 7
    (bode,) = [line for line in figure.axes[1].get_lines() if len(line.get_xdata()) > 1]
    f = np.asarray(bode.get_xdata())
    assert f.size == x.size and np.isclose(f[0], 0.01) and np.isclose(f[-1], 1e5)
    z = 20 + 1e3 / (1 + 2j * np.pi * f * 1e3 * 1e-6)
    assert np.allclose(x + 1j * y, z.real - 1j * z.imag, rtol=1e-9)
