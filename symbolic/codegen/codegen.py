"""Code generation engine: families of CasADi functions -> one C file per function + manifest.

A model is a list of :class:`Family` objects (rpo's own are in :mod:`rpo.symbolic.codegen.functions`; the
build-system tests use a tiny fixture model).  A family is a group of generated functions that
are derived together (the plant; one controller) and is identified by a **family hash** over

* the bytes of every module of the package its derivation imports (the static import closure
  of its seed modules, see :func:`module_closure`),
* the hashes of the families it depends on (a controller's step embeds the plant),
* the generator's format version and the CasADi/SymPy versions.

:func:`generate` rebuilds only the families whose hash changed; the others are taken from the
previous ``generated/`` folder as they are (their files are verified against the manifest
first).  A family that needs an unchanged dependency's CasADi functions deserialises them from
that folder's ``<function>.casadi.gz`` instead of deriving them again, which is what makes a
controller edit cheap: the plant's SymPy derivation is not redone.

Output is deterministic: the same sources and tool versions give byte-identical files whether
a family was rebuilt or reused (``build.py --check`` regenerates everything from scratch and
compares bytes).  Files per generated function ``f``:

* ``f.c`` and ``f.h``: CasADi's C code, behind a banner with the family, its hash, the modules
  it came from and the operation count;
* ``f.casadi.gz``: the serialised CasADi function (for the explicit ``backend="casadi"``
  fallback, and as the derivation cache of dependent families).
"""

from __future__ import annotations

import ast
import gzip
import hashlib
import json
import os
import tempfile
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path
from typing import Any

#: Bump when the layout of generated files or the manifest schema changes.
FORMAT_VERSION = 2
#: Options of every CasADi code generator: a header per file; 64-bit integers (the runtime checks).
CG_OPTIONS = {"with_header": True, "casadi_int": "long long int"}
GENERATED_SUFFIXES = (".c", ".h", ".casadi.gz")


class ModelDefinitionError(ValueError):
    """The model cannot be generated as written (a controller module without DESIGN, two families
    generating one function, ...): build.py reports it in one line and exits 2."""


def tool_versions() -> dict[str, str]:
    """Versions of the tools whose output is committed, read without importing them (fast no-op builds)."""
    return {name: metadata.version(name) for name in ("casadi", "sympy")}


# --------------------------------------------------------------------------- what a model provides


@dataclass(frozen=True)
class Generated:
    """One function to generate: the CasADi function, the manifest layout name of each input and
    output (``None`` for an unnamed vector) and a one-line description."""

    fn: Any  # casadi.Function
    inputs: Sequence[str | None]
    outputs: Sequence[str | None]
    doc: str
    #: (C source, header) written instead of CasADi's code for ``fn`` (a composition of other
    #: generated functions, :mod:`rpo.symbolic.codegen.c_composition`); ``fn`` still gives the shapes and
    #: the serialised function of the CasADi fallback
    c_code: tuple[str, str] | None = None
    #: operation count to report (default: ``fn``'s own)
    ops: int | None = None


@dataclass
class FamilyOutput:
    """What a family's derivation produces: its functions, the layouts it defines (name ->
    ``Layout.describe()``), and top-level manifest entries (dicts are merged across families)."""

    functions: list[Generated]
    layouts: dict[str, list[dict]] = field(default_factory=dict)
    extra: dict[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class Family:
    """A group of functions derived together.

    ``seeds``: the module files the derivation starts from (their import closure inside
    ``root`` is hashed); ``depends``: names of families whose functions ``build`` may ask the
    resolver for; ``build(resolve) -> FamilyOutput``.
    """

    name: str
    seeds: tuple[Path, ...]
    build: Callable[[Callable[[str], Any]], FamilyOutput]
    depends: tuple[str, ...] = ()


# --------------------------------------------------------------------------- hashing


def _module_file(root: Path, parts: Sequence[str]) -> list[Path]:
    """The file(s) that importing the dotted module ``parts`` (relative to ``root``) executes:
    every package ``__init__.py`` on the way, then the module itself."""
    out = []
    cur = root
    for i, part in enumerate(parts):
        cur = cur / part
        if (cur / "__init__.py").exists():
            out.append(cur / "__init__.py")
        elif i == len(parts) - 1 and cur.with_suffix(".py").exists():
            out.append(cur.with_suffix(".py"))
        else:
            break
    return out


def _imports(path: Path, root: Path, package: str) -> set[Path]:
    """Files of ``root`` that ``path`` imports (relative imports, and absolute ones through ``package``)."""
    # the package the file is in (for a package's __init__.py: the package itself), as path parts
    here = list(path.relative_to(root).with_suffix("").parts[:-1])
    found: set[Path] = set()
    for node in ast.walk(ast.parse(path.read_bytes(), str(path))):
        if isinstance(node, ast.ImportFrom):
            if node.level:  # from . import x / from ..pkg.mod import y
                base = here[: len(here) - (node.level - 1)]
                mod = [*base, *(node.module.split(".") if node.module else [])]
            elif node.module == package or (node.module or "").startswith(package + "."):
                mod = [m for m in node.module[len(package):].split(".") if m]
            else:
                continue
            found.update(_module_file(root, mod))
            for alias in node.names:  # `from . import x` / `from .pkg import submodule`
                found.update(_module_file(root, [*mod, alias.name]))
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name == package or alias.name.startswith(package + "."):
                    found.update(_module_file(root, [m for m in alias.name[len(package):].split(".") if m]))
    found.discard(path)
    return {f for f in found if f.is_file()}


def module_closure(seeds: Iterable[Path], root: Path, package: str = "rpo.symbolic") -> list[Path]:
    """Every module file under ``root`` that the seeds import, directly or not (static analysis of
    the import statements; modules imported by computed name are not seen, so a family that
    discovers modules at run time names them as seeds).  Sorted, seeds included."""
    todo = [Path(s).resolve() for s in seeds]
    root = root.resolve()
    seen: set[Path] = set()
    while todo:
        f = todo.pop()
        if f in seen:
            continue
        seen.add(f)
        # importing a module runs the __init__ of its package(s), the root package's included
        for parent in f.relative_to(root).parents:
            init = root / parent / "__init__.py"
            if init != f and init.exists():
                todo.append(init)
        todo.extend(_imports(f, root, package) - seen)
    return sorted(seen)


def family_hashes(families: Sequence[Family], root: Path) -> dict[str, dict]:
    """``{family: {"hash": sha256, "modules": [relative paths]}}`` in dependency order."""
    tools = tool_versions()
    out: dict[str, dict] = {}
    for fam in _ordered(families):
        mods = module_closure(fam.seeds, root)
        h = hashlib.sha256(json.dumps({"format": FORMAT_VERSION, "tools": tools, "family": fam.name,
                                       "depends": {d: out[d]["hash"] for d in fam.depends}},
                                      sort_keys=True).encode())
        rels = [m.relative_to(root.resolve()).as_posix() for m in mods]
        for rel, m in zip(rels, mods, strict=True):
            h.update(rel.encode() + b"\0" + m.read_bytes() + b"\0")
        out[fam.name] = {"hash": h.hexdigest(), "modules": rels}
    return out


def _ordered(families: Sequence[Family]) -> list[Family]:
    by_name = {f.name: f for f in families}
    if len(by_name) != len(families):
        raise ValueError("two families share a name")
    done: list[Family] = []
    placed: set[str] = set()

    def visit(f: Family, chain: tuple[str, ...]) -> None:
        if f.name in placed:
            return
        if f.name in chain:
            raise ValueError(f"families depend on each other in a cycle: {' -> '.join((*chain, f.name))}")
        for d in f.depends:
            if d not in by_name:
                raise ValueError(f"family {f.name} depends on unknown family {d}")
            visit(by_name[d], (*chain, f.name))
        placed.add(f.name)
        done.append(f)

    for f in families:
        visit(f, ())
    return done


def source_hash(hashes: dict[str, dict]) -> str:
    """One hash of the whole model: over the family hashes (recorded in run.json)."""
    return hashlib.sha256(json.dumps({k: v["hash"] for k, v in hashes.items()}, sort_keys=True).encode()).hexdigest()


def manifest_hash(manifest: dict) -> str:
    """sha256 of the manifest's canonical JSON without its own ``manifest_hash`` field.

    The runtime recomputes it at load (a hand-edited layout, unit or default is refused) and
    includes it in the library cache key.  The same definition lives in
    ``rpo.runtime.compiled.manifest_hash``; ``tests/test_build.py`` checks that they agree.
    """
    body = {k: v for k, v in manifest.items() if k != "manifest_hash"}
    return hashlib.sha256(json.dumps(body, sort_keys=True, separators=(",", ":")).encode()).hexdigest()


# --------------------------------------------------------------------------- writing C


def _banner(name: str, doc: str, family: str, fhash: str, modules: list[str], ops: int) -> str:
    mods = "".join(f" *   symbolic/{m}\n" for m in modules)
    return (
        "/* GENERATED FILE - DO NOT EDIT.\n"
        f" * {name}: {doc}\n"
        f" * Produced by `python build.py` from family '{family}' (hash {fhash}),\n"
        " * derived from:\n"
        f"{mods}"
        f" * Operations: {ops} (CasADi SX instructions).  Edit symbolic/ and rebuild instead.\n"
        " */\n"
    )


def function_files(g: Generated, family: str, fhash: str, modules: list[str]) -> dict[str, bytes]:
    """The three files of one generated function, as bytes."""
    import casadi as ca

    name = g.fn.name()
    banner = _banner(name, g.doc, family, fhash, modules, _ops(g))
    if g.c_code is not None:
        files = {f"{name}.c": (banner + g.c_code[0]).encode(), f"{name}.h": (banner + g.c_code[1]).encode()}
        files[f"{name}.casadi.gz"] = gzip.compress(g.fn.serialize().encode(), compresslevel=9, mtime=0)
        return files
    with tempfile.TemporaryDirectory() as tmp:
        cwd = os.getcwd()
        os.chdir(tmp)  # CasADi writes into the working directory
        try:
            cg = ca.CodeGenerator(f"{name}.c", CG_OPTIONS)
            cg.add(g.fn)
            cg.generate()
            files = {f"{name}{ext}": (banner + Path(tmp, f"{name}{ext}").read_text()).encode()
                     for ext in (".c", ".h")}
        finally:
            os.chdir(cwd)
    files[f"{name}.casadi.gz"] = gzip.compress(g.fn.serialize().encode(), compresslevel=9, mtime=0)
    return files


def _ops(g: Generated) -> int:
    if g.ops is not None:
        return g.ops
    return int(g.fn.n_instructions()) if g.fn.is_a("SXFunction") else int(g.fn.n_nodes())


def describe(g: Generated, family: str) -> dict:
    fn = g.fn
    return {
        "doc": g.doc,
        "family": family,
        "source": f"{fn.name()}.c",
        "ops": _ops(g),
        "inputs": [{"name": fn.name_in(i), "shape": list(fn.size_in(i)), "layout": g.inputs[i]}
                   for i in range(fn.n_in())],
        "outputs": [{"name": fn.name_out(i), "shape": list(fn.size_out(i)), "layout": g.outputs[i]}
                    for i in range(fn.n_out())],
    }


# --------------------------------------------------------------------------- generate


def read_previous(gen_dir: Path | None) -> dict | None:
    """The manifest of an existing generated folder, or None (missing, unreadable, other format)."""
    if gen_dir is None or not (gen_dir / "manifest.json").exists():
        return None
    try:
        m = json.loads((gen_dir / "manifest.json").read_text())
    except (OSError, ValueError):
        return None
    if m.get("format_version") != FORMAT_VERSION or m.get("manifest_hash") != manifest_hash(m):
        return None
    return m


def reusable(prev: dict | None, gen_dir: Path | None, name: str, fhash: str) -> bool:
    """Whether family ``name`` (hash ``fhash``) can be taken from ``gen_dir`` as it is: the previous
    manifest records that hash and every file of the family is there with its recorded sha256."""
    if prev is None or gen_dir is None:
        return False
    fam = prev.get("families", {}).get(name)
    if not fam or fam.get("hash") != fhash:
        return False
    for fname in fam["files"]:
        f = gen_dir / fname
        if not f.is_file() or hashlib.sha256(f.read_bytes()).hexdigest() != prev["files"].get(fname):
            return False
    return True


@dataclass
class GenerateResult:
    manifest: dict
    files: dict[str, bytes]
    rebuilt: list[str]
    reused: list[str]


def generate(families: Sequence[Family], root: Path, reuse: Path | None = None,
             log: Callable[[str], None] | None = None) -> GenerateResult:
    """Derive the families whose hash changed (the rest are taken from ``reuse``, a previous
    generated folder); return every file's bytes and the manifest.  Nothing is written."""
    say = log or (lambda _msg: None)
    hashes = family_hashes(families, root)
    prev = read_previous(reuse)
    files: dict[str, bytes] = {}
    fam_records: dict[str, dict] = {}
    built: dict[str, Any] = {}  # function name -> casadi.Function built in this run
    owner: dict[str, str] = {}  # function name -> family
    rebuilt, reused = [], []
    fams = _ordered(families)

    def resolver(fam: Family):
        def resolve(fn_name: str):
            if owner.get(fn_name) not in fam.depends:
                raise ModelDefinitionError(f"family {fam.name} asks for {fn_name}, which no family it depends on "
                                           f"({', '.join(fam.depends) or 'none'}) generates")
            if fn_name in built:
                return built[fn_name]
            import casadi as ca

            return ca.Function.deserialize(gzip.decompress(files[f"{fn_name}.casadi.gz"]).decode())

        return resolve

    def depends_files(fam: Family) -> dict[str, str]:
        """sha256 over each dependency's files as they are now: a dependent family is reused only
        if its dependencies' generated code is what it was built against."""
        out = {}
        for d in fam.depends:
            dh = hashlib.sha256()
            for fname in sorted(fam_records[d]["files"]):
                dh.update(fname.encode() + b"\0" + hashlib.sha256(files[fname]).digest())
            out[d] = dh.hexdigest()
        return out

    for i, fam in enumerate(fams, 1):
        h = hashes[fam.name]
        deps_now = depends_files(fam)
        if (reusable(prev, reuse, fam.name, h["hash"]) and prev is not None
                and prev["families"][fam.name].get("depends_files", {}) == deps_now):
            assert prev is not None and reuse is not None
            rec = prev["families"][fam.name]
            for fname in rec["files"]:
                files[fname] = (reuse / fname).read_bytes()
            fam_records[fam.name] = rec
            for fn_name in rec["functions"]:
                if fn_name in owner:
                    raise ModelDefinitionError(f"function {fn_name} is generated by both {owner[fn_name]} and "
                                               f"{fam.name}")
                owner[fn_name] = fam.name
            reused.append(fam.name)
            continue
        t0 = time.perf_counter()
        say(f"[{i}/{len(fams)}] deriving {fam.name} ...")
        out = fam.build(resolver(fam))
        fnames, descs = [], {}
        for g in out.functions:
            name = g.fn.name()
            if name in owner:
                raise ModelDefinitionError(f"function {name} is generated by both {owner[name]} and {fam.name}")
            owner[name] = fam.name
            built[name] = g.fn
            ff = function_files(g, fam.name, h["hash"], h["modules"])
            files.update(ff)
            fnames.extend(sorted(ff))
            descs[name] = describe(g, fam.name)
        fam_records[fam.name] = {"hash": h["hash"], "modules": h["modules"], "files": fnames,
                                 "functions": descs, "layouts": out.layouts, "extra": out.extra,
                                 "depends_files": deps_now}
        rebuilt.append(fam.name)
        say(f"[{i}/{len(fams)}] {fam.name}: {len(out.functions)} functions in {time.perf_counter() - t0:.1f} s")

    manifest: dict[str, Any] = {
        "format_version": FORMAT_VERSION,
        "generator": "build.py",
        "source_hash": source_hash(hashes),
        "tools": tool_versions(),
        "families": {k: fam_records[k] for k in sorted(fam_records)},
        "files": {name: hashlib.sha256(data).hexdigest() for name, data in sorted(files.items())},
        "sources": sorted(n for n in files if n.endswith(".c")),
        "functions": {},
        "layouts": {},
    }
    for fam in fams:  # union of the families' contributions (dependency order, so deterministic)
        rec = fam_records[fam.name]
        manifest["functions"].update(rec["functions"])
        for lname, lay in rec["layouts"].items():
            if lname in manifest["layouts"] and manifest["layouts"][lname] != lay:
                raise ModelDefinitionError(f"layout {lname} is defined differently by two families")
            manifest["layouts"][lname] = lay
        for key, val in rec["extra"].items():
            if isinstance(val, dict):
                manifest.setdefault(key, {}).update(val)
            else:
                manifest[key] = val
    manifest["manifest_hash"] = manifest_hash(manifest)
    return GenerateResult(manifest, files, rebuilt, reused)


def manifest_bytes(manifest: dict) -> bytes:
    return (json.dumps(manifest, indent=1, sort_keys=True) + "\n").encode()


def is_generated_name(name: str) -> bool:
    return name == "manifest.json" or name.endswith(GENERATED_SUFFIXES)


def update_folder(result: GenerateResult, gen_dir: Path, keep: Iterable[str] = ("__init__.py",)) -> list[str]:
    """Bring ``gen_dir`` to ``result``, touching only files whose bytes differ.

    Each file is written to a temporary name in the folder and renamed over the old one
    (atomic); the manifest goes last, so a reader never sees a manifest that names files not
    yet written (and verifies every file's hash anyway).  Generated files the model no longer
    produces are removed.  The caller holds the folder's lock.  Returns the names written.
    """
    written = []
    wanted = dict(result.files)
    wanted["manifest.json"] = manifest_bytes(result.manifest)
    for name in [n for n in sorted(wanted) if n != "manifest.json"] + ["manifest.json"]:
        dst = gen_dir / name
        if dst.is_file() and dst.read_bytes() == wanted[name]:
            continue
        fd, tmp = tempfile.mkstemp(prefix=f".{name}.", dir=gen_dir)
        with os.fdopen(fd, "wb") as fh:
            fh.write(wanted[name])
        os.chmod(tmp, 0o644)
        os.replace(tmp, dst)
        written.append(name)
    keep = set(keep)
    for f in sorted(gen_dir.iterdir()):
        if f.is_file() and is_generated_name(f.name) and f.name not in wanted and f.name not in keep:
            f.unlink()
            written.append(f.name)
        elif f.is_file() and f.name.startswith(".") and is_generated_name(f.name[1:].rsplit(".", 1)[0]):
            # a temporary file of a build that died mid-write (the caller holds the lock: no live
            # build is writing one now); never loaded, but not left to accumulate either
            f.unlink()
    return written
