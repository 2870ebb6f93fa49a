"""Programs kept across processes (`impedax.fitting.stored`): a stored program gives what the
jitted function gives, a second `StoredProgram` (as in a fresh process) reads it back without
tracing, keys tell apart what traces differently, and a broken file or a user's function
never yields a wrong program."""

import os
import subprocess
import sys
import textwrap

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import impedax as ix
from impedax.fitting import stored
from impedax.fitting.least_squares.candidates import fit_candidates
from impedax.fitting.least_squares.solvers import over_devices
from impedax.fitting.stored import StoredProgram


@pytest.fixture
def cache_dir(tmp_path):
    """JAX's persistent cache (and so the stored programs) in a directory of this test."""
    before = jax.config.jax_compilation_cache_dir
    jax.config.update("jax_compilation_cache_dir", str(tmp_path))
    yield tmp_path / stored._SUBDIR
    jax.config.update("jax_compilation_cache_dir", before)


def _counted():
    """A function that records every trace of itself, and its NumPy oracle."""
    traces = []

    def fn(x, pair):
        traces.append(1)
        y, scale = pair
        return {"sum": x * scale + jnp.sum(y), "norm": (jnp.sqrt(jnp.sum(x**2)),)}

    def oracle(x, pair):
        y, scale = pair
        return {"sum": x * scale + np.sum(y), "norm": (np.sqrt(np.sum(x**2)),)}

    return fn, oracle, traces


def _close(a, b):
    for u, v in zip(jax.tree_util.tree_leaves(a), jax.tree_util.tree_leaves(b)):
        np.testing.assert_allclose(np.asarray(u), v, rtol=1e-15, atol=0)


def test_read_back_without_tracing_and_same_values(cache_dir):
    fn, oracle, traces = _counted()
    x, pair = np.arange(5.0), (np.ones(3) * 0.5, np.float64(3.0))
    first = StoredProgram("test-counted", ("config", 1), jax.jit(fn))(x, pair)
    assert len(traces) == 1
    assert len(list(cache_dir.glob("test-counted-*.bin"))) == 1
    jax.clear_caches()  # JAX's own in-memory cache of traces, as in a fresh process
    again = StoredProgram("test-counted", ("config", 1), jax.jit(fn))
    second = again(x, pair)
    assert len(traces) == 1  # read from the file, not traced
    _close(first, oracle(x, pair))
    _close(second, oracle(x, pair))
    assert isinstance(second["norm"], tuple)  # the output's tree comes back


def test_keys_tell_apart_static_values_and_shapes(cache_dir):
    fn, oracle, traces = _counted()
    pair = (np.ones(3), np.float64(2.0))
    StoredProgram("test-keys", ("config", 1), jax.jit(fn))(np.arange(4.0), pair)
    StoredProgram("test-keys", ("config", 2), jax.jit(fn))(np.arange(4.0), pair)
    out = StoredProgram("test-keys", ("config", 1), jax.jit(fn))(np.arange(6.0), pair)
    assert len(list(cache_dir.glob("test-keys-*.bin"))) == 3
    _close(out, oracle(np.arange(6.0), pair))


def test_a_broken_file_is_replaced(cache_dir):
    fn, oracle, traces = _counted()
    x, pair = np.arange(3.0), (np.zeros(2), np.float64(1.0))
    StoredProgram("test-broken", 0, jax.jit(fn))(x, pair)
    (path,) = cache_dir.glob("test-broken-*.bin")
    blob = path.read_bytes()
    path.write_bytes(blob[: len(blob) // 2])  # cut short, as by a killed process
    jax.clear_caches()
    out = StoredProgram("test-broken", 0, jax.jit(fn))(x, pair)
    _close(out, oracle(x, pair))
    assert len(traces) == 2  # traced again, and stored again
    jax.clear_caches()
    StoredProgram("test-broken", 0, jax.jit(fn))(x, pair)  # the rewritten file is read
    assert len(traces) == 2


def test_without_a_persistent_cache_nothing_is_stored(tmp_path):
    before = jax.config.jax_compilation_cache_dir
    jax.config.update("jax_compilation_cache_dir", None)
    try:
        fn, oracle, traces = _counted()
        x, pair = np.arange(3.0), (np.zeros(2), np.float64(1.0))
        _close(StoredProgram("test-none", 0, jax.jit(fn))(x, pair), oracle(x, pair))
    finally:
        jax.config.update("jax_compilation_cache_dir", before)
    assert not any(tmp_path.rglob("*.bin"))


def user_formula(p, w):
    return p * w


def test_a_function_from_outside_impedax_is_not_stored(cache_dir):
    """A user's element formula may read globals of their script that no key could see: such
    programs are jitted in every process, never read from a file."""
    fn, oracle, traces = _counted()
    x, pair = np.arange(3.0), (np.zeros(2), np.float64(1.0))
    for _ in range(2):
        _close(StoredProgram("test-user", (user_formula,), jax.jit(fn))(x, pair), oracle(x, pair))
    assert not list(cache_dir.glob("test-user-*.bin"))
    assert stored._stable_repr((ix.fit,)) == stored._stable_repr((ix.fit,))
    with pytest.raises(stored._NotStorable):
        stored._stable_repr({"spec": user_formula})


def test_stable_repr_has_no_addresses_and_sees_every_field():
    from impedax.circuits import DEFAULT_REGISTRY, parse

    text = stored._stable_repr((parse("R0 + Q1 || C1"), DEFAULT_REGISTRY))
    assert " at 0x" not in text
    assert "symbol='Q'" in text  # a field the circuit's own repr leaves out
    assert stored._stable_repr(np.arange(3.0)) != stored._stable_repr(np.arange(3.0) + 1e-12)


def test_a_program_on_every_device_reads_back(cache_dir):
    """`solvers.over_devices` programs (sharded over the devices) round-trip too."""

    def per_device(x, y):
        return x * 2.0 + jnp.sum(y)

    n = len(jax.devices())
    x, y = np.arange(4.0 * n).reshape(n, 4), np.ones(3)
    run, _ = over_devices(per_device, 1, stored=("test-devices", "v1"))
    first = np.asarray(run(x, y))
    over_devices.cache_clear()
    run, _ = over_devices(per_device, 1, stored=("test-devices", "v1"))
    np.testing.assert_array_equal(np.asarray(run(x, y)), x * 2.0 + 3.0)
    np.testing.assert_array_equal(first, x * 2.0 + 3.0)
    assert len(list(cache_dir.glob("test-devices-*.bin"))) == 1


@pytest.mark.slow  # (13 s; the suite's budget)
def test_fits_are_the_same_with_and_without_stored_programs(cache_dir, rng):
    """A single fit and the diagnosis' candidate fits, through stored programs (written, then
    read back after the in-memory caches are cleared) and through plain jit: equal values."""
    f = np.logspace(-1, 5, 40)
    w = 2 * np.pi * f
    z = 20 + 1e3 / (1 + 1e3 * 1e-6 * (1j * w) ** 0.8)
    z = z * (1 + 0.005 * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)))
    data = ix.make_spectrum(f, z)

    def run():
        fit = ix.fit("R0 + R1 || CPE1", data)
        (cand,) = fit_candidates(["R0 + R1 || C1"], data, n_starts=3)
        return fit.values, cand.values

    written = run()
    ix.clear_caches()
    read = run()
    assert len(list(cache_dir.glob("fit-single-*.bin"))) == 1
    assert len(list(cache_dir.glob("candidate-queue-*.bin"))) == 1
    jax.config.update("jax_compilation_cache_dir", None)
    ix.clear_caches()
    plain = run()
    for a, b, c in zip(written, read, plain):
        for name in a:
            assert a[name] == b[name] == c[name], name


def test_a_fresh_process_does_not_trace_a_stored_program(tmp_path):
    code = textwrap.dedent(
        """
        import jax, jax.numpy as jnp, numpy as np, sys
        jax.config.update("jax_enable_x64", True)
        jax.config.update("jax_compilation_cache_dir", sys.argv[1])
        from impedax.fitting.stored import StoredProgram

        def fn(x):
            print("traced")
            return jnp.cumsum(x) * 2.0

        print(StoredProgram("test-process", 0, jax.jit(fn))(np.arange(4.0)).tolist())
        """
    )
    outputs = [subprocess.run([sys.executable, "-c", code, str(tmp_path)], capture_output=True, text=True, timeout=120, env=dict(os.environ)) for _ in range(2)]
    for out in outputs:
        assert out.returncode == 0, out.stderr
        assert out.stdout.splitlines()[-1] == "[0.0, 2.0, 6.0, 12.0]"
    assert "traced" in outputs[0].stdout
    assert "traced" not in outputs[1].stdout


def test_compiler_options_reach_the_stored_program_and_the_jitted_one(cache_dir):
    """A program compiled with `stored.QUICK_COMPILE` (as the single-fit solvers are) is still
    exported, read back without tracing, and gives the oracle's values, stored or not."""
    fn, oracle, traces = _counted()
    x, pair = np.linspace(-1.0, 2.0, 7), (np.arange(4.0), np.float64(-1.5))
    first = StoredProgram("test-quick", 0, fn, compiler_options=stored.QUICK_COMPILE)(x, pair)
    assert len(list(cache_dir.glob("test-quick-*.bin"))) == 1  # an export that failed would fall back to plain jit
    jax.clear_caches()
    second = StoredProgram("test-quick", 0, fn, compiler_options=stored.QUICK_COMPILE)(x, pair)
    assert len(traces) == 1
    jax.config.update("jax_compilation_cache_dir", None)
    plain = StoredProgram("test-quick", 0, fn, compiler_options=stored.QUICK_COMPILE)(x, pair)
    for out in (first, second, plain):
        _close(out, oracle(x, pair))


def test_an_entry_is_replaced_by_a_rename_never_written_through_a_link(tmp_path):
    """A cache entry is not a user's output (`impedax.io.atomic`): a link at its name (one
    planted in a shared cache folder) is replaced by the entry, the file it points to is left
    alone, and the entry is private to its owner, as `tempfile.mkstemp` makes it."""
    import pickle

    victim = tmp_path / "elsewhere" / "notes.txt"
    victim.parent.mkdir()
    victim.write_text("mine")
    entry = tmp_path / "cache" / "key.bin"
    entry.parent.mkdir()
    entry.symlink_to(victim)
    stored._write(entry, ("blob", "tree"))
    assert not entry.is_symlink() and victim.read_text() == "mine"
    assert pickle.loads(entry.read_bytes()) == ("blob", "tree")
    assert entry.stat().st_mode & 0o777 == 0o600
    entry.chmod(0o400)  # a read-only entry is replaced too: the cache never refuses
    stored._write(entry, ("new", "tree"))
    assert pickle.loads(entry.read_bytes()) == ("new", "tree")


def test_an_interrupted_write_leaves_no_temporary_file(tmp_path, monkeypatch):
    """Before: only an `Exception` removed the temporary file, so Ctrl-C (or SIGTERM's
    `Interrupted`, a KeyboardInterrupt) during the dump left a ``.tmp`` file in the cache."""
    import pickle

    def interrupted(obj, fh):
        fh.write(b"half")
        raise KeyboardInterrupt

    monkeypatch.setattr(pickle, "dump", interrupted)
    with pytest.raises(KeyboardInterrupt):
        stored._write(tmp_path / "key.bin", ("blob", "tree"))
    assert list(tmp_path.iterdir()) == []
    monkeypatch.setattr(pickle, "dump", lambda obj, fh: (_ for _ in ()).throw(OSError(28, "No space left on device")))
    stored._write(tmp_path / "key.bin", ("blob", "tree"))  # a failure is not an error
    assert list(tmp_path.iterdir()) == []


def _rc_log_prob():
    """SYNTHETIC R0 + R1 || C1 (10 Ω, 1 kΩ, 1 µF) at 12 frequencies with a known σ of 1 % of |Z|,
    every parameter sampled as ln x under a flat prior: the structure, the arrays, and the
    closed-form log-posterior in y = ln x (Gaussian log-likelihood + the Jacobian Σ y)."""
    from impedax.circuits import DEFAULT_REGISTRY, parse
    from impedax.fitting.bayes.logprob import LogProbArgs, LogProbStructure

    freq = np.geomspace(1.0, 1e5, 12)
    w = 2 * np.pi * freq

    def z_of(x):
        r0, r1, c1 = x
        return r0 + r1 / (1 + 1j * w * r1 * c1)

    truth = np.array([10.0, 1e3, 1e-6])
    sigma = 0.01 * np.abs(z_of(truth))
    rng = np.random.default_rng(11)
    data = z_of(truth) + sigma * (rng.standard_normal(freq.size) + 1j * rng.standard_normal(freq.size))
    st = LogProbStructure(circuit=parse("R0 + R1 || C1"), registry=DEFAULT_REGISTRY, circuit_names=("R0", "R1", "C1"), direct_index=(0, 1, 2),
                          reparametrization=None, reparam_index=(), sigma_index=-1, log_scale=(True, True, True))
    lo, hi = np.array([1e-3, 1e-1, 1e-10]), np.array([1e4, 1e6, 1e-2])
    args = LogProbArgs(freq=jnp.asarray(freq), z=jnp.asarray(data), scale=jnp.asarray(sigma), fixed=jnp.ones(3), code=jnp.zeros(3, jnp.int32),
                       a=jnp.asarray(lo), b=jnp.asarray(hi), lo=jnp.asarray(lo), hi=jnp.asarray(hi), log_norm=jnp.zeros(3))

    def oracle(y):
        r = z_of(np.exp(y)) - data
        return -0.5 * np.sum((r.real**2 + r.imag**2) / sigma**2) - np.sum(2 * np.log(sigma) + np.log(2 * np.pi)) - np.sum(np.log(hi - lo)) + np.sum(y)

    return st, args, oracle, np.log(truth)


def _hessian_by_differences(f, y, h=1e-4):
    """Central second differences of ``f`` at ``y`` (NumPy), step ``h`` in ln x."""
    n = y.size
    out = np.empty((n, n))
    for i in range(n):
        for j in range(n):
            e_i, e_j = np.eye(n)[i] * h, np.eye(n)[j] * h
            out[i, j] = (f(y + e_i + e_j) - f(y + e_i - e_j) - f(y - e_i + e_j) + f(y - e_i - e_j)) / (4 * h * h)
    return out


def test_the_bayesian_programs_are_stored_and_read_back_without_tracing(cache_dir, monkeypatch):
    """`impedax sample` traced the Laplace evidence's Hessian (and the other log-probability
    programs) in every fresh process, ~2 s (2026-12-06): they are stored programs now. A second
    set of functions, as in a fresh process, reads all five from their files; tracing would call
    `_pointwise_loglik`, which here refuses. Oracle: the closed-form log-posterior in NumPy."""
    from impedax.fitting.bayes import logprob

    st, args, oracle, y = _rc_log_prob()
    walkers = y + 0.01 * np.random.default_rng(2).standard_normal((8, 3))

    def every(functions):
        log_prob = logprob.walkers_log_prob(functions.batched, args)
        return (np.asarray(functions.single(jnp.asarray(y), args)), np.asarray(functions.value_and_grad(jnp.asarray(y), args)[0]),
                np.asarray(functions.hessian(jnp.asarray(y), args)), log_prob(walkers), np.asarray(functions.batched(jnp.asarray(walkers), args)),
                np.asarray(functions.pointwise(jnp.asarray(walkers), args)))

    logprob.log_prob_functions.cache_clear()
    first = every(logprob.log_prob_functions(st))
    for name in ("single", "value-and-grad", "hessian", "batched", "pointwise"):
        assert len(list(cache_dir.glob(f"bayes-{name}-*.bin"))) == 1, name
    logprob.log_prob_functions.cache_clear()
    jax.clear_caches()  # (JAX's in-memory traces, as in a fresh process)

    def refuse(*a, **k):
        raise AssertionError("traced again")

    monkeypatch.setattr(logprob, "_pointwise_loglik", refuse)
    again = every(logprob.log_prob_functions(st))
    logprob.log_prob_functions.cache_clear()  # (functions of the refusing trace are never kept)
    single, value, hessian, walkers_lp, batched, pointwise = again
    assert single == pytest.approx(oracle(y), rel=1e-12) and value == pytest.approx(oracle(y), rel=1e-12)
    np.testing.assert_allclose(walkers_lp, [oracle(w) for w in walkers], rtol=1e-12)
    np.testing.assert_allclose(batched, walkers_lp, rtol=1e-15)
    np.testing.assert_allclose(pointwise.sum(axis=1), walkers_lp - (np.sum(walkers, axis=1) - float(np.sum(np.log(np.asarray(args.hi) - np.asarray(args.lo))))), rtol=1e-12)
    np.testing.assert_allclose(hessian, _hessian_by_differences(oracle, y), rtol=1e-4, atol=1e-6 * np.abs(hessian).max())
    for a, b in zip(first, again):
        np.testing.assert_allclose(a, b, rtol=1e-15)


def test_the_joint_posteriors_programs_are_stored_and_read_back_without_tracing(cache_dir, monkeypatch):
    """`impedax sample --shared` traced its joint log-posterior (batched and single) in every fresh
    process (2026-12-06): stored programs now, read back by a second set of functions without
    tracing (a tracing would call the refusing `prior_log_density`). Oracle: the joint
    log-posterior of two SYNTHETIC R0 + R1 || C1 spectra (R0 shared) written out in NumPy."""
    from impedax.circuits import DEFAULT_REGISTRY, parse
    from impedax.fitting.bayes import logprob, shared_posterior

    freq = np.geomspace(1.0, 1e5, 10)
    w = 2 * np.pi * freq
    truth = [(10.0, 1e3, 1e-6), (10.0, 2e3, 5e-7)]
    z_true = np.array([r0 + r1 / (1 + 1j * w * r1 * c1) for r0, r1, c1 in truth])
    sigma = 0.01 * np.abs(z_true)
    rng = np.random.default_rng(12)
    data = z_true + sigma * (rng.standard_normal(z_true.shape) + 1j * rng.standard_normal(z_true.shape))
    lo, hi = np.full(5, 1e-12), np.full(5, 1e12)
    st = shared_posterior._Structure(parse("R0 + R1 || C1"), DEFAULT_REGISTRY, 2, (0,), (1, 2), False, (True,) * 5)
    args = {"freq": jnp.asarray(freq), "z": jnp.asarray(data), "scale": jnp.asarray(sigma), "fixed": jnp.ones(3), "code": jnp.zeros(5, jnp.int32),
            "a": jnp.asarray(lo), "b": jnp.asarray(hi), "lo": jnp.asarray(lo), "hi": jnp.asarray(hi), "log_norm": jnp.zeros(5)}

    def oracle(y):  # y = ln(R0, R1_a, C1_a, R1_b, C1_b)
        r0, r1a, c1a, r1b, c1b = np.exp(y)
        model = np.array([r0 + r1 / (1 + 1j * w * r1 * c1) for r1, c1 in ((r1a, c1a), (r1b, c1b))])
        r = model - data
        return float(np.sum(-0.5 * (r.real**2 + r.imag**2) / sigma**2 - 2 * np.log(sigma) - np.log(2 * np.pi)) - np.sum(np.log(hi - lo)) + np.sum(y))

    centre = np.log([10.0, 1e3, 1e-6, 2e3, 5e-7])
    walkers = centre + 0.01 * np.random.default_rng(3).standard_normal((6, 5))
    shared_posterior._log_prob_functions.cache_clear()
    batched, single = shared_posterior._log_prob_functions(st)
    first = (logprob.walkers_log_prob(batched, args)(walkers), float(single(jnp.asarray(centre), args)))
    assert len(list(cache_dir.glob("bayes-shared-batched-*.bin"))) == len(list(cache_dir.glob("bayes-shared-single-*.bin"))) == 1
    shared_posterior._log_prob_functions.cache_clear()
    jax.clear_caches()

    def refuse(*a, **k):
        raise AssertionError("traced again")

    monkeypatch.setattr(shared_posterior, "prior_log_density", refuse)
    batched, single = shared_posterior._log_prob_functions(st)
    again = (logprob.walkers_log_prob(batched, args)(walkers), float(single(jnp.asarray(centre), args)))
    shared_posterior._log_prob_functions.cache_clear()
    np.testing.assert_allclose(again[0], [oracle(y) for y in walkers], rtol=1e-12)
    assert again[1] == pytest.approx(oracle(centre), rel=1e-12)
    np.testing.assert_allclose(first[0], again[0], rtol=1e-15)
