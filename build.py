#!/usr/bin/env python3
"""Regenerate ``generated/`` from the SymPy model in ``symbolic/`` and compile it.

    python build.py            # regenerate the families whose sources changed, then compile into the cache
    python build.py --check    # regenerate everything from scratch in memory; exit 1 with a diff if stale
    python build.py --force    # re-derive every family even if its hash is unchanged
    python build.py --no-compile

Generated code is organised in families (the plant; one per controller module; see
``symbolic/codegen/functions.py``).  A family is re-derived only when a module it imports changed, and a
controller family reuses the plant's CasADi functions from ``generated/`` instead of deriving the
plant again.  Compilation is one object file per generated function, compiled in parallel on
every core and cached by content hash; the library is linked from the cached objects.

The build always uses *this checkout's* symbolic/, runtime/ and generated/, as ``import rpo`` finds
them after ``pip install -e .`` in this checkout; if rpo is not installed, or installed from elsewhere
(another checkout, a wheel), it stops with one line saying so before anything is read or written.
"""

from __future__ import annotations

import argparse
import difflib
import gzip
import importlib.util
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent
GEN = ROOT / "generated"


#: The packages of rpo that must come from this checkout, and their folders in it.
CHECKOUT_PACKAGES = {"rpo.symbolic": "symbolic", "rpo.runtime": "runtime", "rpo.generated": "generated"}


def installed_elsewhere(root: Path = ROOT) -> str | None:
    """None if ``import rpo`` imports this checkout's symbolic/, runtime/ and generated/ (as after
    ``pip install -e .`` here), else one line saying what is wrong and what to run.

    Only looks (``importlib.util.find_spec``): nothing of rpo runs before the check passes.
    """
    fix = f"run `pip install -e .` in this checkout ({root}) with this Python ({sys.executable})"
    for name, folder in CHECKOUT_PACKAGES.items():
        try:
            spec = importlib.util.find_spec(name)
        except (ImportError, ValueError):
            spec = None
        if spec is None or not spec.origin:
            return f"rpo is not installed: {fix}"
        where = Path(spec.origin).resolve().parent
        if where != (root / folder).resolve():
            return f"{name} is imported from {where}, not from this checkout: {fix}"
    return None


def require_checkout(script: str) -> None:
    """Exit 2 with :func:`installed_elsewhere`'s one line unless rpo is this checkout's."""
    problem = installed_elsewhere()
    if problem is not None:
        print(f"{script}: {problem}", file=sys.stderr)
        sys.exit(2)


def _text(name: str, data: bytes) -> list[str]:
    data = gzip.decompress(data) if name.endswith(".gz") else data
    return data.decode().splitlines(keepends=True)


def compare(new: dict[str, bytes], gen_dir: Path) -> list[str]:
    """Readable differences between a fresh generation (name -> bytes) and ``gen_dir`` (empty when equal).

    Serialised functions are compared decompressed, so a different zlib cannot cause a false alarm.
    """
    from rpo.symbolic.codegen.codegen import is_generated_name

    out = []
    old = {p.name for p in gen_dir.iterdir() if p.is_file() and is_generated_name(p.name)}
    for name in sorted(set(new) | old):
        if name not in old:
            out.append(f"generated/{name}: missing (would be created)\n")
            continue
        if name not in new:
            out.append(f"generated/{name}: not produced by the current model (would be removed)\n")
            continue
        a, b = _text(name, (gen_dir / name).read_bytes()), _text(name, new[name])
        if a != b:
            diff = list(difflib.unified_diff(a, b, f"generated/{name} (committed)",
                                             f"generated/{name} (from symbolic/)", n=1))
            out.append(f"generated/{name}: differs ({len(diff)} diff lines)\n")
            out.extend(line if len(line) < 300 else line[:300] + "...\n" for line in diff[:60])
            if len(diff) > 60:
                out.append(f"... {len(diff) - 60} more diff lines\n")
    return out


def stale_families(gen_dir: Path = GEN, families=None, root: Path | None = None) -> tuple[list[str], list[str]]:
    """(families to re-derive, families generated/ has that the model no longer defines).

    ``families``/``root`` default to rpo's model (``symbolic/codegen/functions.py``); tests pass a fixture model.
    """
    from rpo.symbolic.codegen import codegen, functions

    fams = functions.families() if families is None else families
    hashes = codegen.family_hashes(fams, functions.SYMBOLIC_DIR if root is None else root)
    prev = codegen.read_previous(gen_dir)
    stale = [f.name for f in fams if not codegen.reusable(prev, gen_dir, f.name, hashes[f.name]["hash"])]
    gone = sorted(set((prev or {}).get("families", {})) - set(hashes))
    return stale, gone


def regenerate(gen_dir: Path = GEN, force: bool = False, log=print, families=None,
               root: Path | None = None) -> list[str]:
    """Bring ``gen_dir`` up to date under its lock; return the families re-derived ([] if none)."""
    from rpo.runtime.model.cache import file_lock
    from rpo.symbolic.codegen import codegen, functions

    root = functions.SYMBOLIC_DIR if root is None else root
    with file_lock(gen_dir / ".lock"):  # a second build waits here, then finds nothing to do
        fams = functions.families() if families is None else families
        stale, gone = stale_families(gen_dir, fams, root)
        if not (stale or gone or force):
            return []
        if gone:
            log(f"removing families no longer in symbolic/: {', '.join(gone)}")
        result = codegen.generate(fams, root, reuse=None if force else gen_dir, log=log)
        written = codegen.update_folder(result, gen_dir)
        log(f"generated/: re-derived {', '.join(result.rebuilt) or 'nothing'}; "
            f"{len(written)} file(s) written, {len(result.files) + 1 - len(written)} unchanged")
        return result.rebuilt or gone


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--check", action="store_true", help="fail (exit 1) if generated/ does not match symbolic/")
    ap.add_argument("--force", action="store_true", help="re-derive every family even if nothing changed")
    ap.add_argument("--no-compile", action="store_true", help="do not compile the shared library")
    ap.add_argument("--jobs", "-j", type=int, default=None,
                    help="parallel compiler processes (default: every core)")
    args = ap.parse_args(argv)
    if args.jobs is not None and args.jobs < 1:
        print(f"build.py: --jobs must be >= 1 (got {args.jobs})", file=sys.stderr)
        return 2

    require_checkout("build.py")
    from rpo.runtime.errors import RpoError
    from rpo.symbolic.codegen import codegen, functions
    from rpo.symbolic.codegen.codegen import ModelDefinitionError

    t0 = time.perf_counter()
    if args.check:
        try:
            result = codegen.generate(functions.families(), functions.SYMBOLIC_DIR, reuse=None, log=print)
        except ModelDefinitionError as exc:
            print(f"error: {exc}", file=sys.stderr)
            return 2
        files = dict(result.files)
        files["manifest.json"] = codegen.manifest_bytes(result.manifest)
        diff = compare(files, GEN)
        if diff:
            sys.stdout.writelines(diff)
            print("build.py --check: generated/ is STALE: it does not match symbolic/. "
                  "Run `python build.py` and commit generated/.")
            return 1
        print(f"build.py --check: generated/ matches symbolic/ ({len(files)} files, "
              f"{time.perf_counter() - t0:.1f} s)")
        return 0

    try:
        rebuilt = regenerate(GEN, force=args.force)
    except ModelDefinitionError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    if not rebuilt:
        print("generated/ is up to date: nothing to regenerate")
    else:
        print(f"wrote generated/ in {time.perf_counter() - t0:.1f} s")
    if args.no_compile:
        return 0
    from rpo.runtime.model.library import build_library

    try:
        lib, compiled = build_library(GEN, log=print, jobs=args.jobs)
    except RpoError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(f"{'compiled' if compiled else 'library up to date, nothing to compile'}: {lib} "
          f"({time.perf_counter() - t0:.1f} s in all)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
