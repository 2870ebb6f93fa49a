"""Reading tables: `impedax.load` of SYNTHETIC 200,000-row delimited files (three layouts) and of
the REAL instrument files in tests/fixtures/real/ (impedance.py and AutoEIS example data, MIT).

    python benchmarks/bench_read_table.py [--rows N] [--repeat K]

Each file is loaded once untimed (imports, the readers' first calls), then ``--repeat`` times;
the median wall-clock time of one load is printed. The SYNTHETIC files are written to a
temporary folder from R0 + R1 || C1 (R0 = 10 Ω, R1 = 100 Ω, C1 = 10 µF), 1 MHz … 10 mHz.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))

from _timing import median_time  # noqa: E402

REAL = ROOT / "tests" / "fixtures" / "real"


def synthetic_files(folder: Path, rows: int) -> list[Path]:
    """Three SYNTHETIC tables of ``rows`` points: comma-separated Z' and -Z'' under a header
    with units; ';' with decimal commas, a note above and a units row; tab-separated |Z| and
    phase with a time column."""
    f = np.logspace(6, -2, rows)
    z = 10 + 100 / (1 + 1j * 2 * np.pi * f * 1e-3)
    cells = [(f"{a:.10g}", f"{b.real:.10g}", f"{-b.imag:.10g}") for a, b in zip(f, z)]
    files = {
        "points.csv": ["Freq (Hz),Z' (Ohm),-Z'' (Ohm)", *(",".join(c) for c in cells)],
        "commas.txt": ["# exported with a German locale", "Frequency;Re(Z);-Im(Z)", "Hz;Ohm;Ohm",
                       *(";".join(c).replace(".", ",") for c in cells)],
        "polar.tsv": ["Time (s)\tFrequency (Hz)\t|Z| (Ohm)\tPhase (deg)",
                      *(f"{0.1 * k:.1f}\t{a:.10g}\t{abs(b):.10g}\t{np.degrees(np.angle(b)):.10g}" for k, (a, b) in enumerate(zip(f, z)))],
    }
    paths = []
    for name, lines in files.items():
        path = folder / name
        path.write_text("\n".join(lines) + "\n", encoding="utf-8")
        paths.append(path)
    return paths


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rows", type=int, default=200_000)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    import impedax as ix

    real = sorted(p for p in REAL.iterdir() if p.suffix not in (".npz", ".py", ".md", ".json") and not p.name.startswith("LICENSE"))
    with tempfile.TemporaryDirectory() as tmp:
        for path in [*synthetic_files(Path(tmp), args.rows), *real]:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                try:
                    points = ix.load(path)["Z"].size
                except ix.DataError as exc:
                    print(f"{path.name}: not read ({exc})")
                    continue
                seconds = median_time(lambda: ix.load(path), args.repeat)
            kind = "SYNTHETIC" if path.parent != REAL else "REAL"
            print(f"{kind:9s} {path.name:32s} {points:7d} points  {seconds * 1e3:9.1f} ms")


if __name__ == "__main__":
    main()
