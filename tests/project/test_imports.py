"""Dependencies run one way: cases/ never imports benchmarks/ (the timing helpers both use live
in harness/timing.py), and the modules of python/stickslip import each other without a cycle.

Imports are read from the source with `ast`, every one of them: at the top of a module and
inside functions (a deferred import is still a dependency).
"""
from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "python" / "stickslip"


def imported_modules(path: Path, package: str) -> set[str]:
    """Absolute names of the modules `path` imports (relative imports resolved in `package`)."""
    out: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.Import):
            out.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.rsplit(".", node.level - 1)[0] if node.level > 1 else package
                module = f"{base}.{node.module}" if node.module else base
            else:
                module = node.module or ""
            out.add(module)
            out.update(f"{module}.{alias.name}" for alias in node.names)   # from . import x
    return out


def package_graph(directory: Path, package: str) -> dict[str, set[str]]:
    """Module -> the modules of the same package it imports."""
    modules = {f"{package}.{p.stem}" for p in directory.glob("*.py") if p.stem != "__init__"}
    return {f"{package}.{p.stem}": imported_modules(p, package) & modules
            for p in directory.glob("*.py") if p.stem != "__init__"}


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """A cycle of `graph` as a list of nodes (first repeated at the end), or None."""
    state: dict[str, int] = {}                 # 1: on the current path, 2: done
    path: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = 1
        path.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                return path[path.index(nxt):] + [nxt]
            if nxt not in state:
                found = visit(nxt)
                if found:
                    return found
        state[node] = 2
        path.pop()
        return None

    for node in sorted(graph):
        if node not in state:
            found = visit(node)
            if found:
                return found
    return None


def test_cases_never_import_benchmarks() -> None:
    offenders = [f"{p.relative_to(ROOT)} imports {m}"
                 for p in sorted((ROOT / "cases").glob("*.py"))
                 for m in sorted(imported_modules(p, "cases"))
                 if m == "benchmarks" or m.startswith("benchmarks.")]
    assert not offenders, "\n".join(offenders)


def test_stickslip_has_no_import_cycle() -> None:
    graph = package_graph(PACKAGE, "stickslip")
    assert "stickslip.batch" in graph["stickslip.distributed"]      # the graph is read
    assert find_cycle(graph) is None, " -> ".join(find_cycle(graph) or [])


def test_the_checks_find_what_they_look_for(tmp_path: Path) -> None:
    """The readers see deferred and relative imports, and the cycle finder finds a cycle."""
    (tmp_path / "a.py").write_text("def f():\n    from .b import g\n    return g\n")
    (tmp_path / "b.py").write_text("from . import c\n")
    (tmp_path / "c.py").write_text("import os\nfrom pkg.a import f\n")
    graph = package_graph(tmp_path, "pkg")
    assert graph == {"pkg.a": {"pkg.b"}, "pkg.b": {"pkg.c"}, "pkg.c": {"pkg.a"}}
    assert find_cycle(graph) == ["pkg.a", "pkg.b", "pkg.c", "pkg.a"]
    assert find_cycle({"x": {"y"}, "y": set()}) is None
    (tmp_path / "d.py").write_text("x = 1\ndef f():\n    import benchmarks.run\n")
    assert "benchmarks.run" in imported_modules(tmp_path / "d.py", "pkg")
