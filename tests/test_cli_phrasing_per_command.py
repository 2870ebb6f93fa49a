"""A command's report and errors name only options that command has: the Python keywords of the
fitting code's messages become flags (``weighting='modulus'`` → ``--weighting modulus``) only
where the command's own parser accepts them (`impedax.cli.common.command_line_words`,
`option_words`). Until 2026-12-01 ``impedax gap`` told its user to "consider --weighting
modulus", an option gap refuses."""

import argparse
import re

import numpy as np
import pytest

import impedax as ix
from impedax.cli import _COMMAND_MODULES, build_parser, main
from impedax.cli.common import OPTION_OF_KEYWORD_BY_COMMAND, command_line_words, option_words
from impedax.cli import common
from impedax.errors import ParameterError

# a warning of the EDL fit as `gap_analysis` passes it on (`FitResult` warning + solver status)
EDL_WARNING = "EDL fit: the fit is dominated by them; consider weighting='modulus'; the solver reached its step limit; raise max_steps"


def parser_options(command: str) -> set[str]:
    """The option strings of ``impedax command``, read from its real argparse parser (the
    oracle: independent of `common.command_options`)."""
    parser = build_parser(command)
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices[command]
    return {s for action in sub._actions for s in action.option_strings}


def every_trigger() -> str:
    """One text holding every Python phrase or keyword the phrasing translates."""
    return "; ".join([*common._PHRASE_OF_CALL, common._INIT_PHRASE[0], "fix it with fixed={'C_i': VALUE}", "consider weighting='modulus'", "raise max_steps",
                      "use noise='proportional' otherwise", "(over='session', or several: over=['session', 'trial'])", "the steps steps='auto' runs"])


def produced_flags(before: str, after: str) -> set[tuple[str, str | None]]:
    """The flags in ``after`` that ``before`` did not name, each with the command another
    command's flag belongs to (``impedax fit --init``: ``fit``), else None."""
    named = set(re.findall(r"--[a-z][\w-]*", before))
    found = {(flag, other) for other, flag in re.findall(r"(?:impedax (\w+) )?(--[a-z][\w-]*)", after)}
    return {(flag, other or None) for flag, other in found if flag not in named}


@pytest.mark.parametrize("command", _COMMAND_MODULES)
def test_every_flag_the_phrasing_produces_is_an_option_of_the_command(command):
    options = parser_options(command)
    # the keyword map itself
    assert set(OPTION_OF_KEYWORD_BY_COMMAND.get(command, {}).values()) <= options
    text = every_trigger()
    errors = [ParameterError(f"{k} must be positive; {text}") for k in OPTION_OF_KEYWORD_BY_COMMAND.get(command, {})] or [ParameterError(text)]
    for before, after in [(text, command_line_words(text, command))] + [(str(e), option_words(command, e)) for e in errors]:
        for flag, other in produced_flags(before, after):
            assert flag in (parser_options(other) if other else options), f"impedax {command} would name {flag}: {after}"


def test_gap_keeps_python_keywords_it_has_no_option_for():
    out = command_line_words(EDL_WARNING, "gap")
    assert "consider weighting='modulus'" in out and "raise max_steps" in out
    assert "--weighting" not in out and "--max-steps" not in out
    assert command_line_words("keep C_i with fixed={'C_i': VALUE} (bounds=)", "gap") == "keep C_i with fixed={'C_i': VALUE} (bounds=)"
    # the commands that have the options still name them
    assert command_line_words(EDL_WARNING, "fit").endswith("consider --weighting modulus; the solver reached its step limit; raise --max-steps")
    sampled = command_line_words(EDL_WARNING, "sample")  # sample: --max-steps, no --weighting
    assert "weighting='modulus'" in sampled and "raise --max-steps" in sampled
    assert command_line_words("keep C_i with fixed={'C_i': VALUE} (bounds=)", "diagnose") == "keep C_i with --fix C_i=VALUE (--bound)"
    # the refinement's "(pass init=)" becomes the fit command only where it is printed
    assert "impedax fit --init" in command_line_words("x (pass init=)", "refine")
    assert command_line_words("x (pass init=)", "fit") == "x (pass init=)"


def rc_spectrum(freq, r, c, rng):
    """SYNTHETIC: R || C with 0.5 % complex Gaussian noise."""
    z = r / (1 + 2j * np.pi * freq * r * c)
    return z * (1 + 0.005 * (rng.standard_normal(freq.size) + 1j * rng.standard_normal(freq.size)))


def test_gap_report_names_no_option_gap_refuses(tmp_path, monkeypatch, capsys):
    import impedax.models.gap as gap_module

    rng = np.random.default_rng(7)
    freq = np.logspace(1, 5, 20)
    paths = []
    for name, r in (("total", 3e5), ("skin", 1e5), ("ts", 1e5)):
        paths.append(str(tmp_path / f"{name}.nc"))
        ix.save(ix.make_spectrum(freq, np.stack([rc_spectrum(freq, r, 1e-10, rng) for _ in range(3)]), dims=("trial",), coords={"trial": [0, 1, 2]}), paths[-1])

    class Stub:  # the analysis replaced: its report carries the EDL fit's warning
        warnings = (EDL_WARNING,)
        plot = None

        def summary(self):
            return {"warnings": list(self.warnings)}

        def report(self):
            return f"warning: {EDL_WARNING}"

    monkeypatch.setattr(gap_module, "gap_analysis", lambda *a, **k: Stub())
    assert main(["gap", *paths, "--area", "130e-6", "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "consider weighting='modulus'" in out and "--weighting" not in out and "--max-steps" not in out
    for flag in re.findall(r"--[a-z][\w-]*", out):
        assert flag in parser_options("gap")


def two_dimensional(tmp_path):
    """SYNTHETIC R ∥ CPE (R = 100 Ω, Q = 1 µF s^(α−1), α = 0.9) plus 10 Ω over session × trial,
    saved as netCDF."""
    f = np.geomspace(1, 1e5, 20)
    z = 10 + 100 / (1 + 100 * 1e-6 * (2j * np.pi * f) ** 0.9)
    path = str(tmp_path / "rem.nc")
    ix.save(ix.make_spectrum(f, np.broadcast_to(z, (2, 2, f.size)).copy(), dims=("session", "trial"), coords={"session": [0, 1], "trial": [0, 1]}), path)
    return path


@pytest.mark.parametrize("command", ["fit", "sample"])
def test_shared_over_several_dimensions_names_the_over_option(tmp_path, capsys, command):
    """Data with two extra dimensions and no --over: the command line says --over (2026-12-03:
    it said "(over='session' or a list)"); the Python API keeps its keyword."""
    path = two_dimensional(tmp_path)
    assert main([command, path, "--model", "R0 + R1 || CPE1", "--shared", "CPE1.alpha", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.strip() == (f"impedax {command}: error: --over: the data have several extra dimensions (session, trial); "
                           "say which the parameters are shared over (--over session, or several: --over session,trial)")
    with pytest.raises(ParameterError, match=re.escape("(over='session', or several: over=['session', 'trial'])")):
        ix.fit("R0 + R1 || CPE1", ix.load(path), shared=["CPE1.alpha"])


def test_sample_noise_sigma_without_sigma_names_the_noise_option(capsys):
    """--noise sigma on a file without σ: the option's words, not noise='sigma' (2026-12-03:
    "--noise='sigma' needs ...; use noise='proportional' otherwise")."""
    assert main(["sample", "tests/fixtures/real/exampleDataBioLogic.mpt", "--model", "R0 + R1 || CPE1", "--noise", "sigma", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert ": --noise sigma needs a 'sigma' variable in the data" in err and err.rstrip().endswith("or a 'sigma' variable of a netCDF file; use --noise proportional otherwise")
    assert "noise='" not in err and "make_spectrum" not in err
