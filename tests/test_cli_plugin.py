"""``--plugin FILE.py`` (and ``$IMPEDAX_PLUGINS``): a user's own element and reader on the command
line (walkthrough 2026-12-01, item 3: neither could be used from ``impedax`` at all, while the
hint for impedance.py's Gs sent the user to a Python-only ElementSpec).

The plugin, written here as a user would, declares a Gerischer-like element ``Gx``,
Z = R/√(1 + jωτ), and a reader of a made-up ``.lab`` text format (kHz, |Z| and phase in degrees,
one ``key=value`` line per point) that the delimited-text fallback cannot read. Every spectrum
is SYNTHETIC: a numpy formula with seeded noise."""

from __future__ import annotations

import json
import os
from types import SimpleNamespace

import numpy as np
import pytest

from impedax.cli import _first_word
from impedax.cli.common import fit_command

from cli_run import run

FREQ = np.geomspace(0.1, 1e5, 40)  # Hz
R0_TRUE, GX_R_TRUE, GX_TAU_TRUE = 12.0, 250.0, 2e-3  # Ω, Ω, s
NOISE = 0.003  # relative, per component

PLUGIN = '''\
"""My lab's element and file format (a user's plugin)."""
import jax.numpy as jnp
import numpy as np

import impedax as ix
from impedax.io import Reader, register_reader


def gx_impedance(omega, r, tau):
    """Gerischer-like: Z = R / sqrt(1 + j omega tau)."""
    return r / jnp.sqrt(1 + 1j * omega * tau)


GX = ix.ElementSpec(
    "Gx", "Gerischer-like", "Z = R/sqrt(1 + jωτ)",
    (ix.ParameterSpec("R", "Ohm", 100.0, description="DC resistance"), ix.ParameterSpec("tau", "s", 1e-3, description="time constant")),
    gx_impedance, impedance_py="Gxp",
)


def sniff_lab(path, head):
    return None if head.startswith(b"LABFMT 1") else "no 'LABFMT 1' first line"


def read_lab(path):
    values = []
    for number, line in enumerate(open(path), start=1):
        if number == 1 or not line.strip():
            continue
        fields = dict(item.split("=") for item in line.split())
        values.append((float(fields["f_kHz"]) * 1e3, float(fields["mag"]), float(fields["phase_deg"])))
    f, mag, phase = np.array(values).T
    return ix.make_spectrum(f, mag * np.exp(1j * np.deg2rad(phase)), attrs={"format": "LAB text"})


LAB_READERS = register_reader(Reader("LAB text", (".lab",), sniff_lab, read_lab))
'''


def gx_model(freq, r0, r, tau):
    """R0 + Gx: Z = R0 + R/√(1 + jωτ), ω = 2πf (written apart from the plugin's formula)."""
    return r0 + r * (1 + 2j * np.pi * freq * tau) ** -0.5


def write_lab(path, seed=3):
    """SYNTHETIC: R0 + Gx with 0.3 % relative Gaussian noise per component, in the '.lab' layout."""
    rng = np.random.default_rng(seed)
    z = gx_model(FREQ, R0_TRUE, GX_R_TRUE, GX_TAU_TRUE)
    z = z + NOISE * np.abs(z) * (rng.normal(size=FREQ.size) + 1j * rng.normal(size=FREQ.size))
    lines = [f"f_kHz={float(f) / 1e3!r} mag={float(abs(v))!r} phase_deg={float(np.degrees(np.angle(v)))!r}" for f, v in zip(FREQ, z)]
    path.write_text("LABFMT 1\n" + "\n".join(lines) + "\n")
    return z


@pytest.fixture
def lab(tmp_path):
    """(plugin path, SYNTHETIC .lab path) in tmp_path."""
    plugin = tmp_path / "mylab.py"
    plugin.write_text(PLUGIN, encoding="utf-8")
    data = tmp_path / "run1.lab"
    write_lab(data)
    return plugin, data


def values(params: dict) -> dict[str, float]:
    return {name: p["value"] for name, p in params.items()}


def test_fit_recovers_the_user_element_from_a_file_only_the_user_reader_reads(lab, capsys):
    plugin, data = lab
    code, out, err = run(["fit", data, "--model", "R0 + Gx1", "--plugin", plugin, "--json"], capsys)
    assert code == 0, err
    summary = json.loads(out)
    fitted = values(summary["params"])
    assert fitted["R0"] == pytest.approx(R0_TRUE, rel=0.02)
    assert fitted["Gx1.R"] == pytest.approx(GX_R_TRUE, rel=0.01)
    assert fitted["Gx1.tau"] == pytest.approx(GX_TAU_TRUE, rel=0.02)
    assert summary["rms_rel"] < 2 * NOISE  # at the noise: the plugin's formula, not another one
    assert summary["provenance"]["settings"]["plugin"] == [os.path.abspath(plugin)]  # (added key: what the run used)
    # without the plugin, the file is no spectrum impedax knows
    code, _, err = run(["inspect", data], capsys)
    assert code == 2 and "run1.lab" in err


def test_the_program_option_and_the_environment_variable_load_it_too(lab, capsys, monkeypatch):
    plugin, data = lab
    code, out, err = run(["--plugin", plugin, "inspect", data, "--json"], capsys)  # (before the command)
    assert code == 0, err
    shown = json.loads(out)
    assert shown["format"] == "LAB text" and shown["points"] == FREQ.size
    assert shown["frequency_min_hz"] == pytest.approx(0.1) and shown["frequency_max_hz"] == pytest.approx(1e5)
    monkeypatch.setenv("IMPEDAX_PLUGINS", os.pathsep.join(["", str(plugin)]))  # (an empty entry is skipped)
    code, out, err = run(["inspect", data, "--json"], capsys)
    assert code == 0, err
    assert json.loads(out)["format"] == "LAB text"
    # the same file from the variable and the option: read once (else 'Gx' would be declared twice)
    code, out, err = run(["info", "Gx1", "--plugin", plugin, "--json"], capsys)
    assert code == 0, err
    rows = json.loads(out)["parameters"]
    assert [(r["name"], r["unit"], r["default"]) for r in rows] == [("Gx1.R", "Ohm", 100.0), ("Gx1.tau", "s", 1e-3)]


def test_simulate_evaluates_the_user_formula(lab, capsys):
    plugin, _ = lab
    code, out, err = run(["simulate", "R0 + Gx1", "--plugin", plugin, "--param", "R0=5", "Gx1.R=1k", "Gx1.tau=1m", "--fmin", "1", "--fmax", "100k", "--points", "6"], capsys)
    assert code == 0, err
    rows = np.array([[float(v) for v in line.split(",")] for line in out.strip().splitlines()[1:]])
    expected = gx_model(rows[:, 0], 5.0, 1e3, 1e-3)
    np.testing.assert_allclose(rows[:, 1] + 1j * rows[:, 2], expected, rtol=1e-12)


def test_compare_ranks_the_user_element_first_in_either_notation(lab, capsys):
    plugin, data = lab
    # R0-Gxp1: impedance.py's notation with the plugin's impedance_py symbol
    code, out, err = run(["compare", data, "--model", "R0-Gxp1", "--model", "R0 + R1 || C1", "--plugin", plugin, "--json"], capsys)
    assert code == 0, err
    assert "read as impedance.py notation: R0 + Gx1" in err
    summary = json.loads(out)
    assert summary["best"] == "R0 + Gx1"
    best = next(m for m in summary["models"] if m["model"] == "R0 + Gx1")
    assert values(best["params"])["Gx1.tau"] == pytest.approx(GX_TAU_TRUE, rel=0.02)


def test_a_saved_fit_of_the_user_element_is_read_back_with_the_same_plugin(lab, tmp_path, capsys):
    plugin, data = lab
    saved = tmp_path / "fit.nc"
    code, _, err = run(["fit", data, "--model", "R0 + Gx1", "--plugin", plugin, "--out", saved], capsys)
    assert code == 0, err
    code, out, err = run(["inspect", saved, "--plugin", plugin, "--json"], capsys)
    assert code == 0, err
    shown = json.loads(out)
    assert shown["result_kind"] == "fit" and shown["attrs"]["model"] == "R0 + Gx1"  # (the element by its symbol: its formula is the plugin's)
    assert json.loads(shown["attrs"]["provenance"])["settings"]["plugin"] == [os.path.abspath(plugin)]
    # its data refitted, the model named as the file records it
    code, out, err = run(["fit", saved, "--model", shown["attrs"]["model"], "--plugin", plugin, "--json"], capsys)
    assert code == 0, err
    assert values(json.loads(out)["params"])["Gx1.R"] == pytest.approx(GX_R_TRUE, rel=0.01)


def test_without_the_plugin_the_hints_name_it(capsys):
    code, _, err = run(["fit", "no.csv", "--model", "R0 + Gx1"], capsys)
    assert code == 2
    assert "if Gx is an element of your own, declare it in a Python file and pass --plugin FILE.py" in err
    assert err.count("--plugin") == 1  # (the parser's hint in the command line's words, not a second line)
    code, _, err = run(["info", "R0-Gs1"], capsys)
    assert code == 2
    assert "ElementSpec(..., impedance_py='Gs')" in err and "--plugin FILE.py" in err


BAD_PLUGINS = {
    "syntax": ("import impedax\n\nx = (1,\n", "bad.py, line 3: syntax error"),
    "raises": ("import impedax\n\n\nraise RuntimeError('no licence file')\n", "bad.py, line 4: executing it raised RuntimeError: no licence file"),
    "bad spec": (
        "import impedax as ix\nX = ix.ElementSpec('gx', 'lower', 'Z = R', (ix.ParameterSpec('R', 'Ohm', 1.0),), lambda w, r: r)\n",
        "bad.py, line 2: executing it raised CircuitError: element symbol 'gx' must be a capital letter",
    ),
    "built-in symbol": (
        "import impedax as ix\nX = ix.ElementSpec('G', 'mine', 'Z = R', (ix.ParameterSpec('R', 'Ohm', 1.0),), lambda w, r: r + 0 * w)\n",
        "bad.py: element symbol 'G' of element 'mine' is impedax's built-in Gerischer: choose another",
    ),
    "missing unit": (
        "import impedax as ix\nX = ix.ElementSpec('Xa', 'mine', 'Z = R',\n    (ix.ParameterSpec('R', 1.0),), lambda w, r: r + 0 * w)\n",
        "bad.py, line 3: executing it raised CircuitError: parameter 'R': no unit: ParameterSpec('R', 1.0) takes 1.0 for the unit",
    ),
    "declares nothing": ("TOLERANCE = 1e-3\n", "bad.py: declares no ElementSpec and no impedax.io.Reader"),
}


@pytest.mark.parametrize("source, message", BAD_PLUGINS.values(), ids=BAD_PLUGINS.keys())
def test_a_bad_plugin_is_one_message_naming_the_file_and_exit_2(source, message, tmp_path, capsys):
    bad = tmp_path / "bad.py"
    bad.write_text(source)
    code, out, err = run(["info", "R0", "--plugin", bad], capsys)
    assert code == 2 and out == ""
    assert f"impedax info: error: --plugin {bad}" in err and message in err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_a_plugin_reader_whose_sniff_raises_is_named_with_its_file_and_line(tmp_path, capsys):
    """A sniff that raises does not stop the built-in readers; when none claims the file, the
    one message names the reader, the plugin file and the line of the sniff that raised (line
    4 of the file written here), not only the reader's name."""
    bad = tmp_path / "bad_sniff.py"
    bad.write_text("from impedax.io import Reader\n\ndef sniff(path, head):\n    return head[0] + 'x'\n\n"
                   "READER = Reader('Bad', '.bad', sniff, lambda path: None)\n")
    data = tmp_path / "run1.lab"
    data.write_text("LABEIS\n0.1 10 -1\n1 9 -2\n")
    code, out, err = run(["inspect", data, "--plugin", bad], capsys)
    assert code == 2 and out == ""
    # (the plugin named as a read's fault names it, since 2026-12-06: "reader 'Bad': its sniff (FILE, line 4)" before)
    assert f"reader 'Bad' of --plugin {bad}: its sniff (line 4) raised TypeError: unsupported operand" in err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_a_plugin_formula_that_fails_under_jax_is_named_with_its_file_and_line(tmp_path, capsys):
    """An element whose formula calls numpy on the traced ω is refused when the circuit is
    compiled; the one message names the plugin file and the line of the formula that failed
    (line 5 of the file written here; the function starts on line 4), as a sniff's fault is
    named (walkthrough 2026-12-06: the message named the element only, "element Kx: its
    impedance function failed under JAX", and the user had to find the line alone)."""
    bad = tmp_path / "np_formula.py"
    bad.write_text("import numpy as np\nimport impedax as ix\n\ndef kx(omega, r):\n    return r * np.ones_like(omega)\n\n"
                   "KX = ix.ElementSpec('Kx', 'numpy element', 'Z = R', (ix.ParameterSpec('R', 'Ohm', 1.0),), kx)\n")
    code, out, err = run(["simulate", "R0 + Kx1", "--plugin", bad, "--points", "3"], capsys)
    assert code == 2 and out == ""
    assert f"element Kx: its impedance function ({bad}, line 5) failed under JAX (TracerArrayConversionError" in err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_a_missing_plugin_and_a_symbol_in_two_plugins_are_refused(lab, tmp_path, capsys):
    plugin, _ = lab
    code, _, err = run(["--plugin", tmp_path / "nothere.py", "info", "R0"], capsys)
    assert code == 2 and f"--plugin {tmp_path / 'nothere.py'}: no such file" in err
    other = tmp_path / "other.py"
    other.write_text("import impedax as ix\nELEMENTS = [ix.ElementSpec('Gx', 'another Gx', 'Z = R', (ix.ParameterSpec('R', 'Ohm', 1.0),), lambda w, r: r + 0 * w)]\n")
    code, _, err = run(["info", "R0", "--plugin", plugin, "--plugin", other], capsys)
    assert code == 2 and f"--plugin {other}: element symbol 'Gx' of element 'another Gx' is declared in {plugin} too (Gerischer-like)" in err


def test_a_plugin_listed_in_the_environment_is_named_as_such(tmp_path, capsys, monkeypatch):
    """A bad file listed in $IMPEDAX_PLUGINS is named as the variable's, not as a --plugin the
    user never typed (walkthrough 2026-12-06: "--plugin pl/nothere.py: no such file" on a
    command line without --plugin); a file given with --plugin keeps its name."""
    gone = tmp_path / "nothere.py"
    monkeypatch.setenv("IMPEDAX_PLUGINS", str(gone))
    code, out, err = run(["info", "R0"], capsys)
    assert code == 2 and out == ""
    assert err.strip() == f"impedax info: error: $IMPEDAX_PLUGINS {gone}: no such file"
    raising = tmp_path / "raising.py"
    raising.write_text("import impedax\n\nraise RuntimeError('no licence file')\n")
    monkeypatch.setenv("IMPEDAX_PLUGINS", str(raising))
    code, _, err = run(["info", "R0"], capsys)
    assert code == 2 and f"$IMPEDAX_PLUGINS {raising}, line 3: executing it raised RuntimeError: no licence file" in err
    monkeypatch.delenv("IMPEDAX_PLUGINS")
    code, _, err = run(["info", "R0", "--plugin", raising], capsys)
    assert code == 2 and f"--plugin {raising}, line 3: executing it raised RuntimeError" in err


def test_a_plugin_imports_the_modules_beside_it_from_any_folder(tmp_path, capsys, monkeypatch):
    """A plugin whose formula lives in a module beside it (``from sibling_dc import dc``) is
    read from any working folder, as Python runs a script (walkthrough 2026-12-06: outside the
    plugin's own folder it was "executing it raised ModuleNotFoundError"). The formula is
    Davidson–Cole, Z = R/(1 + jωτ)^β, checked at 1 kHz against numpy. A syntax error in the
    module beside it names that module and its line."""
    folder = tmp_path / "plugins"
    folder.mkdir()
    (folder / "sibling_dc.py").write_text("def dc(omega, r, tau, beta):\n    return r / (1 + 1j * omega * tau) ** beta\n")
    (folder / "lab_dc.py").write_text("import impedax as ix\nfrom sibling_dc import dc\n\nDCX = ix.ElementSpec('Dcx', 'Davidson-Cole', 'Z = R/(1 + jωτ)^β', "
                                      "(ix.ParameterSpec('R', 'Ohm', 100.0), ix.ParameterSpec('tau', 's', 1e-3), ix.ParameterSpec('beta', '1', 0.8, upper=1.0, upper_inclusive=True)), dc)\n")
    elsewhere = tmp_path / "work"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    monkeypatch.syspath_prepend(str(elsewhere))  # (the working folder on the path, as `python -m impedax` has it)
    code, out, err = run(["simulate", "Dcx1", "--plugin", folder / "lab_dc.py", "--param", "Dcx1.R=500", "Dcx1.tau=1e-3", "Dcx1.beta=0.7", "--fmin", "1000", "--fmax", "1000"], capsys)
    assert code == 0, err
    f, z_real, z_imag = (float(x) for x in out.splitlines()[1].split(","))
    expected = 500 / (1 + 2j * np.pi * 1000 * 1e-3) ** 0.7
    assert f == 1000 and complex(z_real, z_imag) == pytest.approx(expected, rel=1e-12)
    assert str(folder) not in __import__("sys").path  # (on the path only while the plugin runs)
    broken = tmp_path / "broken"
    broken.mkdir()
    (broken / "broken_sibling.py").write_text("def dc(omega, r\n")
    (broken / "lab_broken.py").write_text("import impedax as ix\nfrom broken_sibling import dc\n")
    code, out, err = run(["info", "R0", "--plugin", broken / "lab_broken.py"], capsys)
    assert code == 2 and out == ""
    assert f"--plugin {broken / 'lab_broken.py'}, line 2: it imports {broken / 'broken_sibling.py'}, which has a syntax error, line 1: " in err


def test_a_user_reader_returning_a_dataset_that_is_no_spectrum_is_named(tmp_path, capsys):
    """A reader that builds its own xarray Dataset (Z called 'impedance', over 'f') is named
    with the fault and the way to build a spectrum (walkthrough 2026-12-06: only "dataset has
    no variable 'Z'", which named neither the reader nor make_spectrum)."""
    plugin = tmp_path / "raw_reader.py"
    plugin.write_text("import numpy as np\nimport xarray as xr\nfrom impedax.io import Reader\n\n"
                      "def sniff(path, head):\n    return None if head.startswith(b'RAWDS') else 'no RAWDS'\n\n"
                      "def read(path):\n    return xr.Dataset({'impedance': ('f', np.array([1 + 1j, 2 + 2j]))}, coords={'f': [1.0, 10.0]})\n\n"
                      "READER = Reader('Raw', '.raw', sniff, read)\n")
    data = tmp_path / "x.raw"
    data.write_text("RAWDS\n")
    code, out, err = run(["inspect", data, "--plugin", plugin], capsys)
    assert code == 2 and out == ""
    # (the plugin named, as a read that raises names it, since 2026-12-06)
    assert err.strip() == (f"impedax inspect: error: {data}: reader 'Raw' of --plugin {plugin} returned a Dataset that is not a spectrum: dataset has no variable 'Z' "
                           "(its data variables: 'impedance') (build it with impedax.make_spectrum(frequency_hz, Z))")


def test_what_a_plugin_prints_goes_to_stderr_and_stdout_stays_json(lab, tmp_path, capsys):
    """A plugin that prints when loaded and when its reader reads (a user's debugging lines):
    standard output is the command's JSON alone, which json.loads reads, and the lines are on
    stderr (walkthrough 2026-12-06: "lab plugin loaded" came before the JSON of impedax info
    --json and the CSV of simulate, and a pipeline's reader failed)."""
    plugin, data = lab
    noisy = tmp_path / "noisy_lab.py"
    noisy.write_text('print("lab plugin loaded")\n' + PLUGIN.replace("    values = []\n", "    print('reading', path)\n    values = []\n", 1), encoding="utf-8")
    code, out, err = run(["inspect", data, "--plugin", noisy, "--json"], capsys)
    assert code == 0, err
    assert json.loads(out)["format"] == "LAB text"
    assert "lab plugin loaded" in err and f"reading {data}" in err
    code, out, err = run(["simulate", "R0 + Gx1", "--plugin", noisy, "--points", "2", "-q"], capsys)
    assert code == 0 and out.splitlines()[0] == "frequency_hz,z_real_ohm,z_imag_ohm" and len(out.splitlines()) == 3


def test_what_a_plugin_formula_and_sniff_print_goes_to_stderr_and_stdout_stays_json(lab, tmp_path, capsys):
    """A formula that prints while JAX traces it and a sniff that prints (a user's debugging
    lines): the JSON of fit --json and inspect --json and the CSV of simulate are alone on
    standard output, the lines on stderr (until 2026-12-06 only what the plugin printed at import
    and what its reader printed were redirected: "tracing Gx" and "sniffing" came before them)."""
    plugin, data = lab
    noisy = tmp_path / "noisy_formula.py"
    noisy.write_text(PLUGIN.replace('    """Gerischer-like: Z = R / sqrt(1 + j omega tau)."""\n', '    print("tracing Gx")\n', 1)
                     .replace("def sniff_lab(path, head):\n", "def sniff_lab(path, head):\n    print('sniffing', path)\n", 1), encoding="utf-8")
    assert noisy.read_text().count("print(") == 2
    code, out, err = run(["fit", data, "--model", "R0 + Gx1", "--plugin", noisy, "--json"], capsys)
    assert code == 0, err
    assert json.loads(out)["model"] == "R0 + Gx1"
    assert "tracing Gx" in err and f"sniffing {data}" in err
    csv_file = tmp_path / "plain.csv"
    csv_file.write_text("frequency_hz,z_real_ohm,z_imag_ohm\n1,10,-1\n10,9,-2\n100,8,-3\n")
    code, out, err = run(["inspect", csv_file, "--plugin", noisy, "--json"], capsys)
    assert code == 0, err
    assert json.loads(out)["format"] == "delimited text" and f"sniffing {csv_file}" in err
    code, out, err = run(["simulate", "R0 + Gx1", "--plugin", noisy, "--points", "2", "-q"], capsys)
    assert code == 0 and out.splitlines() == ["frequency_hz,z_real_ohm,z_imag_ohm", *out.splitlines()[1:]] and len(out.splitlines()) == 3
    assert "tracing Gx" in err


def test_the_command_is_found_after_the_program_option_and_fit_advice_carries_it():
    assert _first_word(["--plugin", "fit.py", "fit", "data.lab"]) == "fit"
    args = SimpleNamespace(data="run 1.lab", weighting="modulus", plugin=["my lab.py"])
    assert fit_command(args) == "impedax fit 'run 1.lab' --plugin 'my lab.py'"


@pytest.mark.slow  # (about 10 s: a diagnosis fits candidates of every effect)
def test_diagnose_finds_the_user_model_adequate(lab, capsys):
    plugin, data = lab
    code, out, err = run(["diagnose", data, "--model", "R0 + Gx1", "--plugin", plugin, "--json"], capsys)
    assert code == 0, err
    summary = json.loads(out)
    assert summary["verdict"] == "adequate"


def test_a_user_reader_that_fails_is_one_message_naming_the_data_file_and_the_plugin(lab, tmp_path, capsys):
    plugin, _ = lab
    broken = tmp_path / "broken.lab"
    broken.write_text("LABFMT 1\nf_kHz=1 mag=oops phase_deg=-10\n")  # (a bad number: the plugin's float() raises)
    code, out, err = run(["inspect", broken, "--plugin", plugin], capsys)
    assert code == 2 and out == ""
    line = next(i for i, text in enumerate(PLUGIN.splitlines(), start=1) if "values.append(" in text)
    assert f"{broken}: the reader 'LAB text' of --plugin {plugin} (line {line}) raised ValueError: could not convert string to float: 'oops'" in err
    assert "Traceback" not in err


def test_stack_joins_files_only_the_user_reader_reads(lab, tmp_path, capsys):
    plugin, first = lab
    second = tmp_path / "run2.lab"
    z2 = write_lab(second, seed=4)
    out = tmp_path / "both.nc"
    code, _, err = run(["stack", first, second, "--out", out, "--plugin", plugin], capsys)
    assert code == 0, err
    code, printed, err = run(["inspect", out, "--json"], capsys)  # (netCDF: no plugin needed to read it back)
    assert code == 0, err
    assert json.loads(printed)["dims"] == {"file": 2, "frequency": FREQ.size}
    import impedax as ix

    stacked = ix.load(out)
    np.testing.assert_allclose(stacked["Z"].sel(file="run2").values, z2, rtol=1e-12)


def test_info_of_parameters_declared_without_description(tmp_path, capsys):
    """A plugin's parameters without a description: the element's kind alone, no dangling colon."""
    plugin = tmp_path / "bare.py"
    plugin.write_text(PLUGIN.replace(', description="DC resistance"', "").replace(', description="time constant"', ""), encoding="utf-8")
    code, out, err = run(["info", "R0 + Gx1", "--plugin", plugin], capsys)
    assert code == 0, err
    lines = out.splitlines()
    assert lines[2].endswith("resistor: resistance")
    assert [line.startswith(name) and line.rstrip().endswith(" Gerischer-like") for name, line in zip(["Gx1.R", "Gx1.tau"], lines[3:])] == [True, True]
    assert not any(line.rstrip().endswith(":") for line in lines)
