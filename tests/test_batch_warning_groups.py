"""A batch's warnings grouped by kind (`impedax.warning_groups`): how the lines name their
spectra, and which texts are one kind of warning."""

from impedax.warning_groups import grouped_warnings, warning_kinds

AT_BOUND = "CPE2.alpha is at its upper bound 1 (CPE2 with alpha = 1 is a capacitor: the model with C2 in its place may be enough)"


def test_the_only_spectrum_of_a_batch_is_named_by_its_labels():
    # `impedax fit cycles.nc --select cycle=0:20` on the REAL 3 battery cycles (0, 64, 129) keeps
    # cycle 0 alone: its warnings read "warning (the 1 spectrum): ...", naming neither the cycle
    # nor that it was the only one picked
    lines = grouped_warnings({"cycle=0": (AT_BOUND,)}, 1, spectra=["cycle=0"])
    assert lines == [f"warning (cycle 0): {AT_BOUND}"]
    two_dims = grouped_warnings({"cell=a, cycle=64": (AT_BOUND,)}, 1)
    assert two_dims == [f"warning (cell=a, cycle=64): {AT_BOUND}"]
    # several spectra keep their count
    assert grouped_warnings({"cycle=0": (AT_BOUND,), "cycle=64": (AT_BOUND,)}, 2) == [f"warning (all 2 spectra): {AT_BOUND}"]
