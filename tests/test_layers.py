"""The package's layers, read from its imports with ``ast`` (module-level and deferred ones alike).

Data flows one way: the update rules (``integrators.schemes``) -> ``symbolic`` (SymPy) ->
``_generated`` (emitted, committed) -> the runtime (``physics``, ``integrators``, ``bodies``, ``impact``,
``packing``, ``scenes``) -> ``codegen`` -> ``bench``, ``figures``, ``notebooks`` -> ``cli``.
A module may import its own layer and the ones before it; the runtime never imports SymPy; and
no chain of imports leads back to where it started.
"""
from __future__ import annotations

import ast
import sys
from pathlib import Path

import pytest
from support.paths import SRC

PACKAGE = SRC / "dtcrit"

# (prefix, rank): the longest matching prefix decides a module's layer
LAYERS = (
    ("dtcrit", 0),  # the lazy public namespace: names modules in strings only
    ("dtcrit.errors", 0),
    ("dtcrit.inputs", 0),  # checks of input values: the standard library, NumPy and dtcrit.errors only
    ("dtcrit.json_meta", 0),
    ("dtcrit.numerics", 0),  # numerical primitives (NumPy; the mpmath references in numerics.reference)
    ("dtcrit.mp_roots", 0),  # mpmath-only cubic roots shared by the 50-digit references  # the JSON envelope: reads generated headers as text, imports nothing
    ("dtcrit.integrators.schemes", 1),  # update rules: plain arithmetic, read by SymPy and the runtime
    ("dtcrit.symbolic", 2),
    ("dtcrit._generated", 3),
    ("dtcrit.physics.local_damping", 3),  # local damping's laws and step factor: NumPy only, read by integrators and physics users
    ("dtcrit.physics", 4),  # contact physics shared by packing and scenes: NumPy only
    ("dtcrit.integrators", 4),
    ("dtcrit.bodies", 5),
    ("dtcrit.impact", 6),
    ("dtcrit.collisions", 6),  # the step that resolves a collision (NumPy/SciPy)
    ("dtcrit.packing", 6),  # packing.step, packing.audit.run, packing.distributed.step: the packing API
    ("dtcrit.paper", 6),  # the paper's printed formulas beside the verified ones (integrators, bodies)
    ("dtcrit.scenes", 7),
    ("dtcrit.plan", 7),  # dtcrit plan: density scaling and stiffness reduction on the audit's snapshot (packing, collisions)
    ("dtcrit.codegen", 8),  # codegen.api: emit_code, the emission API
    ("dtcrit.bench", 9),
    ("dtcrit.figures", 9),
    ("dtcrit.notebooks", 9),
    ("dtcrit.cli", 10),
    ("dtcrit.__main__", 10),
    ("dtcrit.engine_scripts", 11),  # run inside the engines (YADE's Python): a leaf nothing imports
)
RUNTIME = (3, 4, 5, 6, 7)
HEAVY_SYMBOLIC = ("sympy",)


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(SRC).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _rank(module: str) -> tuple[str, int]:
    best = max((p for p, _ in LAYERS if module == p or module.startswith(p + ".")), key=len)
    return best, dict(LAYERS)[best]


def _imports(path: Path) -> list[tuple[int, str]]:
    """(line, module) of every import in the file, resolved against the package layout."""
    tree = ast.parse(path.read_text(), filename=str(path))
    here = _module_name(path).split(".")
    package = here if path.name == "__init__.py" else here[:-1]
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[: len(package) - node.level + 1]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module or ""
            if module == "dtcrit" and all(alias.name == "__version__" for alias in node.names):
                continue  # the version is defined in the namespace itself, not loaded lazily
            out.append((node.lineno, module))
            for alias in node.names:  # ``from dtcrit.pkg import module``
                candidate = f"{module}.{alias.name}"
                if _exists(candidate):
                    out.append((node.lineno, candidate))
    return out


def _exists(module: str) -> bool:
    rel = Path(*module.split("."))
    return (SRC / rel.with_suffix(".py")).exists() or (SRC / rel / "__init__.py").exists()


FILES = sorted(PACKAGE.rglob("*.py"))
GRAPH = {_module_name(f): [(line, m) for line, m in _imports(f) if m.split(".")[0] == "dtcrit" and _exists(m)] for f in FILES}


def test_the_layout_is_walked():
    assert len(FILES) > 50 and "dtcrit.bodies.hull" in GRAPH and "dtcrit.cli" in GRAPH


@pytest.mark.parametrize("path", FILES, ids=lambda p: str(p.relative_to(SRC)))
def test_imports_follow_the_layer_order(path):
    module = _module_name(path)
    layer, rank = _rank(module)
    wrong = []
    for line, target in GRAPH[module]:
        if target == "dtcrit" and module != "dtcrit":
            wrong.append(f"line {line}: imports the lazy namespace 'dtcrit' (import the defining module)")
            continue
        t_layer, t_rank = _rank(target)
        if t_rank > rank or (t_rank == rank and t_layer != layer and rank not in (0, 10)):
            wrong.append(f"line {line}: {target} ({t_layer}, layer {t_rank}) from layer {rank} ({layer})")
    if rank in RUNTIME:
        wrong += [f"line {line}: runtime imports {m}" for line, m in _imports(path) if m.split(".")[0] in HEAVY_SYMBOLIC]
    assert not wrong, f"{module}: " + "; ".join(wrong)


def test_engine_scripts_import_only_the_standard_library_and_yade():
    """The scripts run inside YADE's own Python, where dtcrit and its dependencies are not installed."""
    scripts = sorted((PACKAGE / "engine_scripts").glob("*.py"))
    allowed = set(sys.stdlib_module_names) | {"yade", "__main__"} | {p.stem for p in scripts}  # siblings by name
    wrong = []
    for path in scripts:
        for line, module in _imports(path):
            if not (module.split(".")[0] in allowed or module.startswith("dtcrit.engine_scripts")):
                wrong.append(f"{path.name}:{line}: {module}")
    assert not wrong, "engine scripts import more than the standard library and yade: " + "; ".join(wrong)


def test_no_import_cycles():
    state: dict[str, int] = {}
    cycles = []

    def visit(node: str, trail: list[str]) -> None:
        state[node] = 1
        for _, target in GRAPH.get(node, ()):
            if target not in GRAPH:
                continue
            if state.get(target) == 1:
                cycles.append(" -> ".join(trail[trail.index(target):] + [target]) if target in trail else target)
            elif state.get(target) is None:
                visit(target, trail + [target])
        state[node] = 2

    for module in sorted(GRAPH):
        if state.get(module) is None:
            visit(module, [module])
    # a package's __init__ importing its own submodules is not a cycle back to it
    real = [c for c in cycles if not all(step.startswith(c.split(" -> ")[0]) for step in c.split(" -> "))]
    assert not real, "import cycles: " + "; ".join(real)


def test_no_hand_written_module_over_about_400_lines():
    scripts = sorted((SRC.parent / "derivations").rglob("*.py"))
    long = {str(f.relative_to(SRC.parent)): n for f in FILES + scripts if "_generated" not in f.parts
            for n in [len(f.read_text().splitlines())] if n > 430}
    assert not long, f"modules over about 400 lines: {long}"
