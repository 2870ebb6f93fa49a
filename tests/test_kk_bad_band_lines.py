"""The bad-band lines the linear KK test and Z-HIT share (`kk.bad_band_lines`,
`kk.note_and_hint_lines`): each band by name with the rules that flagged it, in the order the
rules' words are given, a rule that flagged none left out. Oracle: the lines written out here."""

from impedax.fitting.kk import bad_band_lines, note_and_hint_lines


def test_bad_band_lines_name_each_band_and_the_rules_that_flagged_it():
    bands = [(5.34,), (0.5, 1.0), (0.0159, 0.1, 1.0, 10.0, 2020.0)]
    counts = [{"point": 1, "run": 0}, {"point": 0, "run": 0}, {"point": 2, "run": 5}]
    words = {"point": "with |residual| > 5.03 % (point rule)", "run": "in runs of ≥ 3 with |residual| > 3.02 % (run rule)"}
    assert bad_band_lines(bands, counts, words) == [
        "  bad band: the point at 5.34 Hz: 1 point with |residual| > 5.03 % (point rule)",
        "  bad band: the points at 500 mHz, 1 Hz",
        "  bad band: 15.9 mHz – 2.02 kHz: 2 points with |residual| > 5.03 % (point rule); 5 points in runs of ≥ 3 with |residual| > 3.02 % (run rule)",
    ]
    assert bad_band_lines([], [], words) == []


def test_note_and_hint_lines_say_each_where_there_is_one():
    assert note_and_hint_lines("", "") == []
    assert note_and_hint_lines("Re Z < 0 at 2 points", "") == ["note: Re Z < 0 at 2 points"]
    assert note_and_hint_lines("", "swap the sign") == ["hint: swap the sign"]
    assert note_and_hint_lines("a", "b") == ["note: a", "hint: b"]
