"""Every class that impedax's messages name as a reader is reachable as ``impedax.<name>``."""

import impedax as ix
import impedax.fitting
from impedax.io.netcdf import RESULT_KINDS


def test_every_reader_a_message_names_is_a_top_level_name():
    classes = {call.split(".")[0] for _, call in RESULT_KINDS.values() if not call.startswith("impedax.")}
    assert {"BatchComparison", "HierarchicalPosterior", "Refinement", "Diagnosis"} <= classes
    for _, call in RESULT_KINDS.values():
        if call.startswith("impedax."):
            continue
        name, method = call.split(".")
        assert name in ix.__all__, name
        assert callable(getattr(getattr(ix, name), method)), call


def test_the_comparisons_are_the_fitting_subpackages_classes():
    assert ix.BatchComparison is impedax.fitting.BatchComparison
    assert ix.Comparison is impedax.fitting.Comparison


def test_the_hierarchical_sampler_is_a_top_level_name():
    """`HierarchicalPosterior` was ``impedax.HierarchicalPosterior`` but the call that makes one was
    reachable only as impedax.fitting.bayes.hierarchical.sample_hierarchical (AttributeError on
    ``ix.sample_hierarchical``, beside ``ix.sample``)."""
    from impedax.fitting.bayes.hierarchical import sample_hierarchical

    assert "sample_hierarchical" in ix.__all__ and ix.sample_hierarchical is sample_hierarchical
