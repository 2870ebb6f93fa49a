"""`impedax fit --out FILE.tex` with a --select list or range that picks one spectrum writes
that spectrum's table, as the label pick does (REAL battery cycles 0, 64, 129: `--select
cycle=0:20` kept cycle 0 and the run ended in an AttributeError traceback, a batch of one having
no LaTeX table)."""

from pathlib import Path

from impedax.cli import main

THREE = Path(__file__).resolve().parents[1] / "examples" / "data" / "autoeis_battery_cycles.nc"


def test_a_range_that_picks_one_spectrum_writes_its_latex_table_as_its_label_does(tmp_path, capsys):
    tables = []
    for select in ("cycle=0:20", "cycle=0"):
        out = tmp_path / f"{select.replace(':', '_')}.tex"
        assert main(["fit", str(THREE), "--select", select, "--model", "R0 + R1 || C1", "-q", "--out", str(out)]) == 0
        tables.append(out.read_text(encoding="utf-8"))
    capsys.readouterr()
    assert tables[0] == tables[1] and "\\begin{tabular}" in tables[0] and "R1" in tables[0]
