"""``impedax compare --out FILE``: .csv one row per model, .json the --json document, '-' the
JSON to standard output; a bad extension or an unwritable path refused before any fit (exit 2,
one message, the folder unchanged); a failed write leaves no file and no temporary."""

import csv
import errno
import json
import math
import os

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from permissions import read_only_folder

MODELS = ("R0 + R1 || C1", "R0 + R1 || CPE1")


@pytest.fixture
def workdir(tmp_path, monkeypatch):
    """A folder with a spectrum (SYNTHETIC: R0 + R1 ∥ CPE1 by numpy, 1 % noise), a file, and a
    read-only folder (for root, whom permissions do not stop, os.access answers as for a user)."""
    f = np.geomspace(1.0, 1e5, 30)
    rng = np.random.default_rng(3)
    z = (10 + 1 / (1 / 100 + 1e-5 * (2j * np.pi * f) ** 0.9)) * (1 + 0.01 * (rng.normal(size=30) + 1j * rng.normal(size=30)) / np.sqrt(2))
    ix.save(ix.make_spectrum(f, z), tmp_path / "arc.csv")
    with read_only_folder(tmp_path / "ro", monkeypatch):
        monkeypatch.chdir(tmp_path)
        yield tmp_path


def argv(*extra):
    return ["compare", "arc.csv", "--model", MODELS[0], "--model", MODELS[1], *extra]


def snapshot(folder):
    return {p.relative_to(folder).as_posix(): (p.read_bytes() if p.is_file() else None) for p in sorted(folder.rglob("*"))}


def test_csv_holds_one_row_per_model_and_the_json_what_json_prints(workdir, capsys):
    assert main(argv("--out", "c.csv")) == 0
    out, err = capsys.readouterr()
    assert out.startswith("model ") and "wrote c.csv" in err  # (the table still printed)
    rows = list(csv.DictReader(open(workdir / "c.csv", encoding="utf-8")))
    assert [r["model"] for r in rows] == list(MODELS)
    assert {"n_params", "rms_rel", "chi2", "chi2_red", "aic", "aicc", "bic", "delta_aic", "akaike_weight", "delta_aicc", "akaike_weight_aicc", "converged", "undetermined"} <= set(rows[0])
    # the weights are the AIC column's, by hand: exp(−Δ/2)/Σ
    aic = np.array([float(r["aic"]) for r in rows])
    w = np.exp(-(aic - aic.min()) / 2)
    assert [float(r["akaike_weight"]) for r in rows] == pytest.approx(w / w.sum(), abs=1e-12)
    # and the numbers are the --json's, to the last digit (shortest exact form)
    assert main(argv("--json")) == 0
    doc = json.loads(capsys.readouterr().out)
    for r, m in zip(rows, doc["models"]):
        assert float(r["aic"]) == m["aic"] and float(r["aicc"]) == m["aicc"] and int(r["n_params"]) == m["n_params"]
        assert r["converged"] == ("true" if m["converged"] else "false")
    assert main(argv("--json", "--out", "c.json")) == 0
    printed = capsys.readouterr().out
    assert (workdir / "c.json").read_text(encoding="utf-8") == printed


def test_out_dash_prints_the_json_and_nothing_else(workdir, capsys):
    assert main(argv("--out", "-")) == 0
    out = capsys.readouterr().out
    doc = json.loads(out)  # (the whole of standard output is the JSON: no table before it)
    assert [m["model"] for m in doc["models"]] == list(MODELS) and doc["best"] in MODELS
    assert main(argv("--out", "-", "--json")) == 2
    assert "--out - and --json both write to standard output" in capsys.readouterr().err


@pytest.mark.parametrize(
    "path, fragment",
    [
        ("c.txt", "unknown extension '.txt' for a comparison; use .csv (one row per model) or .json"),
        ("c.nc", "--out: .nc is for a comparison over several spectra (a file of several, or a --select leaving several); for one spectrum use .csv"),
        ("c", "unknown extension '(none)' for a comparison"),
        ("missing/c.csv", "directory missing does not exist"),
        ("arc.csv/c.csv", "arc.csv is a file"),
        ("ro/c.csv", "is not writable"),
        ("ro", "unknown extension '(none)'"),
        (".", "unknown extension '(none)'"),
        ("arc.csv", "is the input file"),
        ("", "empty file name"),
    ],
    ids=["txt", "nc", "no-extension", "missing-folder", "under-a-file", "read-only-folder", "a-folder", "dot", "the-input", "empty"],
)
def test_bad_out_is_refused_before_any_fit(path, fragment, workdir, capsys, monkeypatch):
    def no_fit(*args, **kwargs):
        raise AssertionError("compare fitted before refusing --out")

    monkeypatch.setattr(ix, "fit", no_fit)
    before = snapshot(workdir)
    assert main(argv("--out", path)) == 2
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("impedax compare: error: ") and fragment in lines[0], err
    assert out == "" and "Traceback" not in err
    assert snapshot(workdir) == before


def test_a_failed_write_leaves_no_file_and_the_old_one_as_it_was(workdir, capsys, monkeypatch):
    """The disk fills while the CSV is written: exit 2, one message, the earlier file kept, no
    temporary left; with --plot too, neither output appears."""
    import impedax.io.export as export

    (workdir / "c.csv").write_text("an earlier comparison\n")

    def disk_full(rows, path):
        with open(path, "w") as fh:  # a partial file, as a full disk leaves it
            fh.write("model,n_par")
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(export, "write_table", disk_full)
    before = snapshot(workdir)
    assert main(argv("--out", "c.csv", "--plot", "c.png")) == 2
    err = capsys.readouterr().err
    assert "No space left on device" in err and "c.csv" in err and "Traceback" not in err
    assert snapshot(workdir) == before  # c.csv unchanged, no c.png, no temporary


def test_out_and_plot_are_written_together(workdir, capsys):
    assert main(argv("--out", "c.json", "--plot", "c.png")) == 0
    err = capsys.readouterr().err
    assert "wrote c.json" in err and "wrote c.png" in err
    doc = json.loads((workdir / "c.json").read_text(encoding="utf-8"))
    assert doc["ranked_by"] == "aic" and doc["aic_form"] == "n ln(chi2/n) + 2k"
    assert all(not (isinstance(v, float) and math.isnan(v)) for m in doc["models"] for v in m.values())
    assert (workdir / "c.png").read_bytes()[:4] == b"\x89PNG"
