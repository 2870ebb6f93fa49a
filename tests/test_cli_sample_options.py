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


def _nothing_computed(monkeypatch):
    """`impedax.fit` and `impedax.sample` replaced by functions that fail the test if called."""

    def computed(*args, **kwargs):
        raise AssertionError("the start fit or the sampling ran before the option was checked")

    monkeypatch.setattr(ix, "fit", computed)
    monkeypatch.setattr(ix, "sample", computed)


@pytest.mark.parametrize(
    "argv, says",
    [
        (["--corner-params", "R7", "--init", "R1=90"], "--corner-params: unknown parameter 'R7' (parameters: R0, R1, C1, sigma_rel)"),
        (["--corner-params", "R0", "--fix", "R0=10", "--init", "R1=90"], "--corner-params: R0 is fixed (--fix), not sampled; the sampled parameters: R1, C1, sigma_rel"),
        (["--corner-params", "R1[trial=1]", "--shared", "R1"], "--corner-params: unknown parameter 'R1[trial=1]' (parameters: R1, R0[LABEL], C1[LABEL], sigma_rel)"),
    ],
)
def test_an_unknown_corner_parameter_is_refused_before_any_work(capsys, monkeypatch, spectrum, tmp_path, argv, says):
    """``--corner-params R7`` was refused only after the start fit and the sampler's compilation
    (the README: such errors come "before any work"; walkthrough 2026-12-06). The names the
    posterior will have, listed by hand: R0 + R1 ∥ C1's free parameters and sigma_rel."""
    _nothing_computed(monkeypatch)
    png = tmp_path / "c.png"
    assert main(["sample", str(spectrum), "--model", "R0 + R1 || C1", "--corner", str(png), *argv]) == 2
    assert says in capsys.readouterr().err and not png.exists()


@pytest.mark.parametrize("names", ["R1,sigma_rel", "C1,R0"])
def test_known_corner_parameters_pass_the_early_check(monkeypatch, spectrum, tmp_path, names):
    """The names the posterior has reach the start fit (which stands in here, raising)."""
    _nothing_computed(monkeypatch)
    with pytest.raises(AssertionError, match="the start fit or the sampling ran"):
        main(["sample", str(spectrum), "--model", "R0 + R1 || C1", "--init", "R1=90", "--corner", str(tmp_path / "c.png"), "--corner-params", names])


CYCLES = __import__("pathlib").Path(__file__).parents[1] / "examples" / "data" / "autoeis_battery_cycles.nc"


def test_a_corner_label_the_data_lack_is_refused_before_the_sampling(capsys, monkeypatch, tmp_path):
    """``--shared`` with ``--corner-params R1[cycle=65]`` on the REAL battery cycles (cycles 0, 64
    and 129 in the file) was refused only after the whole sampling; now once the data are read."""
    _nothing_computed(monkeypatch)
    png = tmp_path / "c.png"
    argv = ["sample", str(CYCLES), "--model", "R0 + R1 || C1", "--shared", "R0", "--corner", str(png)]
    assert main([*argv, "--corner-params", "R0,R1[cycle=65]"]) == 2
    err = capsys.readouterr().err
    assert "R1[cycle=65]" in err and "cycle=0, cycle=64, cycle=129" in err and "Traceback" not in err and not png.exists()
    with pytest.raises(AssertionError, match="the start fit or the sampling ran"):  # (a label of the data passes)
        main([*argv, "--corner-params", "R0,R1[cycle=64]"])


@pytest.mark.parametrize("bound, prior, said", [
    ("R1=1:10", "R1=uniform:1k,2k", "--prior R1=uniform:1000,2000 reaches outside R1's bounds (1, 10) set by --bound R1=1:10"),
    ("R1=1:10", "R1=loguniform:0.5,5", "--prior R1=loguniform:0.5,5 reaches outside R1's bounds (1, 10) set by --bound R1=1:10"),
])
def test_a_prior_outside_the_bound_names_both_options(capsys, spectrum, bound, prior, said):
    """A hostile walkthrough (2026-12-08): the sampler's words, "prior for R1: uniform:1000,2000
    reaches outside the parameter's bounds (1, 10)", named neither --prior nor --bound."""
    code = main(["sample", str(spectrum), "--model", "R0 + R1 || C1", "--bound", bound, "--prior", prior, "--steps", "20"])
    out, err = capsys.readouterr()
    assert code == 2 and out == "" and err == f"impedax sample: error: {said}\n"


def test_a_bound_up_to_the_elements_own_upper_end_keeps_a_prior_up_to_it(capsys, monkeypatch, spectrum):
    """α of a CPE is bounded (0, 1] by its element: a prior uniform:0.5,1 is taken. ``--bound
    CPE1.alpha=0.4:1`` narrows the lower end only, yet its upper end 1 was excluded, as a user
    bound's upper end is, so the same prior was refused (the adversarial walk of 2026-12-08). A
    bound that ends below 1 still refuses it."""
    argv = ["sample", str(spectrum), "--model", "R0 + R1 || CPE1", "--prior", "CPE1.alpha=uniform:0.5,1", "--steps", "20"]
    assert main([*argv, "--bound", "CPE1.alpha=0.4:0.95"]) == 2
    assert capsys.readouterr().err == "impedax sample: error: --prior CPE1.alpha=uniform:0.5,1 reaches outside CPE1.alpha's bounds (0.4, 0.95) set by --bound CPE1.alpha=0.4:0.95\n"
    _nothing_computed(monkeypatch)
    with pytest.raises(AssertionError, match="the start fit or the sampling ran"):  # (the options pass their checks)
        main([*argv, "--bound", "CPE1.alpha=0.4:1"])


def test_the_sampler_takes_a_prior_up_to_a_bound_at_the_elements_own_upper_end(spectrum):
    """The same in Python: ``bounds={"CPE1.alpha": (0.4, 1)}`` with a prior up to 1 samples, and
    every draw of α lies within the prior's support [0.5, 1]."""
    post = ix.sample("R0 + R1 || CPE1", spectrum, bounds={"CPE1.alpha": (0.4, 1.0)}, priors={"CPE1.alpha": "uniform:0.5,1"}, steps=200, walkers=16, seed=1, progress=False)
    alpha = np.asarray(post.samples["CPE1.alpha"])
    assert alpha.size > 0 and alpha.min() >= 0.5 and alpha.max() <= 1.0
