"""|Z| and the phase beside Z' and Z'' (EC-Lab, CH Instruments, Gamry …) are compared with
|Z'+jZ''| and atan2(Z'', Z') on reading: a |Z| column 1000× off (kΩ beside Ω) or a phase of
the other sign went unnoticed until 2026-12-06. Where they disagree beyond the rounding of the
printed digits, ``attrs["polar_columns_note"]`` says so; Z read stays as before. Every REAL file
must give no note; SYNTHETIC files written here (an R + R‖C spectrum from its formula, numpy
alone) give the expected one, with the line and factor found by numpy on the written numbers."""

import json
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from tests.cli_run import run

REAL = Path(__file__).parent / "fixtures" / "real"
SPECTRA = sorted(p for p in REAL.iterdir() if p.suffix.lower() not in (".md", ".json", ".py", ".npz") and not p.name.startswith("LICENSE"))

F = np.logspace(5, -2, 36)
Z = 20.0 + 1000.0 / (1 + 2j * np.pi * F * 1000.0 * 1e-5)  # R + R‖C: |Z| 20–1020 Ω, phase 0 to −65°


@pytest.mark.parametrize("path", SPECTRA, ids=lambda p: p.name)
def test_real_files_give_no_note(path):
    ds = ix.load(path)
    assert "polar_columns_note" not in ds.attrs, ds.attrs["polar_columns_note"]


def test_real_biologic_columns_do_agree_by_numpy():
    """The oracle behind 'no note' on REAL test_data.txt: its own |Z| and phase columns against
    its Re(Z) and -Im(Z) columns (numpy), within 1e-6 relative and 1e-4°."""
    cols = np.loadtxt(REAL / "test_data.txt", skiprows=1, usecols=(1, 2, 3, 4))
    z = cols[:, 0] - 1j * cols[:, 1]
    assert np.max(np.abs(cols[:, 2] / np.abs(z) - 1)) < 1e-6
    assert np.max(np.abs(cols[:, 3] - np.degrees(np.angle(z)))) < 1e-4
    assert "|Z|/Ohm" in ix.load(REAL / "test_data.txt").attrs["other_columns"]  # (the columns are there, and were checked)


def _write(path, modulus, phase, header="frequency,Z' (Ohm),Z'' (Ohm),|Z| (Ohm),Phase (deg)", digits=7, z=Z):
    rows = [header] + [",".join(f"{v:.{digits}g}" for v in row) for row in zip(F, z.real, z.imag, modulus, phase)]
    path.write_text("\n".join(rows) + "\n")
    return path


def _printed(path, column):
    """The numbers of ``column`` as the file holds them (numpy, not impedax)."""
    return np.loadtxt(path, delimiter=",", skiprows=1, usecols=column)


def test_consistent_synthetic_file_gives_no_note(tmp_path):
    ds = ix.load(_write(tmp_path / "ok.csv", np.abs(Z), np.degrees(np.angle(Z))))
    assert "polar_columns_note" not in ds.attrs


def test_four_digits_agree_within_their_rounding(tmp_path):
    """Printed to 4 significant digits (as CH Instruments does), the columns differ by up to a
    few 1e-4 relative: rounding, no note."""
    path = _write(tmp_path / "chi.csv", np.abs(Z), np.degrees(np.angle(Z)), digits=4)
    zz = _printed(path, 1) + 1j * _printed(path, 2)
    assert np.max(np.abs(_printed(path, 3) / np.abs(zz) - 1)) > 1e-5  # (they do differ, by rounding)
    assert "polar_columns_note" not in ix.load(path).attrs


def test_modulus_1000_times_gives_the_note(tmp_path):
    path = _write(tmp_path / "kohm.csv", 1000 * np.abs(Z), np.degrees(np.angle(Z)))
    ds = ix.load(path)
    note = ds.attrs["polar_columns_note"]
    ratio = np.median(_printed(path, 3) / np.abs(_printed(path, 1) + 1j * _printed(path, 2)))
    assert ratio == pytest.approx(1000, rel=1e-5)
    assert "'|Z| (Ohm)'" in note and "1000× |Z'+jZ''|" in note and f"on {F.size} of {F.size} rows" in note and "first on line 2 of kohm.csv" in note, note
    np.testing.assert_allclose(ds["Z"].values, _printed(path, 1) + 1j * _printed(path, 2), rtol=1e-15)  # (Z as before)


def test_phase_of_flipped_sign_gives_the_note(tmp_path):
    path = _write(tmp_path / "flip.csv", np.abs(Z), -np.degrees(np.angle(Z)))
    note = ix.load(path).attrs["polar_columns_note"]
    phase, zz = _printed(path, 4), _printed(path, 1) + 1j * _printed(path, 2)
    first = int(np.flatnonzero(np.abs(phase - np.degrees(np.angle(zz))) > 1e-3)[0]) + 2  # (line: header on line 1)
    assert "'Phase (deg)'" in note and "opposite sign" in note and f"first on line {first} of flip.csv" in note, note


def test_radians_labelled_as_such_agree(tmp_path):
    path = _write(tmp_path / "rad.csv", np.abs(Z), np.angle(Z), header="frequency,Z' (Ohm),Z'' (Ohm),|Z| (Ohm),Phase (rad)")
    assert "polar_columns_note" not in ix.load(path).attrs


def test_radians_labelled_degrees_give_the_note(tmp_path):
    path = _write(tmp_path / "rad_as_deg.csv", np.abs(Z), np.angle(Z))
    note = ix.load(path).attrs["polar_columns_note"]
    assert "radians read as degrees" in note and "Phase (rad)" in note, note


def test_negated_columns_are_compared_in_the_data_model_sign(tmp_path):
    """-Z'' and -Phase columns, each holding the negated quantity as its name says: no note."""
    rows = ["frequency,Z' (Ohm),-Z'' (Ohm),|Z| (Ohm),-Phase (deg)"] + [
        f"{f:.7g},{z.real:.7g},{-z.imag:.7g},{abs(z):.7g},{-np.degrees(np.angle(z)):.7g}" for f, z in zip(F, Z)]
    (tmp_path / "neg.csv").write_text("\n".join(rows) + "\n")
    assert "polar_columns_note" not in ix.load(tmp_path / "neg.csv").attrs


def test_a_few_rows_off_name_the_first_and_count(tmp_path):
    """|Z| off by 1 % from row 10 on (a 1 % error is 1e4× the 7-digit rounding): the count and
    first line found by numpy on the written numbers."""
    modulus = np.abs(Z) * np.where(np.arange(F.size) >= 10, 1.01, 1.0)
    path = _write(tmp_path / "some.csv", modulus, np.degrees(np.angle(Z)))
    off = np.flatnonzero(np.abs(_printed(path, 3) / np.abs(_printed(path, 1) + 1j * _printed(path, 2)) - 1) > 1e-3)
    note = ix.load(path).attrs["polar_columns_note"]
    assert f"on {off.size} of {F.size} rows, first on line {off[0] + 2} " in note and "1.01× |Z'+jZ''|" in note and "mix-up" not in note, note


def test_long_table_checked_on_a_sample_then_in_full(tmp_path):
    """25,000 rows (above CHECK_ALL_ROWS): a |Z| 1000× off is found, counted on every row."""
    f = np.logspace(5, -2, 25_000)
    z = 20.0 + 1000.0 / (1 + 2j * np.pi * f * 1e-2)
    rows = ["frequency,Z' (Ohm),Z'' (Ohm),|Z| (Ohm),Phase (deg)"] + [
        f"{a:.9g},{b:.9g},{c:.9g},{d:.9g},{e:.9g}" for a, b, c, d, e in zip(f, z.real, z.imag, 1000 * np.abs(z), np.degrees(np.angle(z)))]
    (tmp_path / "long.csv").write_text("\n".join(rows) + "\n")
    note = ix.load(tmp_path / "long.csv").attrs["polar_columns_note"]
    assert "on 25000 of 25000 rows, first on line 2 " in note and "1000×" in note, note


def _gamry(tmp_path, column, change):
    """REAL exampleDataGamry.DTA with one ZCURVE column changed by ``change``."""
    lines = (REAL / "exampleDataGamry.DTA").read_bytes().decode("latin-1").split("\n")
    start = next(k for k, line in enumerate(lines) if line.startswith("ZCURVE"))
    names = lines[start + 1].split("\t")
    k = names.index(column)
    first = None
    for n in range(start + 3, len(lines)):
        if not lines[n].startswith("\t"):
            break
        cells = lines[n].split("\t")
        cells[k] = repr(change(float(cells[k])))
        lines[n] = "\t".join(cells)
        first = first or n + 1
    path = tmp_path / "gamry.DTA"
    path.write_bytes("\n".join(lines).encode("latin-1"))
    return path, first


def test_gamry_zmod_1000_times_gives_the_note(tmp_path):
    path, first = _gamry(tmp_path, "Zmod", lambda v: v * 1000)
    note = ix.load(path).attrs["polar_columns_note"]
    assert "'Zmod'" in note and "1000×" in note and f"first on line {first} of gamry.DTA" in note, note


def test_gamry_zphz_flipped_gives_the_note(tmp_path):
    path, first = _gamry(tmp_path, "Zphz", lambda v: -v)
    note = ix.load(path).attrs["polar_columns_note"]
    assert "'Zphz'" in note and "opposite sign" in note and f"first on line {first} of gamry.DTA" in note, note


def test_cli_warns_and_inspect_shows_it(tmp_path, capsys):
    path = _write(tmp_path / "kohm.csv", 1000 * np.abs(Z), np.degrees(np.angle(Z)))
    code, out, err = run(["inspect", path], capsys)
    assert code == 0 and "polar columns note: column '|Z| (Ohm)'" in out, out
    code, out, err = run(["inspect", "--json", path], capsys)
    assert code == 0 and "1000× |Z'+jZ''|" in json.loads(out)["attrs"]["polar_columns_note"]
    code, out, err = run(["kk", path], capsys)
    assert code == 0 and "impedax: warning:" in err and "1000× |Z'+jZ''|" in err, err


def test_spreadsheet_modulus_1000_times_gives_the_note(tmp_path):
    openpyxl = pytest.importorskip("openpyxl")
    book = openpyxl.Workbook()
    book.active.append(["frequency", "Z' (Ohm)", "Z'' (Ohm)", "|Z| (Ohm)", "Phase (deg)"])
    for f, z in zip(F.tolist(), Z.tolist()):
        book.active.append([f, z.real, z.imag, 1000 * abs(z), float(np.degrees(np.angle(z)))])
    book.save(tmp_path / "kohm.xlsx")
    note = ix.load(tmp_path / "kohm.xlsx").attrs["polar_columns_note"]
    assert "'|Z| (Ohm)'" in note and "1000× |Z'+jZ''|" in note and f"on {F.size} of {F.size} rows" in note, note


def test_sign_hint_cites_the_files_phase_column(tmp_path, capsys):
    """Z'' written as -Z'' under the header Z'' (Z'' > 0 while |Z| falls), the phase column
    right: the sign hint says the file's own phase column agrees (numpy: the column's sign is
    the opposite of atan2 of the written Z', Z'' on every row not resistive)."""
    from impedax.io.sign_check import values_sign_hint

    path = _write(tmp_path / "flipped_z.csv", np.abs(Z), np.degrees(np.angle(Z)), z=Z.conj())
    written = np.degrees(np.angle(_printed(path, 1) + 1j * _printed(path, 2)))
    telling = np.abs(written) > 1
    assert np.all(np.sign(_printed(path, 4)[telling]) == -np.sign(written[telling]))
    ds = ix.load(path)
    hint = values_sign_hint(ds["frequency"].values, ds["Z"].values, ds.attrs)
    assert "the file's own phase column 'Phase (deg)' says so too" in hint, hint
    code, out, err = run(["inspect", path], capsys)
    assert code == 0 and "hint:" in out and "'Phase (deg)' says so too" in out, out
    plain = _write(tmp_path / "plain.csv", np.abs(Z), -np.degrees(np.angle(Z)), z=Z.conj())  # (both flipped: they agree)
    ds = ix.load(plain)
    assert "polar_columns_note" not in ds.attrs
    assert "says so too" not in values_sign_hint(ds["frequency"].values, ds["Z"].values, ds.attrs)


def test_sign_hint_reads_the_flipped_phase_column_not_the_notes_words(tmp_path, monkeypatch):
    """`sign_check` found the flipped phase column by a regex over the note's prose: reworded,
    the hint lost the column. The reader records the column's name in its own attribute,
    ``polar_columns_flipped_phase`` (a string: netCDF keeps it), which the hint reads. SYNTHETIC
    Z'' written as -Z'' beside a right phase column (as above); the note is reworded twice: by the
    words `consistency` writes, and by replacing the whole note after reading."""
    from impedax.io import consistency
    from impedax.io.sign_check import values_sign_hint

    path = _write(tmp_path / "flipped_z.csv", np.abs(Z), np.degrees(np.angle(Z)), z=Z.conj())
    cited = "the file's own phase column 'Phase (deg)' says so too"
    ds = ix.load(path)
    ds.attrs["polar_columns_note"] = "Phase (deg) and Z'' point opposite ways."
    assert cited in values_sign_hint(ds["frequency"].values, ds["Z"].values, ds.attrs)
    monkeypatch.setattr(consistency, "OPPOSITE_SIGN_WORDS", "its sign is reversed")
    ds = ix.load(path)
    assert "its sign is reversed" in ds.attrs["polar_columns_note"] and "opposite sign" not in ds.attrs["polar_columns_note"]
    assert ds.attrs["polar_columns_flipped_phase"] == "Phase (deg)"
    assert cited in values_sign_hint(ds["frequency"].values, ds["Z"].values, ds.attrs)
    ix.save(ds, tmp_path / "flipped_z.nc")
    back = ix.load(tmp_path / "flipped_z.nc")
    assert back.attrs["polar_columns_flipped_phase"] == "Phase (deg)"
    assert cited in values_sign_hint(back["frequency"].values, back["Z"].values, back.attrs)


def test_flipped_phase_attribute_only_for_a_phase_of_the_other_sign(tmp_path):
    """Set beside the note for a phase of the other sign only: not for |Z| 1000× off, radians
    labelled degrees, or columns that agree (SYNTHETIC, as above)."""
    cases = {"kohm": (1000 * np.abs(Z), np.degrees(np.angle(Z))), "rad": (np.abs(Z), np.angle(Z)), "ok": (np.abs(Z), np.degrees(np.angle(Z))),
             "flip": (np.abs(Z), -np.degrees(np.angle(Z)))}
    attrs = {name: ix.load(_write(tmp_path / f"{name}.csv", *columns)).attrs for name, columns in cases.items()}
    assert [name for name, a in attrs.items() if "polar_columns_note" in a] == ["kohm", "rad", "flip"]
    assert [name for name, a in attrs.items() if "polar_columns_flipped_phase" in a] == ["flip"]
    assert attrs["flip"]["polar_columns_flipped_phase"] == "Phase (deg)"


def test_flipped_phase_of_some_sheets_names_no_column_for_the_whole_file(tmp_path):
    """Two sheets (SYNTHETIC): the attribute names the column when every sheet's phase is
    flipped, and is left out when one sheet's only (a batch's hint cannot tell which sheet its
    spectrum came from; the note, labelled by sheet, says which)."""
    openpyxl = pytest.importorskip("openpyxl")

    def book(flips, name):
        wb = openpyxl.Workbook()
        wb.remove(wb.active)
        for k, flip in enumerate(flips):
            ws = wb.create_sheet(f"s{k}")
            ws.append(["frequency", "Z' (Ohm)", "Z'' (Ohm)", "|Z| (Ohm)", "Phase (deg)"])
            for f, z in zip(F.tolist(), Z.tolist()):
                ws.append([f, z.real, z.imag, abs(z), (-1 if flip else 1) * float(np.degrees(np.angle(z)))])
        wb.save(tmp_path / name)
        return ix.load(tmp_path / name).attrs

    both, one = book([True, True], "both.xlsx"), book([True, False], "one.xlsx")
    assert both["polar_columns_flipped_phase"] == "Phase (deg)"
    assert "polar_columns_flipped_phase" not in one and one["polar_columns_note"].startswith("sheet s0: column 'Phase (deg)'"), one


def _first_row_1000_times(cells_by_row):
    """The spreadsheet row (as its program numbers them) of the first data row whose |Z| cell is
    over 100× |Z'+jZ''| of its cells: ``cells_by_row`` maps row number → the row's cell values."""
    for row, cells in sorted(cells_by_row.items()):
        try:
            real, imag, modulus = (float(c) for c in cells[1:4])
        except (TypeError, ValueError, IndexError):
            continue
        if modulus > 100 * abs(complex(real, imag)):
            return row
    raise AssertionError("no row found")


def test_spreadsheet_note_names_the_row_the_program_shows(tmp_path):
    """In a spreadsheet the note says 'row N', N as the spreadsheet program numbers the rows (it
    said 'line N'). SYNTHETIC sheet: two empty rows, a note, the header, a units row, then the
    data, |Z| 1000× off from the third data row on; the row found by openpyxl's own cell.row."""
    openpyxl = pytest.importorskip("openpyxl")
    book = openpyxl.Workbook()
    sheet = book.active
    sheet.cell(row=3, column=1, value="Instrument: SYNTHETIC")
    sheet.append(["frequency", "Z'", "Z''", "|Z|", "Phase"])
    sheet.append(["Hz", "Ohm", "Ohm", "Ohm", "deg"])
    for k, (f, z) in enumerate(zip(F.tolist(), Z.tolist())):
        sheet.append([f, z.real, z.imag, abs(z) * (1000 if k >= 2 else 1), float(np.degrees(np.angle(z)))])
    book.save(tmp_path / "rows.xlsx")
    cells = {row[0].row: [c.value for c in row] for row in openpyxl.load_workbook(tmp_path / "rows.xlsx").active.iter_rows()}
    row = _first_row_1000_times(cells)
    assert row == 8  # (3 rows above the header, the header, the units, two data rows: by hand)
    note = ix.load(tmp_path / "rows.xlsx").attrs["polar_columns_note"]
    assert f"on {F.size - 2} of {F.size} rows, first on row {row} of rows.xlsx [sheet Sheet]" in note and "line" not in note, note


def test_ods_note_names_the_row_the_program_shows(tmp_path):
    """The same in OpenDocument: rows counted from the file's content.xml (a row repeated N
    times is N rows), three empty rows above the header written as one repeated row, as
    LibreOffice writes them."""
    pytest.importorskip("odf")
    import re
    import zipfile

    import pandas as pd

    modulus = np.abs(Z) * np.where(np.arange(F.size) >= 2, 1000, 1)
    frame = pd.DataFrame({"frequency": F, "Z' (Ohm)": Z.real, "Z'' (Ohm)": Z.imag, "|Z| (Ohm)": modulus, "Phase (deg)": np.degrees(np.angle(Z))})
    frame.to_excel(tmp_path / "pandas.ods", engine="odf", index=False, startrow=3)
    with zipfile.ZipFile(tmp_path / "pandas.ods") as zin, zipfile.ZipFile(tmp_path / "rows.ods", "w") as zout:
        for item in zin.infolist():
            data = zin.read(item.filename)
            if item.filename == "content.xml":
                data = data.replace(b"<table:table-row/>" * 3, b'<table:table-row table:number-rows-repeated="3"><table:table-cell/></table:table-row>', 1)
            zout.writestr(item, data)
    content = zipfile.ZipFile(tmp_path / "rows.ods").read("content.xml").decode()
    cells, row = {}, 0
    for element in re.findall(r"<table:table-row[^>]*?(?:/>|>.*?</table:table-row>)", content):
        repeated = re.search(r'number-rows-repeated="(\d+)"', element)
        row += int(repeated.group(1)) if repeated else 1
        cells[row] = re.findall(r"<text:p>(.*?)</text:p>", element)
    assert 'number-rows-repeated="3"' in content and _first_row_1000_times(cells) == 7
    note = ix.load(tmp_path / "rows.ods").attrs["polar_columns_note"]
    assert f"first on row {_first_row_1000_times(cells)} of rows.ods [sheet Sheet1]" in note, note


def _palmsens(tmp_path, name, change):
    """REAL data.pssession with the measurement's array ``name`` changed by ``change`` (a SYNTHETIC
    mutated copy, UTF-16 with a byte-order mark as the original), and the arrays as written
    (json, not impedax)."""
    text = (REAL / "data.pssession").read_bytes().decode("utf-16")
    session, _ = json.JSONDecoder().raw_decode(text.lstrip("\ufeff"))
    values = session["Measurements"][0]["DataSet"]["Values"]
    for entry in values:
        if entry["Description"] == name:
            for point in entry["DataValues"]:
                point["V"] = change(point["V"])
    path = tmp_path / f"{name}.pssession"
    path.write_bytes(("\ufeff" + json.dumps(session)).encode("utf-16-le"))
    arrays = {e["Description"]: np.array([p["V"] for p in e["DataValues"]]) for e in values}
    return path, arrays


def test_real_palmsens_arrays_do_agree_by_numpy():
    """The oracle behind 'no note' on REAL data.pssession: its Z and Phase arrays (Phase holds
    −phase, its 'Q' says '-Phase') against ZRe − j·ZIm, by numpy on the JSON."""
    text = (REAL / "data.pssession").read_bytes().decode("utf-16")
    session, _ = json.JSONDecoder().raw_decode(text.lstrip("\ufeff"))
    entries = {e["Description"]: e for e in session["Measurements"][0]["DataSet"]["Values"]}
    v = {k: np.array([p["V"] for p in e["DataValues"]]) for k, e in entries.items()}
    z = v["ZRe"] - 1j * v["ZIm"]
    assert entries["Phase"]["Unit"]["Q"] == "-Phase" and entries["Z"]["Unit"]["S"] == "\u2126"
    assert np.max(np.abs(v["Z"] / np.abs(z) - 1)) < 1e-12 and np.max(np.abs(-v["Phase"] - np.degrees(np.angle(z)))) < 1e-10
    assert "polar_columns_note" not in ix.load(REAL / "data.pssession").attrs


def test_palmsens_phase_flipped_gives_the_note_and_the_name(tmp_path):
    path, arrays = _palmsens(tmp_path, "Phase", lambda v: -v)
    ds = ix.load(path)
    note = ds.attrs["polar_columns_note"]
    z = arrays["ZRe"] - 1j * arrays["ZIm"]
    off = np.flatnonzero(np.abs(-arrays["Phase"] - np.degrees(np.angle(z))) > 1e-3)  # (points counted from 0, as the reader's messages)
    assert "column 'Phase'" in note and "opposite sign" in note and f"on {off.size} of {z.size} points, first at point {off[0]} of Phase.pssession" in note, note
    assert ds.attrs["polar_columns_flipped_phase"] == "Phase"
    np.testing.assert_array_equal(np.sort_complex(ds["Z"].values), np.sort_complex(z))  # (Z read from ZRe and ZIm, as before)


def test_palmsens_modulus_1000_times_gives_the_note(tmp_path):
    path, arrays = _palmsens(tmp_path, "Z", lambda v: 1000 * v)
    note = ix.load(path).attrs["polar_columns_note"]
    n = arrays["Z"].size
    assert np.median(arrays["Z"] / np.abs(arrays["ZRe"] - 1j * arrays["ZIm"])) == pytest.approx(1000, rel=1e-9)
    assert "column 'Z'" in note and "1000× |Z'+jZ''|" in note and f"on {n} of {n} points, first at point 0 of Z.pssession" in note, note


LABONE = Path(__file__).parent / "fixtures" / "dev3000_imps_0_sample_00000.csv"  # (SYNTHETIC: a LabOne export's layout, two sweeps)


def _labone_rows(tmp_path, field, change):
    """The LabOne fixture with every value of ``field`` changed by ``change``; its fields by sweep
    as written (numpy on the text, not impedax)."""
    lines = LABONE.read_text().splitlines()
    for k, line in enumerate(lines):
        cells = line.split(";")
        if len(cells) > 4 and cells[3] == field:
            lines[k] = ";".join(cells[:4] + [repr(change(float(c))) for c in cells[4:]])
    path = tmp_path / f"{field}.csv"
    path.write_text("\n".join(lines) + "\n")
    fields = {(cells[0], cells[3]): np.array([float(c) for c in cells[4:]]) for cells in (ln.split(";") for ln in lines[1:])}
    return path, fields


def test_labone_fields_agree_and_give_no_note():
    """absz and phasez [rad] beside realz and imagz in the (SYNTHETIC) fixture agree to its 11
    digits (numpy): no note."""
    lines = [ln.split(";") for ln in LABONE.read_text().splitlines()[1:]]
    fields = {(c[0], c[3]): np.array([float(v) for v in c[4:]]) for c in lines}
    for sweep in ("0", "1"):
        z = fields[sweep, "realz"] + 1j * fields[sweep, "imagz"]
        assert np.max(np.abs(fields[sweep, "absz"] / np.abs(z) - 1)) < 1e-9 and np.max(np.abs(fields[sweep, "phasez"] - np.angle(z))) < 1e-9
    assert "polar_columns_note" not in ix.load(LABONE).attrs


@pytest.mark.parametrize("field, change, words", [("phasez", lambda v: -v, "opposite sign"), ("absz", lambda v: 1000 * v, "1000× |Z'+jZ''|")])
def test_labone_csv_mutated_fields_give_the_note(tmp_path, field, change, words):
    """SYNTHETIC copies with phasez negated, absz ×1000: the note, at point 0 (points counted
    from 0, as the reader's messages), once when both sweeps' notes are the same (their phasez
    are), else labelled by sweep; the flipped phase's field named for the file."""
    path, fields = _labone_rows(tmp_path, field, change)
    ds = ix.load(path)
    note = ds.attrs["polar_columns_note"]
    n = fields["0", "realz"].size
    same = np.array_equal(fields["0", field], fields["1", field])
    assert same == (field == "phasez") and note.count(f"column '{field}' disagrees") == (1 if same else 2), note
    assert same or (note.startswith("sweep 0: ") and "; sweep 1: " in note), note
    assert f"on {n} of {n} points, first at point 0 of {path.name}" in note and words in note, note
    assert ds.attrs.get("polar_columns_flipped_phase") == ("phasez" if field == "phasez" else None)


def test_labone_table_layout_names_the_line(tmp_path):
    """One column per field (SYNTHETIC RC, as tests/test_labone_phase_in_degrees.py): the note
    names the line; the line found by numpy on the written text."""
    f = np.array([10.0, 100.0, 1000.0, 10000.0])
    z = 1000 / (1 + 2j * np.pi * f * 1e-3)
    phase = np.where(f >= 100, -np.angle(z), np.angle(z))  # (flipped from the second point on)
    rows = ["frequency;realz;imagz;absz;phasez"] + [f"{a!r};{b.real!r};{b.imag!r};{abs(b)!r};{p!r}" for a, b, p in zip(f.tolist(), z.tolist(), phase.tolist())]
    (tmp_path / "table.csv").write_text("\n".join(rows) + "\n")
    table = np.loadtxt(tmp_path / "table.csv", delimiter=";", skiprows=1)
    first = int(np.flatnonzero(np.abs(table[:, 4] - np.angle(table[:, 1] + 1j * table[:, 2])) > 1e-6)[0]) + 2  # (header on line 1)
    note = ix.load(tmp_path / "table.csv").attrs["polar_columns_note"]
    assert first == 3 and f"on 3 of 4 rows, first on line {first} of table.csv" in note and "opposite sign" in note, note


def test_labone_hdf5_fields_compared(tmp_path):
    """The HDF5 export (SYNTHETIC RC): agreeing fields give no note, phasez negated gives it."""
    h5py = pytest.importorskip("h5py")
    f = np.array([10.0, 100.0, 1000.0, 10000.0])
    z = 1000 / (1 + 2j * np.pi * f * 1e-3)
    for name, phase in (("ok.h5", np.angle(z)), ("flip.h5", -np.angle(z))):
        with h5py.File(tmp_path / name, "w") as fh:
            g = fh.create_group("000/dev3000/imps/0/sample")
            g["frequency"], g["realz"], g["imagz"], g["absz"], g["phasez"] = f, z.real, z.imag, np.abs(z), phase
    assert "polar_columns_note" not in ix.load(tmp_path / "ok.h5").attrs
    ds = ix.load(tmp_path / "flip.h5")
    assert "column 'phasez'" in ds.attrs["polar_columns_note"] and "on 4 of 4 points, first at point 0 of flip.h5" in ds.attrs["polar_columns_note"]
    assert ds.attrs["polar_columns_flipped_phase"] == "phasez"
    np.testing.assert_allclose(ds["Z"].values, z, rtol=1e-15)


def _mpr(tmp_path, monkeypatch, modulus, phase, dtype="f4"):
    """A .mpr read through a stand-in for galvani (as tests/test_readers.py): its record holds
    SYNTHETIC Z of the R + R‖C above as EC-Lab stores it (float32, -Im(Z)), with ``modulus`` and
    ``phase`` [deg] beside it."""
    import sys
    import types

    table = np.zeros(F.size, dtype=[("freq/Hz", dtype), ("Re(Z)/Ohm", dtype), ("-Im(Z)/Ohm", dtype), ("|Z|/Ohm", dtype), ("Phase(Z)/deg", dtype)])
    table["freq/Hz"], table["Re(Z)/Ohm"], table["-Im(Z)/Ohm"], table["|Z|/Ohm"], table["Phase(Z)/deg"] = F, Z.real, -Z.imag, modulus, phase
    fake = types.ModuleType("galvani")
    fake.BioLogic = types.SimpleNamespace(MPRfile=lambda name: types.SimpleNamespace(data=table))
    monkeypatch.setitem(sys.modules, "galvani", fake)
    path = tmp_path / "run.mpr"
    path.write_bytes(b"BIO-LOGIC MODULAR FILE\x1a" + bytes(100))
    return path, table


def test_mpr_polar_columns_compared(tmp_path, monkeypatch):
    """float32 columns that agree (|Z| and the phase rounded to float32 apart from Re and -Im):
    no note; the phase negated: the note and the column's name; |Z| ×1000: the factor."""
    path, table = _mpr(tmp_path, monkeypatch, np.abs(Z), np.degrees(np.angle(Z)))
    stored = table["Re(Z)/Ohm"].astype(float) - 1j * table["-Im(Z)/Ohm"].astype(float)
    assert 0 < np.max(np.abs(table["|Z|/Ohm"] / np.abs(stored) - 1)) < 1e-6  # (they differ, by float32 rounding alone)
    assert "polar_columns_note" not in ix.load(path).attrs
    path, _ = _mpr(tmp_path, monkeypatch, np.abs(Z), -np.degrees(np.angle(Z)))
    ds = ix.load(path)
    assert "column 'Phase(Z)/deg'" in ds.attrs["polar_columns_note"] and f"on {F.size} of {F.size} points, first at point 0 of run.mpr" in ds.attrs["polar_columns_note"]
    assert ds.attrs["polar_columns_flipped_phase"] == "Phase(Z)/deg"
    path, _ = _mpr(tmp_path, monkeypatch, 1000 * np.abs(Z), np.degrees(np.angle(Z)))
    assert "1000× |Z'+jZ''|" in ix.load(path).attrs["polar_columns_note"]


def test_labone_phasez_in_degrees_beside_realz_says_so_without_a_column_to_rename(tmp_path):
    """phasez written in degrees beside realz and imagz (SYNTHETIC RC): the note says degrees read
    as radians, and suggests no header name (LabOne's field names are the format's; a table's
    note says "name the column 'Phase (deg)'")."""
    f = np.array([10.0, 100.0, 1000.0, 10000.0])
    z = 1000 / (1 + 2j * np.pi * f * 1e-3)
    rows = ["chunk;timestamp;size;fieldname"] + [f"0;1;4;{name};" + ";".join(repr(v) for v in values.tolist())
                                                 for name, values in (("frequency", f), ("realz", z.real), ("imagz", z.imag), ("absz", np.abs(z)), ("phasez", np.degrees(np.angle(z))))]
    (tmp_path / "deg.csv").write_text("\n".join(rows) + "\n")
    note = ix.load(tmp_path / "deg.csv").attrs["polar_columns_note"]
    assert "its values are degrees read as radians" in note and "name the column" not in note, note


def test_degrees_labelled_radians_give_the_note(tmp_path):
    """A 'Phase (rad)' column holding degrees (SYNTHETIC): read as radians, its value in degrees
    is 180/π × the number; the note says degrees read as radians (the test of that compared
    with (180/π)³ × the phase and never held, 'off by up to …°' instead)."""
    path = _write(tmp_path / "deg_as_rad.csv", np.abs(Z), np.degrees(np.angle(Z)), header="frequency,Z' (Ohm),Z'' (Ohm),|Z| (Ohm),Phase (rad)")
    note = ix.load(path).attrs["polar_columns_note"]
    assert "its values are degrees read as radians: name the column 'Phase (deg)'" in note, note


def test_inspect_lists_the_flipped_phase_column_once(tmp_path, capsys):
    """`impedax inspect` prints the attrs it has no line for; ``polar_columns_flipped_phase``
    repeats the polar-columns note's column, which inspect prints under "how it was read", so it
    is not listed again (SYNTHETIC phase column of the other sign). The JSON keeps every attr."""
    path = _write(tmp_path / "flipped_phase.csv", np.abs(Z), -np.degrees(np.angle(Z)))
    assert ix.load(path).attrs["polar_columns_flipped_phase"] == "Phase (deg)"
    code, out, err = run(["inspect", path], capsys)
    assert code == 0 and "polar columns note:" in out, out
    assert "polar_columns_flipped_phase" not in out, out
    code, out, err = run(["inspect", "--json", path], capsys)
    assert code == 0 and json.loads(out)["attrs"]["polar_columns_flipped_phase"] == "Phase (deg)"


def test_a_phase_cell_not_finite_gives_no_numpy_warning():
    """A phase cell of inf (a mutated REAL test_data.txt in tests/test_readers_fuzz.py) made the
    angle's wrap print numpy's RuntimeWarning "invalid value encountered in remainder"; the check
    runs quietly and judges the finite rows (SYNTHETIC Z with its own phase, one cell inf)."""
    import warnings

    from impedax.io.consistency import polar_columns_attrs

    phase = np.degrees(np.angle(Z))
    phase[3] = np.inf
    names = {"real": "Z'", "imag": "Z''", "modulus": "|Z|", "phase": "Phase (deg)"}
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        attrs = polar_columns_attrs(Z, np.abs(Z), phase, list(range(2, Z.size + 2)), names, {k: 1.0 for k in names},
                                    lambda rows: {k: [f"{v:.7g}" for v in np.ones(len(rows))] for k in names}, "t.csv")
    assert "polar_columns_flipped_phase" not in attrs
