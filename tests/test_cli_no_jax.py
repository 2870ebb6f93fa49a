"""Commands that compute nothing do not import JAX (its import is most of a fresh process's
1–2 s): each runs in a fresh Python process, which then reports whether ``jax`` is in
``sys.modules``. benchmarks/README.md, "Start-up of the command line", has the wall times."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from impedax.cli import COMMAND_HELP

ROOT = Path(__file__).resolve().parent.parent
REAL = ROOT / "tests" / "fixtures" / "real"


def fresh_process(code: str, env: dict | None = None) -> dict:
    """Run ``code`` in a new interpreter; it ends by printing a JSON object, returned."""
    environment = {**os.environ, "PYTHONPATH": str(ROOT), **(env or {})}
    for name in ("JAX_COMPILATION_CACHE_DIR", "JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS", "IMPEDAX_PLUGINS"):
        if env is None or name not in env:
            environment.pop(name, None)
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=environment, cwd=ROOT, timeout=300)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_the_compilation_cache_is_set_without_importing_jax(tmp_path):
    """`impedax.use_compilation_cache` (which every command calls first) leaves JAX unimported
    and hands it the folder and the 0.05 s threshold that JAX reads when it is imported; until
    2026-12-06 it imported JAX itself, so `impedax inspect` of a REAL file spent ~1.5 s on it."""
    folder = tmp_path / "cache"
    result = fresh_process(f"""
import json, sys
import impedax as ix
given = ix.use_compilation_cache({str(folder)!r})
before = "jax" in sys.modules
import jax
print(json.dumps({{"given": given, "jax_before": before, "dir": jax.config.jax_compilation_cache_dir,
                  "min_s": jax.config.jax_persistent_cache_min_compile_time_secs}}))
""")
    assert result == {"given": str(folder), "jax_before": False, "dir": str(folder), "min_s": 0.05}
    assert folder.is_dir()


def run_command(argv: list[str], tmp_path: Path) -> dict:
    """``impedax *argv`` in a fresh process (its cache in ``tmp_path``): exit code, stdout, and
    whether JAX was imported by the end."""
    code = f"""
import contextlib, io, json, sys
from impedax.cli import main
out = io.StringIO()
with contextlib.redirect_stdout(out):
    try:
        code = main({[str(a) for a in argv]!r})
    except SystemExit as exc:  # (argparse's --help)
        code = exc.code
print(json.dumps({{"code": code, "out": out.getvalue(), "jax": "jax" in sys.modules}}))
"""
    return fresh_process(code, env={"IMPEDAX_CACHE_DIR": str(tmp_path / "cache")})


def test_info_lists_the_elements_without_jax(tmp_path):
    """`impedax info` reads the registry only: parameters and equations, no JAX (the element
    formulas import it when first evaluated; the compiled forms of impedax.circuits load on
    first use)."""
    result = run_command(["info", "R0 + R1 || CPE1", "--json"], tmp_path)
    assert result["code"] == 0 and not result["jax"]
    info = json.loads(result["out"])
    assert [p["name"] for p in info["parameters"]] == ["R0", "R1", "CPE1.Q", "CPE1.alpha"]


def test_info_lists_a_plugin_element_without_jax(tmp_path):
    """`impedax info --plugin FILE.py` lists a user's element whose formula imports jax.numpy
    inside (as the built-in ones do) without loading JAX: the registry is read, not evaluated."""
    plugin = tmp_path / "lab.py"
    plugin.write_text(
        "import impedax as ix\n\ndef gx(omega, r, tau):\n    import jax.numpy as jnp\n\n    return r / jnp.sqrt(1 + 1j * omega * tau)\n\n"
        "GX = ix.ElementSpec('Gx', 'Gerischer-like', 'Z = R/sqrt(1 + jωτ)', (ix.ParameterSpec('R', 'Ohm', 100.0), ix.ParameterSpec('tau', 's', 1e-3)), gx)\n",
        encoding="utf-8")
    result = run_command(["info", "R0 + Gx1", "--plugin", plugin, "--json"], tmp_path)
    assert result["code"] == 0 and not result["jax"]
    assert [p["name"] for p in json.loads(result["out"])["parameters"]] == ["R0", "Gx1.R", "Gx1.tau"]


def test_draw_and_stack_do_not_import_jax(tmp_path):
    """`impedax draw` (a diagram of the parsed circuit) and `impedax stack` of a REAL file
    (impedance.py's exampleData.csv) and of it with Z × 1.01 (two copies are refused as one file
    copied) compute no impedance."""
    drawn = run_command(["draw", "R0 + R1 || C1", "--out", tmp_path / "circuit.svg"], tmp_path)
    assert drawn["code"] == 0 and not drawn["jax"] and (tmp_path / "circuit.svg").stat().st_size > 0
    days = [tmp_path / "day1.csv", tmp_path / "day2.csv"]
    days[0].write_bytes((REAL / "exampleData.csv").read_bytes())
    rows = [line.split(",") for line in (REAL / "exampleData.csv").read_text().splitlines() if line.strip()]
    days[1].write_text("".join(f"{f},{float(re) * 1.01!r},{float(im) * 1.01!r}\n" for f, re, im in rows))
    series = tmp_path / "series.nc"
    stacked = run_command(["stack", *days, "--out", series], tmp_path)
    assert stacked["code"] == 0 and not stacked["jax"] and series.stat().st_size > 0


def test_inspect_reads_real_files_without_jax(tmp_path):
    """`impedax inspect` of REAL files (impedance.py's ZPlot .z with --json, AutoEIS's battery
    cycles in netCDF) reads and describes them; until 2026-12-06 its closing "next:" line took
    the KK test's and the DRT's fewest frequencies from impedax.fitting, which loads JAX."""
    zplot = run_command(["inspect", REAL / "exampleDataZPlot.z", "--json"], tmp_path)
    assert zplot["code"] == 0 and not zplot["jax"]
    rows = (REAL / "exampleDataZPlot.z").read_text().split("End Comments\n")[1].split("\n")
    assert json.loads(zplot["out"])["points"] == len([row for row in rows if row.strip()]) == 21
    cycles = run_command(["inspect", ROOT / "examples" / "data" / "autoeis_battery_cycles.nc"], tmp_path)
    assert cycles["code"] == 0 and not cycles["jax"] and "next: impedax kk" in cycles["out"]


@pytest.mark.parametrize("command", list(COMMAND_HELP))
def test_a_commands_help_does_not_import_jax(command, tmp_path):
    """``impedax COMMAND --help`` prints the command's options without importing JAX; until
    2026-12-06 `force --help` imported it (with impedax.models and impedax.fitting) for a 1 %
    plateau threshold its peak line quotes, and `sample --help` for the sampler's noise models,
    prior kinds and chain lengths, which now live in impedax.arguments."""
    result = run_command([command, "--help"], tmp_path)
    assert result["code"] == 0 and f"usage: impedax {command}" in result["out"] and not result["jax"]


def test_the_circuits_package_loads_jax_with_its_compiled_forms_only(tmp_path):
    """Parsing and converting leave JAX unloaded; a compiled form (here through ``from
    impedax.circuits import *``, which lists them in ``__all__``) loads it and evaluates R0 + C1
    as 50 − j/(2π·1 kHz·1 µF) = 50 − 159.15 j Ω."""
    result = fresh_process("""
import json, sys
import impedax.circuits as circuits
names = circuits.parse("R0 + C1").parameter_names(), circuits.to_cdc(circuits.from_impedance_py("R0-p(R1,C1)"))
before = "jax" in sys.modules
from impedax.circuits import *
z = complex(compile_circuit(parse("R0 + C1"))({"R0": 50.0, "C1": 1e-6}, [1e3])[0])
print(json.dumps({"names": names, "jax_before": before, "z": [z.real, z.imag]}))
""")
    assert result["names"] == [["R0", "C1"], "R(RC)"] and not result["jax_before"]
    assert result["z"] == pytest.approx([50.0, -1 / (2 * 3.141592653589793 * 1e3 * 1e-6)], rel=1e-12)


def test_a_least_squares_fit_imports_neither_the_sampler_nor_the_diagnosis():
    """``from impedax import fit`` (as `impedax fit` does) loads the least-squares fitter and
    what it uses, not the Bayesian sampler, the diagnosis nor the comparison:
    until 2026-12-06 impedax.fitting imported all of them at once. Named later, each is there,
    and `compare` brings the batch comparison with it (its batch path is registered)."""
    result = fresh_process("""
import json, sys
from impedax import fit
loaded = lambda: sorted({".".join(m.split(".")[:3]) for m in sys.modules if m.startswith("impedax.fitting.")})
with_fit = loaded()
import impedax.fitting as fitting
from impedax.fitting import compare, diagnose, sample
print(json.dumps({"with_fit": with_fit, "later": loaded(), "compare_is_registered": fitting.comparison._batch_compare is fitting.batch_comparison.compare_batches,
                  "kk_count": fitting.kk.CONCLUSIVE_POINTS_MIN,
                  "drt_is_the_function": callable(fitting.drt) and fitting.drt.__name__ == "drt"}))
""")
    for unused in ("bayes", "diagnosis", "comparison", "batch_comparison", "derived"):
        assert f"impedax.fitting.{unused}" not in result["with_fit"]
        assert unused == "derived" or f"impedax.fitting.{unused}" in result["later"]
    assert "impedax.fitting.least_squares" in result["with_fit"]
    assert result["compare_is_registered"] and result["kk_count"] == 10 and result["drt_is_the_function"]


def test_sample_help_quotes_the_samplers_vocabulary_without_jax(tmp_path):
    """`impedax sample --help` names the four prior kinds, the two noise models and the chain
    lengths docs/bayesian.md gives (50 autocorrelation times, at most 20000 steps), with JAX
    unloaded; the sampler reads the same objects (one definition, in impedax.arguments)."""
    result = run_command(["sample", "--help"], tmp_path)
    assert result["code"] == 0 and not result["jax"]
    text = " ".join(result["out"].split())
    for words in ("uniform:LO,HI", "loguniform:LO,HI", "normal:MU,SD", "lognormal:MEDIAN,S", "proportional:", "sigma:", "50 autocorrelation times", "at most 20000"):
        assert words in text, words
    import impedax.arguments as arguments
    from impedax.fitting.bayes import chain, diagnostics, logprob, priors

    assert logprob.NOISE_MODELS is arguments.NOISE_MODELS and priors.PRIOR_KINDS is arguments.PRIOR_KINDS
    assert chain.AUTO_MAX_STEPS == arguments.AUTO_MAX_STEPS == 20_000 and diagnostics.CHAIN_TAU_MULTIPLE == 50
