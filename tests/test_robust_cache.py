"""A corrupt, truncated or swapped cached library is detected (its sha256 against its side file)
before it is loaded, and rebuilt, or refused with one line; never a crash."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from rpo.runtime.errors import ModelError
from rpo.runtime.model import cache
from rpo.runtime.model.cache import _INTACT, cache_dir, digest_path, ensure_built, library_intact, sha256_file


def _builder(content: bytes, calls: list[int]):
    def build(tmp: Path) -> None:
        calls.append(1)
        tmp.write_bytes(content)
    return build


@pytest.fixture()
def sealed(tmp_path):
    """Two sealed 'libraries' in a cache folder (plain bytes: nothing here is loaded)."""
    a, b = tmp_path / "rpo_model_aaaa.so", tmp_path / "rpo_lanes_bbbb.so"
    for lib, byte in ((a, b"A"), (b, b"B")):
        ensure_built(lib, _builder(byte * 100_000, []), "a test library")
    _INTACT.clear()  # hash again in every test
    return a, b


def test_a_sealed_library_is_intact_and_hashed_once(sealed, monkeypatch):
    a, _ = sealed
    assert library_intact(a)
    rec = json.loads(digest_path(a).read_text())
    assert rec["name"] == a.name and rec["size"] == 100_000
    hashed: list[Path] = []
    real = sha256_file
    monkeypatch.setattr(cache, "sha256_file", lambda p: hashed.append(p) or real(p))
    assert library_intact(a) and library_intact(a)
    assert hashed == []  # the first call above (fixture cleared the memo) was before the patch
    _INTACT.clear()
    assert library_intact(a) and library_intact(a) and hashed == [a]


@pytest.mark.parametrize("damage", ["truncated", "flipped", "swapped", "no side file", "bad side file"])
def test_a_damaged_library_is_not_intact_and_is_rebuilt(sealed, damage):
    a, b = sealed
    data = a.read_bytes()
    if damage == "truncated":
        a.write_bytes(data[: len(data) // 2])
    elif damage == "flipped":  # same size, one byte changed
        a.write_bytes(data[:500] + b"X" + data[501:])
    elif damage == "swapped":  # another library and its own side file copied under this name
        shutil.copyfile(b, a)
        shutil.copyfile(digest_path(b), digest_path(a))
    elif damage == "no side file":
        digest_path(a).unlink()
    else:
        digest_path(a).write_text("{not json")
    _INTACT.clear()
    assert not library_intact(a)
    calls: list[int] = []
    lines: list[str] = []
    assert ensure_built(a, _builder(b"A" * 100_000, calls), "a test library", log=lines.append)
    assert calls == [1] and library_intact(a) and a.read_bytes() == data
    assert len(lines) == 1 and str(a) in lines[0] and "rebuilding a test library" in lines[0]
    assert not [f for f in a.parent.iterdir() if "tmp" in f.name or f.name.endswith(".part")]


def test_a_damaged_library_that_cannot_be_replaced_is_refused_in_one_line(sealed, monkeypatch):
    a, _ = sealed
    a.write_bytes(b"garbage")
    _INTACT.clear()
    real_unlink = Path.unlink

    def unlink(self, missing_ok=False):
        if self == a:
            raise PermissionError(13, "Permission denied")
        return real_unlink(self, missing_ok=missing_ok)

    monkeypatch.setattr(Path, "unlink", unlink)
    with pytest.raises(ModelError) as err:
        ensure_built(a, _builder(b"A", []), "a test library")
    msg = str(err.value)
    assert "\n" not in msg and str(a) in msg and "corrupt" in msg and "RPO_CACHE_DIR" in msg
    assert a.read_bytes() == b"garbage"  # and it was not loaded: ensure_built never loads


def test_a_build_failure_leaves_no_library_and_no_temporary_file(tmp_path):
    lib = tmp_path / "rpo_model_cccc.so"

    def build(tmp: Path) -> None:
        tmp.write_bytes(b"half")
        raise ModelError("linking failed (planted)")

    with pytest.raises(ModelError, match="planted"):
        ensure_built(lib, build, "a test library")
    assert not lib.exists() and not digest_path(lib).exists()
    assert [f.name for f in tmp_path.iterdir()] == [f".{lib.name}.lock"]


CHECK = """
import numpy as np
from rpo.runtime import load_model
from rpo.runtime.model import fastcall
from rpo.runtime.run.simulate import Simulation
m = load_model(log=print)
m.prepare(m.functions)  # the whole library (the one planted), not only what the run below calls
lanes = m.lanes()
assert fastcall.load() is not None, fastcall.why_not
sim = Simulation(m)
z0 = sim.initial_state({"q_c": [0, 0, 0, 1], "q_t": [0, 0, 0, 1], "r": [60, 0, 25], "v": [0, 0, 0]})
one = sim.run(z0, 0.05, seed=3)
two = sim.run_batch(np.array([z0, z0]), 0.05, seeds=[3, 4])
assert m.lanes().width >= 1 and np.array_equal(one.z, two[0].z) and not np.array_equal(one.z, two[1].z)
print("OK", m.library, m.lanes().path)
"""


def test_truncated_swapped_and_corrupt_cached_libraries_are_rebuilt_before_loading(model, tmp_path):
    """The real libraries: the model's truncated, the lane library replaced by the model's (with
    its side file), the fast-call extension's bytes flipped.  A fresh process detects all three,
    relinks them from the cached objects and runs (a truncated library used to die of SIGBUS)."""
    src = cache_dir()
    model.prepare(model.functions)  # the whole library, as the check below loads it
    lanes = model.lanes().path
    exts = sorted(src.glob("_rpo_fastcall_*.so"))
    assert model.library.parent == src and lanes.parent == src and exts
    cache = tmp_path / "cache"
    shutil.copytree(src / "obj", cache / "obj")
    for f in (model.library, lanes, *exts):
        for g in (f, digest_path(f)):
            shutil.copy2(g, cache / g.name)
    lib_c, lanes_c, ext_c = cache / model.library.name, cache / lanes.name, cache / exts[-1].name
    lib_c.write_bytes(lib_c.read_bytes()[:4096])
    shutil.copyfile(lib_c.with_name(model.library.name), lanes_c)
    shutil.copyfile(digest_path(lib_c), digest_path(lanes_c))
    data = bytearray(ext_c.read_bytes())
    data[len(data) // 2] ^= 0xFF
    ext_c.write_bytes(bytes(data))
    env = {**os.environ, "RPO_CACHE_DIR": str(cache)}
    res = subprocess.run([sys.executable, "-c", CHECK], capture_output=True, text=True, env=env, timeout=300)
    assert res.returncode == 0, res.stderr[-2000:]
    assert f"OK {lib_c} {lanes_c}" in res.stdout
    assert f"{lib_c} does not match its recorded name and sha256" in res.stdout
    assert f"{lanes_c} does not match its recorded name and sha256" in res.stdout
    _INTACT.clear()
    assert all(library_intact(f) for f in (lib_c, lanes_c, ext_c))
    assert lib_c.read_bytes() == model.library.read_bytes() and lanes_c.read_bytes() == lanes.read_bytes()
