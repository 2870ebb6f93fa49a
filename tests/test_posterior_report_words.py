"""The sample report's words: the line under the table spoke of "their draws … their intervals …
their medians" when one parameter alone was marked (REAL exampleDataGamry.DTA's R0, REAL
exampleData.csv's C_gap; 2026-12-06). Oracle: English number agreement counted by hand. (An
undefined WAIC's words: tests/test_posterior_undetermined.py, beside its posterior.)"""

from impedax.fitting.bayes.posterior import marked_rows


def test_one_marked_row_is_spoken_of_in_the_singular():
    _, (edge,) = marked_rows((), ("R0",))
    assert edge.startswith("← R0: its draws pile up against an edge of its prior or bound: that edge, not the data, sets one end of its interval, so its median is")
    _, (undetermined,) = marked_rows(("C_EP",), ())
    assert undetermined.startswith("← C_EP: not determined by the data") and "its interval shows where the priors take over" in undetermined
    for line in (edge, undetermined):
        assert " their " not in line


def test_several_marked_rows_keep_the_plural():
    marks, (undetermined, edge) = marked_rows(("C_EP", "u"), ("R0", "C_gap"))
    assert marks == {"C_EP": "← NOT DETERMINED", "u": "← NOT DETERMINED", "R0": "← AT PRIOR EDGE", "C_gap": "← AT PRIOR EDGE"}
    assert edge.startswith("← R0, C_gap: their draws pile up against an edge of their prior or bound") and "their intervals" in edge
    assert undetermined.startswith("← C_EP, u: not determined") and "their intervals show" in undetermined
