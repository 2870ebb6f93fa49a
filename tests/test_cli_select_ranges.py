"""`--select DIM=L1,L2,...` and `--select DIM=FIRST:LAST`: several spectra of a file by a list
of labels or a range of them (both ends included, by value, as xarray's
``.sel(DIM=slice(FIRST, LAST))``), beside the one-label form of tests/test_cli_select.py,
which keeps its meaning. The cycles are labelled 1, 2, 3, 5, 8, 13, 21 (gaps, so a range whose
ends are not labels is tested) and each is R0 + R1 ∥ C1 with R1 = 100 Ω × its label, written
from the closed form: a wrong pick shows in the fitted values."""

import json
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

F = np.geomspace(1e-1, 1e5, 41)
R0, C1 = 10.0, 1e-6
CYCLES = [1, 2, 3, 5, 8, 13, 21]
REAL = Path(__file__).parent / "fixtures" / "real"


def rc(r1, rng):
    """R0 + R1 ∥ C1 from its transfer function, with 0.1 % complex noise."""
    z = R0 + r1 / (1 + 1j * 2 * np.pi * F * r1 * C1)
    return z * (1 + 1e-3 * (rng.normal(size=F.size) + 1j * rng.normal(size=F.size)))


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """cycles.nc: 7 cycles with numeric labels; text.nc: 4 sheets a, b, "a,b", c; none.nc:
    5 trials without labels (positions). Spectrum k of text.nc and none.nc has R1 = 100 Ω × (k + 1)."""
    rng = np.random.default_rng(11)
    folder = tmp_path_factory.mktemp("select_ranges")
    paths = {}
    stacks = {
        "cycles": (("cycle",), {"cycle": CYCLES}, [100.0 * c for c in CYCLES]),
        "text": (("sheet",), {"sheet": ["a", "b", "a,b", "c"]}, [100.0 * (k + 1) for k in range(4)]),
        "none": (("trial",), None, [100.0 * (k + 1) for k in range(5)]),
    }
    for name, (dims, coords, r1s) in stacks.items():
        ds = ix.make_spectrum(F, np.stack([rc(r1, rng) for r1 in r1s]), dims=dims, coords=coords)
        if coords is None:
            ds = ds.drop_vars(dims[0], errors="ignore")
        paths[name] = str(folder / f"{name}.nc")
        ix.save(ds, paths[name])
    return paths


def json_out(args, capsys):
    assert main(args) == 0
    return json.loads(capsys.readouterr().out)


def kk_labels(path, select, capsys, dim):
    out = json_out(["kk", path, "--select", select, "--json"], capsys)
    assert out["dims"] == [dim] and out["n_spectra"] == len(out["spectra"])
    assert out["sizes"] == {dim: out["n_spectra"]}  # (the mapping fit's JSON calls "dims")
    return [s["labels"][dim] for s in out["spectra"]]


def test_one_label_still_picks_one_spectrum_and_drops_the_dimension(files, capsys):
    out = json_out(["inspect", files["cycles"], "--select", "cycle=5", "--json"], capsys)
    assert out["labels"] == {} and out["dims"] == {"frequency": F.size}
    out = json_out(["kk", files["cycles"], "--select", "cycle=5", "--json"], capsys)
    assert "spectra" not in out and out["rms_rel"] == pytest.approx(ix.kk_test(ix.load(files["cycles"]).sel(cycle=5)).rms_rel, rel=1e-12)


@pytest.mark.parametrize(
    "select, expected",
    [
        ("4:13", [5, 8, 13]),  # ends need not be labels; the last end is included
        ("5:13", [5, 8, 13]),  # both ends included
        ("2:2", [2]),
        (":3", [1, 2, 3]),  # an end left out: open
        ("13:", [13, 21]),
        ("0.5:1e3", CYCLES),
    ],
)
def test_a_range_picks_the_labels_xarray_sel_of_a_slice_picks(files, select, expected, capsys):
    assert kk_labels(files["cycles"], f"cycle={select}", capsys, "cycle") == expected
    first, last = (float(e) if e else None for e in select.split(":"))
    assert ix.load(files["cycles"]).sel(cycle=slice(first, last))["cycle"].values.tolist() == expected


def test_a_list_keeps_the_order_written_and_mixes_with_ranges(files, capsys):
    assert kk_labels(files["cycles"], "cycle=13,2,5", capsys, "cycle") == [13, 2, 5]
    assert kk_labels(files["cycles"], "cycle=1, 8:13", capsys, "cycle") == [1, 8, 13]
    out = json_out(["kk", files["cycles"], "--select", "cycle=13,2", "--json"], capsys)
    data = ix.load(files["cycles"])
    for spectrum, label in zip(out["spectra"], (13, 2)):
        assert spectrum["rms_rel"] == pytest.approx(ix.kk_test(data.sel(cycle=label)).rms_rel, rel=1e-12)


def test_a_batch_fit_of_a_range_carries_the_selected_labels(files, tmp_path, capsys):
    out = json_out(["fit", files["cycles"], "--model", "R0 + R1 || C1", "--select", "cycle=4:13", "--json"], capsys)
    assert out["dims"] == out["sizes"] == {"cycle": 3} and out["n_spectra"] == 3
    assert [s["labels"] for s in out["spectra"]] == [{"cycle": 5}, {"cycle": 8}, {"cycle": 13}]
    for spectrum in out["spectra"]:
        assert spectrum["values"]["R1"] == pytest.approx(100.0 * spectrum["labels"]["cycle"], rel=0.01)
    csv = tmp_path / "fit.csv"
    assert main(["fit", files["cycles"], "--model", "R0 + R1 || C1", "--select", "cycle=13,2", "--out", str(csv)]) == 0
    rows = csv.read_text().splitlines()
    column = rows[0].split(",").index("cycle")
    assert [r.split(",")[column] for r in rows[1:]] == ["13"] * 3 + ["2"] * 3  # three parameters a spectrum


def test_positions_where_a_dimension_has_no_labels_keep_their_file_positions(files, capsys):
    """The picked spectra are labelled by their positions in the file, not in the pick."""
    assert kk_labels(files["none"], "trial=3,1", capsys, "trial") == [3, 1]
    assert kk_labels(files["none"], "trial=1:3", capsys, "trial") == [1, 2, 3]  # both ends included
    assert kk_labels(files["none"], "trial=3:", capsys, "trial") == [3, 4]
    out = json_out(["fit", files["none"], "--model", "R0 + R1 || C1", "--select", "trial=4,0", "--json"], capsys)
    assert [s["labels"] for s in out["spectra"]] == [{"trial": 4}, {"trial": 0}]
    assert [s["values"]["R1"] for s in out["spectra"]] == [pytest.approx(500.0, rel=0.01), pytest.approx(100.0, rel=0.01)]


def test_text_labels_take_lists_and_a_label_with_a_comma_is_itself(files, capsys):
    assert kk_labels(files["text"], "sheet=c,a", capsys, "sheet") == ["c", "a"]
    out = json_out(["inspect", files["text"], "--select", "sheet=a,b", "--json"], capsys)  # the sheet named "a,b"
    assert out["labels"] == {} and out["attrs"]["source"].endswith("[sheet=a,b]")
    z = R0 + 300.0 / (1 + 1j * 2 * np.pi * F * 300.0 * C1)
    assert out["z_abs_max_ohm"] == pytest.approx(np.abs(z).max(), rel=0.01)
    assert main(["kk", files["text"], "--select", "sheet=a:c"]) == 2
    err = capsys.readouterr().err
    assert err.count("error:") == 1 and "a range FIRST:LAST needs numeric labels" in err and "(a, b, a,b, c)" in err


@pytest.fixture(scope="module")
def temperatures(tmp_path_factory):
    """Three small files of spectra over temperature: labelled 25.5, 30 (numbers), "25.5", "30"
    (texts) and "25,5", "30" (texts, a decimal comma). Spectrum k has R1 = 100 Ω × (k + 1)."""
    folder = tmp_path_factory.mktemp("temperatures")
    z = np.stack([rc(100.0 * (k + 1), np.random.default_rng(k)) for k in range(2)])
    paths = {}
    for name, labels in {"numbers": [25.5, 30.0], "texts": ["25.5", "30"], "comma": ["25,5", "30"]}.items():
        paths[name] = str(folder / f"{name}.nc")
        ix.save(ix.make_spectrum(F, z, dims=("temperature",), coords={"temperature": labels}), paths[name])
    return paths


def test_a_decimal_comma_label_is_picked_whole_and_a_decimal_comma_list_is_asked_about(temperatures, capsys):
    """temperature=25,5 picks the label "25,5" where there is one; where the label is 25.5 it
    is the list 25, 5, which picks nothing: the message suggests 25.5."""
    out = json_out(["inspect", temperatures["comma"], "--select", "temperature=25,5", "--json"], capsys)
    assert out["labels"] == {} and out["attrs"]["source"].endswith("[temperature=25,5]")
    assert out["z_abs_max_ohm"] == pytest.approx(np.abs(R0 + 100.0 / (1 + 1j * 2 * np.pi * F * 100.0 * C1)).max(), rel=0.01)
    for name in ("numbers", "texts"):
        assert main(["inspect", temperatures[name], "--select", "temperature=25,5"]) == 2
        err = capsys.readouterr().err
        assert err.count("error:") == 1 and "--select temperature=25,5: no spectrum of" in err and "has the label '25'" in err
        assert "did you mean 25.5? --select takes '.' as the decimal mark; ',' separates a list" in err
    assert main(["inspect", temperatures["numbers"], "--select", "temperature=25,6"]) == 2  # (25.6 is no label: no guess)
    assert "did you mean" not in capsys.readouterr().err
    assert json_out(["inspect", temperatures["numbers"], "--select", "temperature=25.5", "--json"], capsys)["labels"] == {}


def test_a_range_of_text_labels_that_are_all_numbers_compares_them_as_numbers(tmp_path, capsys):
    """Sheets named 1, 2, 10: 2:10 is sheets 2 and 10 (as text, "10" < "2")."""
    path = str(tmp_path / "sheets.nc")
    z = np.stack([rc(100.0 * (k + 1), np.random.default_rng(k)) for k in range(3)])
    ix.save(ix.make_spectrum(F, z, dims=("sheet",), coords={"sheet": ["1", "2", "10"]}), path)
    assert kk_labels(path, "sheet=2:10", capsys, "sheet") == ["2", "10"]


def test_a_labelled_dimension_takes_no_positions(files, capsys):
    """cycle=0 and cycle=0:0 are labels, and no cycle is labelled 0: positions are only for a
    dimension without labels."""
    for select in ("cycle=0", "cycle=0:0", "cycle=0,1"):
        assert main(["kk", files["cycles"], "--select", select]) == 2
        assert "its cycle labels: 1, 2, 3, 5, 8" in capsys.readouterr().err


@pytest.mark.parametrize(
    "select, fragments",
    [
        ("cycle=22:30", ["no spectrum of", "has a cycle label in 22:30 (both ends included); its cycle labels: 1, 2, 3, 5, 8"]),
        ("cycle=6:7", ["has a cycle label in 6:7"]),
        ("cycle=1,4,5", ["no spectrum of", "has the label '4'; its cycle labels: 1, 2, 3, 5, 8"]),
        ("cycle=1,,5", ["item 2 of 3 is empty"]),
        ("cycle=3,", ["item 2 of 2 is empty"]),
        ("cycle=1:5:2", ["'1:5:2' is not a range", "without a step"]),
        ("cycle=a:5", ["'a' in 'a:5' is not a number"]),
        ("cycle=13:5", ["the range 13:5 is reversed", "write 5:13"]),
        ("cycle=2,1:3", ["cycle 2 is picked twice"]),
        ("cycle='5'", ["has that label", "write 5 without the quotes"]),
        ("cycle=1,'5'", ["has the label ''5''", "write 5 without the quotes"]),
    ],
)
def test_a_bad_list_or_range_is_one_message_and_exit_2(files, tmp_path, select, fragments, capsys):
    out = tmp_path / "fit.json"
    assert main(["fit", files["cycles"], "--model", "R0 + R1 || C1", "--select", select, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("error:") == 1 and "Traceback" not in err
    assert f"--select {select}" in err
    for fragment in fragments:
        assert fragment in err
    assert not out.exists()


@pytest.mark.parametrize("select, fragment", [("trial=0,7", "'7' is not a position"), ("trial=x:2", "'x' in 'x:2' is not a position"), ("trial=-1:2", "'-1' in '-1:2' is not a position")])
def test_a_bad_position_in_a_list_or_range(files, select, fragment, capsys):
    assert main(["kk", files["none"], "--select", select]) == 2
    err = capsys.readouterr().err
    assert err.count("error:") == 1 and fragment in err and "has no labels along trial" in err and "0..4" in err


def test_one_spectrum_commands_refuse_a_pick_of_several_naming_how_many_and_which(files, tmp_path, capsys):
    one_spectrum = {
        "impedax diagnose": ["diagnose", "--model", "R0 + R1 || C1"], "impedax refine": ["refine", "--model", "R0 + R1 || C1"],
        "sample": ["sample", "--model", "R0 + R1 || C1"],
    }
    for name, args in one_spectrum.items():
        assert main([args[0], files["cycles"], *args[1:], "--select", "cycle=4:13"]) == 2
        err = capsys.readouterr().err
        assert err.count("error:") == 1 and "Traceback" not in err
        assert f"{name} takes one spectrum; --select cycle=4:13 picks 3 (cycle: 5, 8, 13): give one label, e.g. --select cycle=5" in err
    assert not (tmp_path / "kk.png").exists()
    assert main(["diagnose", files["cycles"], "--model", "R0 + R1 || C1", "--select", "cycle=21,1,2"]) == 2
    assert "picks 3 (cycle: 21, 1, 2)" in capsys.readouterr().err


def test_a_list_or_range_of_one_is_that_spectrum_for_a_one_spectrum_command(files):
    # (the rule every one-spectrum command loads by; `diagnose --select` of a range of one below)
    from impedax.cli.common import load_selected

    data = ix.load(files["cycles"])
    for select in ("cycle=6:10", "cycle=8:8", "cycle=8"):
        one = load_selected(files["cycles"], [select], single="impedax diagnose")
        assert one["Z"].dims == ("frequency",)
        np.testing.assert_array_equal(one["Z"].values, data["Z"].sel(cycle=8).values)


@pytest.mark.slow
def test_diagnose_of_a_range_of_one_diagnoses_that_spectrum(files, capsys):
    """Cycle 8 was written with R1 = 800 Ω (`files`); until 2026-12-06 `kk --method zhit` stood
    for the one-spectrum commands here, and now tests each of several."""
    out = json_out(["diagnose", files["cycles"], "--model", "R0 + R1 || C1", "--select", "cycle=6:10", "--json"], capsys)
    assert out["baseline"]["params"]["R1"]["value"] == pytest.approx(800.0, rel=0.02)


def test_picked_sheets_keep_only_their_own_reading_notes(capsys):
    """A reader's per-sheet texts (``sheet A: ...; sheet B: ...``) are narrowed to the sheets picked."""
    pytest.importorskip("openpyxl")
    xlsx = str(REAL / "data.xlsx")
    out = json_out(["inspect", xlsx, "--select", "sheet=header-variant-2,header-variant-4", "--json"], capsys)
    assert out["labels"] == {"sheet": ["header-variant-2", "header-variant-4"]}
    assert out["sign_convention"].startswith("sheet header-variant-2: column '-Zim' holds -Z''; negated to Z''; sheet header-variant-4: ")
    assert "header-variant-1" not in out["sign_convention"] + out["units"] and "header-variant-3" not in out["sign_convention"] + out["units"]


def test_gap_takes_a_list_of_sessions_as_replicates(tmp_path, monkeypatch, capsys):
    import impedax.models.gap as gap_module

    rng = np.random.default_rng(5)
    paths = []
    for name in ("total", "skin", "ts"):
        z = np.stack([[rc(100.0 * (t + 1) * (s + 1), rng) for t in range(2)] for s in range(3)])
        ds = ix.make_spectrum(F, z, dims=("session", "trial"), coords={"session": [1, 2, 3], "trial": [0, 1]})
        paths.append(str(tmp_path / f"{name}.nc"))
        ix.save(ds, paths[-1])
    seen = []

    class Stub:
        warnings = ()
        plot = None

        def summary(self):
            return {"method": "stub"}

    monkeypatch.setattr(gap_module, "gap_analysis", lambda total, skin, touchscreen, **options: seen.append(total) or Stub())
    assert json_out(["gap", *paths, "--area", "130e-6", "--select", "session=2:3", "--json"], capsys) | {"provenance": None} == {"method": "stub", "provenance": None}  # (provenance: docs/io.md)
    (total,) = seen
    assert total["Z"].dims == ("session", "trial", "frequency") and total["session"].values.tolist() == [2, 3]
    np.testing.assert_array_equal(total["Z"].values, ix.load(paths[0]).sel(session=[2, 3])["Z"].values)
    assert main(["gap", *paths, "--area", "130e-6", "--select", "session=3:1"]) == 2
    assert "the range 3:1 is reversed" in capsys.readouterr().err and len(seen) == 1


def test_the_help_says_how_a_range_is_read(capsys):
    with pytest.raises(SystemExit):
        main(["fit", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "FIRST:LAST" in text and "both ends included" in text and "cycle=3,5,9" in text and "0-based position where DIM has no labels" in text
