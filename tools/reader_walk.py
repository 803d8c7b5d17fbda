"""A reader's walk through the package from one entry point, counted from the source (issue #50).

The walk is the static call graph a reader follows from the entry: every call the source names and
that resolves to a function or class of ``auvplan`` (``f(...)``, ``module.f(...)``, ``self.f(...)``,
``Class(...)``, through re-exports), each function read once, in source order (depth first).  A *step*
is a call into another module; a *climb* is a step into another module of the same folder (the reader
leaves the file for a sibling, not for a lower layer); the *front* is the part of the walk whose caller
sits in the command line, the jobs or the web planner (``cli``/``app``/``serve`` and the old root
``cli*.py`` files).  Calls through variables (callbacks, dispatch tables) are not followed: the count is
a lower bound, the same one before and after.

Usage::

    python tools/reader_walk.py [--src DIR] module:function [module:Class.method ...]
"""

from __future__ import annotations

import argparse
import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


class Package:
    """The parsed modules of one source tree and the names each one binds."""

    def __init__(self, src: Path) -> None:
        self.trees: dict[str, ast.Module] = {}
        self.defs: dict[str, dict[str, ast.AST]] = {}
        self.imports: dict[str, dict[str, tuple[str, str | None]]] = {}
        for p in sorted((src / "auvplan").rglob("*.py")):
            parts = list(p.relative_to(src).with_suffix("").parts)
            is_pkg = parts[-1] == "__init__"
            if is_pkg:
                parts = parts[:-1]
            name = ".".join(parts)
            tree = ast.parse(p.read_text())
            self.trees[name] = tree
            self.defs[name] = {}
            self.imports[name] = {}
            base = name if is_pkg else name.rpartition(".")[0]
            for node in tree.body:
                self._bind(name, base, node)

    def _bind(self, name: str, base: str, node: ast.stmt) -> None:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            self.defs[name][node.name] = node
        elif isinstance(node, ast.ClassDef):
            self.defs[name][node.name] = node
            for item in node.body:
                if isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)):
                    self.defs[name][f"{node.name}.{item.name}"] = item
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.asname:
                    self.imports[name][a.asname] = (a.name, None)
        elif isinstance(node, ast.ImportFrom):
            mod = node.module or ""
            if node.level:
                up = base.split(".")[: len(base.split(".")) - node.level + 1]
                mod = ".".join(up + ([mod] if mod else []))
            for a in node.names:
                self.imports[name][a.asname or a.name] = (mod, a.name)
        elif isinstance(node, ast.If):  # TYPE_CHECKING blocks and the like
            for sub in node.body:
                self._bind(name, base, sub)

    def resolve(self, module: str, name: str, depth: int = 0) -> tuple[str, str] | str | None:
        """``(module, qualified name)`` of a function/class, a module name, or None (not ours)."""
        if depth > 12 or module not in self.defs:
            return None
        if name in self.defs[module]:
            return module, name
        if f"{module}.{name}" in self.trees:
            return f"{module}.{name}"
        if name in self.imports[module]:
            mod, attr = self.imports[module][name]
            if attr is None:
                return mod if mod in self.trees else None
            if f"{mod}.{attr}" in self.trees:
                return f"{mod}.{attr}"
            return self.resolve(mod, attr, depth + 1)
        return None


def _calls(fn: ast.AST) -> list[ast.Call]:
    out = [n for n in ast.walk(fn) if isinstance(n, ast.Call)]
    return sorted(out, key=lambda n: (n.lineno, n.col_offset))


def _annotated(pkg: Package, module: str, fn: ast.AST) -> dict[str, str]:
    """Parameters annotated with one of our classes (``session: Session``): name -> class qualname."""
    out: dict[str, str] = {}
    if isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
        for a in fn.args.args + fn.args.kwonlyargs:
            if isinstance(a.annotation, ast.Name):
                r = pkg.resolve(module, a.annotation.id)
                if isinstance(r, tuple) and isinstance(pkg.defs[r[0]][r[1]], ast.ClassDef):
                    out[a.arg] = f"{r[0]}:{r[1]}"
    return out


def _local_imports(pkg: Package, module: str, fn: ast.AST) -> dict[str, tuple[str, str] | str | None]:
    """Names bound by imports inside the function (``from ..app.run import run_scenario``), resolved."""
    base = module if any(m.startswith(module + ".") for m in pkg.trees) else module.rpartition(".")[0]
    out: dict[str, tuple[str, str] | str | None] = {}
    for node in ast.walk(fn):
        if isinstance(node, ast.ImportFrom):
            mod = node.module or ""
            if node.level:
                up = base.split(".")[: len(base.split(".")) - node.level + 1]
                mod = ".".join(up + ([mod] if mod else []))
            for a in node.names:
                full = f"{mod}.{a.name}"
                out[a.asname or a.name] = full if full in pkg.trees else pkg.resolve(mod, a.name)
    return out


def _callee(pkg: Package, module: str, cls: str | None, call: ast.Call,
            typed: dict[str, str] | None = None,
            local: dict[str, tuple[str, str] | str | None] | None = None) -> tuple[str, str] | None:
    f = call.func
    local = local or {}
    if isinstance(f, ast.Attribute) and isinstance(f.value, ast.Name) and typed and f.value.id in typed:
        mod, qn = typed[f.value.id].split(":")
        key = f"{qn}.{f.attr}"
        return (mod, key) if key in pkg.defs[mod] else None
    if isinstance(f, ast.Name):
        r = local[f.id] if f.id in local else pkg.resolve(module, f.id)
    elif isinstance(f, ast.Attribute) and isinstance(f.value, ast.Name):
        if f.value.id in ("self", "cls") and cls is not None:
            key = f"{cls}.{f.attr}"
            return (module, key) if key in pkg.defs[module] else None
        owner = local[f.value.id] if f.value.id in local else pkg.resolve(module, f.value.id)
        r = pkg.resolve(owner, f.attr) if isinstance(owner, str) else None
        if isinstance(owner, tuple) and f"{owner[1]}.{f.attr}" in pkg.defs[owner[0]]:
            r = (owner[0], f"{owner[1]}.{f.attr}")  # Class.method(...) / classmethod
    else:
        return None
    if not isinstance(r, tuple):
        return None
    mod, name = r
    node = pkg.defs[mod][name]
    if isinstance(node, ast.ClassDef):
        for init in ("__init__", "__post_init__"):
            if f"{name}.{init}" in pkg.defs[mod]:
                return mod, f"{name}.{init}"
        return None
    return r


def _front(module: str) -> bool:
    parts = module.split(".")
    return len(parts) > 1 and (parts[1] in ("cli", "app", "serve") or parts[1].startswith("cli_"))


def _folder(module: str, pkg: Package) -> str:
    return module if module in pkg.trees and pkg.trees[module] is not None and _is_pkg(pkg, module) \
        else module.rpartition(".")[0]


def _is_pkg(pkg: Package, module: str) -> bool:
    return any(m.startswith(module + ".") for m in pkg.trees)


def walk(pkg: Package, entry: str, show: bool = False) -> dict[str, int]:
    """Count the walk's functions, steps and climbs (all, and in the front) from ``module:qualname``."""
    module, name = entry.split(":")
    seen: set[tuple[str, str]] = set()
    counts = {"functions": 0, "steps": 0, "climbs": 0, "front_steps": 0, "front_climbs": 0}
    stack = [(module, name)]
    while stack:
        mod, qn = stack.pop()
        if (mod, qn) in seen:
            continue
        seen.add((mod, qn))
        counts["functions"] += 1
        cls = qn.split(".")[0] if "." in qn else None
        nxt = []
        typed = _annotated(pkg, mod, pkg.defs[mod][qn])
        local = _local_imports(pkg, mod, pkg.defs[mod][qn])
        for call in _calls(pkg.defs[mod][qn]):
            c = _callee(pkg, mod, cls, call, typed, local)
            if c is None or c in seen or c in nxt:
                continue
            nxt.append(c)
            if c[0] != mod:
                climb = _folder(c[0], pkg) == _folder(mod, pkg)
                counts["steps"] += 1
                counts["climbs"] += climb
                if show and climb:
                    print(f"  climb {mod}:{qn} -> {c[0]}:{c[1]}")
                if _front(mod):
                    counts["front_steps"] += 1
                    counts["front_climbs"] += climb
        stack.extend(reversed(nxt))
    return counts


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--src", type=Path, default=ROOT / "src")
    ap.add_argument("--show", action="store_true", help="print every climb")
    ap.add_argument("entries", nargs="+")
    args = ap.parse_args()
    pkg = Package(args.src)
    for e in args.entries:
        c = walk(pkg, e, args.show)
        print(f"{e}: " + ", ".join(f"{k} {v}" for k, v in c.items()))


if __name__ == "__main__":
    main()
