"""The DRT batch report writes resistances with SI prefixes, as the single-spectrum report does
("R_inf = 150.5 mΩ"): on the REAL AutoEIS battery cycles (examples/data, MIT) its lines read
"R_inf 0.1505 Ω", "(0.715 Ω)", "(0.0349 Ω)". Oracles: each spectrum's own numbers, scaled and
written here by hand (×10³ and "mΩ" below 1 Ω), and the single report's R_inf line."""

from __future__ import annotations

import re

import impedax as ix

BATTERY = "examples/data/autoeis_battery_cycles.nc"


def _by_hand(ohm: float, digits: int) -> str:
    return f"{ohm * 1e3:.{digits}g} mΩ" if abs(ohm) < 1 else f"{ohm:.{digits}g} Ω"


def test_the_batch_lines_write_resistances_with_si_prefixes():
    batch = ix.drt(ix.load(BATTERY))
    lines = batch.report().splitlines()[1:1 + len(batch.results)]
    assert len(lines) == 3
    for line, one in zip(lines, batch.results):
        assert 0.1 < one.r_inf_ohm < 1  # the case: R_inf below 1 Ω, in mΩ
        assert f"R_inf {_by_hand(one.r_inf_ohm, 4)}," in line
        assert f"R_pol {_by_hand(one.polarization_resistance, 4)}," in line
        for p in one.peaks:
            assert f"{ix.data.format_time(p.tau_s)} ({_by_hand(p.r_ohm, 3)}" in line
        if one.dropped_peaks:
            assert f"dropped ({_by_hand(sum(p.r_ohm for p in one.dropped_peaks), 3)})" in line
        assert not re.search(r"[ (]0\.\d+ Ω", line), line  # no plain-Ω value below 1 Ω
    single = batch.results[0].report()
    assert f"R_inf = {_by_hand(batch.results[0].r_inf_ohm, 4)}" in single  # the single report's words
