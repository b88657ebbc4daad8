"""The house's import graph (issue 23): one-way layers, no circle, a thin CLI.

Every import of springcad/ and fea/ is read from the source (module level, inside
functions and under ``TYPE_CHECKING`` alike: a lazy import is still a dependency) and
checked against the layer order of docs (shared notes, architecture.md):

    errors/units -> materials -> config -> design -> geometry & fit -> fea, export
    -> synthesis, validation -> report -> api -> cli

A module may import its own layer or lower ones; an import into a higher layer is an
arrow back up. Circles are searched among the files (a strongly connected component
of more than one file).
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: the layer of every room, ground floor first (a room is a top-level module or
#: subpackage of springcad, or the fea package)
LAYERS = [
    {"springcad.errors", "springcad.units", "springcad.version", "springcad.textio",
     "springcad.connections", "springcad.progress", "springcad.data"},
    {"springcad.materials", "springcad.options"},
    {"springcad.config", "springcad.cache", "springcad.parallel", "springcad.stages"},
    {"springcad.design"},
    {"springcad.geometry", "springcad.fit"},
    {"fea", "springcad.export"},
    {"springcad.synthesis", "springcad.validation"},
    {"springcad.report"},
    {"springcad.api"},
    {"springcad.cli", "springcad", "springcad.__main__"},
]
#: layer index by room
FLOOR = {room: i for i, rooms in enumerate(LAYERS) for room in rooms}
#: rooms of one layer that may not import each other (siblings, not a stair)
SIBLINGS_APART = [{"springcad.geometry", "springcad.fit"}, {"springcad.synthesis",
                                                             "springcad.validation"}]


def module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def room(module: str) -> str:
    """The room of a module: ``springcad.design.spring`` -> ``springcad.design``."""
    parts = module.split(".")
    if parts[0] == "fea":
        return "fea"
    if len(parts) == 1:
        return "springcad"
    return ".".join(parts[:2])


def project_modules() -> dict[str, Path]:
    files = sorted((ROOT / "springcad").rglob("*.py")) + sorted((ROOT / "fea").rglob("*.py"))
    return {module_name(p): p for p in files}


def imports_of(path: Path, name: str, known: set[str]) -> set[str]:
    """The project modules ``path`` imports (anywhere in the file), as module names."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = package.split(".")[:len(package.split(".")) - node.level + 1]
                base = ".".join(up + ([base] if base else []))
            # "from pkg import mod" imports the module pkg.mod when there is one
            targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in known else base
                       for a in node.names]
        else:
            continue
        for t in targets:
            while t and t not in known:
                t = t.rpartition(".")[0]
            if t and t.split(".")[0] in ("springcad", "fea") and t != name:
                found.add(t)
    return found


def graph() -> dict[str, set[str]]:
    mods = project_modules()
    return {name: imports_of(path, name, set(mods)) for name, path in mods.items()}


def test_every_room_has_a_layer():
    assert sorted({room(m) for m in project_modules()} - set(FLOOR)) == []


def test_no_import_runs_back_up():
    up = sorted(f"{a} -> {b}" for a, targets in graph().items() for b in targets
                if FLOOR[room(b)] > FLOOR[room(a)])
    assert up == []


def test_siblings_do_not_import_each_other():
    across = sorted(f"{a} -> {b}" for a, targets in graph().items() for b in targets
                    for pair in SIBLINGS_APART
                    if room(a) in pair and room(b) in pair and room(a) != room(b))
    assert across == []


def strongly_connected(g: dict[str, set[str]]) -> list[list[str]]:
    """Tarjan's components of more than one node (iterative)."""
    index, low, on, stack, out, counter = {}, {}, set(), [], [], [0]
    for start in g:
        if start in index:
            continue
        work = [(start, iter(sorted(g[start])))]
        index[start] = low[start] = counter[0]
        counter[0] += 1
        stack.append(start)
        on.add(start)
        while work:
            v, it = work[-1]
            w = next(it, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(g.get(w, ())))))
                elif w in on:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
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
    return out


def test_strongly_connected_finds_a_planted_circle():
    g = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}, "e": set()}
    assert strongly_connected(g) == [["a", "b", "c"]]
    assert strongly_connected({"a": {"b"}, "b": set()}) == []


def test_no_circle_between_files():
    # a package's face (__init__) re-exporting its modules is not a circle of the design:
    # the package imports its modules, they import each other through their own names
    g = {a: {b for b in targets if not (project_modules()[b].name == "__init__.py"
                                         and a.startswith(b + "."))}
         for a, targets in graph().items()}
    assert strongly_connected(g) == []


def test_the_cli_imports_only_the_api_and_its_own_helpers():
    """Each subcommand is argparse -> one API call -> print: no stage internals."""
    allowed = {"springcad.api", "springcad.cli", "springcad.errors", "springcad.options",
               "springcad.units", "springcad.version", "springcad.progress", "springcad.report",
               "springcad", "springcad.parallel"}
    inside = sorted(f"{a} -> {b}" for a, targets in graph().items() if room(a) == "springcad.cli"
                    for b in targets if room(b) not in allowed)
    assert inside == []
