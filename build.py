#!/usr/bin/env python3
"""Regenerate ``generated/`` from the SymPy model in ``symbolic/`` and compile it.

    python build.py            # regenerate if symbolic/ changed, then compile into the cache
    python build.py --check    # regenerate into a temporary folder; exit 1 with a diff if stale
    python build.py --force    # regenerate even if the source hash is unchanged

The build always uses *this checkout's* symbolic/, runtime/ and generated/ (never an installed
copy of rpo), so it works before ``pip install`` and cannot pick up the wrong model.
"""

from __future__ import annotations

import argparse
import difflib
import gzip
import importlib.util
import json
import os
import sys
import tempfile
import time
import types
from pathlib import Path

ROOT = Path(__file__).resolve().parent
GEN = ROOT / "generated"


def _bootstrap() -> None:
    """Import rpo.symbolic / rpo.runtime / rpo.generated from this checkout."""
    pkg = types.ModuleType("rpo")
    pkg.__path__ = []
    sys.modules["rpo"] = pkg
    for sub in ("symbolic", "runtime", "generated"):
        spec = importlib.util.spec_from_file_location(
            f"rpo.{sub}", ROOT / sub / "__init__.py", submodule_search_locations=[str(ROOT / sub)])
        mod = importlib.util.module_from_spec(spec)
        sys.modules[f"rpo.{sub}"] = mod
        setattr(pkg, sub, mod)
        spec.loader.exec_module(mod)


def _read(path: Path) -> list[str]:
    data = gzip.decompress(path.read_bytes()) if path.suffix == ".gz" else path.read_bytes()
    return data.decode().splitlines(keepends=True)


def _compare(new_dir: Path, old_dir: Path) -> list[str]:
    """Readable differences between a fresh generation and generated/ (empty when equal)."""
    out = []
    new_files = {p.name for p in new_dir.iterdir()}
    old_files = {p.name for p in old_dir.iterdir() if p.name not in ("__init__.py", "__pycache__", ".lock")}
    for name in sorted(new_files | old_files):
        if name not in old_files:
            out.append(f"generated/{name}: missing (would be created)\n")
            continue
        if name not in new_files:
            out.append(f"generated/{name}: not produced by the current model (would be removed)\n")
            continue
        a, b = _read(old_dir / name), _read(new_dir / name)
        if a != b:
            diff = list(difflib.unified_diff(a, b, f"generated/{name} (committed)",
                                             f"generated/{name} (from symbolic/)", n=1))
            out.append(f"generated/{name}: differs ({len(diff)} diff lines)\n")
            out.extend(line if len(line) < 300 else line[:300] + "...\n" for line in diff[:60])
            if len(diff) > 60:
                out.append(f"... {len(diff) - 60} more diff lines\n")
    return out


def _up_to_date(codegen) -> tuple[bool, str]:
    from rpo.runtime.compiled import read_manifest
    from rpo.runtime.errors import ModelError

    try:
        manifest = read_manifest(GEN)
    except (ModelError, json.JSONDecodeError, KeyError) as exc:
        return False, str(exc)
    if manifest.get("source_hash") != codegen.source_hash():
        return False, "symbolic/ changed since generated/ was written"
    if manifest.get("tools") != codegen.tool_versions():
        return False, f"tool versions changed: {manifest.get('tools')} -> {codegen.tool_versions()}"
    if manifest.get("format_version") != codegen.FORMAT_VERSION:
        return False, "manifest format changed"
    return True, f"source hash {manifest['source_hash'][:12]}"


def _generate_into_generated(codegen) -> None:
    """Generate into a temporary folder next to generated/, then move files in (manifest last)."""
    from rpo.runtime.compiled import _file_lock

    with _file_lock(GEN / ".lock"), tempfile.TemporaryDirectory(dir=ROOT, prefix=".gen-") as tmp:
        codegen.generate(Path(tmp))
        names = sorted(p.name for p in Path(tmp).iterdir())
        for name in [n for n in names if n != "manifest.json"] + ["manifest.json"]:
            os.replace(Path(tmp) / name, GEN / name)
        for stale in GEN.iterdir():
            if stale.is_file() and stale.name not in names and stale.name not in ("__init__.py", ".lock"):
                stale.unlink()


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--check", action="store_true", help="fail (exit 1) if generated/ does not match symbolic/")
    ap.add_argument("--force", action="store_true", help="regenerate even if nothing changed")
    ap.add_argument("--no-compile", action="store_true", help="do not compile the shared library")
    args = ap.parse_args(argv)

    _bootstrap()
    from rpo.runtime.errors import RpoError
    from rpo.symbolic import codegen

    t0 = time.perf_counter()
    if args.check:
        with tempfile.TemporaryDirectory() as tmp:
            codegen.generate(Path(tmp))
            diff = _compare(Path(tmp), GEN)
        if diff:
            sys.stdout.writelines(diff)
            print("build.py --check: generated/ is STALE: it does not match symbolic/. "
                  "Run `python build.py` and commit generated/.")
            return 1
        print(f"build.py --check: generated/ matches symbolic/ ({time.perf_counter() - t0:.1f} s)")
        return 0

    ok, why = _up_to_date(codegen)
    if ok and not args.force:
        print(f"generated/ is up to date ({why}): nothing to regenerate")
    else:
        print(f"regenerating generated/ ({'forced' if ok else why}) ...")
        _generate_into_generated(codegen)
        print(f"wrote generated/ in {time.perf_counter() - t0:.1f} s")
    if args.no_compile:
        return 0
    from rpo.runtime.compiled import build_library

    try:
        lib, compiled = build_library(GEN, log=print)
    except RpoError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(f"{'compiled' if compiled else 'library up to date, nothing to compile'}: {lib}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
