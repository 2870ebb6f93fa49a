"""A hierarchical posterior's remedies speak the surface they are read on: Python's
`HierarchicalPosterior.warnings` name `sample_hierarchical`'s keywords (``target_accept=``,
``warmup=``, ``draws=``, ``chains=``), `gap_analysis` its own (``steps=``), ``impedax gap`` its
option (``--steps``). Until 2026-12-06 the Python object read "impedax gap: --steps", an option of
a command a user of `sample_hierarchical` never ran. SYNTHETIC draws built by hand
(tests/test_hierarchical_new_session.py), no sampling; oracle: the sampler's signature and the
counts of chains and draws set here."""

import dataclasses
import inspect
import re

import numpy as np

from impedax.cli.common import command_line_words
from impedax.fitting.bayes.hierarchical import sample_hierarchical
from impedax.models.gap import hierarchical_advice_of_gap
from test_hierarchical_new_session import CHAINS, DRAWS, by_hand


def unmixed_and_divergent():
    """2 chains × 4000 draws, μ of R1 0.5 apart between chains (R-hat ≫ 1.05), 7 divergent."""
    post = by_hand(1)
    rng = np.random.default_rng(0)
    mu = np.log(100.0) + 0.01 * rng.standard_normal((CHAINS, DRAWS)) + np.array([0.0, 0.5])[:, None]
    return dataclasses.replace(post, mu=mu[..., None], divergences=7)


def test_python_names_sample_hierarchicals_keywords():
    warnings = unmixed_and_divergent().warnings
    (divergent,) = [w for w in warnings if "divergent" in w]
    (rhat,) = [w for w in warnings if w.startswith("R-hat above 1.05")]
    keywords = set(inspect.signature(sample_hierarchical).parameters)
    for text in (divergent, rhat):
        assert "impedax" not in text and "--" not in text
        assert set(re.findall(r"(\w+)=", text)) <= keywords  # (every keyword named exists)
    assert "target_accept=" in divergent and "warmup= (the default 400)" in divergent
    assert rhat.endswith(f"run more draws per chain ({DRAWS} now): draws={2 * DRAWS}, or more chains ({CHAINS} now): chains={2 * CHAINS}")


def test_the_gap_analysis_and_impedax_gap_say_their_own_words():
    for warning in unmixed_and_divergent().warnings:
        if "divergent" not in warning and not warning.startswith("R-hat"):
            continue
        gap = hierarchical_advice_of_gap(warning, DRAWS)
        assert f"steps={2 * DRAWS}" in gap and "draws=" not in gap and "target_accept" not in gap and "warmup= (" not in gap
        cli = command_line_words(gap, "gap")
        assert f"--steps {2 * DRAWS}" in cli and "=" not in cli
