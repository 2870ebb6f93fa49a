"""`impedax remaining --out REM.csv` says that a CSV keeps no attributes, so a fit of it by sigma
cannot tell that sigma is the trial means' standard error; `impedax gap --remaining REM.csv`
writes the same remainder and said nothing (2026-12-06). It now says it too, naming its own option.
The analysis is a stand-in (its remainder the trial means of SYNTHETIC R ∥ C spectra in numpy)."""

import json

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.models.sirin import remaining_impedance


@pytest.fixture
def contacts(tmp_path):
    rng = np.random.default_rng(3)
    freq = np.logspace(1, 5, 20)
    paths, data = [], []
    for name, r in (("total", 3e5), ("skin", 1e5), ("ts", 1e5)):
        z = np.stack([r / (1 + 2j * np.pi * freq * r * 1e-10) * (1 + 0.005 * (rng.standard_normal(freq.size) + 1j * rng.standard_normal(freq.size))) for _ in range(3)])
        data.append(ix.make_spectrum(freq, z, dims=("trial",), coords={"trial": [0, 1, 2]}))
        paths.append(str(tmp_path / f"{name}.nc"))
        ix.save(data[-1], paths[-1])
    return paths, remaining_impedance(*data)


def _stand_in(remainder):
    class Analysis:
        settings, v0, plot, warnings, alarms, remaining = None, 75.0, None, (), (), remainder

        def summary(self):
            return {"warnings": [], "alarms": []}

    return Analysis()


@pytest.mark.parametrize("name, noted", [("rem.csv", True), ("rem.nc", False)])
def test_gap_says_a_csv_remainder_loses_what_its_sigma_is(contacts, tmp_path, monkeypatch, capsys, name, noted):
    import impedax.models.gap as gap_module

    paths, remainder = contacts
    monkeypatch.setattr(gap_module, "gap_analysis", lambda *a, **k: _stand_in(remainder))
    out = tmp_path / name
    assert main(["gap", *paths, "--area", "130e-6", "--json", "--quiet", "--remaining", str(out)]) == 0
    captured = capsys.readouterr()
    json.loads(captured.out)
    note = f"impedax gap: note: {out} keeps no attributes, so impedax fit of it cannot tell that its sigma is the standard error of trial means"
    assert (note in captured.err) is noted, captured.err
    assert not noted or "write .nc (--remaining FILE.nc) to keep what sigma is" in captured.err
    assert out.exists()
