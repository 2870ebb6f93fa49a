"""``impedax gap --json`` names the alarms on stderr as well as the warnings: a hierarchical run on
the SYNTHETIC demo data printed "impedax gap: 2 warning(s), see the JSON 'warnings'" while the
JSON's ``alarms`` held SAMPLING UNRELIABLE, which voids the bands (2026-12-06). The analysis is a
stand-in here (its warnings and alarms given); the files are SYNTHETIC R ∥ C spectra in numpy."""

import json

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

SAMPLING = "SAMPLING UNRELIABLE: 12 divergent transitions of 1200 draws, R-hat up to 1.080, ESS down to 31: the bands may be wrong"
PAPER = "PAPER METHOD: NO AIR GAP: its u lies below the skin's roughness; its u and C_gap are no measurement"


@pytest.fixture
def contacts(tmp_path):
    rng = np.random.default_rng(7)
    freq = np.logspace(1, 5, 20)
    paths = []
    for name, r in (("total", 3e5), ("skin", 1e5), ("ts", 1e5)):
        z = np.stack([r / (1 + 2j * np.pi * freq * r * 1e-10) * (1 + 0.005 * (rng.standard_normal(freq.size) + 1j * rng.standard_normal(freq.size))) for _ in range(3)])
        paths.append(str(tmp_path / f"{name}.nc"))
        ix.save(ix.make_spectrum(freq, z, dims=("trial",), coords={"trial": [0, 1, 2]}), paths[-1])
    return paths


def stand_in(warnings, alarms):
    class Analysis:
        settings, v0, plot = None, 75.0, None

        def summary(self):
            return {"warnings": list(warnings), "alarms": list(alarms)}

    Analysis.warnings, Analysis.alarms = tuple(warnings), tuple(alarms)
    return Analysis()


@pytest.mark.parametrize("warnings,alarms,line", [
    (("w1", "w2"), (SAMPLING,), "impedax gap: 2 warning(s), see the JSON 'warnings', and 1 alarm: SAMPLING UNRELIABLE; see the JSON 'alarms'"),
    ((), (SAMPLING, PAPER), "impedax gap: 2 alarms: SAMPLING UNRELIABLE, PAPER METHOD: NO AIR GAP; see the JSON 'alarms'"),
    (("w1",), (), "impedax gap: 1 warning(s), see the JSON 'warnings'"),
])
def test_the_json_runs_stderr_line_names_the_alarms(contacts, monkeypatch, capsys, warnings, alarms, line):
    import impedax.models.gap as gap_module

    monkeypatch.setattr(gap_module, "gap_analysis", lambda *a, **k: stand_in(warnings, alarms))
    assert main(["gap", *contacts, "--area", "130e-6", "--json", "--quiet"]) == 0
    captured = capsys.readouterr()
    assert json.loads(captured.out)["alarms"] == list(alarms)
    assert [x for x in captured.err.splitlines() if x.startswith("impedax gap: ") and "see the JSON" in x] == [line]


def test_no_warning_and_no_alarm_say_nothing(contacts, monkeypatch, capsys):
    import impedax.models.gap as gap_module

    monkeypatch.setattr(gap_module, "gap_analysis", lambda *a, **k: stand_in((), ()))
    assert main(["gap", *contacts, "--area", "130e-6", "--json", "--quiet"]) == 0
    assert "see the JSON" not in capsys.readouterr().err
