import os
import shutil
import tempfile

os.environ.setdefault("MPLBACKEND", "Agg")
# A compilation cache of this run's own, made by the first process (pytest itself, which starts
# the test processes of `make test`: they inherit it) and removed when the run ends. The signal
# tests kill processes that may be writing to it, and a half-written entry must never reach a
# user's cache or a later run. Every process of the run reads it (the CLI's subprocesses
# through IMPEDAX_CACHE_DIR, the test processes through JAX's config below), so a program one
# of them compiled is read, not compiled again, by the others and after `clear_caches`.
if "IMPEDAX_TEST_RUN_CACHE" not in os.environ:
    os.environ["IMPEDAX_TEST_RUN_CACHE"] = tempfile.mkdtemp(prefix="impedax-test-cache-")
_RUN_CACHE = os.environ["IMPEDAX_CACHE_DIR"] = os.environ["IMPEDAX_TEST_RUN_CACHE"]

import jax  # noqa: E402

jax.config.update("jax_enable_x64", True)
jax.config.update("jax_numpy_rank_promotion", "raise")
jax.config.update("jax_compilation_cache_dir", _RUN_CACHE)
jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.2)

import numpy as np  # noqa: E402
import pytest  # noqa: E402


_SLOW_LIST = os.path.join(os.path.dirname(__file__), "slow.txt")


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    """Mark slow the tests and files `tests/slow.txt` lists (the longest of the suite, timed by
    tests/slow_list.py), before `-m 'not slow'` leaves them to `make test-all`."""
    with open(_SLOW_LIST, encoding="utf-8") as listing:
        listed = {line.strip() for line in listing if line.strip() and not line.startswith("#")}
    for item in items:
        if item.nodeid in listed or item.nodeid.split("::")[0] in listed:
            item.add_marker(pytest.mark.slow)


@pytest.fixture(autouse=True, scope="module")
def _release_compiled_programs():
    """Each compiled program keeps its machine code in memory maps, and Linux allows a process
    65,530 of them: the whole suite in one process would pass that limit (XLA then crashes while
    compiling), so every test module's programs are released when it ends, and so are the
    figures it left open."""
    yield
    import sys

    import impedax

    impedax.clear_caches()
    if "matplotlib.pyplot" in sys.modules:  # (figures a module left open: past 20, pyplot warns in whichever test comes next)
        sys.modules["matplotlib.pyplot"].close("all")


@pytest.fixture
def rng():
    return np.random.default_rng(20261121)


def pytest_sessionfinish(session):
    if not hasattr(session.config, "workerinput"):  # the first process (not a test process of xdist)
        shutil.rmtree(_RUN_CACHE, ignore_errors=True)
