"""``impedax demo``: the main job on the embedded data (``make demo``)."""

from __future__ import annotations

import time
from pathlib import Path


def register(sub) -> None:
    p = sub.add_parser("demo", help="run the main demonstration (writes to out/)")
    p.add_argument("--out", default="out", help="output folder (default out/)")
    p.add_argument("--fast", action="store_true", help="fewer MCMC steps (used by the tests)")
    p.set_defaults(run=run)


def run(args) -> int:
    import numpy as np

    from .. import compile_circuit, make_spectrum, parse, save
    from ..data import log_frequencies
    from ..plotting import plot_spectrum, save_figure

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    circuit = parse("R_EP || C_EP || C_gap")
    params = {"R_EP": 2e7, "C_EP": 2e-8, "C_gap": 413e-12}
    freq = log_frequencies(1.0, 1e6, 61)
    z = np.asarray(compile_circuit(circuit)(params, freq))
    ds = make_spectrum(freq, z, attrs={"synthetic": "remaining impedance of a finger on a touchscreen, EDL parallel model"}, source="impedax demo")
    save(ds, out / "remaining_impedance.nc")
    save_figure(plot_spectrum(model=ds, title=f"synthetic remaining impedance: {circuit}"), out / "remaining_impedance.png")
    print(f"Simulated the EDL parallel model {circuit} (synthetic, C_gap = 413 pF) in {time.perf_counter() - t0:.2f} s")
    print(f"Wrote {out / 'remaining_impedance.nc'} and {out / 'remaining_impedance.png'}")
    return 0
