"""``impedax kk`` of data with σ says how to judge by the noise estimate instead in its own
option, ``--noise residuals``, beside the Python call: until 2026-12-06 its report said only
"kk_test(noise='residuals')", words an ``impedax kk`` user cannot type. Oracle: the option's
choices as ``impedax kk --help`` lists them; a SYNTHETIC R0 + R1 ∥ C1 with a sigma column."""

import numpy as np

from cli_run import run


def test_the_sigma_note_names_the_option(tmp_path, capsys):
    f = np.geomspace(1.0, 1e5, 40)
    z = 20.0 + 500.0 / (1 + 2j * np.pi * f * 500.0 * 1e-6)
    sigma = 0.005 * np.abs(z)
    rng = np.random.default_rng(1)
    z = z + sigma * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size))
    path = tmp_path / "sigma.csv"
    np.savetxt(path, np.c_[f, z.real, z.imag, sigma], delimiter=",", header="frequency_hz,z_real_ohm,z_imag_ohm,sigma_ohm", comments="")
    code, out, _ = run(["kk", path, "--noise", "sigma"], capsys)
    assert code == 0
    (note,) = [line for line in out.splitlines() if line.startswith("noise: the data's sigma")]
    assert "impedax kk --noise residuals" in note
    _, usage, _ = run(["kk", "--help"], capsys)
    assert "--noise {auto,sigma,residuals}" in usage  # (the option and the choice it names exist)
