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


RUNS = "runs to its lower bound 0 (fitted in log space, it approaches 0 without reaching it; to the data it is 0)"


def test_one_note_in_different_si_prefixes_is_one_kind_ranged_over_its_values():
    # the REAL 130 battery cycles above 3 kHz (R0 + R1 || CPE1 + R2 || CPE2 + W1): W1.sigma runs to
    # 0 in µΩ, nΩ and mΩ s^-1/2, which were three kinds of warning (25 + 4 + 1 spectra)
    warnings = {"cycle=10": (f"W1.sigma = 1.14 µΩ s^-1/2 {RUNS}",), "cycle=11": (f"W1.sigma = 343 nΩ s^-1/2 {RUNS}",), "cycle=12": (f"W1.sigma = 2.21 mΩ s^-1/2 {RUNS}",)}
    (kind,) = warning_kinds(warnings)
    assert kind["n_spectra"] == 3
    # the range from the smallest value (343e-9) to the largest (2.21e-3), each end in its own prefix
    assert kind["warning"] == f"W1.sigma = 343 nΩ s^-1/2 – 2.21 mΩ s^-1/2 {RUNS}"
    # one prefix: the unit written once
    same = {"cycle=0": (f"R0 = 27 nΩ {RUNS}",), "cycle=1": (f"R0 = 756 nΩ {RUNS}",)}
    assert grouped_warnings(same, 2) == [f"warning (all 2 spectra): R0 = 27–756 nΩ {RUNS}"]
    # a CPE's Q in pF and nF (prefixes beyond k…n), and a time constant in ms and s
    q = {"cell=a": ("CPE1.Q = 4.7 pF s^(α-1) cannot be told from its lower bound 0",), "cell=b": ("CPE1.Q = 2.2 nF s^(α-1) cannot be told from its lower bound 0",)}
    assert warning_kinds(q)[0]["warning"] == "CPE1.Q = 4.7 pF s^(α-1) – 2.2 nF s^(α-1) cannot be told from its lower bound 0"
    assert len(warning_kinds({"a=1": ("τ = 3 ms here",), "a=2": ("τ = 1.5 s here",)})) == 1


def test_a_value_and_its_error_share_their_prefix_when_ranged():
    near = "lies within 2 standard errors of its lower bound 0"
    # one prefix: numbers ranged, the unit once (as the REAL 130 cycles above 3 kHz print it)
    same = {"cycle=0": (f"R0 = 121 ± 66 mΩ {near}",), "cycle=3": (f"R0 = 170 ± 150 mΩ {near}",)}
    assert warning_kinds(same)[0]["warning"] == f"R0 = 121 to 170 ± 66 to 150 mΩ {near}"
    # two prefixes: 121 mΩ and 1.2 Ω are one kind, and never "121 to 1.2" in one unit
    mixed = {"cycle=0": (f"R0 = 121 ± 66 mΩ {near}",), "cycle=3": (f"R0 = 1.2 ± 0.3 Ω {near}",)}
    (kind,) = warning_kinds(mixed)
    assert kind["warning"] == f"R0 = 121 mΩ – 1.2 Ω ± 66 mΩ – 0.3 Ω {near}"
