"""`impedax.diagnose` from three common starting models on REAL spectra: the 11 distinct spectra
of tests/fixtures/real/ (impedance.py 1.7 and AutoEIS 0.0.44 example files, MIT; `data.dfr`
stands for its pyimpspec twin `data.pssession`) and the three cycles of
examples/data/autoeis_battery_cycles.nc. Prints per diagnosis the verdict, the residuals
against the noise, whether the two-effect step (`_effect_pairs`, docs/diagnosis.md section 5,
"Two effects missing at once") ran and how many pairs it fitted, the best suggestion and the
wall time (one process; the first diagnosis pays the compilation).

    python benchmarks/bench_diagnose_real.py [--only NAME]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
REAL = ROOT / "tests" / "fixtures" / "real"
SPECTRA = (
    "exampleData.csv", "exampleDataAutolab.txt", "exampleDataBioLogic.mpt", "exampleDataCHInstruments.txt", "exampleDataGamry.DTA",
    "exampleDataParstat.txt", "exampleDataPowersuite.txt", "exampleDataVersaStudio.par", "exampleDataZPlot.z", "test_data.txt", "data.dfr",
)
CYCLES = ROOT / "examples" / "data" / "autoeis_battery_cycles.nc"
MODELS = ("R0 + R1 || C1", "R0 + R1 || CPE1", "R0 + R1 || CPE1 + R2 || CPE2")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", default="", help="run only the data whose name starts with this")
    args = ap.parse_args(argv)

    import impedax as ix
    import impedax.fitting.diagnosis.diagnosis as diagnosis_module

    pairs_fitted: list[int] = []
    step = diagnosis_module._effect_pairs

    def counted(*a, **k):  # (counts the step's pairs; the diagnosis itself is unchanged)
        out = step(*a, **k)
        pairs_fitted.append(len(out[0]))
        return out

    diagnosis_module._effect_pairs = counted
    items = [(name, REAL / name, None) for name in SPECTRA] + [(f"{CYCLES.name} cycle {c}", CYCLES, c) for c in range(3)]
    print("| data | model | verdict | residuals / noise | pairs step | best suggestion | rms_rel | time |")
    print("|---|---|---|---|---|---|---|---|")
    ran = 0
    for label, path, cycle in items:
        if not label.startswith(args.only):
            continue
        data = ix.load(path)
        if cycle is not None:
            data = data.isel(cycle=cycle)
        for model in MODELS:
            pairs_fitted.clear()
            t0 = time.perf_counter()
            d = ix.diagnose(data, model)
            seconds = time.perf_counter() - t0
            ran += bool(pairs_fitted)
            best = d.best
            step_text = f"ran, {sum(pairs_fitted)} pairs" if pairs_fitted else "—"
            best_text = f"{best.effect}: `{best.model}`" if best else "—"
            rms = f"{best.rms_rel * 100:.3g} % (from {d.baseline.rms_rel * 100:.3g} %)" if best else f"{d.baseline.rms_rel * 100:.3g} %"
            print(f"| {label} | `{model}` | {d.verdict} | {d.noise_ratio:.3g} | {step_text} | {best_text} | {rms} | {seconds:.1f} s |", flush=True)
    print(f"\nthe two-effect step ran in {ran} diagnoses")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
