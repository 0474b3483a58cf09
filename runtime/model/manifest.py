"""The generated model's manifest: read and verified against its sources, hashed (the runtime's only
knowledge of the model, the acados way)."""

from __future__ import annotations

import hashlib
import json
from collections.abc import Iterable
from importlib import resources
from pathlib import Path

from rpo.runtime.errors import ModelError

#: The manifest format this runtime reads (``rpo.symbolic.codegen.codegen.FORMAT_VERSION``; a test checks they agree).
MANIFEST_FORMAT = 2


def generated_dir() -> Path:
    """The folder holding the generated sources and manifest (``rpo.generated``)."""
    return Path(str(resources.files("rpo.generated")))


def read_manifest(gen_dir: Path | None = None, verify: bool = True) -> dict:
    """Read ``manifest.json`` and check the generated files against the hashes it records."""
    gen_dir = generated_dir() if gen_dir is None else Path(gen_dir)
    path = gen_dir / "manifest.json"
    if not path.exists():
        raise ModelError(f"{path} is missing: run `python build.py` in the rpo checkout")
    try:
        manifest = json.loads(path.read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ModelError(f"{path} cannot be read ({exc}): run `python build.py`") from exc
    if manifest.get("format_version") != MANIFEST_FORMAT:
        raise ModelError(f"{path} has format {manifest.get('format_version')}, this runtime reads format "
                         f"{MANIFEST_FORMAT}: run `python build.py`")
    if verify:
        if manifest.get("manifest_hash") != manifest_hash(manifest):
            raise ModelError(f"{path} does not match its recorded hash (edited by hand?): run `python build.py`")
        for name, digest in manifest["files"].items():
            f = gen_dir / name
            if not f.exists():
                raise ModelError(f"{f} is missing: run `python build.py`")
            if hashlib.sha256(f.read_bytes()).hexdigest() != digest:
                raise ModelError(f"{f} does not match manifest.json (edited by hand or half-written):"
                                 " run `python build.py`")
    return manifest


def manifest_hash(manifest: dict) -> str:
    """sha256 of the manifest's canonical JSON without its ``manifest_hash`` field.

    Same definition as ``rpo.symbolic.codegen.codegen.manifest_hash`` (the runtime must not import
    rpo.symbolic); ``tests/test_build.py`` checks that the two agree.
    """
    body = {k: v for k, v in manifest.items() if k != "manifest_hash"}
    return hashlib.sha256(json.dumps(body, sort_keys=True, separators=(",", ":")).encode()).hexdigest()


def selected_sources(manifest: dict, controllers: Iterable[str] | None = None) -> list[str]:
    """The generated C files a library needs: all of them, or (``controllers`` given) those of the
    families that belong to no controller (the plant) plus the families of the named controllers.

    A first ``rpo run`` compiles only what its scenario flies; the objects are cached and shared
    with any later, larger selection.
    """
    if controllers is None:
        return list(manifest["sources"])
    ctrls = manifest.get("controllers", {})
    unknown = sorted(set(controllers) - set(ctrls))
    if unknown:
        raise ModelError(f"unknown controller {', '.join(unknown)}; available: {', '.join(sorted(ctrls))}")
    funcs = manifest["functions"]
    owned = {name: {funcs[f]["family"] for f in entry.values() if f in funcs} for name, entry in ctrls.items()}
    all_ctrl = set().union(*owned.values()) if owned else set()
    keep = set().union(*(owned[c] for c in controllers)) if controllers else set()
    return [d["source"] for d in sorted(funcs.values(), key=lambda d: d["source"])
            if d["family"] not in all_ctrl or d["family"] in keep]
