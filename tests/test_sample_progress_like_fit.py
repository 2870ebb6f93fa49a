"""`sample` takes ``progress`` as `fit` does: None (the default) or True, lines on stderr; False,
none; a function of one line of text, each line handed to it. Until 2026-12-06 sample refused
None (and a function), so code passing ``progress=None`` to every call, as it may to `fit`,
failed at sample alone."""

import numpy as np
import pytest

import impedax as ix

MODEL = "R0 + R1 || C1"


@pytest.fixture(scope="module")
def data():
    """SYNTHETIC R0 + R1 ∥ C1 (20 Ω, 500 Ω, 10 µF), 1 % noise, 30 points from 10 kHz to 0.1 Hz."""
    f = np.logspace(4, -1, 30)
    z = 20.0 + 1.0 / (1.0 / 500.0 + 1j * 2 * np.pi * f * 1e-5)
    noise = 1 + 0.01 * np.random.default_rng(0).standard_normal(f.size)
    return ix.make_spectrum(f, z * noise)


def test_sample_takes_progress_none_as_fit_does(data, capsys):
    ix.fit(MODEL, data, progress=None)  # (fit's default, which sample refused)
    capsys.readouterr()
    post = ix.sample(MODEL, data, steps=40, seed=1, progress=None)
    err = capsys.readouterr().err
    assert post.settings["steps"] == 40
    assert "sample: fitting the least-squares start" in err  # None is the default: lines on stderr, as with True


def test_sample_hands_its_lines_to_a_function_as_fit_does(data, capsys):
    lines: list[str] = []
    ix.sample(MODEL, data, steps=40, seed=1, progress=lines.append)
    assert lines[0] == "sample: fitting the least-squares start …"
    assert lines[1].startswith("sample: compiling the log-probability")
    assert capsys.readouterr().err == ""  # (each line to the function, none on stderr)


def test_sample_refuses_other_progress_values_naming_what_it_takes(data):
    with pytest.raises(ix.ParameterError, match=r"progress must be True or False \(None, the default: lines on stderr\), or a function of one line of text"):
        ix.sample(MODEL, data, steps=40, progress="no")
