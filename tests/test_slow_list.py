"""tests/slow.txt names tests that exist, and tests/slow_list.py reads pytest's duration lines."""

import re
from pathlib import Path

from slow_list import slow_ids

TESTS = Path(__file__).parent


def test_every_listed_test_exists():
    listed = [line.strip() for line in (TESTS / "slow.txt").read_text().splitlines() if line.strip() and not line.startswith("#")]
    assert len(listed) == len(set(listed))
    for entry in listed:
        path, _, node = entry.partition("::")
        source = (TESTS.parent / path).read_text()
        if node:
            name = node.split("[")[0].split("::")[-1]
            assert re.search(rf"^\s*def {re.escape(name)}\(", source, flags=re.M), entry


def test_durations_with_spaces_setups_by_file_and_thresholds():
    log = """
============================== slowest durations ===============================
20.44s setup    tests/test_a.py::test_one[in memory]
3.10s call     tests/test_a.py::test_one[in memory]
2.00s call     tests/test_b.py::test_two[R1 || C1]
1.99s call     tests/test_b.py::test_three
9.00s setup    tests/test_b.py::test_two[R1 || C1]
7.00s setup    tests/test_b.py::test_three
0.50s teardown tests/test_c.py::test_four
""".splitlines()
    files, tests = slow_ids(log, seconds=2.0, whole_file_setup=15.0)
    assert files == ["tests/test_a.py", "tests/test_b.py"]  # 20.44 s; 9 + 7 = 16 s of setups
    assert tests == []  # (their tests go with their files)
    files, tests = slow_ids(log, seconds=2.0, whole_file_setup=25.0)
    assert files == [] and tests == ["tests/test_a.py::test_one[in memory]", "tests/test_b.py::test_two[R1 || C1]"]


def test_the_architecture_checks_never_go_to_the_slow_list():
    """An import cycle landed unseen while they were listed slow (2026-12-03): `make test` runs them."""
    log = """
3.00s call     tests/test_architecture.py::test_no_import_cycles
40.0s setup    tests/test_architecture.py::test_imports_run_one_way[x]
3.00s call     tests/test_b.py::test_two
""".splitlines()
    files, tests = slow_ids(log, seconds=2.0, whole_file_setup=15.0)
    assert files == [] and tests == ["tests/test_b.py::test_two"]
    listed = [line.strip() for line in (TESTS / "slow.txt").read_text().splitlines() if line.strip() and not line.startswith("#")]
    assert not [entry for entry in listed if entry.split("::")[0] == "tests/test_architecture.py"]
