"""A corrosion engineer's walk (2026-12-01): several NAME=VALUE after one --init, --fix, --bound
or --prior; ``impedax stack`` (and `impedax.stack_files`) turning one file per day into one
series that ``impedax fit`` fits as a batch; the too-few-points message naming the file in
good grammar. Every spectrum here is SYNTHETIC: numpy formulas with seeded noise."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import _spread_params, main

from cli_run import run

FREQ = np.geomspace(0.1, 1e5, 31)  # Hz
R0_TRUE = 20.0  # Ω, the electrolyte
C1_TRUE = 5e-6  # F, the double layer
R1_BY_DAY = (43e3, 30e3, 21e3)  # Ω, a charge-transfer resistance falling as the film breaks down


def rc_impedance(freq, r0, r1, c1):
    """R0 + R1 || C1: Z = R0 + R1 / (1 + jωR1C1), ω = 2πf."""
    return r0 + r1 / (1 + 2j * np.pi * freq * r1 * c1)


def write_day(path, r1, seed, freq=FREQ, noise=0.003):
    """SYNTHETIC: one day's spectrum with 0.3 % relative Gaussian noise per component, as CSV."""
    rng = np.random.default_rng(seed)
    z = rc_impedance(freq, R0_TRUE, r1, C1_TRUE)
    z = z + noise * np.abs(z) * (rng.normal(size=freq.size) + 1j * rng.normal(size=freq.size))
    rows = "".join(f"{float(f)!r},{float(v.real)!r},{float(v.imag)!r}\n" for f, v in zip(freq, z))
    path.write_text("frequency_hz,z_real_ohm,z_imag_ohm\n" + rows)
    return z


@pytest.fixture
def days(tmp_path):
    """Three SYNTHETIC days: (paths, Z written)."""
    paths, zs = [], []
    for day, r1 in enumerate(R1_BY_DAY, start=1):
        path = tmp_path / f"day{day:02d}.csv"
        zs.append(write_day(path, r1, seed=day))
        paths.append(path)
    return paths, np.array(zs)


# --- 1. several NAME=VALUE after one option -------------------------------------------------------

def test_spread_gives_each_assignment_its_own_option_and_stops_at_other_words():
    argv = ["fit", "d.csv", "--init", "R1=43k", "C2=5u", "--fix=R0=20", "L1=1u", "--bound", "R1=1:1M", "C2=1n:1m", "--model", "R0", "--", "X=1"]
    assert _spread_params(argv) == ["fit", "d.csv", "--init", "R1=43k", "--init", "C2=5u", "--fix=R0=20", "--fix", "L1=1u",
                                    "--bound", "R1=1:1M", "--bound", "C2=1n:1m", "--model", "R0", "--", "X=1"]
    # an option as the value is argparse's to refuse, not a value to spread after
    assert _spread_params(["--init", "--fix", "R0=1", "C1=2"]) == ["--init", "--fix", "R0=1", "--fix", "C1=2"]


@pytest.mark.parametrize("command", ["fit", "compare", "sample", "diagnose", "refine"])
def test_every_command_with_fix_reads_a_second_value_after_one_fix(command, days, capsys):
    """The second value reaches --fix's own check (an unknown name, named with its flag), where
    it used to be argparse's "unrecognized arguments: C9=5u"."""
    models = ["--model", "R0 + R1 || C1"] + (["--model", "R0 + C1"] if command == "compare" else [])
    code, _, err = run([command, days[0][0], *models, "--fix", "R0=20", "C9=5u"], capsys)
    assert code == 2 and "unrecognized" not in err and "C9" in err, err


@pytest.mark.parametrize("option, values, fragment", [
    ("--init", ["R1=43k", "C1=abc"], "--init 'C1=abc': 'abc' is not a number"),
    ("--bound", ["R1=10:1M", "C1=5:1"], "--bound C1=5:1: the lower end 5 must be below the upper end 1"),
    ("--prior", ["R1=loguniform:1e2,1e5", "C1=beta:1,2"], "unknown prior kind 'beta'"),
])
def test_init_bound_and_prior_read_every_value_after_one_option(option, values, fragment, days, capsys):
    command = "sample" if option == "--prior" else "fit"
    code, _, err = run([command, days[0][0], "--model", "R0 + R1 || C1", option, *values], capsys)
    assert code == 2 and fragment in err, err


def test_several_values_after_one_option_fit_as_the_repeated_options_do(days, capsys):
    """``--fix R0=20 --init R1=43k C1=5u --bound R1=1k:1M C1=1n:1m`` is the repeated form, fit
    for fit; the fixed value is held exactly and R1, C1 come back within 3 % of the formula's."""
    data = days[0][0]
    spread = ["--fix", "R0=20", "--init", "R1=43k", "C1=5u", "--bound", "R1=1k:1M", "C1=1n:1m"]
    repeated = ["--fix", "R0=20", "--init", "R1=43k", "--init", "C1=5u", "--bound", "R1=1k:1M", "--bound", "C1=1n:1m"]
    results = []
    for options in (spread, repeated):
        code, out, err = run(["fit", data, "--model", "R0 + R1 || C1", *options, "--json"], capsys)
        assert code == 0, err
        results.append(json.loads(out))
    params = results[0]["params"]
    assert params == results[1]["params"]
    assert params["R0"] == {"value": 20.0, "stderr": None, "fixed": True, "unit": "Ohm", "linearised_stderr": None}  # (unit: added 2026-12-01; linearised_stderr 2026-12-02)
    assert results[0]["user_bounds"] == {"R1": [1e3, 1e6], "C1": [1e-9, 1e-3]}
    assert params["R1"]["value"] == pytest.approx(R1_BY_DAY[0], rel=0.03) and params["C1"]["value"] == pytest.approx(C1_TRUE, rel=0.03)


def test_a_stray_value_names_the_options_that_take_it_and_a_second_file_names_stack(days, capsys):
    code, _, err = run(["fit", days[0][0], "R1=5", "--model", "R1 + C1"], capsys)
    assert code == 2 and "unrecognized arguments: R1=5; a NAME=VALUE follows its option (--init, --fix, --bound): e.g. --init R1=5" in err
    code, _, err = run(["fit", days[0][0], days[0][1], "--model", "R1 + C1"], capsys)
    assert code == 2 and "fit reads one DATA file: join files of one spectrum each into one series with impedax stack" in err


def test_a_file_whose_name_reads_like_an_assignment_stays_the_data(days, tmp_path, monkeypatch, capsys):
    """``fit --fix R0=20 run=3.csv``: run=3.csv is a file here, so it is the DATA, not a --fix."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "run=3.csv").write_text(days[0][0].read_text())
    assert _spread_params(["fit", "--fix", "R0=20", "run=3.csv"]) == ["fit", "--fix", "R0=20", "run=3.csv"]


# --- 2. impedax stack / ix.stack_files ----------------------------------------------------------

def test_stack_writes_one_series_with_the_files_values_labels_and_sources(days, tmp_path, capsys):
    paths, z_written = days
    out = tmp_path / "days.nc"
    code, _, err = run(["stack", *paths, "--dim", "day", "--coords", "1", "2", "3", "--out", out], capsys)
    assert code == 0, err
    assert f"wrote {out}" in err and "3 spectra at 31 frequencies along 'day'" in err
    series = ix.load(out)
    assert series["Z"].dims == ("day", "frequency")
    assert series["day"].values.tolist() == [1, 2, 3] and series["day"].dtype.kind == "i"
    np.testing.assert_allclose(series["frequency"].values, FREQ, rtol=1e-15)
    np.testing.assert_allclose(series["Z"].values, z_written, rtol=1e-15)  # (repr round-trips floats)
    assert series.attrs["sources"] == [str(p) for p in paths] and series.attrs["stacked_along"] == "day"
    # the file is netCDF; its data were first read from delimited text (inspect said "delimited text")
    assert series.attrs["format"] == "impedax netCDF" and series.attrs["data_format"] == "delimited text"
    code, printed, _ = run(["inspect", out], capsys)
    assert code == 0 and printed.startswith(f"{out}: impedax netCDF (its data first read from delimited text), 31 frequencies")
    code, printed, _ = run(["inspect", out, "--json"], capsys)
    assert json.loads(printed)["format"] == "impedax netCDF" and json.loads(printed)["data_format"] == "delimited text"


def _entry(column, unit, scale=1.0, negated=False):
    return {"column": column, "unit": unit, "scale": scale, "negated": negated}


def test_stacked_files_of_different_headers_keep_each_files_columns(days, tmp_path, capsys):
    """SYNTHETIC: day 1 as written by `write_day` (Hz, Ω), day 2 the same formula written in kHz
    and kΩ with -Z'' on ';': the series keeps each file's record of its columns, by file path."""
    first = days[0][0]
    z2 = rc_impedance(FREQ, R0_TRUE, R1_BY_DAY[1], C1_TRUE)
    second = tmp_path / "day02_khz.csv"
    second.write_text("Frequency (kHz);Z' (kOhm);-Z'' (kOhm)\n" + "".join(f"{float(f) / 1e3!r};{float(v.real) / 1e3!r};{float(-v.imag) / 1e3!r}\n" for f, v in zip(FREQ, z2)))
    series = ix.stack_files([first, second])
    np.testing.assert_allclose(series["Z"].values[1], z2, rtol=1e-12)
    hz = {"frequency": _entry("frequency_hz", "Hz"), "z_real": _entry("z_real_ohm", "Ω"), "z_imag": _entry("z_imag_ohm", "Ω")}
    khz = {"frequency": _entry("Frequency (kHz)", "kHz", 1000.0), "z_real": _entry("Z' (kOhm)", "kOhm", 1000.0),
           "z_imag": _entry("-Z'' (kOhm)", "kOhm", 1000.0, negated=True)}
    assert ix.load(first).attrs["columns"] == hz  # (the oracle's spelling of the first file's record)
    assert "columns" not in series.attrs
    assert series.attrs["columns_by_file"] == {str(first): hz, str(second): khz}
    out = tmp_path / "mixed.nc"
    code, _, err = run(["stack", first, second, "--out", out], capsys)
    assert code == 0, err
    code, printed, _ = run(["inspect", out, "--json"], capsys)
    summary = json.loads(printed)
    assert summary["columns"] == {} and summary["columns_by_file"] == {str(first): hz, str(second): khz}
    # files that agree keep one record, as before, and no per-file one
    paths, _ = days
    agreed = ix.stack_files(paths)
    assert agreed.attrs["columns"] == hz and "columns_by_file" not in agreed.attrs
    code, printed, _ = run(["stack", *paths, "--out", tmp_path / "agreed.nc"], capsys)
    code, printed, _ = run(["inspect", tmp_path / "agreed.nc", "--json"], capsys)
    assert json.loads(printed)["columns"] == hz and json.loads(printed)["columns_by_file"] == {}


def test_stack_labels_are_the_file_stems_by_default_and_text_when_not_numbers(days, tmp_path):
    paths, _ = days
    assert ix.stack_files(paths)["file"].values.tolist() == ["day01", "day02", "day03"]
    assert ix.stack_files(paths, dim="day", coords=["mon", "tue", "3"])["day"].values.tolist() == ["mon", "tue", "3"]
    assert ix.stack_files(paths, coords=["0.5", "1", "1.5"])["file"].values.tolist() == [0.5, 1.0, 1.5]


def test_stack_aligns_a_file_written_in_the_other_order_and_keeps_sigma(tmp_path):
    """A descending sweep is the same grid: its Z lands at the first file's frequencies. sigma
    (a SYNTHETIC 1 % of |Z|) is kept when every file has it."""
    z = [rc_impedance(FREQ, R0_TRUE, r1, C1_TRUE) for r1 in R1_BY_DAY[:2]]
    ix.save(ix.make_spectrum(FREQ, z[0], sigma=0.01 * np.abs(z[0])), tmp_path / "up.nc")
    ix.save(ix.make_spectrum(FREQ[::-1], z[1][::-1], sigma=0.01 * np.abs(z[1][::-1])), tmp_path / "down.nc")
    series = ix.stack_files([tmp_path / "up.nc", tmp_path / "down.nc"])
    np.testing.assert_array_equal(series["Z"].values, np.array(z))
    np.testing.assert_allclose(series["sigma"].values, 0.01 * np.abs(np.array(z)), rtol=1e-15)  # (|z| of a reversed view: ulps apart)


def test_stack_refuses_another_grid_naming_the_file_and_writes_nothing(days, tmp_path, capsys):
    paths, _ = days
    odd = tmp_path / "day04.csv"
    write_day(odd, 15e3, seed=4, freq=np.geomspace(0.1, 1e5, 25))
    before = sorted(p.name for p in tmp_path.iterdir())
    code, _, err = run(["stack", *paths, odd, "--out", tmp_path / "days.nc"], capsys)
    assert code == 2 and f"error: {odd}: its frequency grid differs from {paths[0]}'s (25 vs 31 points" in err, err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == before


def test_stack_refuses_a_file_of_several_spectra_and_a_wrong_count_of_coords(days, tmp_path, capsys):
    paths, _ = days
    several = tmp_path / "week.nc"
    assert main(["stack", *map(str, paths), "--dim", "day", "--out", str(several)]) == 0
    capsys.readouterr()
    code, _, err = run(["stack", paths[0], several, "--out", tmp_path / "again.nc"], capsys)
    # (a file of several spectra joins files of the same dimensions only, 2026-12-01: tests/test_stack_dimensions.py)
    assert code == 2 and f"{several}: holds 3 spectra (over day) but {paths[0]} holds one spectrum; a stack joins files of the same dimensions" in err, err
    code, _, err = run(["stack", *paths, "--coords", "1", "2", "--out", tmp_path / "again.nc"], capsys)
    assert code == 2 and "--coords: 2 labels for 3 files" in err, err
    assert not (tmp_path / "again.nc").exists()


# the name of the new dimension: one rule, one message, in Python and on the command line
# (docs/io.md, "Several files as one series"); the reasons below are written by hand from the rule
REFUSED_DIMENSION_NAMES = [
    ("a b", "' ' cannot stand in it"), ("a=b", "'=' cannot stand in it"), ("a,b", "',' cannot stand in it"),
    ("-x", "'-' cannot lead it"), ("0", "'0' cannot lead it"), ("1e3", "'1' cannot lead it"),
    ("_a", "'_' cannot lead it (netCDF keeps names led by '_' for its own)"),
    ("nan", "it reads as a number"), ("Infinity", "it reads as a number"),
    ("½", "'½' (U+00BD) cannot stand in it"), ("température", "'é' (U+00E9) cannot stand in it"), ("温度", "'温' (U+6E29), '度' (U+5EA6) cannot stand in it"),
    ("class", "it is a Python keyword"), ("None", "it is a Python keyword"),
    ("a" * 257, "its 257 characters are more than netCDF's 256"),
]


@pytest.mark.parametrize("dim, reason", REFUSED_DIMENSION_NAMES, ids=[d[:12] for d, _ in REFUSED_DIMENSION_NAMES])
def test_a_dimension_name_is_refused_alike_by_stack_files_and_impedax_stack(days, tmp_path, capsys, dim, reason):
    paths, _ = days
    with pytest.raises(ValueError) as info:
        ix.stack_files(paths, dim=dim)
    message = str(info.value)
    assert isinstance(info.value, ix.ParameterError) and message.startswith(f"dim: {dim!r}"[:60]) and reason in message, message
    out = tmp_path / "s.nc"
    code, printed, err = run(["stack", *paths, f"--dim={dim}", "--out", out], capsys)
    assert (code, printed, err) == (2, "", f"impedax stack: error: --{message}\n") and not out.exists()


@pytest.mark.parametrize("dim", ["day", "cell_2", "cell_2.v-1", "Day3", "x" * 256])
def test_a_dimension_name_of_the_rule_names_the_series_and_selects_it(days, tmp_path, dim):
    paths, zs = days
    series = ix.stack_files(paths, dim=dim, coords=[1, 2, 3])
    assert series["Z"].dims == (dim, "frequency")
    np.testing.assert_allclose(series.sel({dim: 2})["Z"].values, zs[1], rtol=1e-15)
    ix.save(series, tmp_path / "s.nc")
    assert ix.load(tmp_path / "s.nc")["Z"].dims == (dim, "frequency")


def test_a_folder_names_stack(tmp_path, capsys):
    code, _, err = run(["kk", tmp_path], capsys)
    assert code == 2 and "is a directory, not a spectrum file (its files of one spectrum each join into one series with impedax stack" in err


def test_fit_of_the_stacked_file_fits_every_day(days, tmp_path, capsys):
    """The walk's end: impedax fit OUT.nc fits the three days as a batch over 'day'; each R1
    within 3 % of its formula's value, in the files' order."""
    paths, _ = days
    out = tmp_path / "days.nc"
    assert main(["stack", *map(str, paths), "--dim", "day", "--out", str(out)]) == 0
    capsys.readouterr()
    code, text, err = run(["fit", out, "--model", "R0 + R1 || C1", "--json"], capsys)
    assert code == 0, err
    summary = json.loads(text)
    assert summary["sizes"] == {"day": 3} and summary["source"] == str(out)
    assert [s["day"] for s in summary["spectra"]] == ["day01", "day02", "day03"]
    np.testing.assert_allclose([s["values"]["R1"] for s in summary["spectra"]], R1_BY_DAY, rtol=0.03)
    np.testing.assert_allclose([s["values"]["C1"] for s in summary["spectra"]], C1_TRUE, rtol=0.03)


# --- 3. too few points: the file named, "1 frequency" -------------------------------------------

def test_too_few_points_names_the_file_in_the_singular(tmp_path, capsys):
    path = tmp_path / "day01.csv"
    path.write_text("frequency_hz,z_real_ohm,z_imag_ohm\n1000,120,-35\n")  # SYNTHETIC: one point
    code, _, err = run(["fit", path, "--model", "R0 + R1 || C1"], capsys)
    assert code == 2 and f"error: {path}: 3 free parameters but only 2 real data values (1 frequency);" in err, err
    with pytest.raises(ix.FitError, match=r"^4 free parameters but only 4 real data values \(2 frequencies\)"):
        ix.fit("R0 + R1 || C1 + R2", ix.make_spectrum([10.0, 100.0], [120 - 35j, 110 - 20j]))  # in memory: no file to name


def test_one_file_given_twice_is_refused_however_it_is_written(days, tmp_path, capsys):
    """The same day twice would stand in the series as two measurements; the repeated name's
    message sent the user to --coords, which then wrote the copies (2026-12-03 walkthrough)."""
    paths, _ = days
    first = paths[0]
    again = tmp_path / "sub" / ".." / first.name  # (another path to the same file)
    (tmp_path / "sub").mkdir()
    out = tmp_path / "twice.nc"
    assert main(["stack", str(first), str(paths[1]), str(again), "--coords", "1", "2", "3", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert f"{again}: is given twice (files 1 and 3 of 3)" in err and not out.exists()
    with pytest.raises(ix.DataError, match="is given twice"):
        ix.stack_files([first, first], coords=[1, 2])


# --- 4. --common-frequencies: files whose grids differ by a skipped point (added 2026-12-04) ----

def test_common_frequencies_keep_the_points_every_file_has_and_name_the_rest(days, tmp_path, capsys):
    """SYNTHETIC: day 2 skipped two frequencies of the plan (0.398 Hz and 251 Hz), day 3's
    frequencies read 0.03 % high (inside the 0.1 % a grid is matched within). The series keeps
    the 29 frequencies every day has, at day 1's values, each day's own measured Z there (the
    formula at that day's own frequencies, nothing interpolated), and names what it left out."""
    paths, _ = days
    skipped = [3, 17]
    freq2, freq3 = np.delete(FREQ, skipped), FREQ * (1 + 3e-4)
    z2 = write_day(paths[1], R1_BY_DAY[1], seed=12, freq=freq2, noise=0.0)
    z3 = write_day(paths[2], R1_BY_DAY[2], seed=13, freq=freq3, noise=0.0)
    with pytest.raises(ix.DataError, match=r"its frequency grid differs .*--common-frequencies; common_frequencies=True"):
        ix.stack_files(paths)
    series = ix.stack_files(paths, common_frequencies=True)
    kept = np.delete(np.arange(FREQ.size), skipped)
    np.testing.assert_array_equal(series["frequency"].values, FREQ[kept])
    np.testing.assert_allclose(series["Z"].values[1], z2, rtol=1e-15)
    np.testing.assert_allclose(series["Z"].values[2], z3[kept], rtol=1e-15)
    np.testing.assert_allclose(series["Z"].values[2], rc_impedance(freq3[kept], R0_TRUE, R1_BY_DAY[2], C1_TRUE), rtol=1e-12)
    left_out = {str(paths[0]): FREQ[skipped].tolist(), str(paths[2]): freq3[skipped].tolist()}
    assert series.attrs["frequencies_left_out"] == left_out
    out = tmp_path / "days.nc"
    code, printed, err = run(["stack", *paths, "--common-frequencies", "--out", out, "--json"], capsys)
    assert code == 0, err
    assert json.loads(printed)["frequencies_left_out"] == left_out and json.loads(printed)["frequencies"] == 29
    assert f"note: {paths[0]}: 2 frequencies not in every file left out (398 mHz, 251 Hz)" in err, err
    assert f"note: {paths[2]}: 2 frequencies not in every file left out (398 mHz, 251 Hz)" in err and str(paths[1]) + ":" not in err
    assert ix.load(out).attrs["frequencies_left_out"] == left_out  # (kept in the file)
    code, printed, _ = run(["inspect", out], capsys)
    assert f"  left out of {paths[0]} by the stack (not in every file): 398 mHz, 251 Hz" in printed, printed
    code, printed, _ = run(["inspect", out, "--json"], capsys)
    assert json.loads(printed)["frequencies_left_out"] == left_out
    code, printed, _ = run(["inspect", paths[1], "--json"], capsys)
    assert json.loads(printed)["frequencies_left_out"] == {}
    # files on one grid lose nothing and carry no record of it
    same_grid = tmp_path / "day04.csv"
    write_day(same_grid, 15e3, seed=4)
    alike = ix.stack_files([paths[0], same_grid], common_frequencies=True)
    assert "frequencies_left_out" not in alike.attrs and alike.sizes["frequency"] == FREQ.size


def test_common_frequencies_refuse_files_not_measured_on_one_plan(days, tmp_path, capsys):
    """SYNTHETIC: 31 frequencies against 12 over the same decades, which share 2 (the ends): a
    file would keep under half its points, so the stack is refused naming it, nothing written."""
    paths, _ = days
    sparse = tmp_path / "sparse.csv"
    write_day(sparse, 15e3, seed=5, freq=np.geomspace(0.1, 1e5, 12))
    out = tmp_path / "days.nc"
    code, _, err = run(["stack", paths[0], sparse, "--common-frequencies", "--out", out], capsys)
    assert code == 2 and f"error: {paths[0]}: shares only 2 of its 31 frequencies with the other files (within 0.1 %): under half" in err, err
    assert "Traceback" not in err and not out.exists()


def test_inspect_of_a_stack_along_a_dimension_named_as_an_attribute_keeps_the_files_attribute(tmp_path, capsys):
    """REAL files of three instruments (tests/fixtures/real, one circuit measured alike) stacked
    along a dimension named 'instrument': each file's own instrument, from its header, is still
    reported (walkthrough 2026-12-06: the report left the attribute out, taking it for the
    labels it lists). A workbook's 'sheet' attribute, which only repeats the labels, stays out."""
    real = Path(__file__).parent / "fixtures" / "real"
    out = tmp_path / "by_instrument.nc"
    code, _, err = run(["stack", real / "data.dfr", real / "data.idf", real / "data.pssession", "--dim", "instrument", "--coords", "dfr", "idf", "ps", "--out", out, "-q"], capsys)
    assert code == 0, err
    code, text, err = run(["inspect", out], capsys)
    assert code == 0, err
    # the instruments' names as the files' own headers give them
    assert "PS4A22B003671" in (real / "data.pssession").read_text(encoding="utf-16")
    assert "  instrument: instrument dfr: Metrohm Autolab (FRA); instrument idf: Ivium; instrument ps: PalmSens PS4A22B003671\n" in text
    assert "  instrument: 3 spectra (dfr, idf, ps)" in text
    code, text, err = run(["inspect", real / "data.xlsx"], capsys)
    assert code == 0, err
    assert [line for line in text.splitlines() if line.startswith("  sheet:")] == ["  sheet: 4 spectra (header-variant-1, header-variant-2, header-variant-3, header-variant-4); pick one with --select sheet=LABEL"]


def test_inspect_shows_a_saved_files_provenance_as_text(tmp_path, capsys):
    """The provenance of a stack of REAL files, read with xarray from the netCDF file itself,
    is shown by `impedax inspect` as one line to read (walkthrough 2026-12-06: the JSON record
    itself, "source": "... \\u2026 ..." and nulls); --json keeps the record as it is."""
    import xarray as xr

    real = Path(__file__).parent / "fixtures" / "real"
    out = tmp_path / "st.nc"
    files = [real / "data.dfr", real / "data.pssession"]
    code, _, err = run(["stack", *files, "--coords", "dfr", "ps", "--out", out, "-q"], capsys)
    assert code == 0, err
    with xr.open_dataset(out, engine="scipy") as raw:
        record = json.loads(raw.attrs["provenance"])
    code, text, err = run(["inspect", out], capsys)
    assert code == 0, err
    line = next(line for line in text.splitlines() if line.startswith("  provenance: "))
    assert line == (f"  provenance: impedax stack, {record['written_utc']} (impedax {record['impedax_version']}); settings dim=file, coords=dfr ps; "
                    f"data {', '.join(str(f.resolve()) for f in files)}")
    code, text, err = run(["inspect", out, "--json"], capsys)
    assert json.loads(json.loads(text)["attrs"]["provenance"]) == record


def test_inspect_says_a_file_was_saved_from_data_built_in_python(tmp_path, capsys):
    """A file saved from data built in Python stores impedax's in-memory marker 'memory' as its
    source (read here with xarray), which `impedax inspect` printed as "saved_from: memory"
    (walkthrough 2026-12-06, on the REAL benchmarks/data/autoeis_battery_130.nc, which now names
    the file it was built from: tests/test_shipped_data_source.py). SYNTHETIC R0 + R1 || C1."""
    import xarray as xr

    f = np.logspace(4, -1, 21)
    path = tmp_path / "built.nc"
    ix.save(ix.make_spectrum(f, 10 + 100 / (1 + 1j * 2 * np.pi * f * 1e-4)), path)
    with xr.open_dataset(path, engine="scipy") as raw:
        assert raw.attrs["source"] == "memory"
    code, text, err = run(["inspect", path], capsys)
    assert code == 0, err
    assert "  saved_from: data built in a Python session (impedax.make_spectrum), not read from a file\n" in text
    assert "saved_from: memory" not in text


def test_a_stack_of_saved_results_is_spectra_not_a_result(tmp_path, capsys):
    """Two KK tests' .nc files (SYNTHETIC R0 + R1 ∥ C1 days) stacked: their Z over (file,
    frequency), a spectrum stack with no impedax_kind and none of the files' provenance, which
    describes each file, not the stack; until 2026-12-06 it kept the first file's
    impedax_kind, and impedax inspect showed the stack as "a saved Kramers-Kronig test"."""
    paths = []
    for day, (r1, seed) in enumerate([(1000.0, 1), (1200.0, 2)]):
        write_day(tmp_path / f"day{day}.csv", r1, seed)
        data = ix.load(tmp_path / f"day{day}.csv")
        paths.append(tmp_path / f"kk{day}.nc")
        ix.write_result(ix.kk_test(data), paths[-1])
        assert ix.load(paths[-1]).attrs["impedax_kind"] == "kk"
    stacked = ix.io.stack_files(paths, dim="day")
    assert not {"impedax_kind", "impedax_version", "written_utc", "provenance"} & set(stacked.attrs)
    np.testing.assert_array_equal(stacked["Z"].sel(day="kk1").values, ix.load(tmp_path / "day1.csv")["Z"].values)
    out = tmp_path / "days.nc"
    code, printed, err = run(["stack", *paths, "--dim", "day", "--out", out], capsys)
    assert code == 0, err
    code, printed, err = run(["inspect", out, "--json"], capsys)
    summary = json.loads(printed)
    assert "result_kind" not in summary and json.loads(summary["attrs"]["provenance"])["command"] == "impedax stack"


def test_a_copy_of_a_file_under_another_name_is_refused(days, tmp_path, capsys):
    """A hostile walkthrough (2026-12-08): day02.csv a byte-for-byte copy of day01.csv was stacked
    as a second measurement (a file given twice by path was refused, its copy not); impedax gap
    refuses identical spectra alike. A copy with other line endings holds the same spectrum too."""
    (paths, _) = days
    copy = tmp_path / "day04.csv"
    copy.write_bytes(paths[0].read_bytes().replace(b"\n", b"\r\n"))
    out = tmp_path / "series.nc"
    code, stdout, err = run(["stack", paths[0], paths[1], copy, "--out", out], capsys)
    assert code == 2 and stdout == "" and not out.exists()
    assert err == f"impedax stack: error: {copy}: holds the same spectrum as {paths[0]} (every Z equal: a copy of that file?): each file is one measurement of the series; give each once\n"
    with pytest.raises(ix.DataError, match=r"day04\.csv: holds the same spectrum as .*day01\.csv"):
        ix.stack_files([paths[0], copy])
    # two measurements that differ in one value stack as two
    z = write_day(tmp_path / "day05.csv", R1_BY_DAY[0], seed=1)
    text = (tmp_path / "day05.csv").read_text().splitlines()
    text[-1] = text[-1].rsplit(",", 1)[0] + f",{float(z[-1].imag) * 1.0001!r}"
    (tmp_path / "day05.csv").write_text("\n".join(text) + "\n")
    assert ix.stack_files([paths[0], tmp_path / "day05.csv"]).sizes["file"] == 2
