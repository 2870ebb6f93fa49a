"""The "to apply" line names what its own fit will warn of: a parameter at a bound (a
walkthrough, 2026-12-05: a suggestion carried --init CPE2.alpha=1 with no word, and running it
warned "CPE2.alpha is at its upper bound 1"). Oracle: a SYNTHETIC spectrum of two ideal R ∥ C
arcs written here with numpy (its capacitors are CPEs of α = 1 by construction), and the
warning the printed command gives when run."""

from __future__ import annotations

import shlex

import numpy as np

from impedax.cli import main


def test_a_cpe_at_alpha_one_is_named_under_the_command_that_will_warn_of_it(tmp_path, capsys):
    f = np.logspace(5, -2, 71)
    w = 2 * np.pi * f
    z = 10 + 1 / (1 / 50 + 1j * w * 1e-5) + 1 / (1 / 80 + 1j * w * 1e-2)
    rng = np.random.default_rng(1)
    z = z + np.abs(z) * 0.005 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size))
    path = tmp_path / "two_rc.csv"
    np.savetxt(path, np.c_[f, z.real, z.imag], delimiter=",", header="frequency_hz,z_real_ohm,z_imag_ohm", comments="", fmt="%.10g")
    assert main(["diagnose", str(path), "--model", "R0 + R1 || CPE1", "-q"]) == 0
    lines = capsys.readouterr().out.splitlines()
    i = next(k for k, line in enumerate(lines) if line.startswith("  to apply 1."))
    note = lines[i + 1]
    assert note.startswith("     note: in this fit CPE1.alpha is at its upper bound 1")
    command = shlex.split(lines[i].split(": ", 1)[1])
    assert main([*command[1:], "-q"]) == 0
    assert "warning: CPE1.alpha is at its upper bound 1" in capsys.readouterr().out
