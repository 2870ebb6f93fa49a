"""The comparison table's posterior columns (log_evidence, waic): a least-squares fit's row, which
has neither, read "nan", as did a posterior's undefined value, where the AICc column writes "—"
(2026-12-06); a WAIC its row calls unreliable (``waic_reliable``) is marked "*" as an unreliable
log evidence is. Rows set by hand on fits of SYNTHETIC R0 + R1 ∥ CPE1 spectra
(`test_compare_criteria.spectrum`); oracle: the values written here."""

import dataclasses
import functools
import math

import pytest

import impedax as ix
from test_compare_criteria import MODELS, spectrum


pytestmark = pytest.mark.slow  # (the two fits compile their solvers: ~9 s on the shared 2-core machine)


@functools.cache
def _comparison():
    return ix.compare([ix.fit(m, spectrum(alpha=0.997, seed=3), progress=False) for m in MODELS])


def _table(first: dict) -> list[str]:
    c = _comparison()
    rows = ({**c.rows[0], **first}, dict(c.rows[1]))
    lines = dataclasses.replace(c, rows=rows).table().splitlines()
    return [next(line for line in lines if line.startswith(r["label"] + " ")) for r in rows] + lines


def test_a_fit_without_posterior_columns_shows_a_dash():
    first, second, *lines = _table({"log_evidence": -100.0, "log_evidence_reliable": True, "waic": 250.5, "waic_reliable": False})
    assert {"-100.00", "250.50*"} <= set(first.split())
    assert second.split().count("—") == 2 and "nan" not in second  # (its AICc is a number here: the two dashes are the posterior columns)
    assert any(line.startswith("* WAIC undefined, from a chain too short") and line.endswith(f"{MODELS[0]}; do not compare models by it") for line in lines)


def test_an_undefined_value_reads_undefined():
    first, *_ = _table({"log_evidence": math.nan, "log_evidence_reliable": False, "waic": 250.5, "waic_reliable": True})
    assert "undefined*" in first.split() and "nan" not in first and "250.50" in first.split()
