"""`impedax drt` closes its progress printer on every way out: after an error inside the DRT
solve, a printer left open printed its pending line once its delay ran out, into whatever the
process ran next (a flaky `impedax fit -q` test that found "DRT of 1 spectrum" on its stderr,
2026-12-05)."""

import time

import numpy as np

from impedax.cli import common, main


def test_an_error_in_the_drt_leaves_no_progress_line_behind(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(common, "PROGRESS_AFTER_S", 0.3)
    f = np.array([1e3, 1e2, 1e1])  # (three points: too few for a DRT, refused inside the solve)
    path = tmp_path / "three.csv"
    np.savetxt(path, np.c_[f, 10 + 0 * f, -1 / f], delimiter=",", header="frequency_hz,z_real_ohm,z_imag_ohm", comments="")
    assert main(["drt", str(path)]) == 2
    first = capsys.readouterr().err
    assert "DRT of 1 spectrum" not in first  # (the error came before the printer's delay)
    time.sleep(0.8)  # past the delay: an open printer's timer would print its pending line now
    assert "DRT of 1 spectrum" not in capsys.readouterr().err
