"""Write `tests/slow.txt`, the tests `make test` leaves to `make test-all`, from a timed run.

    make test-all PYTEST_ARGS='--durations=0' > durations.log
    python tests/slow_list.py durations.log --seconds 2 --whole-file-setup 20 \\
        --timed 'the whole suite, 2 cores, DATE' > tests/slow.txt

A test whose call took at least ``--seconds`` goes to the list; so does every test of a file
whose module fixtures took at least ``--whole-file-setup`` seconds to set up (a costly fixture
is paid by whichever of its tests runs first, so listing only that test would move its cost to
the next). Tests marked ``@pytest.mark.slow`` in their file stay slow whatever the list says.
"""

import argparse
import collections
import re
import sys

DURATION = re.compile(r"^([\d.]+)s (setup|call|teardown)\s+(\S+)$")


def slow_ids(log_lines, seconds: float, whole_file_setup: float) -> tuple[list[str], list[str]]:
    """(whole files, single test ids) to mark slow, from pytest's ``--durations=0`` lines."""
    call = collections.defaultdict(float)
    setup_by_file = collections.defaultdict(float)
    for line in log_lines:
        match = DURATION.match(line.strip())
        if match is None:
            continue
        duration, phase, node_id = float(match.group(1)), match.group(2), match.group(3)
        if phase == "call":
            call[node_id] += duration
        elif phase == "setup":
            setup_by_file[node_id.split("::")[0]] += duration
    files = sorted(f for f, total in setup_by_file.items() if total >= whole_file_setup)
    tests = sorted(n for n, duration in call.items() if duration >= seconds and n.split("::")[0] not in files)
    return files, tests


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("log", help="output of a pytest run with --durations=0")
    parser.add_argument("--seconds", type=float, default=2.0)
    parser.add_argument("--whole-file-setup", type=float, default=20.0)
    parser.add_argument("--timed", default="", help="where and when the run was timed, for the list's header")
    args = parser.parse_args(argv)
    with open(args.log, encoding="utf-8") as log:
        files, tests = slow_ids(log, args.seconds, args.whole_file_setup)
    print(f"# Tests `make test` leaves to `make test-all` (made by tests/slow_list.py: calls of at least {args.seconds:g} s,")
    print(f"# and whole files whose module fixtures take at least {args.whole_file_setup:g} s to set up).")
    if args.timed:
        print(f"# Timed: {args.timed}.")
    print("# One pytest node id or test file per line; tests/conftest.py marks them slow.")
    for line in files + tests:
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
