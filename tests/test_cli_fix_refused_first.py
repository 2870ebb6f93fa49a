"""A --fix value outside its element's bounds is refused before anything is read or fitted: one
error line on stderr, nothing before it (sample printed "fitting the least-squares start …" and
compare a note on the data's sigma before the refusal; walkthrough 2026-12-05)."""

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main


@pytest.fixture(scope="module")
def spectrum_file(tmp_path_factory):
    # SYNTHETIC R0 + R1 || C1 (numpy formula) with a sigma column, which compare notes when unused
    f = np.geomspace(1e5, 0.1, 30)
    z = 50.0 + 1000.0 / (1.0 + 2j * np.pi * f * 1000.0 * 1e-5)
    path = tmp_path_factory.mktemp("fix") / "s.nc"
    ix.save(ix.make_spectrum(f, z, sigma=0.01 * np.abs(z)), path)
    return str(path)


@pytest.mark.parametrize("args", [
    ["sample", "--model", "R0 + R1 || C1", "--fix", "R0=-5", "--steps", "100"],
    ["compare", "--model", "R0 + R1 || C1", "--model", "R0 + C1", "--fix", "R0=-5"],
    ["fit", "--model", "R0 + R1 || C1", "--fix", "R0=-5"],
])
def test_a_fixed_value_outside_its_bounds_is_the_only_line(spectrum_file, capsys, args):
    command, rest = args[0], args[1:]
    assert main([command, spectrum_file, *rest]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.strip().splitlines() == [err.strip()] and "--fix: R0=-5 is outside its bounds (0, inf)" in err
