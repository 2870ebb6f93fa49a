"""The package's architecture as docs/architecture.md states it, checked from the source with
`ast`: no import cycles (function-level imports included), no private name imported from
another module, and imports that run one way between the layers."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent / "impedax"

# lower layers first; a module may import from its own layer or a lower one only
LAYERS = [
    ("impedax.errors", "impedax.constants", "impedax.arguments", "impedax.data", "impedax.warning_groups", "impedax.progress", "impedax.passivity"),
    ("impedax.io",),
    ("impedax.circuits",),
    ("impedax.plotting", "impedax.diagram"),
    ("impedax.fitting",),
    ("impedax.models",),
    ("impedax.demo", "impedax.cli", "impedax.__main__", "impedax"),
]


def module_name(path: Path) -> str:
    parts = ("impedax",) + path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1]) if parts[-1] == "__init__" else ".".join(parts)


def is_package(path: Path) -> bool:
    return path.name == "__init__.py"


MODULES = {module_name(p): p for p in sorted(ROOT.rglob("*.py"))}


def imports(name: str) -> list[tuple[str, str | None, int]]:
    """(imported module, imported name or None, line) for every import in module ``name``,
    at any depth (function-level imports too); relative imports resolved; ``from pkg import
    sub`` recorded as the submodule."""
    path = MODULES[name]
    package = name if is_package(path) else name.rpartition(".")[0]
    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            out += [(a.name, None, node.lineno) for a in node.names if a.name.startswith("impedax")]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if not target.startswith("impedax"):
                continue
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                out.append((sub, None, node.lineno) if sub in MODULES else (target, alias.name, node.lineno))
    return out


def graph() -> dict[str, set[str]]:
    return {m: {t for t, _, _ in imports(m) if t in MODULES and t != m} for m in MODULES}


def cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index, low, stack, on, out, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(edges[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return out


def layer_of(name: str) -> int:
    best, depth = None, -1
    for i, prefixes in enumerate(LAYERS):
        for p in prefixes:
            if (name == p or name.startswith(p + ".")) and len(p) > depth:
                best, depth = i, len(p)
    assert best is not None, f"{name} belongs to no layer of docs/architecture.md"
    return best


def test_the_graph_sees_lazy_imports():
    """The checker itself: function-level imports count (they hid the old cycles)."""
    found = {t for t, _, _ in imports("impedax.fitting.problem")}
    assert "impedax.io" in found  # imported inside open_spectrum


def test_the_cycle_finder_finds_a_cycle():
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


def test_no_import_cycles():
    edges = graph()
    # a package's __init__ re-exporting its own submodules is not a cycle of the design; the
    # root package `impedax` (the public API) is left out as a target for the same reason
    for m in edges:
        edges[m] = {t for t in edges[m] if t != "impedax" and not (is_package(MODULES[t]) and m.startswith(t + "."))}
    assert cycles(edges) == []


def test_no_private_name_imported_from_another_module():
    offenders = [
        f"{m}:{line} imports {name} from {target}"
        for m in MODULES
        for target, name, line in imports(m)
        if name is not None and name.startswith("_") and not name.startswith("__") and target != m
    ]
    assert offenders == []


@pytest.mark.parametrize("module", sorted(MODULES))
def test_imports_run_one_way(module):
    mine = layer_of(module)
    upward = [f"{t} (line {line})" for t, _, line in imports(module) if t in MODULES and layer_of(t) > mine]
    assert upward == [], f"{module} imports from a higher layer"


def test_every_layer_is_used():
    assert all(any(layer_of(m) == i for m in MODULES) for i in range(len(LAYERS)))


def test_docs_the_code_cites_exist_in_the_repository():
    """Docstrings and comments send readers to docs/*.md files of this repository, never to a
    file outside it (the physics the code cites lives in docs/physics.md)."""
    import re

    repo = ROOT.parent
    cited = {m for path in MODULES.values() for m in re.findall(r"docs/[\w-]+\.md", path.read_text(encoding="utf-8"))}
    assert cited and all((repo / c).is_file() for c in cited), sorted(c for c in cited if not (repo / c).is_file())
    assert not [str(p) for p in MODULES.values() if "PHYSICS.md" in p.read_text(encoding="utf-8")]


def _layout_block() -> str:
    """The tree of docs/architecture.md's "Layout": one line per file."""
    text = (ROOT.parent / "docs" / "architecture.md").read_text(encoding="utf-8")
    section = text[text.index("## Layout") :]
    return section.split("```")[1]


def test_docs_layout_names_every_module():
    """docs/architecture.md's tree has a line for every file (README.md: "the tree with one line
    per file"): a `name.py` of the tree for each module, a word of the `plotting/` line for each
    figure module; the command and file-format folders are described as one file per command and
    per format, so their files are not listed one by one. Both ways: no file listed is missing."""
    import re

    block = _layout_block()
    plotting_line = next(line for line in block.splitlines() if line.strip().startswith("plotting/"))
    unnamed = []
    for path in sorted(ROOT.rglob("*.py")):
        relative = path.relative_to(ROOT)
        if path.name in ("__init__.py", "__main__.py") or relative.parts[0] == "cli" or relative.parts[:2] == ("io", "formats"):
            continue
        if relative.parts[0] == "plotting":
            named = re.search(rf"\b{path.stem}\b", plotting_line)
        else:
            named = re.search(rf"(?<![\w/]){re.escape(path.name)}\b", block)
        if not named:
            unnamed.append(str(relative))
    assert not unnamed, f"modules docs/architecture.md's layout does not name: {unnamed}"
    first_columns = " ".join(line.strip().split("  ")[0] for line in block.splitlines())  # the file names, not the descriptions
    listed = set(re.findall(r"[a-z_]+\.py", first_columns))
    existing = {p.name for p in ROOT.rglob("*.py")}
    assert listed <= existing, sorted(listed - existing)
