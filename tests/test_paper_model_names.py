"""A paper model's name (meyer, meyer-rc, meyer-cpe) in every command that takes a model, not
only ``impedax simulate``: fit, sample, compare, diagnose, refine, info and draw read it as
Meyer's circuit, and the commands that fit start from the thesis's eq 3.13 values (never fixed;
--init overrides). The oracles: the thesis's circuit written in numpy,
Z = 1/(jωC_s) + 1/(jωC_i) + R_sc/(1 + jωR_sc C_sc) + R_f, with eq 3.13's values (C_s = 140 pF,
C_i = 1.7 nF, R_sc = 130 kΩ, C_sc = 2.2 nF, R_f = 500 Ω; /work/shared/PHYSICS.md), on a SYNTHETIC
spectrum whose truth a fit must recover (C_s and C_i in series are seen as their series
capacitance only)."""

import json

import numpy as np
import pytest

from cli_run import run

THESIS = {"C_s": 140e-12, "C_i": 1.7e-9, "R_sc": 130e3, "C_sc": 2.2e-9, "R_f": 500.0}  # eq 3.13, rounded
TRUTH = {"C_s": 120e-12, "C_i": 1.7e-9, "R_sc": 90e3, "C_sc": 3.1e-9, "R_f": 800.0}  # away from the thesis: the fit must move
MEYER = "C_s + C_i + R_sc || C_sc + R_f"


def meyer_z(f, p):
    s = 2j * np.pi * f
    return 1 / (s * p["C_s"]) + 1 / (s * p["C_i"]) + p["R_sc"] / (1 + s * p["R_sc"] * p["C_sc"]) + p["R_f"]


@pytest.fixture(scope="module")
def synthetic(tmp_path_factory):
    """A SYNTHETIC noise-free spectrum of Meyer's circuit at `TRUTH`, 10 Hz–1 MHz."""
    f = np.logspace(1, 6, 31)
    z = meyer_z(f, TRUTH)
    path = tmp_path_factory.mktemp("meyer") / "meyer.csv"
    path.write_text("frequency_hz,z_real_ohm,z_imag_ohm\n" + "".join(f"{float(a)!r},{float(b.real)!r},{float(b.imag)!r}\n" for a, b in zip(f, z)))
    return path


def _values(summary):
    return {k: v["value"] for k, v in summary["params"].items()}


def _series(p):
    return 1 / (1 / p["C_s"] + 1 / p["C_i"])


def test_fit_takes_meyer_and_recovers_the_synthetic_truth(synthetic, capsys):
    code, out, err = run(["fit", synthetic, "--model", "meyer", "--json"], capsys)
    assert code == 0, err
    summary = json.loads(out)
    assert summary["paper_model"] == "meyer" and summary["model"] == MEYER
    got = _values(summary)
    for name in ("R_sc", "C_sc", "R_f"):
        assert got[name] == pytest.approx(TRUTH[name], rel=1e-6), name
    assert _series(got) == pytest.approx(_series(TRUTH), rel=1e-6)
    # said once on stderr: the thesis's values start the fit, they are not held
    assert err.count("thesis's eq 3.13 values") == 1
    assert "starting values, not fixed ones: C_s = 140 pF, C_i = 1.7 nF, R_sc = 130 kΩ, C_sc = 2.2 nF, R_f = 500 Ω" in err


def test_fit_of_meyer_is_fit_of_its_circuit_from_the_thesis_values(synthetic, capsys):
    """The name is the circuit started at eq 3.13's values: the same fit as the circuit typed with
    those values as --init."""
    code, out, err = run(["fit", synthetic, "--model", "Meyer-RC", "--init", "R_sc=50k", "--json"], capsys)
    assert code == 0, err
    named = json.loads(out)
    assert "--init gives R_sc" in err and "R_sc = 130 kΩ" not in err
    inits = [f"{k}={v!r}" for k, v in {**THESIS, "R_sc": 50e3}.items()]
    code, out, err = run(["fit", synthetic, "--model", MEYER, "--init", *inits, "--json"], capsys)
    assert code == 0, err
    typed = json.loads(out)
    assert "paper_model" not in typed and "thesis" not in err
    assert _values(named) == pytest.approx(_values(typed), rel=1e-12)


def test_a_fixed_or_bounded_parameter_takes_no_thesis_start(synthetic, capsys):
    code, out, err = run(["fit", synthetic, "--model", "meyer", "--fix", "R_f=800", "--bound", "R_sc=10k:1M", "--json"], capsys)
    assert code == 0, err
    got = _values(json.loads(out))
    assert got["R_f"] == 800.0 and got["R_sc"] == pytest.approx(TRUTH["R_sc"], rel=1e-6)
    # (stderr's note lists the thesis starts it uses: not R_f's 500 Ω, which --fix holds at 800 Ω,
    # nor R_sc's 130 kΩ, which --bound starts from the data; walkthrough 2026-12-07)
    note = next(line for line in err.splitlines() if "thesis's eq 3.13 values" in line)
    assert "R_f = 500 Ω" not in note and "R_sc = 130 kΩ" not in note and "C_sc = 2.2 nF" in note
    assert note.endswith("(--fix holds R_f; R_sc under --bound starts from the data, within its range)")


def test_meyer_cpe_names_the_fractional_circuit(capsys):
    code, out, err = run(["info", "meyer-cpe", "--json"], capsys)
    assert code == 0, err
    assert json.loads(out)["model"] == "C_s + C_i + R_sc || CPE_sc + R_f"


def test_compare_takes_a_name_beside_a_circuit(synthetic, capsys):
    code, out, err = run(["compare", synthetic, "--model", "meyer", "--model", "C_s + R_sc || C_sc + R_f", "--json"], capsys)
    assert code == 0, err
    summary = json.loads(out)
    assert summary["paper_model"] == {MEYER: "meyer"}
    assert err.count("thesis's eq 3.13 values") == 1


def test_an_unknown_name_is_still_refused(synthetic, capsys):
    code, out, err = run(["fit", synthetic, "--model", "meyerr"], capsys)
    assert code == 2 and "Traceback" not in err and "thesis" not in err


def test_sample_starts_its_start_fit_from_the_thesis_values(synthetic, capsys):
    """sample --model meyer is sample of the circuit with eq 3.13's values as --init (same seed:
    the same draws), and its JSON names the paper model."""
    common = ["--steps", "20", "--walkers", "12", "--seed", "3", "--quiet", "--json"]
    code, out, err = run(["sample", synthetic, "--model", "meyer", *common], capsys)
    assert code == 0, err
    named = json.loads(out)
    assert named["paper_model"] == "meyer" and err.count("thesis's eq 3.13 values") == 1
    code, out, err = run(["sample", synthetic, "--model", MEYER, "--init", *[f"{k}={v!r}" for k, v in THESIS.items()], *common], capsys)
    assert code == 0, err
    typed = json.loads(out)
    assert "paper_model" not in typed
    assert {k: v["median"] for k, v in named["params"].items()} == pytest.approx({k: v["median"] for k, v in typed["params"].items()}, rel=1e-12)


def test_diagnose_reads_the_name_and_says_its_start_is_the_datas(synthetic, capsys):
    """diagnose (and refine, which shares its reading) take the name as the circuit; their
    baseline fit guesses its start as for any circuit, and stderr says so."""
    code, out, err = run(["diagnose", synthetic, "--model", "meyer", "--quiet", "--json"], capsys)
    assert code == 0, err
    summary = json.loads(out)
    assert summary["paper_model"] == "meyer"
    assert f"meyer is {MEYER}; the fit starts from values guessed from the data" in err


def test_force_takes_meyer_rc_and_meyer_cpe_as_meyers_variants(capsys):
    """force's MODEL takes the same names: meyer-rc is thesis Fig 3.4's force (164 mN peak near
    37 kHz with eq 3.13's values), meyer-cpe is meyer --variant cpe."""
    code, out, err = run(["force", "Meyer-RC", "--json"], capsys)
    assert code == 0, err
    doc = json.loads(out)
    assert doc["model"] == "meyer" and doc["variant"] == "rc"
    assert doc["peak"]["force_n"] == pytest.approx(0.164, abs=0.5e-3) and doc["peak"]["frequency_hz"] == pytest.approx(37e3, rel=0.03)
    code, out, err = run(["force", "meyer-cpe", "--json"], capsys)
    assert code == 0, err
    named = json.loads(out)
    code, out, err = run(["force", "meyer", "--variant", "cpe", "--json"], capsys)
    assert code == 0, err
    assert named["variant"] == "cpe" and named["peak"] == json.loads(out)["peak"]
    code, out, err = run(["force", "meyer-rc", "--variant", "cpe"], capsys)
    assert code == 2 and "--variant cpe names the other" in err and len(err.strip().splitlines()) == 1


def test_a_shared_fit_takes_the_thesis_start_too(tmp_path, capsys):
    """fit --shared (one global solve) starts from eq 3.13's values as a single fit does, and
    recovers a SYNTHETIC pair whose R_f and C_sc are shared and R_sc differs."""
    import impedax as ix

    f = np.logspace(1, 6, 31)
    second = {**TRUTH, "R_sc": 60e3}
    path = tmp_path / "two.nc"
    ix.save(ix.make_spectrum(f, np.stack([meyer_z(f, TRUTH), meyer_z(f, second)]), dims=("trial",)), str(path))
    code, out, err = run(["fit", path, "--model", "meyer", "--shared", "R_f,C_sc", "--quiet", "--json"], capsys)
    assert code == 0, err
    summary = json.loads(out)
    assert summary["paper_model"] == "meyer" and "starting values, not fixed ones" in err
    assert summary["shared"]["R_f"]["value"] == pytest.approx(TRUTH["R_f"], rel=1e-6)
    assert summary["shared"]["C_sc"]["value"] == pytest.approx(TRUTH["C_sc"], rel=1e-6)
    assert [s["params"]["R_sc"]["value"] for s in summary["spectra"]] == pytest.approx([TRUTH["R_sc"], second["R_sc"]], rel=1e-6)
