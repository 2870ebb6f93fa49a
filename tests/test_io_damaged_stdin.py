"""Damaged data piped in with '-': named as standard input, not as a file."""

import subprocess
import sys


def test_empty_standard_input_is_named_so():
    """Nothing piped in (the command before '|' wrote nothing): one line saying standard input
    is empty, exit 2; not '<stdin>: file is empty', which has the user look for a file."""
    run = subprocess.run([sys.executable, "-m", "impedax", "inspect", "-"], input=b"", capture_output=True, timeout=300)
    err = run.stderr.decode()
    assert run.returncode == 2 and err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith("impedax inspect: error: <stdin>: standard input is empty") and "file is empty" not in err
