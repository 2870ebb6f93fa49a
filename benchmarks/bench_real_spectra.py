"""The real-spectra study: ``refine`` from ``R0 + R1 || C1`` on the 12 real spectra shipped in
tests/fixtures/real/ (impedance.py 1.7 and AutoEIS 0.0.44 example files, MIT). Prints the table
of docs/diagnosis.md: data, first verdict, refine path, final model, rms_rel, parameters,
undetermined parameters, masked points, time.

    python benchmarks/bench_real_spectra.py [--only NAME] [--json FILE] [--max-effects N]

Times are wall-clock in this process (the first spectrum pays the compilation).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

REAL = Path(__file__).resolve().parent.parent / "tests" / "fixtures" / "real"
SPECTRA = (
    "exampleData.csv", "exampleDataAutolab.txt", "exampleDataBioLogic.mpt", "exampleDataCHInstruments.txt", "exampleDataGamry.DTA",
    "exampleDataParstat.txt", "exampleDataPowersuite.txt", "exampleDataVersaStudio.par", "exampleDataZPlot.z", "test_data.txt",
    "data.dfr", "data.pssession",  # the same pyimpspec test spectrum in two instrument formats
)
START = "R0 + R1 || C1"


def run_one(name: str, max_effects: int) -> dict:
    import impedax as ix
    from impedax.fitting.diagnosis.diagnosis import undetermined_parameters

    data = ix.load(REAL / name)
    t0 = time.perf_counter()
    r = ix.refine(data, START, max_effects=max_effects)
    seconds = time.perf_counter() - t0
    first = r.steps[0].diagnosis
    return {
        "data": name, "points": int(data.sizes["frequency"]), "first_verdict": str(first.verdict) if first else None,
        "kk_rms": float(first.kk.rms_rel) if first and first.kk else None, "path": [s.effect for s in r.steps if s.effect],
        "final_model": r.final_model, "rms_rel": r.final.rms_rel, "n_params": r.final.n_params, "verdict": str(r.verdict),
        "undetermined": sorted(undetermined_parameters(r.final)), "masked": len(r.masked_points), "seconds": seconds,
        "discrepancy": first.discrepancy if first else None,
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", default="", help="run only spectra whose file name starts with this")
    ap.add_argument("--names", default="", help="comma-separated file names to run (default: all 12)")
    ap.add_argument("--json", default=None)
    ap.add_argument("--max-effects", type=int, default=4)
    args = ap.parse_args(argv)
    rows = []
    print("| data | N | KK rms | δ | first verdict | refine path | final model | rms_rel | k | undetermined | masked | verdict | time |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name in SPECTRA:
        if not name.startswith(args.only) or (args.names and name not in args.names.split(",")):
            continue
        row = run_one(name, args.max_effects)
        rows.append(row)
        path = " → ".join(row["path"]) or "—"
        print(
            f"| {name} | {row['points']} | {row['kk_rms'] * 100:.2g} % | {row['discrepancy'] * 100:.2g} % | {row['first_verdict']} | {path} | `{row['final_model']}` | "
            f"{row['rms_rel'] * 100:.3g} % | {row['n_params']} | {', '.join(row['undetermined']) or 'none'} | {row['masked']} | {row['verdict']} | {row['seconds']:.0f} s |",
            flush=True,
        )
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rows, fh, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
