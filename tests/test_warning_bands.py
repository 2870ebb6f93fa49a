"""A batch's warnings merged over spectra whose frequency bands differ (`warning_groups`): one
line per finding whatever the SI prefix of its frequencies, each band written as one band with
how its ends vary over the spectra, not ranged number by number (walkthrough 2026-12-02:
"larger at 1 Hz – 5.01 Hz than at 1.58 to 10 kHz – 7.94 to 100 kHz", over three lines)."""

import re

import numpy as np

from impedax.fitting.least_squares.result import UNEVEN_BAND_POINTS, uneven_residual_notes
from impedax.warning_groups import grouped_warnings, warning_kinds

PREFIX = {"m": 1e-3, "": 1.0, "k": 1e3, "M": 1e6}  # SI prefixes, written out for the oracle
QUANTITY = r"([\d.]+) ?(m|k|M)?Hz"


def hertz(number: str, prefix: str | None) -> float:
    return float(number) * PREFIX[prefix or ""]


def note(a, b, c, d):
    return f"the weighted residuals are over 4× larger (rms) at {a} – {b} than at {c} – {d}: the standard errors are not to be trusted"


def test_the_walkthroughs_bands_read_as_bands_on_one_line():
    # hand-made texts as the walkthrough met them: the loud band one for all, the quiet band's
    # ends in Hz for some spectra and kHz for others
    warnings = {
        "voltage=0, repeat=0": (note("1 Hz", "5.01 Hz", "1.58 kHz", "7.94 kHz"),),
        "voltage=0, repeat=1": (note("1 Hz", "5.01 Hz", "10 kHz", "100 kHz"),),
        "voltage=100, repeat=0": (note("1 Hz", "5.01 Hz", "800 Hz", "5 kHz"),),
    }
    lines = grouped_warnings(warnings, 3)
    assert len(lines) == 1  # (three kinds until 2026-12-02: Hz and kHz were two wordings)
    assert "at 1 Hz – 5.01 Hz than at 800 Hz – 100 kHz (the spectra's lower ends 800 Hz – 10 kHz, upper ends 5–100 kHz)" in lines[0]
    assert not re.search(r"\d to \d", lines[0])  # (no end ranged number by number)
    # one end that varies, in one unit: the unit once; the JSON's kinds carry the same text
    kinds = warning_kinds({"a=1": (note("1 Hz", "5.01 Hz", "1 kHz", "2 kHz"),), "a=2": (note("1 Hz", "7.94 Hz", "1 kHz", "2 kHz"),)})
    assert len(kinds) == 1 and kinds[0]["n_spectra"] == 2
    assert "at 1–7.94 Hz (the spectra's upper ends 5.01–7.94 Hz) than at 1 kHz – 2 kHz:" in kinds[0]["warning"]


def test_plain_numbers_still_range_and_one_quantity_ranges_with_its_unit_once():
    warnings = {"t=1": ("r = -0.993 at 2 kHz",), "t=2": ("r = -0.990 at 900 Hz",), "t=3": ("r = -0.991 at 1.5 kHz",)}
    (line,) = grouped_warnings(warnings, 3)
    assert line.endswith("r = -0.993 to -0.990 at 900 Hz – 2 kHz")


def test_a_stack_of_synthetic_spectra_whose_loud_band_moves_gives_one_line_with_its_envelope():
    # SYNTHETIC: R 100 Ω + 1 kΩ ∥ 1 µF at 41 frequencies 1 Hz – 100 kHz, 0.3 % noise, 20× larger
    # in one band of `UNEVEN_BAND_POINTS` points: band i in spectrum i (so the bands and their
    # units, Hz to kHz, differ over the spectra)
    rng = np.random.default_rng(20261202)
    freq = np.geomspace(1.0, 1e5, 41)
    w = 2 * np.pi * freq
    model = 100.0 + 1e3 / (1 + 1j * w * 1e3 * 1e-6)
    n_spectra = 4
    rel = np.full((n_spectra, freq.size), 0.003)
    for i in range(n_spectra):
        rel[i, i * UNEVEN_BAND_POINTS : (i + 1) * UNEVEN_BAND_POINTS] *= 20
    z = model * (1 + rel * (rng.standard_normal(rel.shape) + 1j * rng.standard_normal(rel.shape)))
    inv = 1 / np.abs(z)
    notes = uneven_residual_notes(freq, z, np.broadcast_to(model, z.shape), inv, inv, "modulus")
    assert all(len(n) == 1 for n in notes)
    lines = grouped_warnings({f"spectrum={i}": n for i, n in enumerate(notes)}, n_spectra)
    # one line per direction (since 2026-12-03: the quiet band at lower or at higher frequencies),
    # so that one line's envelopes never mix the two; here the quietest band of spectrum 2 lies
    # below its loud one, of the others above
    assert len(lines) == 2 and "(3 of 4 spectra: spectrum 0, 1, 3)" in lines[0] and "than at the higher frequencies" in lines[0]
    assert "(1 of 4 spectra: spectrum 2)" in lines[1] and "than at the lower frequencies" in lines[1]
    # the oracle: the loud bands' ends straight from the frequencies, over the first line's spectra
    shown = [0, 1, 3]
    lows = np.array([freq[i * UNEVEN_BAND_POINTS] for i in shown])
    highs = np.array([freq[(i + 1) * UNEVEN_BAND_POINTS - 1] for i in shown])
    loud = re.search(rf"at {QUANTITY} ?– ?{QUANTITY} \(the spectra's lower ends {QUANTITY} ?– ?{QUANTITY}, upper ends {QUANTITY} ?– ?{QUANTITY}\) than", lines[0])
    assert loud, lines[0]
    found = [hertz(loud.group(k), loud.group(k + 1)) for k in range(1, 13, 2)]
    expected = [lows.min(), highs.max(), lows.min(), lows.max(), highs.min(), highs.max()]
    np.testing.assert_allclose(found, expected, rtol=5e-3)  # (three significant digits)


NOT_DETERMINED = "shared R0, R1 are not separately determined by the data"


def test_global_fits_keys_are_not_counted_as_spectra_nor_cut_at_their_labels():
    """A global fit per group (``shared over cycle (group=a)``) files its notes under a key
    holding ``=``: the line names those fits, not "2 of 6 spectra: shared over cycle (group a), b)"."""
    warnings = {"shared over cycle (group=a)": (NOT_DETERMINED,), "shared over cycle (group=b)": (NOT_DETERMINED,)}
    spectra = [f"group={g}, cycle={c}" for g in "ab" for c in range(3)]
    assert grouped_warnings(warnings, 6, spectra=spectra) == [f"warning (shared over cycle (group a, b)): {NOT_DETERMINED}"]
    (kind,) = warning_kinds(warnings)
    assert kind["spectra"] == [] and kind["n_spectra"] == 0
    assert kind["scope"] == ["shared over cycle (group=a)", "shared over cycle (group=b)"]
    # groups of several dimensions, and spectra with a global fit in one kind: spectra counted, the fit named after them
    two = {"shared over cycle (group=a, cell=1)": (NOT_DETERMINED,), "shared over cycle (group=b, cell=1)": (NOT_DETERMINED,)}
    assert grouped_warnings(two, 12) == [f"warning (shared over cycle (group=a, cell=1; group=b, cell=1)): {NOT_DETERMINED}"]
    mixed = {"group=a, cycle=0": ("R2 is at its bound",), "group=b, cycle=2": ("R2 is at its bound",), "shared over cycle (group=a)": ("R2 is at its bound",)}
    assert grouped_warnings(mixed, 6, spectra=spectra) == ["warning (2 of 6 spectra: group=a, cycle=0; group=b, cycle=2; shared over cycle (group a)): R2 is at its bound"]
    # one dimension shared over with no other: the key as it was
    assert grouped_warnings({"shared over trial": (NOT_DETERMINED,)}, 4) == [f"warning (shared over trial): {NOT_DETERMINED}"]


def test_numbers_of_different_powers_of_ten_are_not_ranged_as_one():
    """A near-bound note writes a value and its error with a shared power of ten, "(8.4 ±
    1.6)e-15"; two spectra's notes of different powers were merged to "(3.2 to 8.4 ± 0.5 to
    1.6)e-14 to 15", numbers of scales 10x apart ranged as one. They stay two lines (as two SI
    prefixes would), each its own text; notes of one power still range."""
    def alpha(pair):
        return f"CPE1.alpha lies {pair} below its upper bound 1, on it to 1 part in 10⁴ or better"

    apart = grouped_warnings({"cycle=0": (alpha("(8.4 ± 1.6)e-15"),), "cycle=1": (alpha("(3.2 ± 0.5)e-14"),)}, 2)
    assert sorted(line.split("): ", 1)[1] for line in apart) == sorted([alpha("(8.4 ± 1.6)e-15"), alpha("(3.2 ± 0.5)e-14")]), apart
    (together,) = grouped_warnings({"cycle=0": (alpha("(8.4 ± 1.6)e-15"),), "cycle=1": (alpha("(3.2 ± 0.5)e-15"),)}, 2)
    assert together.endswith(alpha("(3.2 to 8.4 ± 0.5 to 1.6)e-15")), together
