"""The real-spectra study: ``refine`` from ``R0 + R1 || C1`` on the 12 real spectra shipped in
tests/fixtures/real/ (impedance.py 1.7 and AutoEIS 0.0.44 example files, MIT). Prints the table
of docs/diagnosis.md: data, first verdict, refine path, final model, rms_rel, parameters,
undetermined parameters, masked points, time.

    python benchmarks/bench_real_spectra.py [--only NAME] [--json FILE] [--max-effects N] [--hand [--hand-starts N]]

``--hand`` also fits the hand-made circuits of `HAND` on exactly the points refine judged (its
masked frequencies left out), each from impedax's default fit and ``--hand-starts`` (48)
log-uniform random starts (`random_start` of tests/fixtures/real/make_best_known.py, solved
with ``n_starts=1, max_steps=2000``; the lowest rms_rel is kept), and adds to each row the best
hand circuit with at most k + 2 parameters (k: refine's), the ratio of refine's rms_rel to its
rms_rel (refine is within 10 % when the ratio is ≤ 1.10), the same for the best hand circuit
whose parameters the data all determine (the rule refine applies to its own models), and the
best hand circuit with at most k.

Times are wall-clock in this process (the first spectrum pays the compilation).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import time
import warnings
from pathlib import Path

import numpy as np

REAL = Path(__file__).resolve().parent.parent / "tests" / "fixtures" / "real"
SPECTRA = (
    "exampleData.csv", "exampleDataAutolab.txt", "exampleDataBioLogic.mpt", "exampleDataCHInstruments.txt", "exampleDataGamry.DTA",
    "exampleDataParstat.txt", "exampleDataPowersuite.txt", "exampleDataVersaStudio.par", "exampleDataZPlot.z", "test_data.txt",
    "data.dfr", "data.pssession",  # the same pyimpspec test spectrum in two instrument formats
)
START = "R0 + R1 || C1"

# The hand-made circuits: what an electrochemist would try on these spectra (not a search over
# topologies). L0 is a series (lead/cable) inductance, for the spectra whose high-frequency end
# turns inductive (exampleData.csv, Autolab, Parstat, VersaStudio, CH Instruments' last point).
HAND = (
    # one arc
    "R0 + R1 || C1",  # ideal (Debye) arc: refine's start
    "R0 + R1 || CPE1",  # depressed arc
    "R0 + L0 + R1 || C1",  # ideal arc + lead inductance
    "R0 + L0 + R1 || CPE1",  # depressed arc + lead inductance (ZPlot, Parstat)
    "R0 + L0 || R_L + R1 || CPE1",  # inductance shunted by a resistance: a damped HF tail (Parstat)
    # Randles: double layer across charge transfer + diffusion
    "R0 + C1 || (R1 + W1)",  # textbook Randles
    "R0 + CPE1 || (R1 + W1)",  # Randles with a CPE double layer
    "R0 + L0 + CPE1 || (R1 + W1)",  # the same + lead inductance
    "R0 + CPE1 || (R1 + Wo1)",  # Randles, finite-length diffusion, reflective (blocking) boundary
    "R0 + CPE1 || (R1 + Ws1)",  # Randles, finite-length diffusion, transmissive boundary
    "R0 + L0 + CPE1 || (R1 + Wo1)",
    "R0 + L0 + CPE1 || (R1 + Ws1)",
    # one arc + diffusion in series
    "R0 + R1 || CPE1 + W1",
    "R0 + L0 + R1 || CPE1 + W1",
    "R0 + R1 || CPE1 + Wo1",
    "R0 + R1 || CPE1 + Ws1",
    "R0 + L0 + R1 || CPE1 + Wo1",
    # one arc + a blocking low-frequency branch (CH Instruments: phase → 70° at 0.1 Hz, no DC path)
    "R0 + R1 || CPE1 + CPE2",
    "R0 + CPE1 || (R1 + CPE2)",  # Randles with a CPE for the diffusion branch
    # two arcs
    "R0 + R1 || C1 + R2 || C2",
    "R0 + R1 || CPE1 + R2 || CPE2",
    "R0 + R1 || CPE1 + R2 || C2",  # test_data.txt: a small high-frequency arc (phase rising above 10 kHz) beside the main CPE arc
    "R0 + L0 + R1 || CPE1 + R2 || CPE2",  # Autolab, VersaStudio, exampleData.csv
    "R0 + L0 || R_L + R1 || CPE1 + R2 || CPE2",
    "R0 + R1 || C1 + R2 || W1",  # data.dfr / data.pssession: pyimpspec's generating circuit R(RC)(RW)
    "R0 + CPE1 || (R1 + R2 || CPE2)",  # coated metal: coating CPE across pore R + interface arc (Gamry)
    # two arcs + diffusion
    "R0 + R1 || CPE1 + R2 || CPE2 + W1",  # AutoEIS's battery circuit
    "R0 + R1 || CPE1 + (R2 + W1) || CPE2",  # AutoEIS's circuit for test_data.txt
    "R0 + L0 + R1 || CPE1 + R2 || CPE2 + W1",  # exampleData.csv, Autolab: HF inductance, two arcs, LF diffusion line
    "R0 + L0 + R1 || CPE1 + (R2 + W1) || CPE2",
    "R0 + L0 + R1 || CPE1 + (R2 + Wo1) || CPE2",
    "R0 + L0 + R1 || CPE1 + R2 || CPE2 + Wo1",
    "R0 + L0 + R1 || CPE1 + R2 || CPE2 + CPE3",  # exampleData.csv: its low-frequency line is not at 45° (a CPE, not W)
    "R0 + CPE1 || (R1 + CPE2 || (R2 + W1))",  # coated metal with diffusion at the interface (Gamry's LF line)
    # three arcs
    "R0 + R1 || CPE1 + R2 || CPE2 + R3 || CPE3",
    "R0 + L0 + R1 || CPE1 + R2 || CPE2 + R3 || CPE3",  # VersaStudio: HF shoulder, main arc, LF tail + lead
    "R0 + L0 + R1 || CPE1 + R2 || CPE2 + R3 || CPE3 + W1",  # exampleData.csv: three time constants + diffusion
)
HAND_SEED = 20261126
RATIO_FLOOR = 1e-9  # rms_rel below this counts as this (machine-precision fits: data.dfr)


def random_start_function():
    """`random_start` of tests/fixtures/real/make_best_known.py (the best-known fits' starts)."""
    spec = importlib.util.spec_from_file_location("make_best_known", REAL / "make_best_known.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.random_start


def judged_points(data, masked):
    """The spectrum refine judged: ``data`` less its masked frequencies (as `refine` selects them)."""
    if not masked:
        return data
    out = set(float(f) for f in masked)
    return data.sel(frequency=[f for f in data["frequency"].values if float(f) not in out])


def hand_fit(circuit: str, data, n_random: int, rng, random_start) -> dict:
    """The lowest rms_rel of ``circuit`` on ``data`` over impedax's default fit and ``n_random``
    random starts: {rms_rel, from (which start gave it), undetermined (the parameters of that
    fit the data do not determine, impedax's rule), failed (starts whose fit raised), errors
    (the first three of them: start and error)}. A fit that raises `impedax.ImpedaxError` is
    counted, not fatal."""
    import impedax as ix
    from impedax.fitting.diagnosis.diagnosis import undetermined_parameters

    names = ix.parse(circuit).parameter_names()
    freq, z = data["frequency"].values, data["Z"].values
    out = {"rms_rel": np.inf, "from": None, "undetermined": None, "failed": 0, "errors": []}

    def attempt(label, start):
        try:
            r = ix.fit(circuit, data) if start is None else ix.fit(circuit, data, init=start, n_starts=1, max_steps=2000)
        except ix.ImpedaxError as err:
            out["failed"] += 1
            if len(out["errors"]) < 3:
                out["errors"].append({"start": start, "error": f"{type(err).__name__}: {err}"})
            return
        if np.isfinite(r.rms_rel) and r.rms_rel < out["rms_rel"]:
            out["rms_rel"], out["from"], out["undetermined"] = float(r.rms_rel), label, sorted(undetermined_parameters(r))

    attempt("default", None)
    for i in range(n_random):
        attempt(f"random {i}", random_start(names, freq, z, rng))
    return out


def hand_columns(row: dict, data, masked, judged, n_random: int, index: int) -> dict:
    """Fit the `HAND` circuits with at most k + 2 parameters on the judged points (``data`` less
    ``masked``; ``judged``: the frequencies of refine's final fit, checked to be the same); the
    best of them, the best of those whose parameters are all determined, the best with at most
    k, and refine's ratio to the first two."""
    import impedax as ix

    warnings.simplefilter("ignore")
    random_start = random_start_function()
    used = judged_points(data, masked)
    if sorted(used["frequency"].values.tolist()) != sorted(np.asarray(judged).tolist()):
        raise RuntimeError(f"{row['data']}: the hand fits' points are not those of refine's final fit")
    k = row["n_params"]
    t0 = time.perf_counter()
    fits = []
    for j, circuit in enumerate(HAND):
        n = len(ix.parse(circuit).parameter_names())
        if n > k + 2:
            continue
        fits.append({"circuit": circuit, "k": n, **hand_fit(circuit, used, n_random, np.random.default_rng([HAND_SEED, index, j]), random_start)})
        # each circuit's compiled solvers hold ~1,000–1,700 memory maps; Linux allows 65,530
        ix.clear_caches()
    best2 = min(fits, key=lambda f: f["rms_rel"])
    determined = [f for f in fits if f["undetermined"] == []]
    best_det = min(determined, key=lambda f: f["rms_rel"]) if determined else None
    within_k = [f for f in fits if f["k"] <= k]
    best0 = min(within_k, key=lambda f: f["rms_rel"]) if within_k else None
    ratio = max(row["rms_rel"], RATIO_FLOOR) / max(best2["rms_rel"], RATIO_FLOOR)
    ratio_det = max(row["rms_rel"], RATIO_FLOOR) / max(best_det["rms_rel"], RATIO_FLOOR) if best_det else None
    return {
        "hand_points": int(used.sizes["frequency"]), "hand_starts": n_random, "hand_fits": fits,
        "hand_best": best2["circuit"], "hand_rms_rel": best2["rms_rel"], "hand_k": best2["k"], "hand_undetermined": best2["undetermined"],
        "ratio": ratio, "within_10pct": bool(ratio <= 1.10),
        "hand_best_determined": best_det["circuit"] if best_det else None, "hand_rms_rel_determined": best_det["rms_rel"] if best_det else None,
        "hand_k_determined": best_det["k"] if best_det else None, "ratio_determined": ratio_det,
        "within_10pct_determined": bool(ratio_det <= 1.10) if best_det else None,
        "hand_best_at_k": best0["circuit"] if best0 else None, "hand_rms_rel_at_k": best0["rms_rel"] if best0 else None,
        "hand_k_at_k": best0["k"] if best0 else None, "hand_seconds": time.perf_counter() - t0,
    }


def refine_one(name: str, max_effects: int):
    """Refine on spectrum ``name``: (the table row, the `Refinement`, the loaded data)."""
    import impedax as ix
    from impedax.fitting.diagnosis.diagnosis import undetermined_parameters

    data = ix.load(REAL / name)
    t0 = time.perf_counter()
    r = ix.refine(data, START, max_effects=max_effects)
    seconds = time.perf_counter() - t0
    first = r.steps[0].diagnosis
    row = {
        "data": name, "points": int(data.sizes["frequency"]), "first_verdict": str(first.verdict) if first else None,
        "kk_rms": float(first.kk.rms_rel) if first and first.kk else None, "path": [s.effect for s in r.steps if s.effect],
        "final_model": r.final_model, "rms_rel": r.final.rms_rel, "n_params": r.final.n_params, "verdict": str(r.verdict),
        "undetermined": sorted(undetermined_parameters(r.final)), "masked": len(r.masked_points), "seconds": seconds,
        "discrepancy": first.discrepancy if first else None, "masked_points": [float(f) for f in r.masked_points],
    }
    return row, r, data


def run_one(name: str, max_effects: int) -> dict:
    """The table row of refine on spectrum ``name``."""
    return refine_one(name, max_effects)[0]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", default="", help="run only spectra whose file name starts with this")
    ap.add_argument("--names", default="", help="comma-separated file names to run (default: all 12)")
    ap.add_argument("--json", default=None)
    ap.add_argument("--max-effects", type=int, default=4)
    ap.add_argument("--hand", action="store_true", help="also fit the hand-made circuits (HAND) and compare")
    ap.add_argument("--hand-starts", type=int, default=48, help="random starts per hand circuit, besides the default fit")
    args = ap.parse_args(argv)
    rows = []
    head = "| data | N | KK rms | δ | first verdict | refine path | final model | rms_rel | k | undetermined | masked | verdict | time |"
    if args.hand:
        head += (
            " best hand ≤ k+2 | its rms_rel | its k | its undetermined | ratio | within 10 % |"
            " best determined hand ≤ k+2 | its rms_rel | its k | ratio | within 10 % | best hand ≤ k | its rms_rel | hand time |"
        )
    print(head)
    print("|---" * head.count(" | ") + "|---|")
    names = [n for n in SPECTRA if n.startswith(args.only) and (not args.names or n in args.names.split(","))]
    # --hand: every refine first, in one process as without it (so its times mean the same:
    # the first spectrum pays the compilation), then the hand fits, which clear the caches
    refined = [refine_one(name, args.max_effects) for name in names] if args.hand else None
    for i, name in enumerate(names):
        if args.hand:
            row, r, data = refined[i]
            row.update(hand_columns(row, data, r.masked_points, r.final.frequency, args.hand_starts, SPECTRA.index(name)))
        else:
            row = run_one(name, args.max_effects)
        rows.append(row)
        path = " → ".join(row["path"]) or "—"
        line = (
            f"| {name} | {row['points']} | {row['kk_rms'] * 100:.2g} % | {row['discrepancy'] * 100:.2g} % | {row['first_verdict']} | {path} | `{row['final_model']}` | "
            f"{row['rms_rel'] * 100:.3g} % | {row['n_params']} | {', '.join(row['undetermined']) or 'none'} | {row['masked']} | {row['verdict']} | {row['seconds']:.0f} s |"
        )
        if args.hand:
            at_k = f"`{row['hand_best_at_k']}` | {row['hand_rms_rel_at_k'] * 100:.3g} %" if row["hand_best_at_k"] else "— | —"
            det = (
                f"`{row['hand_best_determined']}` | {row['hand_rms_rel_determined'] * 100:.3g} % | {row['hand_k_determined']} | {row['ratio_determined']:.3g} | "
                f"{'yes' if row['within_10pct_determined'] else 'no'}"
                if row["hand_best_determined"] else "— | — | — | — | —"
            )
            line += (
                f" `{row['hand_best']}` | {row['hand_rms_rel'] * 100:.3g} % | {row['hand_k']} | {', '.join(row['hand_undetermined'] or []) or 'none'} | "
                f"{row['ratio']:.3g} | {'yes' if row['within_10pct'] else 'no'} | {det} | {at_k} | {row['hand_seconds']:.0f} s |"
            )
        print(line, flush=True)
        if args.json:  # after every row: a long --hand run keeps what it has done
            with open(args.json, "w") as fh:
                json.dump(rows, fh, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
