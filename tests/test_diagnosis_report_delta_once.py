"""Each suggestion of ``impedax diagnose``'s report gives its ΔAIC and ΔBIC once, on its model
line (``model …   rms_rel …   ΔAIC …   ΔBIC …``), not again at the end of its explanation: the
REAL Autolab file from R0 + R1 || C1 gave "(ΔAIC -280.0, ΔBIC -275.2)" and, the next line,
"ΔAIC -280.0   ΔBIC -275.2". The JSON keeps ``delta_aic`` and ``delta_bic``."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np

import impedax as ix
from impedax.cli import main
from spectra import noisy, rc

REAL = Path(__file__).parent / "fixtures" / "real"
_ITEM = re.compile(r"^  (\d+)\. \[")


def _blocks(report: str) -> dict[int, list[str]]:
    """The report's numbered suggestions: number → its lines (the item's and those indented under it)."""
    blocks: dict[int, list[str]] = {}
    current = None
    for line in report.splitlines():
        found = _ITEM.match(line)
        if found:
            current = int(found.group(1))
            blocks[current] = [line]
        elif current is not None and line.startswith("     "):
            blocks[current].append(line)
        else:
            current = None
    return blocks


def _check_once(report: str, suggestions: list[dict]) -> None:
    """Every block names ΔAIC and ΔBIC in its model line alone, with the JSON's numbers."""
    blocks = _blocks(report)
    assert blocks, report
    for number, lines in blocks.items():
        own = [line for line in lines if not line.lstrip().startswith(("ranked before", "the same fit"))]  # (those name another's ΔAIC)
        with_aic = [line for line in own if "ΔAIC" in line]
        with_bic = [line for line in own if "ΔBIC" in line]
        assert len(with_aic) == 1 and len(with_bic) == 1 and with_aic == with_bic, lines
        assert with_aic[0].startswith("     model "), lines
        s = suggestions[number - 1]
        assert f"ΔAIC {s['delta_aic']:+.1f}" in with_aic[0] and f"ΔBIC {s['delta_bic']:+.1f}" in with_bic[0], (with_aic, s)
        assert "lowers rms_rel from" in lines[0], lines  # (the error before and after stays in the prose)


def _run(capsys, *arguments) -> tuple[str, dict]:
    assert main(["diagnose", *arguments, "--quiet"]) == 0
    report = capsys.readouterr().out
    assert main(["diagnose", *arguments, "--quiet", "--json"]) == 0
    return report, json.loads(capsys.readouterr().out)


def test_the_real_autolab_report_gives_each_delta_once(capsys):
    report, doc = _run(capsys, str(REAL / "exampleDataAutolab.txt"), "--model", "R0 + R1 || C1")
    _check_once(report, doc["suggestions"])
    assert all(k in s for s in doc["suggestions"] for k in ("delta_aic", "delta_bic", "explanation"))


def test_a_synthetic_report_gives_each_delta_once(tmp_path, capsys):
    """SYNTHETIC R0 + R1 || C1 with a lead inductance of 2 µH (written in numpy, 0.3 % noise), diagnosed from R0 + R1 || C1."""
    f = np.logspace(-1, 6, 50)
    z = noisy(rc(f, {"R0": 20.0, "R1": 500.0, "C1": 1e-7}) + 2j * np.pi * f * 2e-6, 0.003, np.random.default_rng(3))
    path = tmp_path / "synthetic.csv"
    ix.save(ix.make_spectrum(f, z), path)
    report, doc = _run(capsys, str(path), "--model", "R0 + R1 || C1")
    _check_once(report, doc["suggestions"])


def test_an_explanation_gives_the_error_before_and_after_but_no_delta():
    """The explanation (the report's item line, the JSON's ``explanation``) says what is added, its
    values and rms_rel before and after; ΔAIC and ΔBIC are the model line's."""
    from types import SimpleNamespace

    from impedax.fitting.diagnosis.diagnosis import _explain

    circuit = ix.parse("R0 + R1 || C1 + L_lead")
    base = SimpleNamespace(rms_rel=0.0135, values={"R0": 1.0, "R1": 2.0, "C1": 3e-8})
    cand = SimpleNamespace(rms_rel=0.00511, values={"R0": 1.0, "R1": 2.0, "C1": 3e-8, "L_lead": 2.99e-6}, free_names=("R0", "R1", "C1", "L_lead"), circuit=circuit, registry=ix.DEFAULT_REGISTRY)
    effect = SimpleNamespace(id="series_inductance", title="series inductance")
    proposal = SimpleNamespace(added="L_lead", where="in series with the whole circuit (leads)", evidence="", expected={})
    text = _explain(effect, proposal, base, cand, ())
    assert text == "series inductance: adding L_lead in series with the whole circuit (leads) (L_lead = 2.99 µH) lowers rms_rel from 1.35 % to 0.511 %.", text
