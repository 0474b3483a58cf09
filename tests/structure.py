"""The shape of the code, measured: import cycles, layers, module sizes, manifest subscripts, packaging.

    python -m tests.structure           # a readable summary
    python -m tests.structure --json    # one JSON line with the figures (issue 23's keys)

(from the repository's root; the vocabulary figures reuse the scanners of tests/test_vocabularies.py)

The import graph is read from the sources (``ast``), every ``import`` and ``from ... import`` counted
wherever it is written (a function-local import is still a dependency), except those under
``if TYPE_CHECKING:`` (annotations only, never executed).  ``tests/test_structure.py`` asserts on the same
functions.
"""

from __future__ import annotations

import argparse
import ast
import json
import re
import sys
import tomllib
from collections.abc import Iterator
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT / "tests") not in sys.path:       # the vocabulary scanners live in tests/test_vocabularies.py
    sys.path.insert(0, str(ROOT / "tests"))
TOPS = ("symbolic", "runtime", "generated")

#: The runtime's layers, lowest first, as docs/architecture.md draws them: a module may import modules of its
#: own layer and of lower ones.  ``rpo.runtime`` itself (the package's public names) sits above them all.
RUNTIME_LAYERS: tuple[tuple[str, ...], ...] = (
    ("rpo.runtime.errors", "rpo.runtime.frames", "rpo.runtime.formats"),
    ("rpo.runtime.model", "rpo.runtime.flight"),
    ("rpo.runtime.scenario",),
    ("rpo.runtime.run",),
    ("rpo.runtime.outputs",),
    ("rpo.runtime.jobs", "rpo.runtime.campaign"),
    ("rpo.runtime.cli", "rpo.runtime.docgen"),
    ("rpo.runtime.api",),
)


def modules(root: Path = ROOT) -> dict[str, Path]:
    """Every module of rpo in this checkout: dotted name -> file."""
    out = {}
    for top in TOPS:
        for p in sorted((root / top).rglob("*.py")):
            parts = list(p.relative_to(root).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts = parts[:-1]
            out["rpo." + ".".join(parts)] = p
    return out


def _type_checking_nodes(tree: ast.AST) -> set[int]:
    skip: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            for sub in node.body:
                skip.update(id(n) for n in ast.walk(sub))
    return skip


def imports(name: str, path: Path, mods: dict[str, Path]) -> Iterator[tuple[str, int]]:
    """(imported rpo module, line) for every import of ``name`` (TYPE_CHECKING blocks excepted)."""
    tree = ast.parse(path.read_text(), str(path))
    skip = _type_checking_nodes(tree)
    pkg = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.Import):
            for a in node.names:
                if a.name in mods:
                    yield a.name, node.lineno
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = pkg.split(".")[: len(pkg.split(".")) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            subs = [f"{target}.{a.name}" for a in node.names if f"{target}.{a.name}" in mods]
            if subs:
                yield from ((s, node.lineno) for s in subs)
            if len(subs) < len(node.names) and target in mods:
                yield target, node.lineno


def graph(root: Path = ROOT) -> dict[str, set[str]]:
    mods = modules(root)
    return {m: {t for t, _ in imports(m, p, mods) if t != m} for m, p in mods.items()}


def cycles(g: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []
    counter = 0
    for start in sorted(g):
        if start in index:
            continue
        work = [(start, iter(sorted(g[start])))]
        index[start] = low[start] = counter
        counter += 1
        stack.append(start)
        on.add(start)
        while work:
            v, it = work[-1]
            for w in it:
                if w not in g:
                    continue
                if w not in index:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(g[w]))))
                    break
                if w in on:
                    low[v] = min(low[v], index[w])
            else:
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


def layer_of(name: str) -> int | None:
    for i, prefixes in enumerate(RUNTIME_LAYERS):
        if any(name == p or name.startswith(p + ".") for p in prefixes):
            return i
    return None


def layer_violations(g: dict[str, set[str]]) -> list[str]:
    """Runtime imports that go up the layers (or a runtime module outside every layer), and any import of
    rpo.symbolic by the runtime."""
    out = []
    for m, targets in sorted(g.items()):
        if not m.startswith("rpo.runtime") or m == "rpo.runtime":
            continue
        lm = layer_of(m)
        if lm is None:
            out.append(f"{m} is in no layer of docs/architecture.md")
            continue
        for t in sorted(targets):
            if t.startswith("rpo.symbolic"):
                out.append(f"{m} imports {t} (the runtime never imports rpo.symbolic)")
            elif t.startswith("rpo.runtime") and t != "rpo.runtime":
                lt = layer_of(t)
                if lt is not None and lt > lm:
                    out.append(f"{m} (layer {lm}) imports {t} (layer {lt})")
    return out


def module_lines(prefix: str = "runtime", root: Path = ROOT) -> dict[str, int]:
    return {str(p.relative_to(root)): len(p.read_text().splitlines()) for p in sorted((root / prefix).rglob("*.py"))}


#: A module over this many lines must say why at its top (``# size: <reason>`` in its first lines).
MAX_LINES = 600


def oversized(root: Path = ROOT) -> list[str]:
    out = []
    for f, n in module_lines("runtime", root).items():
        head = "\n".join((root / f).read_text().splitlines()[:40])
        if n > MAX_LINES and "# size:" not in head:
            out.append(f"{f}: {n} lines")
    return out


def manifest_subscripts(root: Path = ROOT, outside: str = "runtime/model/") -> list[str]:
    """``manifest["..."]`` (or ``manifest.get("...")``) in the runtime outside the model package: the
    manifest's raw dict read where only its typed form should be."""
    out = []
    for p in sorted((root / "runtime").rglob("*.py")):
        rel = str(p.relative_to(root))
        if rel.startswith(outside):
            continue
        for node in ast.walk(ast.parse(p.read_text())):
            target = None
            if isinstance(node, ast.Subscript) and isinstance(node.slice, ast.Constant) \
                    and isinstance(node.slice.value, str):
                target = node.value
            elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "get":
                target = node.func.value
            if target is not None and re.search(r"(^|\.)_?manifest$", ast.unparse(target)):
                out.append(f"{rel}:{node.lineno}")
    return out


def hand_kept_packages(root: Path = ROOT) -> int:
    data = tomllib.loads((root / "pyproject.toml").read_text())
    pk = data.get("tool", {}).get("setuptools", {}).get("packages", [])
    return len(pk) if isinstance(pk, list) else 0


def vocabulary_copies() -> dict[str, list[str]]:
    """Per vocabulary, the places in runtime/ that spell its names outside the module that declares it
    (the scanners of tests/test_vocabularies.py): an empty list is a vocabulary declared once."""
    import test_vocabularies as tv

    from rpo.runtime.campaign.dispersions import DISTRIBUTIONS
    from rpo.runtime.formats import FIGURE_FORMATS, OUTPUT_FORMATS
    from rpo.runtime.model.manifest import read_manifest

    kinds = set(read_manifest().faults.kinds)
    return {"output formats": tv._literal_uses(set(OUTPUT_FORMATS), tv.FORMATS_PY),
            "figure formats": tv._literal_uses(set(FIGURE_FORMATS), tv.FORMATS_PY),
            # a distribution's name may be a word of another vocabulary (a parameter's kind "inertia"):
            # a second copy is a module listing them all, or a switch on a name
            "distributions": files_naming_every(set(DISTRIBUTIONS), exclude=tv.DISPERSIONS_PY)
            + [f"{rel}: {c}" for rel, tree in tv.SOURCES.items() for c in tv._switches_on_dist(tree)],
            "fault kinds": tv._literal_uses(kinds, tv.FAULT_STUDY)}


def files_naming_every(names: set[str], exclude: str = "") -> list[str]:
    """The runtime modules that spell every one of ``names``: where a new name would have to be added."""
    import test_vocabularies as tv

    return sorted(rel for rel, tree in tv.SOURCES.items()
                  if rel != exclude and names <= {c.value for c in tv._strings(tree)})


def figures(root: Path = ROOT) -> dict:
    g = graph(root)
    lines = module_lines("runtime", root)
    largest = max(lines.items(), key=lambda kv: kv[1])
    return {"import_cycles": len(cycles(g)), "layer_violations": len(layer_violations(g)),
            "largest_runtime_module_lines": largest[1], "largest_runtime_module": largest[0],
            "runtime_modules_over_600_without_reason": len(oversized(root)),
            "manifest_subscripts_outside_model": len(manifest_subscripts(root)),
            "hand_kept_package_entries": hand_kept_packages(root), **_vocabulary_figures()}


def _vocabulary_figures() -> dict:
    from rpo.runtime.formats import OUTPUT_FORMATS
    from rpo.runtime.model.manifest import read_manifest

    copies = vocabulary_copies()
    kinds = set(read_manifest().faults.kinds)
    in_runtime = files_naming_every(kinds)
    return {"vocabularies_defined_twice": sum(bool(v) for v in copies.values()),
            "files_to_add_fault_kind": "symbolic + docs" if not in_runtime else f"symbolic + docs + {in_runtime}",
            "files_to_add_output_format": len(files_naming_every(set(OUTPUT_FORMATS)))}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--json", action="store_true", help="one JSON line")
    args = ap.parse_args(argv)
    f = figures()
    if args.json:
        print(json.dumps(f))
        return 0
    g = graph()
    for k, v in f.items():
        print(f"{k}: {v}")
    for c in cycles(g):
        print("cycle:", " -> ".join(c))
    for v in layer_violations(g):
        print("layer:", v)
    return 0


if __name__ == "__main__":
    sys.exit(main())
