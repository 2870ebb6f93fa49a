"""Progress of long Python calls (2026-12-02): `ix.fit`, `ix.diagnose` and `ix.refine` given no
callback print their stage lines on stderr once the call has run `progress.PROGRESS_AFTER_S`,
as the command line does (two walkthroughs met a first batch fit and a diagnosis running
12-50 s silent); ``progress=False`` prints nothing; a call inside another says nothing of its
own; the samplers keep their own lines. The threshold is set to 0 here, so every line prints
at once (no timing is asserted)."""

from __future__ import annotations

import re

import numpy as np
import pytest

import impedax as ix
import impedax.progress as progress_module

LINE = re.compile(r"^\[\s*\d+\.\d s\] ")


@pytest.fixture
def at_once(monkeypatch):
    monkeypatch.setattr(progress_module, "PROGRESS_AFTER_S", 0.0)


def rc_spectrum():
    """R0 10 Ω + R1 100 Ω ∥ C1 10 µF (numpy), 30 points 0.1 Hz–100 kHz, 1 % noise (SYNTHETIC)."""
    f = np.logspace(-1, 5, 30)
    z = 10 + 1 / (1 / 100 + 2j * np.pi * f * 1e-5)
    rng = np.random.default_rng(2)
    return ix.make_spectrum(f, z * (1 + 0.01 * (rng.standard_normal(30) + 1j * rng.standard_normal(30)) / np.sqrt(2)))


def stderr_lines(capsys) -> list[str]:
    return [line for line in capsys.readouterr().err.splitlines() if line.strip()]


def test_a_python_fit_says_its_stages_on_stderr_by_default_and_nothing_with_false(at_once, capsys):
    ix.fit("R0 + R1 || C1", rc_spectrum())
    lines = stderr_lines(capsys)
    assert lines and all(LINE.match(line) for line in lines) and "fitting R0 + R1 || C1" in lines[0]
    ix.fit("R0 + R1 || C1", rc_spectrum(), progress=False)
    assert stderr_lines(capsys) == []
    said = []
    ix.fit("R0 + R1 || C1", rc_spectrum(), progress=said.append)
    assert stderr_lines(capsys) == [] and said and said[0].startswith("fitting R0 + R1 || C1")


def test_a_diagnosis_says_its_own_stages_once_not_each_fit_beneath_it(at_once, capsys):
    ix.diagnose(rc_spectrum(), "R0 + R1 || C1", effects=ix.DEFAULT_EFFECTS.select(["series_inductance"]))
    lines = stderr_lines(capsys)
    assert lines[0].endswith("fitting the baseline R0 + R1 || C1")
    assert all(LINE.match(line) for line in lines)
    # (its candidate fits report through it, not with lines of their own: one clock, rising)
    times = [float(LINE.match(line).group(0).strip("[] s")) for line in lines]
    assert times == sorted(times) and not any("(a circuit's first fit compiles" in line for line in lines)


def test_a_sampler_without_progress_prints_nothing_from_its_start_fit(at_once, capsys):
    ix.sample("R0 + R1 || C1", rc_spectrum(), steps=20, walkers=8, progress=False)
    assert stderr_lines(capsys) == []


def test_a_progress_that_is_no_function_is_named():
    with pytest.raises(ix.ParameterError, match=r"progress must be a function of one line of text \(e\.g\. print\), False \(no lines\) or None"):
        ix.fit("R0 + R1 || C1", rc_spectrum(), progress=3)
