"""Build and load ``_rpo_fastcall`` (runtime/csrc/fastcall.c), the in-place call path of the
generated functions, into the cache.

It needs Python's C headers; without them (or without a C compiler) :func:`load` returns None
and the functions are called through ctypes: the same results, about 2 µs more per call.  The
extension is keyed like the model's objects (its source, the compiler identity, the Python
version and ABI), built through a temporary file and renamed into place under a lock.
"""

from __future__ import annotations

import hashlib
import importlib.machinery
import importlib.util
import os
import sys
import sysconfig
from pathlib import Path
from types import ModuleType

from rpo.runtime.errors import ModelError
from rpo.runtime.model.cache import cache_dir, ensure_built
from rpo.runtime.model.toolchain import compiler_command, csrc_dir, run_cc

SOURCE = "fastcall.c"
_loaded: dict[str, ModuleType | None] = {}
#: Why the extension is not in use (empty when it is).
why_not: list[str] = []


def load(cache: Path | None = None) -> ModuleType | None:
    """The ``_rpo_fastcall`` module, built if needed; None when it cannot be (see :data:`why_not`)."""
    if os.environ.get("RPO_NO_FASTCALL"):
        why_not[:] = ["RPO_NO_FASTCALL is set"]
        return None
    include = sysconfig.get_paths().get("include", "")
    if not include or not (Path(include) / "Python.h").exists():
        why_not[:] = [f"Python's C headers are not installed (no {include}/Python.h)"]
        return None
    try:
        cc, cc_id = compiler_command()
    except ModelError as exc:
        why_not[:] = [str(exc)]
        return None
    cache = cache_dir() if cache is None else Path(cache)
    src = (csrc_dir() / SOURCE).read_bytes()
    suffix = sysconfig.get_config_var("EXT_SUFFIX") or ".so"
    key = hashlib.sha256(src + cc_id.encode() + sys.version.encode() + suffix.encode() + include.encode()).hexdigest()
    path = cache / f"_rpo_fastcall_{key[:24]}{suffix}"
    if str(path) in _loaded:
        return _loaded[str(path)]
    try:
        cache.mkdir(parents=True, exist_ok=True)
        # built, or rebuilt when its bytes do not match the recorded sha256, before it is imported
        ensure_built(path, lambda tmp: run_cc([*cc, "-O2", "-fPIC", "-shared", "-I", include,
                                                str(csrc_dir() / SOURCE), "-o", str(tmp)],
                                               "compiling the fast-call extension", cc), "the fast-call extension")
        loader = importlib.machinery.ExtensionFileLoader("_rpo_fastcall", str(path))
        spec = importlib.util.spec_from_file_location("_rpo_fastcall", str(path), loader=loader)
        assert spec is not None
        module = importlib.util.module_from_spec(spec)
        loader.exec_module(module)
    except (OSError, ImportError, ModelError) as exc:
        why_not[:] = [f"the fast-call extension could not be built or loaded: {exc}"]
        module = None
    _loaded[str(path)] = module
    return module
