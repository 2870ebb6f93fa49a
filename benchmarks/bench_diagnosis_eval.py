"""The diagnosis over its evaluation set (tests/evaluation_set.py, SYNTHETIC spectra from
independent numpy formulas): top-1 and top-3 hit rates on single missing effects, false alarms on
adequate models, non-KK data found, refine's success on two missing effects, seconds per case.

    python benchmarks/bench_diagnosis_eval.py [--split dev|heldout|dev2|heldout2|both] [--only PREFIX] [--json FILE] [--reproduce]

``--reproduce`` also fits each best suggestion's model string with `impedax.fit` on the points
the diagnosis kept and reports the share within 1 % of the suggestion's rms_rel.

The held-out splits are for reporting only: tune on dev and dev2 (``both``: dev and heldout).
Each case is printed as it finishes.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))

import evaluation_set as es  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--split", choices=["dev", "heldout", "dev2", "heldout2", "both"], default="dev")
    ap.add_argument("--only", default="", help="run only cases whose name starts with this")
    ap.add_argument("--json", default=None, help="write every outcome and the summary to this file")
    ap.add_argument("--no-refine", action="store_true", help="skip refine on two-effect cases")
    ap.add_argument("--reproduce", action="store_true", help="also fit each best suggestion's model string with impedax.fit (to 1 %% in rms_rel)")
    args = ap.parse_args(argv)
    splits = ["dev", "heldout"] if args.split == "both" else [args.split]
    report = {}
    for split in splits:
        cases = [c for c in es.cases(split) if c.name.startswith(args.only)]
        outcomes = []
        t0 = time.perf_counter()
        for c in cases:
            o = es.run_case(c, refine_two=not args.no_refine, reproduce=args.reproduce)
            outcomes.append(o)
            mark = "ok " if o.correct else "MISS"
            extra = f" refine+{list(o.refine_effects)}→{o.refine_verdict}" if o.refine_effects is not None else ""
            extra += "" if o.structure is None else (" (generating structure reached)" if o.structure else " (generating structure not reached)")
            extra += " (the generating circuit's function, other labels)" if o.equivalent and not o.two_named else ""
            again = f" fit/suggestion {o.reproduced:.4f}" if o.reproduced is not None else ""
            print(f"{mark} {split:7s} {c.name:40s} want {','.join(c.expected) or 'adequate':40s} got {o.verdict:15s} {list(o.ranked[:3])}{extra} {o.seconds:6.1f}s{again}", flush=True)
        summary = es.summarise(outcomes)
        summary["wall_s"] = time.perf_counter() - t0
        print(f"== {split}: " + ", ".join(f"{k} {v:.3g}" if isinstance(v, float) else f"{k} {v}" for k, v in summary.items()), flush=True)
        report[split] = {
            "summary": summary,
            "cases": [{"name": o.case.name, "kind": o.case.kind, "expected": list(o.case.expected), "verdict": o.verdict, "ranked": list(o.ranked),
                       "refine_effects": None if o.refine_effects is None else list(o.refine_effects), "refine_verdict": o.refine_verdict,
                       "correct": o.correct, "seconds": o.seconds, "reproduced": o.reproduced, "structure": o.structure,
                       "equivalent": o.equivalent, "two_recovered": o.two_recovered if o.case.kind == "two" else None} for o in outcomes],
        }
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(report, fh, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
