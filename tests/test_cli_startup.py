"""``impedax --version`` and ``impedax --help`` answer without importing NumPy or JAX (issue 14:
≤ 0.3 s; they imported NumPy through the commands' shared helpers, 0.3–0.4 s a call on the
2-core machine, 0.08 s without). Checked by the modules a fresh interpreter holds after the
call, not by timing it."""

import subprocess
import sys

import pytest

PROBE = """
import sys
from impedax.cli import main
try:
    main({argv!r})
except SystemExit as exc:
    code = exc.code
print("CODE", code, file=sys.stderr)
print("HEAVY", sorted(m for m in ("numpy", "jax", "xarray", "scipy", "matplotlib") if m in sys.modules), file=sys.stderr)
"""


def _run(argv: list[str]) -> tuple[str, str]:
    done = subprocess.run([sys.executable, "-c", PROBE.format(argv=argv)], capture_output=True, text=True, timeout=120)
    return done.stdout, done.stderr


@pytest.mark.parametrize("argv, code, shows", [
    (["--version"], "0", "impedax 0."),
    (["--help"], "0", "refine"),
    ([], "2", "usage: impedax"),
    (["fitt"], "2", "did you mean fit?"),
])
def test_version_help_and_a_missing_command_import_no_numerics(argv, code, shows):
    out, err = _run(argv)
    assert f"CODE {code}" in err, err
    assert shows in out + err
    assert "HEAVY []" in err, err
