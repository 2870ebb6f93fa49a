import os
import tempfile

os.environ.setdefault("MPLBACKEND", "Agg")
# A compilation cache of the suite's own: the signal tests kill processes that may be writing
# to it, and a half-written entry must never reach a user's cache (or a later run).
os.environ["IMPEDAX_CACHE_DIR"] = tempfile.mkdtemp(prefix="impedax-test-cache-")

import jax  # noqa: E402

jax.config.update("jax_enable_x64", True)
jax.config.update("jax_numpy_rank_promotion", "raise")

import numpy as np  # noqa: E402
import pytest  # noqa: E402


@pytest.fixture(autouse=True, scope="module")
def _release_compiled_programs():
    """Each compiled program keeps its machine code in memory maps, and Linux allows a process
    65,530 of them: the whole suite in one process would pass that limit (XLA then crashes while
    compiling), so every test module's programs are released when it ends."""
    yield
    import impedax

    impedax.clear_caches()


@pytest.fixture
def rng():
    return np.random.default_rng(20261121)
