"""``SharedPosterior.summary`` (``impedax sample --shared --json``) has ``warning_tags`` as
`Posterior.summary` has them: a list parallel to ``warnings``, empty for the sampling's own
warnings, the start fit's tags for each "least-squares start …" line (a grouped line: the tags of
the warnings it stands for). All data SYNTHETIC, written here in numpy."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import impedax as ix
from impedax.warning_groups import grouped_warning_tags, grouped_warnings

F = np.logspace(0, 5, 21)


def _depressed_trials(count: int) -> xr.Dataset:
    """R0 + R1 ∥ CPE (α = 0.7) spectra, R1 by trial, 0.2 % noise: R0 + R1 ∥ C1 misses their
    depression, so the start fit warns of the model's misfit in every spectrum."""
    rng = np.random.default_rng(0)
    z = np.stack([50.0 + r1 / (1 + (2j * np.pi * F * r1 * 1e-7) ** 0.7) for r1 in np.linspace(1e3, 2e3, count)])
    z = z * (1 + 0.002 * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape)))
    return xr.Dataset({"Z": (("trial", "frequency"), z)}, coords={"trial": np.arange(count), "frequency": F})


@pytest.fixture(scope="module")
def shared():
    return ix.sample("R0 + R1 || C1", _depressed_trials(3), shared="R0", steps=20, seed=1, progress=False)


def test_shared_summary_has_warning_tags_parallel_to_warnings(shared):
    summary = shared.summary()
    tags, warnings = summary["warning_tags"], summary["warnings"]
    assert len(tags) == len(warnings) and all(isinstance(t, list) for t in tags)
    start = [i for i, w in enumerate(warnings) if w.startswith("least-squares start")]
    assert start, warnings  # (the misfit of R0 + R1 || C1 on the depressed arcs)
    assert all(tags[i] == [] for i in range(len(warnings)) if i not in start)  # (the sampling's own: none)
    # (the start fit's own tags of the misfit note, in every spectrum, as the single spectrum's JSON gives them)
    own = {tuple(t) for key in shared.fit.warnings for t in shared.fit.spectrum_warning_tags(key)}
    assert own == {("misfit", "model_misfit")}, own
    (misfit,) = [i for i in start if "misses structure" in warnings[i]]
    assert tags[misfit] == ["misfit", "model_misfit"]


def test_a_single_spectrum_posterior_tags_the_same_warning_alike(shared):
    single = ix.sample("R0 + R1 || C1", _depressed_trials(3).isel(trial=0), steps=20, seed=1, progress=False).summary()
    (i,) = [i for i, w in enumerate(single["warnings"]) if "misses structure" in w]
    assert single["warning_tags"][i] == ["misfit", "model_misfit"]


def test_grouped_tags_follow_the_grouped_lines():
    """Hand-made warnings of three spectra: two kinds; each line gets its members' tags, in
    order, once; a line past the kinds shown gets the rest's."""
    warnings = {"trial=0": ("alpha 1 is low", "beta"), "trial=1": ("alpha 2 is low",), "trial=2": ("gamma",)}
    tags = {"trial=0": (("a",), ("b", "x")), "trial=1": (("a", "c"),), "trial=2": ((),)}
    lines = grouped_warnings(warnings, 3)
    got = grouped_warning_tags(warnings, tags)
    assert len(got) == len(lines)
    by_line = dict(zip(lines, got))
    (alpha,) = [line for line in lines if "alpha" in line]
    (beta,) = [line for line in lines if "beta" in line]
    (gamma,) = [line for line in lines if "gamma" in line]
    assert by_line[alpha] == ("a", "c") and by_line[beta] == ("b", "x") and by_line[gamma] == ()
    many = {f"trial={i}": (f"kind{'x' * i} of its own",) for i in range(15)}
    many_tags = {f"trial={i}": ((f"t{i}",),) for i in range(15)}
    lines, got = grouped_warnings(many, 15), grouped_warning_tags(many, many_tags)
    assert len(lines) == len(got) == 13  # (12 kinds shown, then "3 more kinds")
    assert sorted(got[-1]) == sorted(set(t for i in range(15) for t in many_tags[f"trial={i}"][0]) - {t for g in got[:-1] for t in g})


def test_shared_table_ends_with_the_run_s_warnings(shared):
    """The joint posterior's CSV rows (`to_table`) end as a single spectrum's: ``chain_converged``
    and ``warnings`` joined by "; ", the same on every row (20 steps: too short)."""
    summary, rows = shared.summary(), shared.to_table()
    assert all(list(r)[-2:] == ["chain_converged", "warnings"] for r in rows)
    assert all(r["chain_converged"] is False and r["warnings"] == "; ".join(summary["warnings"]) for r in rows)
    assert "chain_converged" not in shared._repr_html_() and "misses structure" in rows[0]["warnings"]
