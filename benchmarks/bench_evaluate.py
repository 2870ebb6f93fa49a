"""Evaluations per second of a compiled 10-element circuit at 100 frequencies.

Run: `.venv/bin/python benchmarks/bench_evaluate.py`. Prints a table; figures go to
benchmarks/README.md. Timings are wall-clock medians on this machine, after compilation.
"""

from __future__ import annotations

from functools import partial

import jax
import jax.numpy as jnp
import numpy as np

import impedax as ix
from impedax.circuits import CircuitProgram, evaluate_program
from _timing import median_time

CIRCUIT = "R0 + R1 || CPE1 + R2 || C2 + (R3 + W3) || CPE3 + L4 + Wo5"  # 10 elements
FREQ = jnp.geomspace(1e-1, 1e6, 100)
BATCH = 10_000


def main() -> list[tuple[str, float]]:
    circuit = ix.parse(CIRCUIT)
    compiled = ix.compile_circuit(circuit)
    names = circuit.parameter_names()
    assert len(list(circuit.elements())) == 10
    rng = np.random.default_rng(0)
    params = {n: (0.8 if n.endswith("alpha") else float(10 ** rng.uniform(-6, 3))) for n in names}
    batch = {n: jnp.asarray(v * rng.uniform(0.5, 1.5, BATCH)) for n, v in params.items()}

    single = jax.jit(compiled)
    vmapped = jax.jit(jax.vmap(compiled, in_axes=(0, None)))
    prog = CircuitProgram.build(circuit)
    arrays = prog.arrays()
    theta = jnp.asarray(prog.pack(params))
    evaluate = partial(evaluate_program, layout=prog.layout)
    prog_single = jax.jit(evaluate)
    thetas = jnp.asarray(np.stack([prog.pack({n: float(batch[n][i]) for n in names}) for i in range(1000)]))
    prog_vmapped = jax.jit(jax.vmap(evaluate, in_axes=(None, 0, None)))

    rows = []
    t = median_time(lambda: single(params, FREQ), 7, number=200, warmup=True, block=jax.block_until_ready)
    rows.append(("compiled tree, one parameter set", 1.0 / t))
    t = median_time(lambda: vmapped(batch, FREQ), 5, warmup=True, block=jax.block_until_ready)
    rows.append((f"compiled tree, vmapped over {BATCH:,}", BATCH / t))
    t = median_time(lambda: prog_single(arrays, theta, FREQ), 7, number=200, warmup=True, block=jax.block_until_ready)
    rows.append(("padded program, one parameter set", 1.0 / t))
    t = median_time(lambda: prog_vmapped(arrays, thetas, FREQ), 5, warmup=True, block=jax.block_until_ready)
    rows.append(("padded program, vmapped over 1,000", 1000 / t))
    # value and Jacobian ∂Z/∂θ (what a least-squares step needs): analytic vs forward mode
    thetas_tree = jnp.stack([batch[n][:1000] for n in names], axis=1)
    analytic = jax.jit(jax.vmap(lambda th: compiled.value_and_jacobian(th, FREQ)))
    forward = jax.jit(jax.vmap(lambda th: (compiled.vector(th, FREQ), jax.jacfwd(lambda t: jnp.stack([compiled.vector(t, FREQ).real, compiled.vector(t, FREQ).imag]))(th))))
    t = median_time(lambda: analytic(thetas_tree), 5, warmup=True, block=jax.block_until_ready)
    rows.append(("value + Jacobian, analytic, vmapped 1,000", 1000 / t))
    t = median_time(lambda: forward(thetas_tree), 5, warmup=True, block=jax.block_until_ready)
    rows.append(("value + Jacobian, forward mode, vmapped 1,000", 1000 / t))
    print(f"10-element circuit {CIRCUIT!r} at {FREQ.size} frequencies, {jax.devices()[0].platform.upper()}")
    print(f"{'evaluation':<48} {'spectra / s':>14}")
    for name, rate in rows:
        print(f"{name:<48} {rate:>14,.0f}")
    return rows


if __name__ == "__main__":
    main()
