"""Remedies of the sampler's warnings in the words of the surface that shows them: a pile-up at a
bound of the user's said "(bounds=, --bound)" and WAIC's uneven-noise cause "(a sigma column,
--noise sigma)" in Python and on the command line alike (2026-12-06); Python now names its
keywords and ``impedax sample`` its options (`cli.common.command_line_words`). SYNTHETIC draws
made here; oracle: `sample`'s keywords and ``impedax sample``'s options."""

import inspect
import re

import numpy as np

import impedax as ix
from impedax.circuits import DEFAULT_REGISTRY
from impedax.cli.common import command_line_words, command_options
from impedax.fitting.bayes.diagnostics import prior_edges, user_bound_sides
from impedax.fitting.bayes.evidence import START_UNEVEN_NOISE, waic_cause
from impedax.fitting.bayes.priors import Prior


def _at_users_bound() -> str:
    circuit = ix.parse("R0 + R1 || C1")
    draws = (1e4 * np.exp(-np.random.default_rng(0).exponential(0.01, 4000).clip(max=2.0)))[:, None]  # piled against 10 kΩ
    sides = user_bound_sides({"R1": (1e3, 1e4)}, circuit, DEFAULT_REGISTRY)
    (warning,) = prior_edges(("R1",), ("Ohm",), draws, {"R1": Prior("loguniform", 1e3, 1e4)}, (1e3,), (1e4,), None, None, sides).warnings
    return warning


def _uneven_noise() -> str:
    chain = np.random.default_rng(0).normal(size=(8, 200, 3))
    return waic_cause(chain, ["a", "b", "c"], start_y=np.zeros(3), model_misfit=START_UNEVEN_NOISE)


def test_python_names_keywords_of_sample():
    keywords = set(inspect.signature(ix.sample).parameters)
    for text in (_at_users_bound(), _uneven_noise()):
        assert "--" not in text
        assert {k for k in re.findall(r"\b(\w+)=", text) if k != "sigma"} <= keywords  # (sigma= is make_spectrum's)
    assert "the bound you set (bounds=) (" in _at_users_bound()


def test_impedax_sample_names_its_options():
    options = command_options("sample")
    bound = command_line_words(_at_users_bound(), "sample")
    assert "the bound you set (--bound) (" in bound and "bounds=" not in bound and "--bound" in options
    noise = command_line_words(_uneven_noise(), "sample")
    assert "(a sigma column of the file or a 'sigma' variable of a netCDF file, and --noise sigma)" in noise and "=" not in noise and "--noise" in options


def test_the_evidence_note_leaves_waic_out_where_waic_has_a_note_of_its_own():
    """(2026-12-06) "Compare models by WAIC" beside "Do not compare models by this WAIC"."""
    from impedax.fitting.bayes.evidence import EVIDENCE_NOTE_LEAD, WAIC_REMEDY, evidence_note_beside_waic

    note = f"{EVIDENCE_NOTE_LEAD}is unreliable: the posterior is not Gaussian at the MAP along R0. {WAIC_REMEDY}"
    assert evidence_note_beside_waic(note, "") == note
    kept = evidence_note_beside_waic(note, "WAIC is unreliable: … Do not compare models by this WAIC")
    assert kept == f"{EVIDENCE_NOTE_LEAD}is unreliable: the posterior is not Gaussian at the MAP along R0. WAIC is no score to compare models by either (see its warning): fix or bound that parameter"
    other = f"{EVIDENCE_NOTE_LEAD}undefined: the Hessian at the MAP is not finite"
    assert evidence_note_beside_waic(other, "WAIC undefined: non-finite likelihood at the draws") == other
