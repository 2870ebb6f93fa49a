"""`impedax sample --fix/--init/--max-steps`: the options its own warnings name ("raise
--max-steps or give better starting values"), as `impedax fit` has them. Oracle: a SYNTHETIC
R0 + R1 ∥ C1 spectrum written here (R0 = 10 Ω, R1 = 100 Ω, C1 = 1 µF, 1 % noise)."""

import json

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

F = np.geomspace(1.0, 1e5, 30)


@pytest.fixture(scope="module")
def spectrum(tmp_path_factory):
    rng = np.random.default_rng(3)
    z = 10.0 + 100.0 / (1 + 2j * np.pi * F * 100.0 * 1e-6)
    z = z * (1 + 0.01 * (rng.normal(size=F.size) + 1j * rng.normal(size=F.size)) / np.sqrt(2))
    path = tmp_path_factory.mktemp("sample") / "rc.csv"
    ix.save(ix.make_spectrum(F, z), path)
    return path


def _json(capsys, *argv):
    assert main(["sample", *map(str, argv), "--json", "--steps", "200", "--walkers", "16"]) == 0
    return json.loads(capsys.readouterr().out)


def test_fix_holds_a_parameter_in_the_start_and_the_sampling(capsys, spectrum):
    out = _json(capsys, spectrum, "--model", "R0 + R1 || C1", "--fix", "R0=12")
    assert "R0" not in out["params"] and {"R1", "C1"} <= set(out["params"])
    assert out["fixed"] == {"R0": 12.0}  # (the text's "(fixed)" row; it was in no JSON key)
    free = _json(capsys, spectrum, "--model", "R0 + R1 || C1")
    assert free["fixed"] == {}
    # R0 held 2 Ω above its value: R1 takes up the difference at low frequency (R0 + R1 ≈ 110 Ω)
    assert out["params"]["R1"]["median"] < free["params"]["R1"]["median"] - 1.0


def test_init_and_max_steps_set_the_least_squares_start(capsys, spectrum):
    out = _json(capsys, spectrum, "--model", "R0 + R1 || C1", "--init", "R1=90", "--init", "C1=2u", "--max-steps", "800")
    assert out["params"]["R1"]["median"] == pytest.approx(100.0, rel=0.05)


@pytest.mark.parametrize(
    "argv, says",
    [
        (["--fix", "R9=1"], "--fix: unknown parameter 'R9'"),
        (["--init", "R1=90", "--shared", "R0", "--over", "trial"], "--init and --max-steps are not available with --shared"),
        (["--max-steps", "0"], "--max-steps must be at least 1"),
    ],
)
def test_bad_options_are_one_message(capsys, spectrum, argv, says):
    assert main(["sample", str(spectrum), "--model", "R0 + R1 || C1", *argv]) == 2
    assert says in capsys.readouterr().err


def test_prior_bounds_take_si_prefixes(capsys, spectrum):
    out = _json(capsys, spectrum, "--model", "R0 + R1 || C1", "--prior", "R1=loguniform:10,1k")
    assert out["params"]["R1"]["prior"] == "loguniform:10,1000"
    assert main(["sample", str(spectrum), "--model", "R0 + R1 || C1", "--prior", "R1=loguniform:1k,10"]) == 2
    assert "'R1=loguniform:1k,10'" in capsys.readouterr().err  # (the error quotes what was typed)
