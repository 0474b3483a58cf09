"""The hostile-input corpus of campaign folders and campaign files (``tests/campaign_corpus/cases.toml``,
issue 25): a tiny real campaign is flown once (:func:`build_reference`: ``tests/campaign_corpus/tiny.toml``,
6 runs of 20 s in 2 batches), each case copies its folder, damages it (:func:`damage`), maybe arms a
fault (:func:`fault`: a full disk, a read-only file system, a lock held elsewhere, all without root) and
runs one ``rpo`` command in-process, its exit code and output captured (:func:`play`).
``tests/test_campaign_corpus.py`` checks every case; the summary for quoting is

    python -m tests.campaign_corpus_summary        (from the repository root)

which prints one line per case and the counts by exit code and by group.
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import io
import json
import os
import shutil
import sys
import tomllib
import traceback
from collections import Counter
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

HERE = Path(__file__).with_name("campaign_corpus")
CASES_FILE = HERE / "cases.toml"
TINY = HERE / "tiny.toml"
RUNS = 6  # tiny.toml's [campaign] runs


@dataclass(frozen=True)
class Case:
    """One hostile input.  ``command``: ``resume``, ``report``, ``replay`` (``rpo run --campaign DIR
    --case N``) or ``run`` (``rpo mc run FILE --out OUT``: ``campaign`` is the file's text appended
    to tiny.toml's scenario, or the whole file with ``whole = true``); ``damage``: what is done to
    the reference folder first; ``fault``: an OSError armed while the command runs; ``then``: a
    command run afterwards without the fault (``resume``: the folder must be resumable to the
    reference summary).  ``exit`` and ``fragment``: the exit code and a piece of its output."""

    id: str
    exit: int
    fragment: str
    command: str = "resume"
    args: tuple[str, ...] = ()
    damage: tuple[dict, ...] = ()
    fault: str = ""
    then: str = ""
    campaign: str = ""
    whole: bool = False
    out: str = "new"
    same_summary: bool | None = None

    @property
    def group(self) -> str:
        return self.id.split("-")[0]


def load_cases(path: Path = CASES_FILE) -> list[Case]:
    raw = tomllib.loads(path.read_text())["case"]
    out = []
    for c in raw:
        c = dict(c)
        c["args"] = tuple(c.get("args", ()))
        c["damage"] = tuple(c.get("damage", ()))
        out.append(Case(**c))
    ids = [c.id for c in out]
    assert len(ids) == len(set(ids)), "case ids must be unique"
    return out


# --------------------------------------------------------------------------- running rpo in this process


@dataclass
class Outcome:
    """A command's exit code (None: an exception escaped ``main``), stdout and stderr."""

    code: int | None
    stdout: str
    stderr: str
    then: Outcome | None = None
    #: summary.parquet's bytes before the command (None: none): a summary the damage wrote is not rpo's
    summary_before: bytes | None = None


def invoke(argv: list[str]) -> Outcome:
    """``rpo ARGV`` in this process (the entry point's ``main``), stdout and stderr captured."""
    from rpo.runtime.cli.main import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code: int | None = main([str(a) for a in argv])
        except BaseException:  # noqa: BLE001 - a traceback is what the corpus must never see
            traceback.print_exc(file=err)
            code = None
    return Outcome(code, out.getvalue(), err.getvalue())


def build_reference(folder: Path) -> Path:
    """Fly tiny.toml into ``folder/ref`` (one process, quiet) and return the campaign folder."""
    ref = folder / "ref"
    o = invoke(["mc", "run", TINY, "--out", ref, "--workers", "1", "-q"])
    if o.code != 0:
        raise RuntimeError(f"the corpus's reference campaign did not fly: {o.stderr}")
    return ref


# --------------------------------------------------------------------------- damage


def _target(folder: Path, name: str) -> Path:
    """A path of the folder; ``@0``/``@1``: the first/second history file (cases 0-2, 3-5)."""
    if name.startswith("@"):
        return sorted((folder / "histories").glob("batch_*.parquet"))[int(name[1:])]
    return folder / name


def damage(folder: Path, ops: tuple[dict, ...]) -> None:
    """Apply each operation of a case's ``damage`` to the campaign ``folder`` (see cases.toml's head)."""
    man = folder / "manifest.jsonl"
    for op in ops:
        kind = op["op"]
        lines = man.read_bytes().splitlines(keepends=True) if man.exists() else []
        if kind == "append":
            man.write_bytes(b"".join(lines) + op["text"].encode() + (b"" if op.get("raw") else b"\n"))
        elif kind == "dup":
            man.write_bytes(b"".join(lines) + lines[op["line"] - 1])
        elif kind == "edit":  # merge a JSON object into line N (``drop``: keys removed)
            row = json.loads(lines[op["line"] - 1])
            row.update(json.loads(op.get("json", "{}")))
            for k in op.get("drop", []):
                row.pop(k, None)
            lines[op["line"] - 1] = (json.dumps(row, sort_keys=True) + "\n").encode()
            man.write_bytes(b"".join(lines))
        elif kind == "edit_all":
            out = []
            for ln in lines:
                row = json.loads(ln)
                row.update(json.loads(op.get("json", "{}")))
                for k in op.get("drop", []):
                    row.pop(k, None)
                out.append((json.dumps(row, sort_keys=True) + "\n").encode())
            man.write_bytes(b"".join(out))
        elif kind == "replace":
            lines[op["line"] - 1] = op["text"].encode() + b"\n"
            man.write_bytes(b"".join(lines))
        elif kind == "delete_line":
            del lines[op["line"] - 1]
            man.write_bytes(b"".join(lines))
        elif kind == "cut_last":  # the last line cut half-way, as a killed or full-disk write leaves it
            man.write_bytes(b"".join(lines[:-1]) + lines[-1][: len(lines[-1]) // 2])
        elif kind == "remove":
            p = _target(folder, op["path"])
            shutil.rmtree(p) if p.is_dir() else p.unlink()
        elif kind == "write":
            _target(folder, op["path"]).write_text(op["text"])
        elif kind == "truncate":  # keep the first ``head`` and the last ``tail`` bytes
            p = _target(folder, op["path"])
            b = p.read_bytes()
            p.write_bytes(b[: op.get("head", 0)] + (b[-op["tail"]:] if op.get("tail") else b""))
        elif kind == "flip":  # one byte changed (``at`` from the start; negative: from the end)
            p = _target(folder, op["path"])
            b = bytearray(p.read_bytes())
            b[op["at"]] ^= 0xFF
            p.write_bytes(bytes(b))
        elif kind == "dir":  # a folder where a file should be
            p = _target(folder, op["path"])
            p.unlink(missing_ok=True)
            p.mkdir()
        elif kind == "copy":  # another file's bytes in place of this one
            _target(folder, op["to"]).write_bytes(_target(folder, op["path"]).read_bytes())
        elif kind == "summary_case":  # the summary with one more row: the first row's copy as case ``case``
            import pyarrow as pa
            import pyarrow.parquet as pq
            t = pq.read_table(folder / "summary.parquet")
            extra = t.slice(0, 1).set_column(0, "case", pa.array([op["case"]], pa.int64()))
            pq.write_table(pa.concat_tables([t, extra]), folder / "summary.parquet")
        elif kind == "tmp":  # a temporary file a killed writer left
            (folder / op["path"]).write_bytes(b"half a file")
        elif kind == "resolved":  # merge into resolved.json (``drop``: keys removed)
            p = folder / "resolved.json"
            data = json.loads(p.read_text())
            data.update(json.loads(op.get("json", "{}")))
            for k in op.get("drop", []):
                data.pop(k, None)
            p.write_text(json.dumps(data))
        else:
            raise ValueError(f"unknown damage op {kind!r}")


# --------------------------------------------------------------------------- faults (no root needed)


def _oserror(code: int, path: Any) -> OSError:
    return OSError(code, os.strerror(code), str(path))


@contextlib.contextmanager
def fault(name: str, folder: Path) -> Iterator[None]:
    """Arm the OSError ``name`` for the block by monkeypatching the writer it hits: the disk full
    (``enospc-*``), a read-only file system or a refused permission (``erofs-*``, ``eacces-*``),
    a lock held by another open file (``lock-held``).  Patching, not a real full disk or chmod:
    the tests run without root and without a small file system (and root ignores permissions)."""
    if not name:
        yield
        return
    from rpo.runtime.campaign import execute, storage
    from rpo.runtime.cli import campaign as cli_campaign

    saved: list[tuple[Any, str, Any]] = []

    def patch(obj: Any, attr: str, new: Any) -> None:
        saved.append((obj, attr, getattr(obj, attr)))
        setattr(obj, attr, new)

    real_append, real_write = storage.append_rows, storage._atomic_write
    if name == "enospc-manifest":  # the lines of the first batch written half-way, then the disk is full
        def append(folder_: Path, rows: Any, sync: bool = True) -> bool:
            import orjson
            data = b"".join(orjson.dumps(r, option=storage._LINE) for r in rows)
            with open(Path(folder_) / storage.MANIFEST, "ab") as fh:
                fh.write(data[: len(data) // 2])
            raise _oserror(errno.ENOSPC, Path(folder_) / storage.MANIFEST)
        patch(storage, "append_rows", append)
    elif name == "enospc-fsync":  # every fsync fails: the manifest's and the summary's
        def fsync(fd: int) -> None:
            raise _oserror(errno.ENOSPC, folder / storage.MANIFEST)
        patch(os, "fsync", fsync)
    elif name in ("enospc-summary", "eacces-summary"):  # the summary's temporary written, then refused
        code = errno.ENOSPC if name.startswith("enospc") else errno.EACCES

        def write(path: Path, data: bytes, durable: bool = True) -> None:
            if path.name == storage.SUMMARY:
                tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
                tmp.write_bytes(data[: len(data) // 2])
                try:
                    raise _oserror(code, tmp)
                finally:
                    tmp.unlink()  # what _atomic_write's cleanup does
            real_write(path, data, durable)
        patch(storage, "_atomic_write", write)
    elif name == "enospc-history":  # the worker cannot write its batch's histories
        def history(folder_: Path, runs: Any, units: Any) -> tuple[str, str]:
            name_ = storage.history_name([r.case for r in runs])
            raise _oserror(errno.ENOSPC, Path(folder_) / storage.HISTORIES / name_)
        patch(storage, "write_history_file", history)
    elif name == "erofs-start":  # the new folder's first file refused
        def write(path: Path, data: bytes, durable: bool = True) -> None:
            raise _oserror(errno.EROFS, path)
        patch(storage, "_atomic_write", write)
    elif name == "erofs-cache":  # the model cache is read-only: its lock cannot be made
        def model(controller: str, quiet: bool) -> Any:
            raise _oserror(errno.EROFS, "rpo-cache/.lock")
        patch(cli_campaign, "_model", model)
    elif name == "eacces-lock":  # the folder's lock file cannot be created
        real_open = os.open

        def open_(path: Any, flags: int, mode: int = 0o777, *a: Any, **kw: Any) -> int:
            if str(path).endswith("/.lock"):
                raise _oserror(errno.EACCES, path)
            return real_open(path, flags, mode, *a, **kw)
        patch(os, "open", open_)
    elif name == "no-dask":  # the dask extra not installed
        import importlib.util
        real_find = importlib.util.find_spec

        def find_spec(name_: str, *a: Any, **kw: Any) -> Any:
            return None if name_ == "distributed" else real_find(name_, *a, **kw)
        patch(importlib.util, "find_spec", find_spec)
    elif name == "lock-held":  # another command holds the folder (another open file: flock says busy)
        fd = os.open(folder / ".lock", os.O_RDWR | os.O_CREAT)
        fcntl.flock(fd, fcntl.LOCK_EX)
        os.ftruncate(fd, 0)
        os.write(fd, b"4242\n")
        saved.append((os, "close", fd))
    else:
        raise ValueError(f"unknown fault {name!r}")
    del real_append, execute
    try:
        yield
    finally:
        for obj, attr, old in reversed(saved):
            if attr == "close":
                os.close(old)
            else:
                setattr(obj, attr, old)


# --------------------------------------------------------------------------- a case


def _argv(case: Case, folder: Path, work: Path) -> list[Any]:
    if case.command == "resume":
        return ["mc", "resume", folder, "--workers", "1", *case.args]
    if case.command == "report":
        return ["mc", "report", folder, *case.args]
    if case.command == "replay":
        return ["run", "--campaign", folder, "--no-plots", "--out", work / "case", *case.args]
    if case.command == "run":
        return ["mc", "run", work / "c.toml", "--out", folder, "--workers", "1", "-q", *case.args]
    raise ValueError(f"unknown command {case.command!r}")


def play(case: Case, ref: Path, work: Path) -> tuple[Outcome, Path]:
    """Run ``case`` in ``work`` (an empty folder) against the reference folder ``ref``; returns its
    outcome (with ``then``'s) and the campaign folder it acted on."""
    folder = work / "mc"
    if case.command == "run":
        text = case.campaign if case.whole else TINY.read_text().split("[campaign]")[0] + case.campaign
        (work / "c.toml").write_text(text)
        if case.out == "nonempty":
            folder.mkdir()
            (folder / "notes.txt").write_text("mine")
        elif case.out == "file":
            folder.write_text("a file")
        elif case.out == "ref":
            shutil.copytree(ref, folder)
    else:
        shutil.copytree(ref, folder)
        damage(folder, case.damage)
    summary = folder / "summary.parquet"
    before = summary.read_bytes() if summary.is_file() else None
    with fault(case.fault, folder):
        o = invoke(_argv(case, folder, work))
    o.summary_before = before
    if case.then == "resume":
        o.then = invoke(["mc", "resume", folder, "--workers", "1", "-q"])
    elif case.then:
        raise ValueError(f"unknown then {case.then!r}")
    return o, folder


def expect_same_summary(case: Case) -> bool:
    """Whether the case's folder must end with the reference's summary bytes: a resume that
    succeeds, or a case followed by a resume."""
    if case.same_summary is not None:
        return case.same_summary
    return case.then == "resume" or (case.command == "resume" and case.exit == 0)


def check(case: Case, o: Outcome, folder: Path, ref: Path) -> list[str]:
    """What is wrong with an outcome (empty: as expected): the exit code, the fragment, no traceback,
    one ``error:`` line for a refusal, nothing made by a refused ``mc run``, the summary never counting
    a line that is not a run record, and the reference's summary bytes where the folder is resumed."""
    import pyarrow.parquet as pq

    wrong = []
    text = o.stdout + o.stderr
    if o.code != case.exit:
        wrong.append(f"exit {o.code}, expected {case.exit}: {o.stderr.strip()[-300:]}")
    if case.fragment not in text:
        wrong.append(f"{case.fragment!r} not in the output: {text.strip()[-300:]}")
    if "Traceback" in text:
        wrong.append("a traceback")
    errors = [ln for ln in o.stderr.splitlines() if ln.startswith("error:")]
    if case.exit == 2 and len(errors) != 1:
        wrong.append(f"{len(errors)} error lines, expected one")
    if case.exit == 2 and case.command == "run" and case.out == "new" and folder.exists():
        wrong.append(f"a refused `rpo mc run` left {folder}")
    summary = folder / "summary.parquet"
    if folder.is_dir() and summary.is_file() and summary.read_bytes() != o.summary_before:  # written by rpo
        try:
            cases = pq.read_table(summary, columns=["case"]).column("case").to_pylist()
        except Exception:  # noqa: BLE001 - a junk summary the case wrote itself
            cases = None
        if cases is not None and (len(cases) > RUNS or len(set(cases)) != len(cases)
                                  or any(not 0 <= c < RUNS for c in cases)):
            wrong.append(f"the summary counts {len(cases)} rows: {cases}")
    if o.then is not None:
        if o.then.code != 0:
            wrong.append(f"the resume afterwards: exit {o.then.code}: {o.then.stderr.strip()[-300:]}")
        if "Traceback" in o.then.stderr:
            wrong.append("a traceback in the resume afterwards")
    if expect_same_summary(case):
        if not summary.is_file() or summary.read_bytes() != (ref / "summary.parquet").read_bytes():
            wrong.append("the resumed summary differs from the uninterrupted campaign's")
        if list(folder.rglob(".*.tmp")):
            wrong.append(f"temporary files left: {list(folder.rglob('.*.tmp'))}")
    return wrong


def main() -> int:
    import tempfile

    from rpo.runtime.model.manifest import read_manifest

    cases = load_cases()
    by_code: Counter = Counter()
    by_group: Counter = Counter()
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        read_manifest()
        ref = build_reference(Path(tmp))
        for i, case in enumerate(cases):
            work = Path(tmp) / str(i)
            work.mkdir()
            o, folder = play(case, ref, work)
            wrong = check(case, o, folder, ref)
            failures += bool(wrong)
            by_code[o.code] += 1
            by_group[case.group] += 1
            shown = next((ln for ln in (o.stderr + o.stdout).splitlines() if case.fragment in ln), "")
            print(f"{'ok  ' if not wrong else 'FAIL'} exit {o.code}  {case.id:<36s} {shown.strip()[:150]}")
            for w in wrong:
                print(f"       {w[:300]}")
    print(f"\n{len(cases)} cases, {failures} not as expected")
    print("exit codes: " + ", ".join(f"{code}: {n}" for code, n in sorted(by_code.items(), key=str)))
    print("groups: " + ", ".join(f"{g} {n}" for g, n in sorted(by_group.items())))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
