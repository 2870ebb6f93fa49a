"""docs/io.md, "Names and signs in a result's Dataset": the table of each result's model impedance,
residual (its definition as an equation: its sign), ``rms_rel`` and parameter dimension is read
from the doc and checked against every result's ``to_xarray()``, so the doc cannot drift: each
named variable exists with the dimensions it gives, each residual equals its equation computed
here from the Dataset's own ``Z`` and model variable (a sign flipped in the code or the doc
fails), and a "—" has nothing of that name. SYNTHETIC spectra: R0 + R1 ∥ CPE1 written by its
closed form below, with 1 % noise (seed 0), so the residuals are far from zero; the hierarchical
posterior and the gap analysis are built by hand (tests/test_hierarchical_new_session.py,
tests/test_gap_outputs.py)."""

import re
from pathlib import Path

import numpy as np
import pytest

import impedax as ix
from test_gap_outputs import _stub as gap_stub
from test_hierarchical_new_session import by_hand

DOC = Path(__file__).resolve().parent.parent / "docs" / "io.md"
FREQ = np.geomspace(0.1, 1e5, 41)
CIRCUIT = "R0 + R1 || CPE1"
BATCH_DIMS = ("cell",)
# the results whose construction samples, diagnoses or refines (tens of seconds): run with -m slow
SLOW = {"Diagnosis", "Refinement", "Posterior", "SharedPosterior", "BatchComparison"}


def _table() -> dict[str, dict[str, str]]:
    """The doc's table: result name → {column heading: cell}, ``\\|`` read as ``|``."""
    text = DOC.read_text(encoding="utf-8")
    start = text.index("| result | model impedance |")
    lines = text[start : text.index("\n\n", start)].splitlines()

    def cells(line):
        return [c.strip().replace("\\|", "|") for c in re.split(r"(?<!\\)\|", line.strip())[1:-1]]

    heads = cells(lines[0])
    rows = [dict(zip(heads, cells(line))) for line in lines[2:]]
    return {row["result"].strip("`"): row for row in rows}


TABLE = _table()


def _named(cell: str) -> list[tuple[str, tuple[str, ...] | None]]:
    """The variables a cell names with their dimensions: ``name`` (dims) → (name, dims), the
    batch's dimensions for ``*dims``; ``(attr)`` an attribute → (name, None). Names listed
    before one parenthesis share it."""
    found = []
    for names, dims in re.findall(r"((?:`\w+`(?:, )?)+) \(([^)]*)\)", cell):
        if dims == "attr":
            shape = None
        else:
            shape = tuple(d for part in dims.split(", ") if part for d in (BATCH_DIMS if part == "*dims" else (part,)))
        found += [(name, shape) for name in re.findall(r"`(\w+)`", names)]
    return found


def _spectra():
    z = 10 + 100 / (1 + (2j * np.pi * FREQ * 1e-3) ** 0.9)  # R0 + R1 ∥ CPE (Q = 1e-3/R1 ... in closed form)
    rng = np.random.default_rng(0)
    z = z * (1 + 0.01 * (rng.normal(size=FREQ.size) + 1j * rng.normal(size=FREQ.size)))
    return ix.make_spectrum(FREQ, z), ix.make_spectrum(FREQ, np.stack([z, 1.1 * z]), dims=BATCH_DIMS)


def _build(kind: str):
    one, stack = _spectra()
    builders = {
        "FitResult": lambda: ix.fit(CIRCUIT, one, progress=False),
        "BatchFitResult": lambda: ix.fit(CIRCUIT, stack, progress=False),
        "SharedFitResult": lambda: ix.fit(CIRCUIT, stack, shared=["CPE1.alpha"], progress=False),
        "KKResult": lambda: ix.kk_test(one),
        "KKBatchResult": lambda: ix.kk_test_batch(stack),
        "ZHITResult": lambda: ix.zhit(one),
        "ZHITBatchResult": lambda: ix.zhit_batch(stack),
        "DRTResult": lambda: ix.drt(one),
        "DRTBatchResult": lambda: ix.drt(stack),
        "Comparison": lambda: ix.compare([ix.fit(CIRCUIT, one, progress=False), ix.fit("R0 + R1 || C1", one, progress=False)]),
        "BatchComparison": lambda: ix.compare([ix.fit(CIRCUIT, stack, progress=False), ix.fit("R0 + R1 || C1", stack, progress=False)]),
        "Diagnosis": lambda: ix.diagnose(one, "R0 + R1 || C1"),
        "Refinement": lambda: ix.refine(one, "R0 + R1 || C1"),
        "Posterior": lambda: ix.sample(CIRCUIT, one, seed=1, steps=60, walkers=16, progress=False),
        "SharedPosterior": lambda: ix.sample(CIRCUIT, stack, shared=["CPE1.alpha"], seed=1, steps=30, walkers=32, progress=False),
        "HierarchicalPosterior": lambda: by_hand(2),
        "GapAnalysis": gap_stub,
    }
    assert set(builders) == set(TABLE), "every result the table lists is built here, and only those"
    return builders[kind]()


_DATASETS: dict = {}


def _dataset(kind: str):
    if kind not in _DATASETS:
        result = _build(kind)
        assert type(result).__name__ == kind
        _DATASETS[kind] = result.to_xarray()
    return _DATASETS[kind]


def _kinds():
    return [pytest.param(k, marks=pytest.mark.slow) if k in SLOW else k for k in TABLE]


def _has(ds, name, dims) -> None:
    if dims is None:
        assert name in ds.attrs, f"attribute {name!r} missing"
    else:
        assert name in ds.variables, f"variable {name!r} missing"
        assert ds[name].dims == dims, (name, ds[name].dims, dims)


def _operand(ds, text: str) -> np.ndarray:
    """``X`` → the variable X, ``|X|`` → its modulus."""
    if text.startswith("|"):
        return np.abs(ds[text.strip("|")])
    return ds[text]


# an equation of the table: name = [Re|Im](a − b)/|Z|, a and b a variable or its modulus
EQUATION = re.compile(r"^(\w+) = (Re|Im)?\((\|?\w+\|?) − (\|?\w+\|?)\)/\|Z\|$")


def test_the_table_parses_with_one_equation_per_residual():
    assert len(TABLE) == 17
    for kind, row in TABLE.items():
        equations = re.findall(r"`([^`]*=[^`]*)`", row["residual definition"])
        residuals = [n for n, _ in _named(row["residual"])]
        assert [EQUATION.match(e).group(1) for e in equations] == residuals, kind


@pytest.mark.parametrize("kind", _kinds())
def test_the_table_row_matches_the_dataset(kind):
    ds, row = _dataset(kind), TABLE[kind]
    for column in ("model impedance", "residual", "`rms_rel`", "parameters, unit"):
        for name, dims in _named(row[column]):
            _has(ds, name, dims)
    if row["model impedance"].startswith("—"):
        assert not {"Z_model", "Z_fit", "Z_kk", "modulus_zhit"} & set(ds.variables)
    if row["residual"] == "—":
        assert not [n for n in ds.data_vars if str(n).startswith("resid")], kind
    if row["`rms_rel`"] == "—":
        assert "rms_rel" not in ds.variables and "rms_rel" not in ds.attrs
    if row["parameters, unit"] == "—":
        assert not {"param", "parameter"} & set(ds.dims)
    if row["parameters, unit"].endswith("no unit"):
        assert "param" in ds.dims and "unit" not in ds.variables

    for equation in re.findall(r"`([^`]*=[^`]*)`", row["residual definition"]):
        name, part, a, b = EQUATION.match(equation).groups()
        expected = (_operand(ds, a) - _operand(ds, b)) / np.abs(ds["Z"])
        expected = {"Re": np.real, "Im": np.imag, None: lambda x: x}[part](expected)
        stored = ds[name]
        if "step" in stored.dims:  # (a refinement: every step's fit; the last is the final fit)
            stored = stored.isel(step=-1)
        assert np.iscomplexobj(stored.values) == ("complex" in row["residual"]), (kind, name)
        assert np.max(np.abs(stored.values)) > 1e-3  # (1 % noise: a flipped sign shows)
        np.testing.assert_allclose(stored.transpose(*expected.dims).values, expected.values, rtol=1e-9, atol=1e-12, err_msg=f"{kind}: {equation}")
