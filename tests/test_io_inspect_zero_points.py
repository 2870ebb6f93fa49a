"""`impedax inspect` names the points where Z is exactly 0 (an instrument's lost point, written
as 0,0), which the KK test, the DRT and fits weighted by |Z| refuse, and its "next:" commands
leave them out with --exclude, so that they run. A hostile walkthrough (2026-12-08): inspect said
"|Z| 0 Ω–53.55 mΩ" and "next: impedax kk FILE", which then refused the file.

The oracle: the REAL exampleDataGamry.DTA with its point 40 written as 0,0 (and a copy of it
all zero): the frequency is the file's own, the --exclude value that frequency to 6 digits."""

import json
from pathlib import Path

import numpy as np

import impedax as ix
from impedax.cli import main
from impedax.data import format_frequency

REAL = Path(__file__).parent / "fixtures" / "real"


def _with_zeros(tmp_path, points):
    ds = ix.load(REAL / "exampleDataGamry.DTA")
    z = ds["Z"].values.copy()
    z[points] = 0
    path = tmp_path / "zeros.csv"
    ix.save(ix.make_spectrum(ds["frequency"].values, z), path)
    return path, ds["frequency"].values


def test_a_point_of_zero_impedance_is_named_and_left_out_of_the_next_commands(tmp_path, capsys):
    path, f = _with_zeros(tmp_path, [40])
    assert main(["inspect", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["zero_impedance_hz"] == [float(f[40])]
    assert main(["inspect", str(path)]) == 0
    out = capsys.readouterr().out.splitlines()
    exclude = f"{f[40]:.6g}"
    assert f"  Z = 0: at {format_frequency(f[40])}: the KK test, the DRT and fits weighted by |Z| refuse such a point; leave it out with --exclude {exclude}" in out
    assert out[-1] == (f"next: impedax kk {path} --exclude {exclude} (are the data themselves sound?), "
                       f"then impedax drt {path} --exclude {exclude} (how many arcs; it ends with a starting circuit to fit)")
    assert main(["kk", str(path)]) == 2  # (refused as it stands)
    capsys.readouterr()
    assert main(["kk", str(path), "--exclude", exclude]) == 0  # (the command inspect gives runs)


def test_a_spectrum_zero_everywhere_has_nothing_to_analyse(tmp_path, capsys):
    path, f = _with_zeros(tmp_path, slice(None))
    assert main(["inspect", str(path)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert f"  Z = 0: at every one of the {f.size} points: nothing was recorded; no analysis takes it" in out
    assert out[-1] == "next: nothing to analyse: Z is 0 at every point; measure again"


def test_no_zero_no_line(tmp_path, capsys):
    assert main(["inspect", str(REAL / "exampleDataGamry.DTA"), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["zero_impedance_hz"] == []
    assert main(["inspect", str(REAL / "exampleDataGamry.DTA")]) == 0
    assert not [line for line in capsys.readouterr().out.splitlines() if line.startswith("  Z = 0")]
    assert np.all(ix.load(REAL / "exampleDataGamry.DTA")["Z"].values != 0)


def test_the_figure_of_a_spectrum_zero_everywhere_says_its_warning_as_one_note(tmp_path, capsys):
    """Its |Z| panel has nothing to put on a log axis: matplotlib's warning was printed with the
    file and line of impedax.plotting that drew it and that line's source; now one note."""
    path, _ = _with_zeros(tmp_path, slice(None))
    figure = tmp_path / "zeros.png"
    assert main(["inspect", str(path), "--plot", str(figure)]) == 0
    err = capsys.readouterr().err.splitlines()
    assert figure.stat().st_size > 0
    notes = [line for line in err if line.startswith("impedax: note: the figure: ")]
    assert len(notes) == 1 and "log-scaled" in notes[0], err
    assert not [line for line in err if "Warning" in line or ".py:" in line or line.startswith(" ")], err
    assert err[-1] == f"wrote {figure}"
