"""Write `tests/slow.txt`, the tests `make test` leaves to `make test-all`, from a timed run.

    make test PYTEST_ARGS='--durations=0' > durations.log
    python tests/slow_list.py durations.log --seconds 1.5 --whole-file-setup 15 \\
        --keep tests/slow.txt --timed 'make test, 2 cores, DATE' > slow.txt && mv slow.txt tests/

Repeat until `make test` is short enough: a test left out hands the compilation it paid for to
the next test of its file, which may then cross the line.

A test whose call took at least ``--seconds`` goes to the list; so does every test of a file
whose module fixtures took at least ``--whole-file-setup`` seconds to set up (a costly fixture
is paid by whichever of its tests runs first, so listing only that test would move its cost to
the next). Tests marked ``@pytest.mark.slow`` in their file stay slow whatever the list says.
"""

import argparse
import collections
import re
import sys

DURATION = re.compile(r"^([\d.]+)s (setup|call|teardown)\s+(.+)$")

NEVER_SLOW = ("tests/test_architecture.py",)
"""Files kept in `make test` whatever their tests take: the architecture checks (import cycles,
private names) guard every change, in ~3 s. Listed slow from 2026-12-02, they let an import
cycle land on 2026-12-03 that only `make test-all` saw."""


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
    files = sorted(f for f, total in setup_by_file.items() if total >= whole_file_setup and f not in NEVER_SLOW)
    tests = sorted(n for n, duration in call.items() if duration >= seconds and n.split("::")[0] not in files and n.split("::")[0] not in NEVER_SLOW)
    return files, tests


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("log", help="output of a pytest run with --durations=0")
    parser.add_argument("--seconds", type=float, default=1.5)
    parser.add_argument("--whole-file-setup", type=float, default=15.0)
    parser.add_argument("--keep", help="a list to add to (its entries stay listed)")
    parser.add_argument("--timed", default="", help="where and when the run was timed, for the list's header")
    args = parser.parse_args(argv)
    with open(args.log, encoding="utf-8") as log:
        files, tests = slow_ids(log, args.seconds, args.whole_file_setup)
    timings = []
    if args.keep:  # its entries, and the runs it was made from
        with open(args.keep, encoding="utf-8") as kept:
            lines = [line.strip() for line in kept if line.strip()]
        timings = [line for line in lines if line.startswith("# Timed:")]
        listed = [line for line in lines if not line.startswith("#")]
        files = sorted(set(files) | {entry for entry in listed if "::" not in entry and entry not in NEVER_SLOW})
        tests = sorted(t for t in set(tests) | {entry for entry in listed if "::" in entry} if t.split("::")[0] not in files and t.split("::")[0] not in NEVER_SLOW)
    print("# Tests `make test` leaves to `make test-all`, made by tests/slow_list.py from timed runs: the calls that took at")
    print("# least --seconds, and whole files whose module fixtures took at least --whole-file-setup seconds to set up.")
    timings.append(f"# Timed: {args.timed or 'a run'}; --seconds {args.seconds:g} --whole-file-setup {args.whole_file_setup:g}.")
    print(*timings, sep="\n")
    print("# One pytest node id or test file per line; tests/conftest.py marks them slow.")
    for line in files + tests:
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
