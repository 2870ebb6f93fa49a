"""A batch fit's parameters at a bound, spectrum by spectrum, in the form a single fit gives them:
`BatchFitResult.at_bound_of(**labels)` is the tuple of names `FitResult.at_bound` is, the batch
JSON's rows hold the same list (``spectra[i]["at_bound"]``), and ``summary()["at_bound"]`` stays
{name: count of spectra}. SYNTHETIC spectra R0 + R1 ∥ C1 written with numpy, R1 = 100, 150, 90 Ω,
fitted with R1 bounded to 0–120 Ω: by construction only the spectrum of R1 = 150 Ω (cycle 2) ends
on the bound, R1 = 120 Ω."""

from __future__ import annotations

import numpy as np
import pytest

import impedax as ix

MODEL = "R0 + R1 || C1"
FREQ = np.geomspace(0.1, 1e5, 30)
TRUTHS = [(10.0, 100.0, 1e-5), (12.0, 150.0, 2e-5), (8.0, 90.0, 5e-6)]
BOUNDS = {"R1": (0.0, 120.0)}


@pytest.fixture(scope="module")
def stack():
    z = [r0 + r1 / (1 + 2j * np.pi * FREQ * r1 * c1) for r0, r1, c1 in TRUTHS]
    return ix.make_spectrum(FREQ, np.array(z), dims=("cycle",)).assign_coords(cycle=[1, 2, 3])


@pytest.fixture(scope="module")
def batch(stack):
    return ix.fit(MODEL, stack, bounds=BOUNDS, n_starts=1)


def test_each_spectrum_gives_its_names_as_a_single_fit_does(batch, stack):
    assert batch.at_bound_of(cycle=2) == ("R1",)
    assert batch.at_bound_of(cycle=1) == batch.at_bound_of(cycle=3) == ()
    assert float(batch.values("R1").sel(cycle=2)) == pytest.approx(120.0, rel=1e-6)
    alone = ix.fit(MODEL, stack.sel(cycle=2), bounds=BOUNDS, n_starts=1)
    assert isinstance(alone.at_bound, tuple) and batch.at_bound_of(cycle=2) == alone.at_bound == ("R1",)


def test_the_json_rows_and_the_counts_agree(batch):
    summary = batch.summary()
    assert summary["at_bound"] == {"R1": 1}
    assert {row["cycle"]: row["at_bound"] for row in summary["spectra"]} == {c: list(batch.at_bound_of(cycle=c)) for c in (1, 2, 3)}


def test_labels_are_given_by_keyword(batch):
    with pytest.raises(ix.ParameterError, match=r"at_bound_of\(cycle=2\)"):
        batch.at_bound_of(2)
    with pytest.raises(ix.ParameterError, match="cycle=7 is not among the batch's labels"):
        batch.at_bound_of(cycle=7)


def test_the_readme_loop_over_every_spectrum(batch):
    """README.md's one line for every spectrum's names runs as written."""
    assert {key: batch.at_bound_of(**labels) for key, labels in batch.spectrum_keys()} == {"cycle=1": (), "cycle=2": ("R1",), "cycle=3": ()}


def test_a_global_fit_gives_each_spectrums_names_too(stack):
    """A global fit (C1 shared over cycle: the spectra are written with other C1s, so
    their shared value fits none exactly) is a batch result too: the bound R1 = 120 Ω still holds
    only the spectrum of R1 = 150 Ω."""
    shared = ix.fit(MODEL, stack, shared=["C1"], over="cycle", bounds=BOUNDS, n_starts=1)
    assert [shared.at_bound_of(cycle=c) for c in (1, 2, 3)] == [(), ("R1",), ()]
    assert [row["at_bound"] for row in shared.summary()["spectra"]] == [[], ["R1"], []]
