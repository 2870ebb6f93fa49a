"""Every ```python block of README.md and docs/*.md runs as written and prints what its comments
say.

How the blocks run: the blocks of one page run in the page's order in one namespace, in one
empty folder of the page's (the working directory while they run), as a reader who copies a page
from its top runs them: a block may use what an earlier block of its page made (`data`,
`result`, ...). Each block is a test of its own (file, index and first line in its id); run
alone, a block's test first runs the earlier blocks of its page. Paths the docs give from the
repository's root (`tests/fixtures/real/...`, the REAL example files; `benchmarks/data/...`)
are reached through links to those folders in the page's folder. matplotlib draws with Agg;
`ix.use_compilation_cache` is replaced by a stub, as in tests/test_docs_claims.py (the real call
would point the whole test process's JAX cache at the reader's home).

What a block takes from its prose rather than from an earlier block (a file it names as the
reader's own, the batch the paragraph above it talks about) is made by `GIVEN`, short code run
before the block (SYNTHETIC data, or the shipped example), the two in a copy of the page's
namespace: what the block makes from its given data does not reach the later blocks, what it
imports does (bayesian.md's `derive` block works on the posterior of the page's first block, not
on the Meyer one just above it). `SKIP` names the
blocks that cannot run here or take half an hour, with the reason. Where a block's comment states a value it prints
or shows, `CHECKS` reads the value from the block's text and compares, to the digits written.

All of it is slow (fits, samplings, diagnoses and refinements from cold: ~15 min on the 2-core
machine under load, 2026-12-07), so the module is left to `make test-all`.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import numpy as np
import pytest

import impedax as ix

pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parent.parent
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def _blocks() -> list[tuple[str, int, str]]:
    """(page, index on its page, text) of every ```python block, in the pages' order."""
    found = []
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        for index, match in enumerate(re.finditer(r"^```python\n(.*?)^```", text, re.S | re.M)):
            found.append((page.relative_to(ROOT).as_posix(), index, match.group(1)))
    return found


BLOCKS = _blocks()

SKIP = {
    ("docs/fitting.md", 3): "connects to a reader's dask scheduler (Client('scheduler:8786'))",
    ("docs/migrating.md", 2): "patches impedance.py, which impedax's test environment does not install",
    ("docs/models.md", 1): "two gap analyses, hierarchical NUTS over the example's 30 trials: 1,465 s on the 2-core machine "
                           "under load (2026-12-07); tests/test_gap_*.py run gap_analysis",
}

# SYNTHETIC unless it says REAL; `spectra` is tests/spectra.py (numpy formulas, not impedax's compiler)
GIVEN = {
    # the batch over (voltage, repeat) the paragraph plots: R_s + R_p || CPE_p, CPE_p.Q falling with the voltage
    ("docs/fitting.md", 2): """
import spectra
freq = ix.log_frequencies(1.0, 1e5, 31)
voltage, repeat = [0.0, 100.0, 200.0, 300.0], [0, 1, 2]
q = [[2e-6 * (1 - v / 600) * (1 + 0.02 * r) for r in repeat] for v in voltage]
z = np.array([[10 + spectra.z_parallel(1e3, spectra.z_cpe(freq, qq, 0.85)) for qq in row] for row in q])
result = ix.fit("R_s + R_p || CPE_p", ix.make_spectrum(freq, z, dims=("voltage", "repeat"),
                coords={"voltage": voltage, "repeat": repeat}), progress=False)
""",
    # the reader's trials.nc: a touchscreen arc shared by 4 trials, a finger arc of each trial's own
    ("docs/fitting.md", 5): """
import spectra
freq = ix.log_frequencies(1.0, 1e5, 31)
z = [spectra.two_arcs(freq, {"R0": 100.0, "R1": 2e3, "CPE1.Q": 1e-8, "CPE1.alpha": 0.9,
                             "R2": 5e4 * k, "CPE2.Q": 1e-6, "CPE2.alpha": 0.8}) for k in (0.8, 1.0, 1.2, 1.4)]
ix.save(ix.make_spectrum(freq, np.array(z), dims="trial"), "trials.nc")
""",
    # a file of the reader's format: the signature line, then f [Hz], Z' [Ω], Z'' [Ω]
    ("docs/io.md", 0): """
Path("run.my").write_text("MYFORMAT\\n1000 100.0 -20.0\\n100 110.0 -50.0\\n10 150.0 -80.0\\n", encoding="utf-8")
""",
    # the reader's data/day1.csv ... day3.csv: R0 + R1 || CPE1, R1 growing by the day
    ("docs/io.md", 1): """
import spectra
Path("data").mkdir()
freq = ix.log_frequencies(1.0, 1e5, 31)
for day in (1, 2, 3):
    ix.save(ix.make_spectrum(freq, spectra.r_cpe(freq, {"R0": 20.0, "R1": 1e3 * day, "CPE1.Q": 1e-6, "CPE1.alpha": 0.9})),
            f"data/day{day}.csv")
""",
    # the circuit with R1, CPE1 and C_gap the priors are written for, and a spectrum of it
    ("docs/bayesian.md", 1): """
import spectra
freq = ix.log_frequencies(1.0, 1e6, 41)
circuit = "R0 + R1 || CPE1 || C_gap"
z = 100 + spectra.z_parallel(1e4, spectra.z_cpe(freq, 1e-8, 0.8), 1 / (2j * np.pi * freq * 4e-10))
noise = np.random.default_rng(1).standard_normal((2, freq.size))
data = ix.make_spectrum(freq, z * (1 + 0.005 * (noise[0] + 1j * noise[1])))
""",
    # the remaining impedance Z_R of the shipped example (sliding total minus skin and touchscreen)
    ("docs/bayesian.md", 2): """
from impedax.models import example_spectra, sirin
s = example_spectra()
remainder = sirin.remaining_impedance(s["total_sliding"], s["skin"], s["touchscreen"])
""",
    # Meyer's skin circuit at his thesis values, 0.5 % noise
    ("docs/bayesian.md", 3): """
import spectra
from impedax.models.meyer import THESIS_PARAMS
freq = ix.log_frequencies(1.0, 1e6, 41)
noise = np.random.default_rng(1).standard_normal((2, freq.size))
data = ix.make_spectrum(freq, spectra.meyer(freq, THESIS_PARAMS) * (1 + 0.005 * (noise[0] + 1j * noise[1])))
""",
    # Z over (trial, frequency): two arcs, R1, CPE1.Q, R2, CPE2.Q varying by trial, 0.5 % noise
    ("docs/bayesian.md", 5): """
import spectra
freq = ix.log_frequencies(0.1, 1e5, 31)
rng = np.random.default_rng(1)
z = []
for k in (0.9, 1.0, 1.1, 1.2):
    clean = spectra.two_arcs(freq, {"R0": 50.0, "R1": 500 * k, "CPE1.Q": 1e-7 / k, "CPE1.alpha": 0.9,
                                    "R2": 2e3 * k, "CPE2.Q": 1e-4 * k, "CPE2.alpha": 0.8})
    z.append(clean * (1 + 0.005 * (rng.standard_normal(freq.size) + 1j * rng.standard_normal(freq.size))))
data = ix.make_spectrum(freq, np.array(z), dims="trial")
""",
    # the files `impedax refine ... --out r.nc` and `impedax diagnose ... --out d.nc` write, of the page's first block
    ("docs/diagnosis.md", 3): 'ix.write_result(r, "r.nc"); ix.write_result(d, "d.nc")',
}


def _rounded(text: str) -> tuple[float, float]:
    """A number as written and half a unit of its last digit (what its rounding allows)."""
    mantissa = text.lower().split("e")[0]
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    exponent = int(text.lower().split("e")[1]) if "e" in text.lower() else 0
    return float(text), 0.5 * 10.0 ** (exponent - decimals)


def _close(value: float, written: str) -> bool:
    target, half = _rounded(written)
    return abs(value - target) <= half * (1 + 1e-9)


def _comment(block: str, code: str) -> str:
    """The comment of the block's line that holds ``code``."""
    line = next(line for line in block.splitlines() if code in line)
    return line.split("#", 1)[1].strip()


def _check_readme_names(block, scope, printed):
    assert printed[0] == str(eval(_comment(block, "print(circuit.parameter_names())")))


def _check_drt_peak(block, scope, printed):
    quoted = re.search(r'"(R = [^"]+)"', _comment(block, "print(result.report())")).group(1)
    assert quoted in printed[0], quoted


def _check_gerischer(block, scope, printed):
    for piece in _comment(block, "print(diagnosis.report())").split("..."):
        assert piece.strip() in printed[0], piece


def _check_sirin_gap(block, scope, printed):
    from impedax.models import sirin

    naive_words = _comment(block, "naive = ix.fit(")
    c_naive, u_naive, rms_naive = re.search(r"C_gap ≈ ([\d.]+) pF → u ≈ ([\d.]+) µm.*rms_rel ([\d.]+)", naive_words).groups()
    naive = scope["naive"]
    assert _close(1e12 * naive.values["C_gap"], c_naive)
    assert _close(1e6 * sirin.gap_thickness(naive.values["C_gap"], area=130e-6), u_naive)
    assert _close(naive.rms_rel, rms_naive)
    best = scope["d"].suggestions[0]
    assert repr(best.effect) == _comment(block, "d.suggestions[0].effect")
    assert repr(best.model) == _comment(block, "d.suggestions[0].model")
    c_best, u_best, rms_best = re.search(r"≈ ([\d.]+) pF → u ≈ ([\d.]+) µm.*rms_rel ([\d.]+)", _comment(block, 'fit.values["C_gap"]')).groups()
    assert _close(1e12 * best.fit.values["C_gap"], c_best)
    assert _close(1e6 * sirin.gap_thickness(best.fit.values["C_gap"], area=130e-6), u_best)
    assert _close(best.fit.rms_rel, rms_best)


def _check_impedance_py_numbers(block, scope, printed):
    value, stderr = _comment(block, 'print(unweighted.values["R0"]').split("(")[0].split()
    printed_value, printed_stderr = map(float, printed[0].split())
    assert _close(printed_value, value) and _close(printed_stderr, stderr)
    assert _close(float(printed[1]), _comment(block, 'print(by_modulus.values["R0"])').split()[0])


def _check_custom_element_names(block, scope, printed):
    assert printed[0] == _comment(block, "print(circuit.parameter_names(registry))")
    assert printed[1] == _comment(block, "print(circuit.to_impedance_py(registry))")


def _check_transmission_line_names(block, scope, printed):
    written = _comment(block, "fn = compile_circuit(").removeprefix("parameters ").split(", ")
    assert list(scope["fn"].parameter_names) == written


def _check_force_maximum(block, scope, printed):
    force, frequency = re.fullmatch(r"([\d.]+) N at ([\d.e+]+) Hz", _comment(block, "peak = force_maximum(")).groups()
    assert _close(scope["peak"].force_n, force) and _close(scope["peak"].frequency_hz, frequency)


def _check_result_rows(block, scope, printed):
    first = scope["rows"][0]
    name, value = re.search(r"\[\{'name': '(\w+)', 'value': '([\d.]+)…'", _comment(block, "rows = list(")).groups()
    assert first["name"] == name and _close(float(first["value"]), value)


CHECKS = {
    ("README.md", 0): _check_readme_names,
    ("docs/drt.md", 0): _check_drt_peak,
    ("docs/diagnosis.md", 2): _check_gerischer,
    ("docs/diagnosis.md", 4): _check_sirin_gap,
    ("docs/migrating.md", 0): _check_impedance_py_numbers,
    ("docs/migrating.md", 1): _check_custom_element_names,
    ("docs/circuits.md", 1): _check_transmission_line_names,
    ("docs/models.md", 0): _check_force_maximum,
    ("docs/io.md", 2): _check_result_rows,
}


class _PageRun:
    """A page's namespace and folder, and how far its blocks have run."""

    def __init__(self, folder: Path):
        self.folder = folder
        for name in ("tests", "benchmarks"):
            (folder / name).symlink_to(ROOT / name, target_is_directory=True)
        self.printed: list[str] = []
        self.scope: dict = {"__name__": "__docs__", "print": lambda *args, **kwargs: self.printed.append(" ".join(map(str, args)))}
        self.done = 0


_RUNS: dict[str, _PageRun] = {}


def _imported_names(block: str) -> set[str]:
    """The names the block's import statements bind."""
    names = set()
    for node in ast.walk(ast.parse(block)):
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            names |= {alias.asname or alias.name.split(".")[0] for alias in node.names}
    return names


def _run_block(run: _PageRun, page: str, index: int, block: str) -> tuple[list[str], dict]:
    """Run the block in the page's namespace, or GIVEN's code and the block in a copy of it (what
    a block makes from its own given data does not reach the later blocks; what it imports
    does); what the block printed, and the namespace it ran in."""
    scope = run.scope
    if (page, index) in GIVEN:
        scope = dict(run.scope)
        exec("from pathlib import Path\nimport numpy as np\nimport impedax as ix\n" + GIVEN[page, index], scope)
    run.printed.clear()
    exec(compile(block, f"{page} block {index}", "exec"), scope)
    for name in _imported_names(block) if scope is not run.scope else ():
        run.scope[name] = scope[name]
    return list(run.printed), scope


@pytest.fixture
def page_run(request, tmp_path_factory, monkeypatch):
    monkeypatch.setattr(ix, "use_compilation_cache", lambda path=None: None)
    page = request.node.callspec.params["page"]
    if page not in _RUNS:
        _RUNS[page] = _PageRun(tmp_path_factory.mktemp(re.sub(r"\W", "_", page)))
    monkeypatch.chdir(_RUNS[page].folder)
    return _RUNS[page]


@pytest.mark.parametrize(("page", "index", "block"), BLOCKS, ids=[f"{p}#{i}:{b.splitlines()[0][:50]}" for p, i, b in BLOCKS])
def test_the_docs_python_block_runs_and_prints_what_its_comments_say(page_run, page, index, block):
    if (page, index) in SKIP:
        pytest.skip(SKIP[page, index])
    earlier = [(i, b) for p, i, b in BLOCKS if p == page and page_run.done <= i < index and (p, i) not in SKIP]
    for i, b in earlier:  # (run alone: the page's earlier blocks first)
        try:
            _run_block(page_run, page, i, b)
        except Exception as error:
            pytest.fail(f"the earlier block {i} of {page} failed: {type(error).__name__}: {error}")
        page_run.done = i + 1
    page_run.done = index + 1
    printed, scope = _run_block(page_run, page, index, block)
    if (page, index) in CHECKS:
        CHECKS[page, index](block, scope, printed)


def test_every_page_with_python_blocks_is_read_and_the_lists_name_blocks_that_exist():
    """The extraction finds the blocks of README.md and docs/*.md (36 in all), and every entry of
    SKIP, GIVEN and CHECKS names a block that exists (a renumbered page would leave one idle)."""
    assert len(BLOCKS) >= 36
    existing = {(p, i) for p, i, _ in BLOCKS}
    for listed in (SKIP, GIVEN, CHECKS):
        assert set(listed) <= existing, set(listed) - existing
    assert not set(SKIP) & set(GIVEN)
