"""What a user's walk through the commands on real instrument files found (2026-11-30), each
with the case that showed it:

- parameter tables whose names are shorter than the header "parameter" printed the values
  six columns left of their headers (`fit`, `info`, the posteriors, `kk` of a batch, `compare`);
- `compare` said a model that contains another "did not reach its optimum" when its extra term
  sat at its bound and the two χ² differed by 1.6e-8 relative (BioLogic's real file);
- a spectrum with Z' negated got the hint to flip the sign of Z'', which leaves Z' < 0;
- `sample` on a file of several spectra answered in Python's words, without --select or
  --shared; `inspect` did not mention a sigma column;
- a plain CSV with NOVA-like column names was labelled "Metrohm Autolab"; a quoted header
  cell holding the delimiter was split in two;
- `sample --steps auto` showed "≈3798 needed" for thousands of steps past it while it waited
  for τ to settle, without saying so;
- `diagnose` on fewer than 10 frequencies read the inconclusive KK test's chain misfit as the
  noise and called a 26 % misfit adequate; its JSON had no baseline parameters;
- a memory refusal read "1e+03 kB";
- `Comparison.report()` in Python repeated a warning every model has under each model;
- a header `Z"` (a double prime) lost its quote and read as |Z|.

Spectra come from closed forms written here (R0 + R1 ∥ C1), except where the real file was
the case (`tests/fixtures/real/`, impedance.py's and AutoEIS's examples, MIT)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

ROOT = Path(__file__).resolve().parent.parent
REAL = ROOT / "tests" / "fixtures" / "real"
CYCLES = ROOT / "examples" / "data" / "autoeis_battery_cycles.nc"


def rc_spectrum(f: np.ndarray, noise: float = 0.0, seed: int = 0) -> np.ndarray:
    """R0 + R1 ∥ C1 = 20 + 1000/(1 + jω·1000·1e-6) Ω, with relative complex noise."""
    z = 20 + 1000 / (1 + 1j * 2 * np.pi * f * 1e-3)
    rng = np.random.default_rng(seed)
    return z * (1 + noise * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)))


def write_csv(path: Path, f: np.ndarray, z: np.ndarray, header: str = "frequency_hz,z_real_ohm,z_imag_ohm") -> Path:
    path.write_text(header + "\n" + "".join(f"{a:.10g},{b.real:.10g},{b.imag:.10g}\n" for a, b in zip(f, z)))
    return path


def value_column_ends(lines: list[str], header_word: str, first_column: str) -> tuple[int, list[int]]:
    """Where ``header_word`` ends in the header line, and where the second field ends in each
    row whose first field is in ``first_column``."""
    header = next(line for line in lines if line.split()[:1] == [first_column] and header_word in line)
    end = header.index(header_word) + len(header_word)
    rows = [line for line in lines[lines.index(header) + 1 :] if line[:1].isalnum() and not line.startswith(("warning", "note"))]
    ends = [m.end() for m in (re.match(r"\S+\s+\S+", row) for row in rows) if m]
    return end, ends


# --- tables -----------------------------------------------------------------------------------


def test_the_values_of_short_parameter_names_sit_under_their_header(tmp_path, capsys):
    f = np.geomspace(1, 1e5, 31)
    data = write_csv(tmp_path / "rc.csv", f, rc_spectrum(f, 1e-3))
    assert main(["fit", str(data), "--model", "R0 + R1 || C1"]) == 0
    end, ends = value_column_ends(capsys.readouterr().out.splitlines(), "value", "parameter")
    assert len(ends) == 3 and set(ends) == {end}  # (right-aligned values end where "value" ends)
    assert main(["info", "R0 + R1 || C1"]) == 0
    lines = capsys.readouterr().out.splitlines()
    header = next(line for line in lines if line.startswith("parameter"))
    assert all(line.index("Ω" if line.startswith("R") else "F") == header.index("unit") for line in lines if line[:2] in ("R0", "R1", "C1"))


# --- compare ----------------------------------------------------------------------------------


def test_a_model_whose_extra_term_sits_at_its_bound_is_not_called_short_of_its_optimum(capsys):
    # (BioLogic's real file: W1.sigma at 0, the two fits' χ² 1.6e-8 apart relative)
    code = main(["compare", str(REAL / "exampleDataBioLogic.mpt"), "--model", "R0 + R1 || CPE1", "--model", "R0 + R1 || CPE1 + W1", "--json"])
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    (test,) = out["f_tests"]
    assert test["f"] == pytest.approx(0.0, abs=1e-3) and test["p_value"] > 0.99
    # no F-test with W1.sigma on its bound (Self & Liang 1987), and said to be the smaller model
    assert test["valid"] is False and test["reason"] == "reduces_to_simple" and test["at_bound"] == ["W1.sigma"], test
    assert "did not reach its optimum" not in test["note"] and "the extra element does nothing" in test["note"]


# --- sign hints -------------------------------------------------------------------------------


def test_a_negated_real_part_gets_the_real_parts_hint_not_the_imaginary_parts(tmp_path, capsys):
    f = np.geomspace(1, 1e5, 21)
    z = rc_spectrum(f)
    path = write_csv(tmp_path / "neg_real.csv", f, -z.real + 1j * z.imag, header="freq,Zreal,Zimag")
    assert main(["kk", str(path)]) == 0
    out = capsys.readouterr().out
    assert "the real part may be stored with the opposite sign (−Z'): Z' < 0 at 21 of 21 points" in out
    assert "imaginary part may be stored" not in out  # (conj(Z) passes the KK test but keeps Z' < 0)
    assert main(["inspect", str(path)]) == 0
    assert "hint: the real part may be stored with the opposite sign" in capsys.readouterr().out
    flipped = write_csv(tmp_path / "flipped.csv", f, np.conj(z), header="freq,Zreal,Zimag")  # (the other mistake keeps its hint)
    assert main(["kk", str(flipped)]) == 0
    assert "the imaginary part may be stored with the opposite sign" in capsys.readouterr().out
    negated = write_csv(tmp_path / "negated.csv", f, -z, header="freq,Zreal,Zimag")  # (both: -Z, not -conj(Z), mends it)
    for command in ("kk", "inspect"):
        assert main([command, str(negated)]) == 0
        out = capsys.readouterr().out
        assert "Z may be stored with the opposite sign (−Z" in out and "data.assign(Z=-data['Z'])" in out


def test_a_spectrum_with_its_signs_right_gets_no_sign_hint(tmp_path, capsys):
    f = np.geomspace(1, 1e5, 21)
    path = write_csv(tmp_path / "good.csv", f, rc_spectrum(f, 1e-3))
    assert main(["inspect", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["sign_hint"] is None


# --- files ------------------------------------------------------------------------------------


def test_sample_on_several_spectra_names_select_and_shared(capsys):
    code = main(["sample", str(CYCLES), "--model", "R0 + R1 || CPE1", "--steps", "20"])
    err = capsys.readouterr().err
    assert code == 2
    assert "sample takes one spectrum; the file holds 3 over cycle" in err and "--select cycle=0" in err
    assert "or sample them jointly with --shared NAMES" in err


def test_inspect_says_the_file_has_a_sigma_column(tmp_path, capsys):
    f = np.geomspace(1, 1e3, 8)
    z = rc_spectrum(f)
    path = tmp_path / "sigma.csv"
    path.write_text("frequency_hz,z_real_ohm,z_imag_ohm,sigma_ohm\n" + "".join(f"{a:g},{b.real:.8g},{b.imag:.8g},{0.1 * (k + 1):g}\n" for k, (a, b) in enumerate(zip(f, z))))
    assert main(["inspect", str(path)]) == 0
    assert "sigma: a standard deviation of Z per point, 0.1–0.8 Ω" in capsys.readouterr().out


def test_a_plain_table_with_nova_like_names_is_not_labelled_autolab(tmp_path):
    f = np.geomspace(1, 1e3, 6)
    z = rc_spectrum(f)
    path = tmp_path / "plain.csv"
    path.write_text("Frequency (kHz),Z' (kOhm),-Z'' (kOhm)\n" + "".join(f"{a / 1e3:.10g},{b.real / 1e3:.10g},{-b.imag / 1e3:.10g}\n" for a, b in zip(f, z)))
    ds = ix.load(path)
    assert ds.attrs["format"] == "delimited text" and "instrument" not in ds.attrs
    np.testing.assert_allclose(ds["Z"].values, z, rtol=1e-9)
    nova = ix.load(ROOT / "tests" / "fixtures" / "autolab_nova.txt")  # (NOVA's own export keeps its label)
    assert nova.attrs["format"] == "Metrohm Autolab NOVA text"


def test_a_quoted_header_cell_may_hold_the_delimiter_and_loses_its_quotes(tmp_path):
    f = np.geomspace(1, 1e3, 6)
    z = rc_spectrum(f)
    path = tmp_path / "quoted.csv"
    path.write_text('"Point, no.","Frequency (Hz)","Z\' (Ohm)","Z\'\' (Ohm)"\n'  # (split at its comma, every column had moved one place)
                    + "".join(f'{k},{a:.10g},{b.real:.10g},{b.imag:.10g}\n' for k, (a, b) in enumerate(zip(f, z))))
    ds = ix.load(path)
    np.testing.assert_allclose(ds["Z"].values, z, rtol=1e-9)
    assert "'Frequency (Hz)'" in ds.attrs["units"] and "'\"" not in ds.attrs["units"]  # (the names as written, without their quotes)


# --- sampling progress ------------------------------------------------------------------------


def test_an_auto_runs_progress_says_when_it_waits_for_tau_to_settle():
    from impedax.fitting.bayes.chain import ChainLength, _length_goal
    from impedax.fitting.bayes.progress import ProgressLine

    length = ChainLength(None, 1)
    length.needed, length.long, length.tau_change = 3798, False, None
    assert _length_goal(length, 2000) == (3798, "50 τ")
    length.long, length.tau_change = True, 0.034
    steps, note = _length_goal(length, 9075)
    assert steps is None and note == "50 τ reached; waiting for τ to settle (changed 3.4 % at the last check, < 1 % stops)"
    bar = ProgressLine(20000, True, label="sampling", interactive=False, open_ended=True)
    bar.first = (0.0, 0)
    bar.set_target(steps, note)
    text = bar.text(9075, 19.0)
    assert "waiting for τ to settle" in text and "needed" not in text and "s left" not in text


# --- diagnose on few points -------------------------------------------------------------------


def test_diagnose_on_fewer_than_ten_frequencies_needs_a_noise_level(tmp_path, capsys):
    f = np.geomspace(10, 1e4, 6)
    path = write_csv(tmp_path / "six.csv", f, rc_spectrum(f, 0.01, seed=1))
    with pytest.raises(ix.DataError, match=r"six\.csv: 6 frequencies are too few to tell the model's misfit from noise"):
        ix.diagnose(ix.load(path), "R0 + R1 || C1")
    assert main(["diagnose", str(path), "--model", "R0 + R1 || C1", "--noise", "1%", "--effects", "series_resistance", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["kk"]["conclusive"] is False
    assert out["noise"]["source"] == "given" and out["noise"]["level"] == pytest.approx(0.01)
    assert any("inconclusive on 6 frequencies" in note for note in out["notes"])
    assert not any("in-memory data" in note for note in out["notes"])
    assert set(out["baseline"]["params"]) == {"R0", "R1", "C1"}
    assert out["baseline"]["params"]["C1"]["value"] == pytest.approx(1e-6, rel=0.1)


def test_too_few_frequencies_are_refused_before_the_baseline_fit(tmp_path, monkeypatch):
    """Without a noise level the refusal costs no fit (it had come after the baseline's compile
    and solve); fmin leaves 6 of 12 points in the band, and 6 points with a sigma column pass."""
    import impedax.fitting.diagnosis.diagnosis as dg

    def no_fit(*args, **kwargs):
        raise AssertionError("the baseline was fitted before the refusal")

    monkeypatch.setattr(dg, "fit_candidates", no_fit)
    f = np.geomspace(10, 1e4, 12)
    path = write_csv(tmp_path / "twelve.csv", f, rc_spectrum(f, 0.01, seed=1))
    with pytest.raises(ix.DataError, match=r"twelve\.csv: 6 frequencies are too few"):
        ix.diagnose(path, "R0 + R1 || C1", fmin=300.0)
    six = ix.load(path).isel(frequency=slice(0, 6))
    with pytest.raises(AssertionError, match="fitted before"):  # a sigma column: no refusal, the fit is reached
        ix.diagnose(six.assign(sigma=0.01 * np.abs(six["Z"])), "R0 + R1 || C1")


# --- memory message ---------------------------------------------------------------------------


@pytest.mark.parametrize("n, text", [(1000 * 1024, "1000 kB"), (1536, "1.5 kB"), (12.5 * 2**20, "12.5 MB"), (100, "100 B")])
def test_sizes_read_without_exponents(n, text):
    from impedax.cli.common import _format_bytes

    assert _format_bytes(n) == text


def test_the_diagnosis_reports_the_kk_test_as_judged_against_the_local_noise():
    """SYNTHETIC R0 + R1 ∥ CPE1 (closed form) with noise growing ×8 toward low frequency (0.25 %
    at 100 kHz, 2 % at 0.1 Hz; seed 0): the test's one global scale flags 7 points of the noisy
    end, which the local judgement clears, and the diagnosis (report, JSON) says the data are
    KK consistent, as its note says they count as data (the walkthrough's change had briefly
    reported the test before that judgement)."""
    f = np.geomspace(0.1, 1e5, 61)
    z = 10.0 + 1.0 / (1 / 1000.0 + 1e-5 * (2j * np.pi * f) ** 0.8)
    sigma = 0.0025 * 8 ** (np.log10(f[-1] / f) / np.log10(f[-1] / f[0]))
    rng = np.random.default_rng(0)
    z = z + sigma * np.abs(z) * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size))
    d = ix.diagnose(ix.make_spectrum(f, z), "R0 + R1 || CPE1", effects=ix.DEFAULT_EFFECTS.select(["series_resistance"]), drt_evidence=False)  # (the test is judged before any candidate)
    assert int(d.kk_as_tested.flagged.sum()) > 0 and any("count as data" in n for n in d.notes)  # (the premise)
    assert d.kk.valid and not d.kk.flagged.any()
    assert d.summary()["kk"]["valid"] is True and "the data are Kramers–Kronig consistent" in d.report()


def test_a_warning_every_model_has_is_listed_once_in_the_python_report_as_on_the_command_line():
    data = ix.load(REAL / "exampleDataBioLogic.mpt")  # (REAL: both fits get the data's own KK-misfit note, and that of residuals uneven across the band)
    comparison = ix.compare([ix.fit("R0 + R1 || CPE1", data), ix.fit("R0 + R1 || CPE1 + W1", data)])
    common, own = comparison.warnings_by_model()
    assert len(common) == 2 and "weighted residuals are over 4× larger" in common[0] and "Kramers–Kronig-consistent model" in common[1]
    report = comparison.report()
    assert all(report.count(w) == 1 for w in common) and "every model:" in report
    assert own[0] == [] and any(w.startswith("W1.sigma") and "its lower bound 0" in w for w in own[1])


@pytest.mark.parametrize("header, sign", [("Freq,Z',Z\"", 1), ("Freq (Hz);Z' (kOhm);-Z\" (kOhm)", -1)])
def test_a_double_prime_written_as_a_quote_names_the_imaginary_part(tmp_path, header, sign):
    f = np.geomspace(1, 1e3, 6)
    z = rc_spectrum(f)
    delimiter, scale = ("," if "," in header else ";"), (1e3 if "kOhm" in header else 1.0)
    path = tmp_path / "double_prime.csv"
    path.write_text(header + "\n" + "".join(f"{a:.10g}{delimiter}{b.real / scale:.10g}{delimiter}{sign * b.imag / scale:.10g}\n" for a, b in zip(f, z)))
    np.testing.assert_allclose(ix.load(path)["Z"].values, z, rtol=1e-9)  # (the quote had been stripped: 'Z' read as |Z|, the file refused)


def test_inspect_ends_with_the_next_commands_and_they_run(capsys):
    """A beginner's walkthrough: `inspect` suggested no next command. It ends with the `kk` and
    `drt` commands of the same file and selection, and both run as written (REAL ZPlot file)."""
    import shlex

    path = str(Path(__file__).parent / "fixtures" / "real" / "exampleDataZPlot.z")
    assert main(["inspect", path]) == 0
    last = capsys.readouterr().out.strip().splitlines()[-1]
    assert last.startswith(f"next: impedax kk {path} (")
    for command in re.findall(r"impedax (\w+ [^(]+?) \(", last):
        words = shlex.split(command)
        assert words[0] in ("kk", "drt") and main(words) == 0
    out = capsys.readouterr().out
    assert "verdict: valid" in out and "starting circuit from the DRT" in out
