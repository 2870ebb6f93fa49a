"""Sweeps of one grid in one table (a frequency list that restarts, EC-Lab's cycle number) are
stacked from arrays (`impedax.io.table._sweeps_at_once`), where a Dataset was built per sweep and
concatenated by xarray: 4,000 SYNTHETIC EC-Lab cycles took 6.4 s, now 1.9 s. The oracle: the
Dataset per sweep, concatenated as before (the fast path switched off), which must be identical
(values, attributes, coordinates) or give the same message."""

import numpy as np
import pytest

import impedax as ix
from impedax.io import table

# SYNTHETIC: R0 + R1 || C1 (10 Ω, 100 Ω, 1 µF), 20 points 10 kHz … 1 Hz, a sweep per cycle, R1 growing
F = np.logspace(4, 0, 20)


def _sweep(k: int) -> np.ndarray:
    return 10 + (100 + 5 * k) / (1 + 1j * 2 * np.pi * F * 1e-4)


def _table(n_sweeps: int, *, cycle=False, sigma=False, stray=0.0, edit=None) -> str:
    header = ["time/s", "freq/Hz", "Re(Z)/Ohm", "-Im(Z)/Ohm", *(["sigma"] if sigma else []), *(["cycle number"] if cycle else [])]
    rows = []
    for k in range(n_sweeps):
        for j, (f, z) in enumerate(zip(F * (1 + stray * k), _sweep(k))):
            rows.append([f"{0.5 * len(rows):g}", f"{f:.10g}", f"{z.real:.10g}", f"{-z.imag:.10g}", *([f"{0.01 * abs(z):.6g}"] if sigma else []),
                         *([str(k + 1)] if cycle else [])])
    if edit is not None:
        edit(rows)
    return "\n".join(["\t".join(header), *("\t".join(r) for r in rows)]) + "\n"


def _both(tmp_path, monkeypatch, text: str):
    path = tmp_path / "sweeps.txt"
    path.write_text(text)
    used = []
    at_once = table._sweeps_at_once

    def spy(*args):
        used.append(at_once(*args) is not None)
        return at_once(*args)

    def read():
        try:
            return ix.load(path)
        except ix.DataError as exc:
            return str(exc)

    monkeypatch.setattr(table, "_sweeps_at_once", spy)
    fast = read()
    monkeypatch.setattr(table, "_sweeps_at_once", lambda *args: None)
    return fast, read(), used


@pytest.mark.parametrize("options", [dict(), dict(cycle=True), dict(sigma=True), dict(cycle=True, sigma=True), dict(stray=2e-4)],
                         ids=["restarts", "cycles", "sigma", "cycles and sigma", "grids stray"])
def test_sweeps_stacked_at_once_are_the_sweeps_concatenated(tmp_path, monkeypatch, options):
    fast, slow, used = _both(tmp_path, monkeypatch, _table(4, **options))
    assert used == [True]
    assert not isinstance(fast, str), fast
    assert fast.identical(slow)
    dim = "cycle" if options.get("cycle") else "sweep"
    assert fast["Z"].dims == (dim, "frequency") and fast.sizes[dim] == 4
    np.testing.assert_allclose(fast["Z"].values, np.stack([_sweep(k) for k in range(4)]), rtol=1e-9)  # (10 digits written)
    np.testing.assert_array_equal(fast["time"].values, 0.5 * np.arange(80).reshape(4, 20))
    assert fast.attrs["sweeps"].startswith(f"4 {dim}s of 20 points")


def test_a_dc_row_between_sweeps_is_skipped_as_before(tmp_path, monkeypatch):
    fast, slow, used = _both(tmp_path, monkeypatch, _table(3, edit=lambda rows: rows.insert(20, ["10", "0", "1", "0"])))
    assert used == [True] and fast.identical(slow)
    assert fast.attrs["skipped_rows"] == ["line 22: f = 0 (DC row, not an impedance point)"]


@pytest.mark.parametrize("edit, message", [
    (lambda rows: rows[45].__setitem__(1, "-" + rows[45][1]), "frequency must be positive"),
    (lambda rows: rows[65].__setitem__(4, "-0.5"), "sigma must be positive, got -0.5"),
], ids=["negative frequency", "negative sigma"])
def test_a_bad_sweep_is_named_as_before(tmp_path, monkeypatch, edit, message):
    fast, slow, used = _both(tmp_path, monkeypatch, _table(4, sigma=True, edit=edit))
    assert isinstance(slow, str) and message in slow
    assert fast == slow
