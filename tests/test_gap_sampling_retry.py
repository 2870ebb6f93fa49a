"""A hierarchical gap run with more than 1 % of its draws divergent samples once more at a higher
NUTS target acceptance (smaller steps), says so, and keeps the run with fewer divergent draws
(2026-12-02: a walkthrough's clean 3-repeat set was "SAMPLING UNRELIABLE" at every voltage,
72/2000 divergent; 7 at 0.99). The sampler here is a stand-in that records its calls: the NUTS
runs themselves take minutes (their measured figures: `RETRY_TARGET_ACCEPT`'s docstring)."""

from types import SimpleNamespace

from impedax.fitting.bayes.hierarchical import TARGET_ACCEPT
from impedax.models.gap import RETRY_TARGET_ACCEPT, SAMPLING_DIVERGENT_MAX, sampled_with_retry


def stand_in(divergent_at: dict[float, int], n_draws: int = 2000):
    calls = []

    def sample(target):
        calls.append(target)
        return SimpleNamespace(divergences=divergent_at[target], n_draws=n_draws, target=target)

    return sample, calls


def test_a_divergent_run_is_sampled_again_at_the_higher_target_and_said_so(capsys):
    sample, calls = stand_in({TARGET_ACCEPT: 72, RETRY_TARGET_ACCEPT: 7})
    post, notes = sampled_with_retry(sample, progress=True)
    assert calls == [TARGET_ACCEPT, RETRY_TARGET_ACCEPT] and post.target == RETRY_TARGET_ACCEPT
    assert notes == [f"sampling: 72 divergent transitions of 2000 draws at NUTS's target acceptance {TARGET_ACCEPT:g}; "
                     f"sampled again at {RETRY_TARGET_ACCEPT:g} (smaller steps): 7 divergent; these draws are kept"]
    assert "sampling again at 0.99" in capsys.readouterr().err  # (the wait is explained while it runs)


def test_a_run_within_the_rule_is_not_sampled_again():
    limit = int(SAMPLING_DIVERGENT_MAX * 2000)  # 20 of 2000: at the rule, not beyond it
    sample, calls = stand_in({TARGET_ACCEPT: limit})
    post, notes = sampled_with_retry(sample)
    assert calls == [TARGET_ACCEPT] and notes == [] and post.divergences == limit


def test_a_retry_that_diverges_more_keeps_the_first_run():
    sample, calls = stand_in({TARGET_ACCEPT: 30, RETRY_TARGET_ACCEPT: 45})
    post, notes = sampled_with_retry(sample)
    assert post.target == TARGET_ACCEPT and notes[0].endswith("45 divergent; the first run's draws are kept (fewer divergent)")
