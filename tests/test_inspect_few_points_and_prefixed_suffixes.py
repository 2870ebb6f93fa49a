"""`impedax inspect` after a walkthrough (2026-12-05): a one-point file was told to run
`impedax kk`, which needs 4 frequencies; a `z_real_mohm` header (a unit suffix with a prefix)
was not read. Oracles: the values written here, scaled by hand (milli = 1e-3, kilo = 1e3), and
the minimum point counts the KK test and the DRT state in their own errors.
"""

from __future__ import annotations

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main
from impedax.errors import DataError

ROWS = [(100.0, 10.0, -1.0), (10.0, 12.0, -3.0), (1.0, 15.0, -2.0)]


def written(tmp_path, header: str, rows=ROWS):
    path = tmp_path / "spectrum.csv"
    path.write_text(header + "\n" + "".join(",".join(f"{v:g}" for v in row) + "\n" for row in rows))
    return path


@pytest.mark.parametrize(("suffix", "scale"), [("mohm", 1e-3), ("mOhm", 1e-3), ("kohm", 1e3), ("kOhm", 1e3), ("MOhm", 1e6)])
def test_a_prefixed_ohm_suffix_scales_the_impedance(tmp_path, suffix, scale):
    data = ix.load(written(tmp_path, f"frequency_hz,z_real_{suffix},z_imag_{suffix}"))
    expected = np.array([(re + 1j * im) * scale for _, re, im in ROWS])
    np.testing.assert_allclose(data["Z"].sel(frequency=[100.0, 10.0, 1.0]).values, expected, rtol=1e-12)


def test_a_prefixed_hz_suffix_scales_the_frequency(tmp_path):
    data = ix.load(written(tmp_path, "freq_kHz,z_real_ohm,z_imag_ohm"))
    assert sorted(data.frequency.values) == [1e3, 1e4, 1e5]


def test_an_all_capitals_m_prefix_is_refused_as_ambiguous(tmp_path, capsys):
    path = written(tmp_path, "frequency_hz,z_real_MOHM,z_imag_MOHM")
    with pytest.raises(DataError, match="ambiguous"):
        ix.load(path)
    assert main(["inspect", str(path)]) == 2
    assert "z_real_MOHM" in capsys.readouterr().err


def test_an_unprefixed_suffix_still_reads_as_before(tmp_path):
    data = ix.load(written(tmp_path, "frequency_hz,z_real_ohm,z_imag_ohm"))
    assert complex(data["Z"].sel(frequency=100.0).values) == 10 - 1j


@pytest.mark.parametrize("n", [1, 2, 4])
def test_too_few_points_for_kk_and_drt_are_told_to_fit_a_circuit(tmp_path, capsys, n):
    rows = [(10.0**k, 10.0 + k, -1.0 - k) for k in range(n)]
    path = written(tmp_path, "frequency_hz,z_real_ohm,z_imag_ohm", rows)
    assert main(["inspect", str(path)]) == 0
    last = capsys.readouterr().out.strip().splitlines()[-1]
    assert last.startswith(f"next: {n} frequenc") and "too few for impedax kk" in last
    assert f"at most {2 * n} parameters" in last and f"impedax fit {path}" in last
    # the commands it no longer suggests do refuse these points, as it says
    for command in (["drt", str(path)],) + ((["kk", str(path)],) if n < 4 else ()):
        assert main(command) == 2
    capsys.readouterr()


def test_six_points_are_told_the_kk_verdict_will_be_inconclusive(tmp_path, capsys):
    rows = [(10.0**k, 100.0 + 1000.0 / (1 + 1e-3j * 2 * np.pi * 10.0**k), 0.0) for k in range(6)]
    rows = [(f, z.real, z.imag) for f, z, _ in rows]
    path = written(tmp_path, "frequency_hz,z_real_ohm,z_imag_ohm", rows)
    assert main(["inspect", str(path)]) == 0
    last = capsys.readouterr().out.strip().splitlines()[-1]
    assert last.startswith(f"next: impedax kk {path}") and "inconclusive: it needs 10" in last and "impedax drt" in last


def test_the_first_line_counts_one_point_in_the_singular(tmp_path, capsys):
    """One point was "1 frequencies 1–1 Hz, |Z| 3.606–3.606 Ω"; it is "1 frequency, 1 Hz, |Z|
    3.606 Ω" (|Z| of 2 - 3j is √13 = 3.6056 by hand), and three points keep their ranges."""
    path = written(tmp_path, "frequency_hz,z_real_ohm,z_imag_ohm", rows=[(1.0, 2.0, -3.0)])
    assert main(["inspect", str(path)]) == 0
    assert capsys.readouterr().out.splitlines()[0] == f"{path}: delimited text, 1 frequency, 1 Hz, |Z| 3.606 Ω, dims {{'frequency': 1}}"
    path = written(tmp_path, "frequency_hz,z_real_ohm,z_imag_ohm")
    assert main(["inspect", str(path)]) == 0
    # |Z| from √(10² + 1²) = 10.05 to √(15² + 2²) = 15.13
    assert capsys.readouterr().out.splitlines()[0] == f"{path}: delimited text, 3 frequencies 1 Hz–100 Hz, |Z| 10.05 Ω–15.13 Ω, dims {{'frequency': 3}}"


def test_the_first_line_writes_frequencies_and_z_with_their_prefixes(capsys):
    """REAL exampleDataParstat.txt (impedance.py, MIT) read "31 frequencies 10–1e+04 Hz, |Z|
    0.0165–0.03349 Ω": now as impedax writes quantities elsewhere. Oracle: the file's own
    columns (rows with f > 0), read here with numpy: 10 Hz to 10 kHz, |Z| 16.50 mΩ to 33.49 mΩ."""
    import numpy as np

    path = "tests/fixtures/real/exampleDataParstat.txt"
    table = np.genfromtxt(path, delimiter="\t", skip_header=1, usecols=(3, 4, 5))
    table = table[table[:, 0] > 0]
    modulus = np.hypot(table[:, 1], table[:, 2])
    assert (table[:, 0].min(), table[:, 0].max()) == (10.0, 10000.0)
    assert (f"{modulus.min() * 1e3:.4g}", f"{modulus.max() * 1e3:.4g}") == ("16.5", "33.49")
    assert main(["inspect", path]) == 0
    assert capsys.readouterr().out.splitlines()[0] == f"{path}: Parstat text, 31 frequencies 10 Hz–10 kHz, |Z| 16.5 mΩ–33.49 mΩ, dims {{'frequency': 31}}"
