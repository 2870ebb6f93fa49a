"""What read-only results cost on a batch of 1,000 SYNTHETIC spectra (docs/fitting.md,
"Results are read-only"): the fit's time against the copy a result takes of its arrays when it
is built (`impedax.fitting.frozen.read_only_dataset`, run by the constructor) and the copy
``to_xarray`` hands out.

    python benchmarks/bench_frozen_results.py
"""

from __future__ import annotations

import time

import numpy as np

import impedax as ix

N_SPECTRA, N_FREQ = 1000, 50
MODEL = "R0 + R1 || C1"


def best_of(fn, repeats: int = 5) -> float:
    """The shortest of ``repeats`` wall-clock times of ``fn()`` [s]."""
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def main() -> None:
    rng = np.random.default_rng(0)
    freq = np.geomspace(1e-1, 1e5, N_FREQ)
    r0, r1, c1 = 100 * rng.uniform(0.5, 2, N_SPECTRA), 1e4 * rng.uniform(0.5, 2, N_SPECTRA), 1e-6 * rng.uniform(0.5, 2, N_SPECTRA)
    omega = 2 * np.pi * freq
    z = r0[:, None] + r1[:, None] / (1 + 1j * omega * r1[:, None] * c1[:, None])
    z = z * (1 + 0.002 * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape)))
    data = ix.make_spectrum(freq, z, dims="cell", coords={"cell": np.arange(N_SPECTRA)})
    ix.fit(MODEL, data.isel(cell=slice(0, 2)))  # (compiled outside the timing)
    t = time.perf_counter()
    batch = ix.fit(MODEL, data)
    fit_s = time.perf_counter() - t
    to_xarray_s = best_of(batch.to_xarray)
    print(f"fit of {N_SPECTRA} SYNTHETIC spectra × {N_FREQ} points: {fit_s:.2f} s")
    print(f"to_xarray: {to_xarray_s * 1e3:.2f} ms ({to_xarray_s / fit_s:.2%} of the fit)")
    try:
        from impedax.fitting.frozen import read_only_dataset
    except ImportError:  # (before results were read-only)
        return
    editable = batch.to_xarray()
    freeze_s = best_of(lambda: read_only_dataset(editable))
    print(f"the constructor's read-only copy: {freeze_s * 1e3:.2f} ms ({freeze_s / fit_s:.2%} of the fit)")


if __name__ == "__main__":
    main()
