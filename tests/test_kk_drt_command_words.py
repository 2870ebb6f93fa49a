"""The notes of `impedax kk` (linear and Z-HIT) and `impedax drt` speak the command's words on the
command line and Python's in the Python API, as fit's and diagnose's do: until 2026-12-06 they
said both ("need γ < 0 somewhere (signed=True, --signed)", "give a smaller λ (lam, --lam) or let
it be chosen (lam='auto', --lam auto)"), and some Python notes the options alone ("leave them out
with --fmin/--fmax", the batch DRT's "(--lam)"). Oracles: the Python keywords are the parameters
of `kk_test`, `zhit` and `drt` (`inspect.signature`), the options those of the commands' parsers;
REAL files whose outputs hold each note (PowerSuite: R_inf < 0, Re Z < 0, a misfit; Gamry: a
misfit, a dropped peak, a band from the low end; BioLogic: points to leave out), the REAL battery
cycles for the batch DRT, and SYNTHETIC spectra for the sigma line and an over-smoothing λ."""

import inspect
import json
import re

import numpy as np
import pytest

import impedax as ix
from cli_run import run
from impedax.cli.common import command_line_words, command_options
from impedax.fitting import drt, kk_test, zhit

REAL = "tests/fixtures/real/"
KEYWORDS = sorted({name for f in (kk_test, zhit, drt) for name in inspect.signature(f).parameters if name != "data"}, key=len, reverse=True)
PYTHON_KEYWORD = re.compile(r"(?<![\w.-])(" + "|".join(KEYWORDS) + r")=")  # (name=value of a Python argument)
PYTHON_CALL = re.compile(r"\b(data|result)\.\w+|\bkk_test\(")
OPTIONS = sorted((command_options("kk") | command_options("drt")) - {"-h", "--help", "-q"}, key=len, reverse=True)
CLI_FLAG = re.compile(r"(?<![\w-])(" + "|".join(map(re.escape, OPTIONS)) + r")(?![\w-])")


def _sigma_file(tmp_path):
    """SYNTHETIC R0 + R1 ∥ C1 (20 Ω, 500 Ω, 1 µF) with 0.5 % noise and its σ column."""
    f = np.geomspace(1.0, 1e5, 40)
    z = 20.0 + 500.0 / (1 + 2j * np.pi * f * 500.0 * 1e-6)
    sigma = 0.005 * np.abs(z)
    z = z + sigma * (np.random.default_rng(1).standard_normal(f.size) + 1j * np.random.default_rng(2).standard_normal(f.size))
    path = tmp_path / "sigma.csv"
    np.savetxt(path, np.c_[f, z.real, z.imag, sigma], delimiter=",", header="frequency_hz,z_real_ohm,z_imag_ohm,sigma_ohm", comments="")
    return path


CLI_CASES = [
    ("kk", REAL + "exampleDataPowersuite.txt"),
    ("kk", REAL + "exampleDataGamry.DTA"),
    ("kk", REAL + "exampleDataBioLogic.mpt"),
    ("kk", REAL + "exampleDataPowersuite.txt", "--method", "zhit"),
    pytest.param(("drt", REAL + "exampleDataPowersuite.txt"), marks=pytest.mark.slow),  # (~4 s each, twice a DRT and its KK check)
    pytest.param(("drt", REAL + "exampleDataGamry.DTA"), marks=pytest.mark.slow),
    pytest.param(("drt", "examples/data/autoeis_battery_cycles.nc", "--lam", "10"), marks=pytest.mark.slow),
]


@pytest.mark.parametrize("argv", CLI_CASES, ids=lambda a: " ".join(str(w).rpartition("/")[2] for w in a))
def test_the_command_line_names_no_python_keyword(argv, capsys):
    for extra in ([], ["--json"]):
        code, out, err = run([*argv, *extra], capsys)
        assert code == 0, err
        if extra:
            json.loads(out)
        for line in (out + err).splitlines():
            assert not PYTHON_KEYWORD.search(line), line
            assert not PYTHON_CALL.search(line), line


def test_the_commands_say_their_options_where_python_says_keywords(capsys):
    """The words each note gives on the command line (REAL PowerSuite and Gamry; the batch DRT of
    the REAL battery cycles at λ = 10)."""
    out = run(["drt", REAL + "exampleDataPowersuite.txt"], capsys)[1]
    assert "leave the top points out (--fmax)" in out and "or need γ < 0 somewhere (--signed)" in out
    assert "dropped" not in out or ": --min-peak-fraction)" in out
    out = run(["drt", REAL + "exampleDataGamry.DTA"], capsys)[1]
    assert "5 % when resolved: --min-peak-fraction) dropped" in out
    out = run(["kk", REAL + "exampleDataPowersuite.txt", "--json"], capsys)[1]
    assert any(n.endswith("leave them out with --fmin/--fmax") for n in json.loads(out)["notes"])
    out = run(["kk", REAL + "exampleDataGamry.DTA"], capsys)[1]
    assert "from the low end through it (--fmin) would keep 20" in out
    out = run(["drt", "examples/data/autoeis_battery_cycles.nc", "--lam", "10"], capsys)[1]
    assert "give a smaller λ (--lam) or let it be chosen (--lam auto)" in out


def test_the_sigma_line_says_the_option(tmp_path, capsys):
    code, out, _ = run(["kk", _sigma_file(tmp_path), "--noise", "sigma"], capsys)
    assert code == 0
    (line,) = [x for x in out.splitlines() if x.startswith("noise: the data's sigma")]
    assert "impedax kk --noise residuals judges by the noise estimate instead" in line and "kk_test(" not in line


def test_a_drt_failure_message_in_the_command_words():
    """The DRT solve's failure (`drt._drt`) on the command line, by hand."""
    python = "give a fixed λ (lam=1e-3) or lam_method='lcurve'"
    assert command_line_words(python, "drt") == "give a fixed λ (--lam 1e-3) or --lam-method lcurve"
    assert command_line_words("the rule that chooses λ is lam_method='gcv' (with lam='auto')", "drt") == "the rule that chooses λ is --lam-method gcv (with --lam auto)"
    assert command_line_words(python, "gap") == python  # (gap has neither option: Python's words stay)


def _notes(result):
    """The prose a result's summary holds (notes, warnings, hints, λ's note)."""
    s = result.summary()
    out = [*s.get("notes", ()), *s.get("warnings", ())]
    return out + [s[k] for k in ("sign_hint", "lambda_note") if s.get(k)]


def _report_lines(result):
    """The report's lines that are no ``impedax`` command line (the batch's ``next: impedax kk
    FILE --select …`` names a command to run, with its options)."""
    return [line for line in result.report().splitlines() if "impedax kk " not in line]


@pytest.mark.parametrize("name", ["exampleDataPowersuite.txt", pytest.param("exampleDataGamry.DTA", marks=pytest.mark.slow), pytest.param("exampleDataBioLogic.mpt", marks=pytest.mark.slow)])
def test_the_python_api_names_no_option(name):
    data = ix.load(REAL + name)
    for result in (kk_test(data, find_passing_band=True), zhit(data), drt(data), drt(data, signed=True)):
        for text in [*_notes(result), *_report_lines(result)]:
            assert not CLI_FLAG.search(text), text


def test_the_python_api_says_keywords_that_run(tmp_path):
    """The Python words are calls that work: the points the notes name are dropped by them
    (REAL PowerSuite, Re Z < 0 at 1.12 and 2 MHz; REAL BioLogic, four points to leave out)."""
    data = ix.load(REAL + "exampleDataPowersuite.txt")
    result = kk_test(data)
    assert any(n.endswith("leave them out (data.drop_sel(frequency=result.non_passive_frequencies))") for n in result.notes)
    assert data.drop_sel(frequency=result.non_passive_frequencies).sizes["frequency"] == data.sizes["frequency"] - 2
    data = ix.load(REAL + "exampleDataBioLogic.mpt")
    result = kk_test(data)
    assert "next: leave them out and test again: kk_test(data.drop_sel(frequency=result.excludable_frequencies))" in result.report()
    assert data.drop_sel(frequency=result.excludable_frequencies).sizes["frequency"] == data.sizes["frequency"] - 4  # (5.34, 56.2, 123, 270 Hz: docs/kk.md)
    sigma = kk_test(ix.load(_sigma_file(tmp_path)), noise="sigma")
    assert "kk_test(noise='residuals') judges by the noise estimate instead" in sigma.report()
    batch = drt(ix.load("examples/data/autoeis_battery_cycles.nc"), lam=10.0)
    assert "give a smaller λ (lam) or let it be chosen (lam='auto')" in batch.report()
