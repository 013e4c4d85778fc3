"""The package's layers: every import in ``flexarm/`` points down the documented order,
and no module imports itself back through a chain of others.

Layer order (README, *Layout*): ``fe`` < ``meshes``, ``reduction`` < ``robot`` <
``assembly`` < ``validation`` < ``studies`` < ``cli``.  A module may import its own
layer and the layers below; ``meshes`` and ``reduction`` are siblings and import neither
each other.  Imports inside functions count the same as those at the top.

Inside a layer, the sub-layer tables (:data:`SUBLAYERS`) order the sub-packages and
modules of ``validation``, ``studies``, ``studies.exudyn`` and ``studies.compensation``
(and its sub-packages) the same way: a member
imports itself and members of lower rank only.  Members a table does not name take its
``"*"`` rank and may import each other (the flat floor of ``studies``).  A package's
``__init__`` re-exports its members and is not checked.

The house size: no module of the package is over :data:`MAX_LINES` lines (split it by job).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import flexarm

PACKAGE = Path(flexarm.__file__).parent
#: layer -> rank; equal ranks are siblings
LAYERS = {"fe": 0, "meshes": 1, "reduction": 1, "robot": 2, "assembly": 3, "validation": 4,
          "studies": 5, "cli": 6}

#: package -> {member: rank}; a member is a direct sub-package or module of the package
SUBLAYERS = {
    "flexarm.validation": {"tolerances": 0, "models": 0, "distributions": 0, "data": 1,
                           "static": 2, "dynamic": 3, "lab": 4, "planning": 4, "diagnosis": 4,
                           "workflow": 5},
    "flexarm.studies": {"tolerances": 0, "plots": 0, "contact": 1, "*": 2, "exudyn": 3},
    "flexarm.studies.exudyn": {"bodies": 0, "damping": 0, "script": 0, "script_standalone": 0,
                               "model": 1, "impulse": 2, "path": 2, "standalone": 2},
    "flexarm.studies.compensation": {"plots": 0, "solve": 0, "program": 1, "result": 2,
                                     "workflow": 3, "lab": 4},
    "flexarm.studies.compensation.solve": {"forces": 0, "ik_batch": 0, "sag": 0,
                                           "path_ik": 1, "loaded": 1, "fixed_point": 2,
                                           "limits": 2, "runs": 2},
    "flexarm.studies.compensation.program": {"rapid_out": 0, "program_path": 0,
                                             "program_out": 1, "krl_in": 1, "densify": 1,
                                             "path_in": 2},
    "flexarm.studies.compensation.lab": {"measured": 0, "lab_run": 0, "history": 1},
}
#: The most lines a module of the package may have.
MAX_LINES = 400


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def _imports(path: Path) -> list[tuple[int, str]]:
    """(line, absolute module) of every flexarm import in ``path``."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    found = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            subs = [f"{target}.{a.name}" for a in node.names]
            found += [(node.lineno, s if _exists(s) else target) for s in subs]
        elif isinstance(node, ast.Import):
            found += [(node.lineno, a.name) for a in node.names]
    return [(line, t) for line, t in found if t == "flexarm" or t.startswith("flexarm.")]


def _exists(module: str) -> bool:
    rel = Path(*module.split(".")[1:])
    return (PACKAGE / rel).with_suffix(".py").is_file() or (PACKAGE / rel / "__init__.py").is_file()


def _layer(module: str) -> str | None:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else None


def _graph() -> dict[str, list[tuple[int, str]]]:
    return {_module_name(p): _imports(p) for p in sorted(PACKAGE.rglob("*.py"))}


def violations(graph) -> list[str]:
    """One line per import that points up (or sideways between sibling layers)."""
    out = []
    for module, targets in graph.items():
        src = _layer(module)
        if src is None:  # flexarm/__init__.py imports nothing but its version
            out += [f"{module}:{line} imports {t}" for line, t in targets]
            continue
        if src not in LAYERS:
            out.append(f"{module}: not in a documented layer")
            continue
        for line, target in targets:
            dst = _layer(target)
            if dst is None or dst == src:
                continue
            if dst not in LAYERS or LAYERS[dst] >= LAYERS[src]:
                out.append(f"{module}:{line} ({src}) imports {target} ({dst})")
    return out


def sublayer_violations(graph, tables=SUBLAYERS) -> list[str]:
    """One line per import between members of a package that points up its sub-layer
    table or sideways between sibling members, and per member the table does not rank."""
    out = []
    for package, table in tables.items():
        def member(module, package=package):
            rest = module[len(package) + 1:] if module.startswith(package + ".") else None
            return rest.split(".")[0] if rest else None

        for module, targets in graph.items():
            src = member(module)
            if src is None:
                continue
            rank = table.get(src, table.get("*"))
            if rank is None:
                out.append(f"{module}: not in the sub-layer table of {package}")
                continue
            for line, target in targets:
                dst = member(target)
                if dst is None or dst == src:
                    continue
                dst_rank = table.get(dst, table.get("*"))
                flat = src not in table and dst not in table
                if dst_rank is None or (dst_rank >= rank and not flat):
                    out.append(f"{module}:{line} ({src}) imports {target} ({dst})")
    return out


def oversized(paths, limit: int = MAX_LINES) -> dict[str, int]:
    """Path -> line count of each file of ``paths`` with more than ``limit`` lines."""
    counts = {str(p): len(Path(p).read_text().splitlines()) for p in paths}
    return {p: n for p, n in counts.items() if n > limit}


def cycles(graph) -> list[list[str]]:
    """Import cycles between modules (each as the list of modules around it)."""
    edges = {m: sorted({t for _, t in ts if t in graph and t != m}) for m, ts in graph.items()}
    # a package's __init__ re-exports its modules; importing a module runs its package's
    # __init__ first, which is not an import *by* the module
    for m in edges:
        edges[m] = [t for t in edges[m] if not m.startswith(t + ".")]
    found, state, stack = [], {}, []

    def visit(m):
        state[m] = 1
        stack.append(m)
        for t in edges[m]:
            if state.get(t) == 1:
                found.append(stack[stack.index(t):] + [t])
            elif t not in state:
                visit(t)
        stack.pop()
        state[m] = 2

    for m in sorted(edges):
        if m not in state:
            visit(m)
    return found


def test_every_import_points_down_the_layers():
    assert violations(_graph()) == []


def test_every_import_points_down_the_sublayers():
    assert sublayer_violations(_graph()) == []


@pytest.mark.parametrize("package", sorted(SUBLAYERS))
def test_every_member_of_a_sublayer_table_exists_and_says_what_it_may_import(package):
    folder = PACKAGE.parent.joinpath(*package.split("."))
    members = {p.stem for p in folder.glob("*.py") if p.stem != "__init__"}
    members |= {p.parent.name for p in folder.glob("*/__init__.py")}
    assert set(SUBLAYERS[package]) - {"*"} <= members
    for sub in folder.glob("*/__init__.py"):
        if f"{package}.{sub.parent.name}" in SUBLAYERS or package == "flexarm.validation":
            doc = ast.get_docstring(ast.parse(sub.read_text())) or ""
            assert "import" in doc, f"{sub}: the docstring says nothing of what it may import"


def test_no_import_cycles():
    assert cycles(_graph()) == []


def test_no_module_is_over_the_house_size():
    assert oversized(sorted(PACKAGE.rglob("*.py"))) == {}


def test_the_size_check_counts_lines_and_sees_one_over(tmp_path):
    at, over = tmp_path / "at.py", tmp_path / "over.py"
    at.write_text("x = 1\n" * MAX_LINES)
    over.write_text("x = 1\n" * MAX_LINES + "y = 2")  # the last line without its newline
    assert oversized([at, over]) == {str(over): MAX_LINES + 1}


def test_the_check_sees_an_upward_and_a_sibling_import():
    graph = {"flexarm.fe.mesh": [(3, "flexarm.assembly.system")],
             "flexarm.meshes.surface": [(4, "flexarm.reduction.tie")],
             "flexarm.studies.demo": [(5, "flexarm.validation.diagnosis.search")]}
    assert violations(graph) == [
        "flexarm.fe.mesh:3 (fe) imports flexarm.assembly.system (assembly)",
        "flexarm.meshes.surface:4 (meshes) imports flexarm.reduction.tie (reduction)"]


def test_the_sublayer_check_sees_an_upward_a_sibling_and_an_unranked_import():
    graph = {"flexarm.validation.data.units": [(3, "flexarm.validation.static.fit")],
             "flexarm.validation.lab.faults": [(4, "flexarm.validation.diagnosis.search")],
             "flexarm.validation.static.fit": [(5, "flexarm.validation.data.units")],
             "flexarm.validation.extra": [(6, "flexarm.validation.data.units")],
             "flexarm.studies.demo": [(7, "flexarm.studies.arm_study")]}
    assert sublayer_violations(graph) == [
        "flexarm.validation.data.units:3 (data) imports flexarm.validation.static.fit (static)",
        "flexarm.validation.lab.faults:4 (lab) imports flexarm.validation.diagnosis.search "
        "(diagnosis)",
        "flexarm.validation.extra: not in the sub-layer table of flexarm.validation"]


@pytest.mark.parametrize("loop", [["a", "b"], ["a", "b", "c"]])
def test_the_check_sees_a_cycle(loop):
    names = [f"flexarm.fe.{n}" for n in loop]
    graph = {n: [(1, names[(i + 1) % len(names)])] for i, n in enumerate(names)}
    assert len(cycles(graph)) == 1
