"""The layering contract (docs/architecture.md), checked on the source: every import statement,
function-level ones included, must point downwards.

- packages: ``geometry`` imports nothing of ``importers`` or ``solver``; ``importers`` only
  ``geometry``;
- inside ``solver``: a module imports only its own layer and the layers below it (LAYERS, bottom
  first);
- no import cycle between any two modules of the project.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("geometry", "importers", "solver")

# solver's layers, bottom first: each may import the ones before it (and itself)
LAYERS = [
    ("ibfem.solver.reference",),
    ("ibfem.solver.model",),
    ("ibfem.solver.fem",),
    ("ibfem.solver.solution",),
    ("ibfem.solver.contact",),
    ("ibfem.solver.solving",),
    ("ibfem.solver.io",),
    ("ibfem.solver.commands", "ibfem.solver.cli", "ibfem.solver.kernel_warmup"),
    ("ibfem.solver.reports", "ibfem.solver.sweep"),
]
# the package's own __init__ names the public API lazily (strings), so it sits on top
TOP = ("ibfem.solver",)


def _modules() -> dict[str, Path]:
    out = {}
    for pkg in PACKAGES:
        for path in (ROOT / pkg).rglob("*.py"):
            name = ".".join(("ibfem",) + path.relative_to(ROOT).with_suffix("").parts)
            out[name.removesuffix(".__init__")] = path
    return out


MODULES = _modules()


def _imports(name: str, path: Path) -> set[str]:
    """Project modules imported by a module (resolved to the longest known module name)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module or ""
            found.add(module)
            found.update(f"{module}.{a.name}" for a in node.names)
    deps = set()
    for m in found:
        while m and m not in MODULES:
            m = m.rpartition(".")[0]
        if m and m != name:
            deps.add(m)
    return deps


GRAPH = {name: _imports(name, path) for name, path in MODULES.items()}


def _layer(module: str) -> int:
    if module in TOP:
        return len(LAYERS)
    for k, prefixes in enumerate(LAYERS):
        if any(module == p or module.startswith(p + ".") for p in prefixes):
            return k
    raise AssertionError(f"{module} is in no layer of tests/test_architecture.py: add it to LAYERS")


def test_packages_import_downwards():
    wrong = []
    for name, deps in GRAPH.items():
        top = name.split(".")[1]
        allowed = {"geometry": {"geometry"}, "importers": {"geometry", "importers"}, "solver": set(PACKAGES)}[top]
        wrong += [f"{name} imports {d}" for d in deps if d.split(".")[1] not in allowed]
    assert not wrong, "\n".join(wrong)


def test_solver_layers_import_downwards():
    wrong = []
    for name, deps in GRAPH.items():
        if not name.startswith("ibfem.solver"):
            continue
        mine = _layer(name)
        wrong += [f"{name} (layer {mine}) imports {d} (layer {_layer(d)})"
                  for d in deps if d.startswith("ibfem.solver") and _layer(d) > mine]
    assert not wrong, "\n".join(wrong)


def test_no_import_cycles():
    state: dict[str, int] = {}  # 1 visiting, 2 done
    cycles = []

    def visit(node: str, stack: list[str]) -> None:
        state[node] = 1
        for dep in sorted(GRAPH.get(node, ())):
            # a package's __init__ re-exporting its own modules is not a cycle of behaviour
            if node.startswith(dep + "."):
                continue
            if state.get(dep) == 1:
                cycles.append(" -> ".join(stack[stack.index(dep):] + [dep]) if dep in stack else f"{node} -> {dep}")
            elif dep not in state:
                visit(dep, stack + [dep])
        state[node] = 2

    for name in sorted(GRAPH):
        if name not in state:
            visit(name, [name])
    assert not cycles, "\n".join(cycles)


@pytest.mark.parametrize("module", ["ibfem.solver.contact.driver", "ibfem.solver.fem.space", "ibfem.solver.model.problem"])
def test_the_contract_sees_real_imports(module):
    """Guard against a checker that passes because it reads nothing."""
    assert GRAPH[module], f"no imports found for {module}"
