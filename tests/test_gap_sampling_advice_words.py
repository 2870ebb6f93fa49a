"""The hierarchical gap sampling's remedies in the gap analysis's words: `impedax gap` and
`gap_analysis` set neither NUTS's target acceptance nor the number of chains, where the
warnings advised "a higher target_accept" and "more chains" (a walkthrough's SYNTHETIC Sirin
trials: "2 divergent NUTS transitions of 2000 draws … sample with a higher target_accept (smaller
steps: 0.95 or 0.99, the default 0.85) or a longer warmup"), and Python read "impedax gap: --steps".
Oracle: the warnings' own text, written out here, and the options `impedax gap` takes."""

from impedax.cli.common import command_line_words, command_options
from impedax.models.gap import hierarchical_advice_of_gap

DIVERGENT = ("2 divergent NUTS transitions of 2000 draws: the intervals may be biased; sample with a higher "
             "target_accept= (smaller steps: 0.95 or 0.99, the default 0.85) or a longer warmup= (the default 400)")
RHAT = ("R-hat above 1.05 for u (1.08): the chains disagree, so the intervals are not yet the posterior's; "
        "run more draws per chain (500 now): draws=1000, or more chains (4 now): chains=8")


def test_the_python_words_name_what_gap_analysis_takes():
    divergent = hierarchical_advice_of_gap(DIVERGENT, 500)
    assert divergent == ("2 divergent NUTS transitions of 2000 draws: the intervals may be biased; sample with a longer warm-up, steps=1000 "
                         "(as many warm-up steps as draws per chain, unless warmup= is given); the gap analysis itself samples again with smaller steps "
                         "(target acceptance 0.99) when over 1 % of the draws diverge")
    rhat = hierarchical_advice_of_gap(RHAT, 500)
    assert rhat.endswith("the intervals are not yet the posterior's; run more draws per chain (500 now): steps=1000, or more chains (4 now): chains=8")
    for text in (divergent, rhat):
        assert "target_accept" not in text and "--" not in text
    import inspect

    from impedax.models.gap import gap_analysis

    assert {"steps", "warmup", "chains"} <= set(inspect.signature(gap_analysis).parameters)  # (the keywords named exist)


def test_the_command_line_says_steps():
    assert "--steps" in command_options("gap") and "--target-accept" not in command_options("gap")
    assert "sample with a longer warm-up, --steps 1000 (as many warm-up steps as draws per chain); the gap" in command_line_words(hierarchical_advice_of_gap(DIVERGENT, 500), "gap")
    assert command_line_words(hierarchical_advice_of_gap(RHAT, 500), "gap").endswith("run more draws per chain (500 now): --steps 1000")
    for advice in (DIVERGENT, RHAT):
        assert "=" not in command_line_words(hierarchical_advice_of_gap(advice, 500), "gap")  # (no Python keyword left)


def test_other_warnings_pass_unchanged():
    other = "effective sample size below 100 for u (42) of 2000 draws: their medians are uncertain"
    assert hierarchical_advice_of_gap(other, 500) == other
