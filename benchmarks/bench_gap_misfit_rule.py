"""Evaluation of `impedax gap`'s misfit rule on SYNTHETIC single contacts (2026-12-06): the EDL
model R_EP ∥ CPE_EP ∥ C_gap fitted as the gap analysis fits one spectrum without sigma (weighting
modulus), its rms_rel against what the Kramers–Kronig test's Voigt chain reaches on the same data
(`known_kk_misfits`); MODEL DOES NOT FIT holds at rms_rel ≥ 5 % and over `MISFIT_RATIO_MAX` (5) ×
that; the note of `models.gap._near_misfit_note` from `NEAR_MISFIT_RATIO` (2.5) ×. Every spectrum is
written here in numpy (no impedax circuit), with relative complex noise 0.2–5 %, 30–60 points
from 0.01–1 Hz to 10–200 kHz:

* ``gap``: R_EP ∥ CPE_EP ∥ C_gap itself (u 0.5–10 µm at 1 cm², α 0.3–0.9) — the model holds;
* ``imperfect``: that contact with C_gap a CPE of α 0.97–1 and a series resistance of 0.1–5 % of
  |Z| at the top frequency — the model nearly holds;
* ``cell``: electrochemical cells, R0 + R1 ∥ CPE with a Warburg tail, a second arc or a lead
  inductance — no air gap;
* ``series``: an ionic conductor between blocking electrodes, R_b ∥ C_b + CPE_dl in series (the
  REAL exampleDataGamry.DTA's shape) — no air gap, yet C_b (50 pF–2 nF) looks like a gap.

Three studies (the seeds of the figures in docs/models.md and the commit that added the note):
``a`` seeds 0–159 (gap if seed % 4 < 2, else cell), ``b`` seeds 1000–1179 (gap, imperfect,
cell by seed % 3), ``c`` seeds 2000–2079 (series). Even seeds are the dev split, odd the held-out.

Usage: ``python benchmarks/bench_gap_misfit_rule.py [--study a|b|c|all] [--out FILE.jsonl]``
(rows appended to ``--out``, default out/gap_misfit_rule_run.jsonl; ~2–5 s per spectrum, so
``all`` takes 15–35 min), then its table; ``--table`` alone prints that of the recorded run,
benchmarks/gap_misfit_rule.jsonl (or of ``--out``).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

import impedax as ix
from impedax.fitting.least_squares.branches import undetermined_names
from impedax.fitting.least_squares.result import known_kk_misfits

EPS0 = 8.8541878128e-12
STUDIES = {"a": range(0, 160), "b": range(1000, 1180), "c": range(2000, 2080)}


def _cpe(q, a, w):
    return 1 / (q * (1j * w) ** a)


def _par(*zs):
    return 1 / sum(1 / z for z in zs)


def gap_case(rng, f):
    w = 2 * np.pi * f
    u = 10 ** rng.uniform(np.log10(0.5e-6), np.log10(10e-6))
    c = EPS0 * 1.00059 * 1e-4 / u
    a = rng.uniform(0.3, 0.9)
    fx = 10 ** rng.uniform(0, 3)  # the EP admittance equals ωC_gap there
    q = c * (2 * np.pi * fx) ** (1 - a)
    r = 10 ** rng.uniform(5, 9)
    return _par(r + 0j, _cpe(q, a, w), 1 / (1j * w * c)), c


def imperfect_gap_case(rng, f):
    w = 2 * np.pi * f
    z, c = gap_case(rng, f)
    ag = rng.uniform(0.97, 1.0)
    z = 1 / (1 / z - 1j * w * c + 1 / _cpe(c * (2 * np.pi * 1e3) ** (1 - ag), ag, w))
    return z + 10 ** rng.uniform(-3, np.log10(0.05)) * abs(z[-1]), c


def cell_case(rng, f):
    w = 2 * np.pi * f
    kind = int(rng.integers(4))
    r0 = 10 ** rng.uniform(0, 3)
    r1 = r0 * 10 ** rng.uniform(-0.5, 2)
    a = rng.uniform(0.7, 0.98)
    tau = 10 ** rng.uniform(-4, 0)
    q = tau**a / r1
    z = r0 + _par(r1 + 0j, _cpe(q, a, w))
    if kind == 1:
        z = r0 + _par(r1 + _cpe(1 / (r1 * 10 ** rng.uniform(-1, 1)), 0.5, w), _cpe(q, a, w))
    elif kind == 2:
        r2 = r1 * 10 ** rng.uniform(-1, 1)
        t2 = tau * 10 ** rng.uniform(1.5, 3)
        z = z + _par(r2 + 0j, 1 / (1j * w * t2 / r2))
    elif kind == 3:
        z = z + 1j * w * 10 ** rng.uniform(-7, -5)
    return z, kind


def series_case(rng, f):
    w = 2 * np.pi * f
    cb = 10 ** rng.uniform(np.log10(50e-12), np.log10(2e-9))
    rb = 10 ** rng.uniform(2, 6)
    a = rng.uniform(0.3, 0.9)
    fx = 10 ** rng.uniform(-2, 1)  # |Z_dl| = R_b there
    return _par(rb + 0j, 1 / (1j * w * cb)) + _cpe(1 / (rb * (2 * np.pi * fx) ** a), a, w), cb


def one(study: str, seed: int) -> dict:
    rng = np.random.default_rng(seed)
    f = np.geomspace(10 ** rng.uniform(-2, 0), 10 ** rng.uniform(4, 5.3), int(rng.integers(30, 61)))
    noise = 10 ** rng.uniform(np.log10(0.002), np.log10(0.05))
    cls = {"a": lambda: "gap" if seed % 4 < 2 else "cell", "b": lambda: ("gap", "imperfect", "cell")[seed % 3], "c": lambda: "series"}[study]()
    c, kind = None, -1
    if cls == "gap":
        z, c = gap_case(rng, f)
    elif cls == "imperfect":
        z, c = imperfect_gap_case(rng, f)
    elif cls == "series":
        z, c = series_case(rng, f)
    else:
        z, kind = cell_case(rng, f)
    z = z * (1 + noise * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)))
    fit = ix.fit("R_EP || CPE_EP || C_gap", ix.make_spectrum(f, z), weighting="modulus", progress=False)
    kk = float(known_kk_misfits(f, z[None], np.array([0]), None)[0])
    return {"study": study, "seed": seed, "class": cls, "kind": kind, "noise": noise, "rms": float(fit.rms_rel), "kk": kk, "ratio": float(fit.rms_rel) / kk,
            "undetermined": undetermined_names(fit), "at_bound": list(fit.at_bound), "c_gap_error": float(fit.values["C_gap"]) / c - 1 if c else None}


def table(path: Path) -> None:
    rows = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    for split, parity in (("dev (even seeds)", 0), ("held-out (odd seeds)", 1)):
        sub = [r for r in rows if r["seed"] % 2 == parity]
        print(f"== {split}")
        for cls in ("gap", "imperfect", "cell", "series"):
            group = [r for r in sub if r["class"] == cls]
            if not group:
                continue
            rates = ", ".join(f"> {th:g}×: {sum(r['rms'] >= 0.05 and r['ratio'] > th for r in group)}" for th in (5, 4, 3, 2.5, 2))
            print(f"  {cls:9s} {len(group):3d} spectra; flagged at rms_rel ≥ 5 % and ratio {rates}; largest ratio at rms_rel ≥ 5 %: "
                  f"{max([r['ratio'] for r in group if r['rms'] >= 0.05], default=float('nan')):.3g}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--study", choices=[*STUDIES, "all"], default="all")
    parser.add_argument("--out", type=Path, help="rows appended here (default out/gap_misfit_rule_run.jsonl, beside the repository's out/)")
    parser.add_argument("--table", action="store_true", help="print the rates of --out (default: the recorded run, benchmarks/gap_misfit_rule.jsonl) and stop")
    args = parser.parse_args()
    if args.table:
        table(args.out or Path(__file__).with_name("gap_misfit_rule.jsonl"))
        return
    args.out = args.out or Path(__file__).resolve().parent.parent / "out" / "gap_misfit_rule_run.jsonl"
    args.out.parent.mkdir(parents=True, exist_ok=True)
    with args.out.open("a") as out:
        for study in STUDIES if args.study == "all" else [args.study]:
            for seed in STUDIES[study]:
                start = time.perf_counter()
                row = one(study, seed)
                row["seconds"] = time.perf_counter() - start
                out.write(json.dumps(row) + "\n")
                out.flush()
    table(args.out)


if __name__ == "__main__":
    main()
