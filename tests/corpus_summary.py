"""The malformed-input corpus of ``tests/corpus/cases.toml``: each case's file made, the ``rpo``
command run in-process on it, its exit code and stderr captured.  ``tests/test_corpus.py`` runs
every case through :func:`outcomes`; the summary the issue asks for is

    python -m tests.corpus_summary        (from the repository root)

which prints one line per case and per command (exit code, whether the fragment was found) and the
counts by exit code and by group (the id's first word).
"""

from __future__ import annotations

import contextlib
import io
import os
import sys
import tomllib
import traceback
from collections import Counter
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CASES_FILE = Path(__file__).with_name("corpus") / "cases.toml"
SCENARIOS = ROOT / "scenarios"
DEFAULT_BASE = "000_scenario_III"


@dataclass(frozen=True)
class Case:
    """One input: ``toml`` is a variant of the paper scenario ``base`` (``raw:<text>``: the whole file;
    ``cut:<scenario>:<table>``: that scenario without a table), or ``special`` names a file that is not
    a plain scenario text (see :func:`materialise`).  ``command``: ``both`` (validate and run) or
    ``run``; ``args``: extra options of ``rpo run``.  ``exit`` and ``fragment``: what stderr must show
    (``run_exit``: the run's code where it differs from validate's, e.g. 3 for a divergence)."""

    id: str
    exit: int
    fragment: str
    toml: str = ""
    base: str = DEFAULT_BASE
    special: str | None = None
    command: str = "both"
    args: tuple[str, ...] = ()
    run_exit: int | None = None

    @property
    def group(self) -> str:
        """What the case is about: ``file`` (the file itself), ``syntax``, ``command line``, ``valid``
        or the first table it sets (``controller`` for every gains table)."""
        if self.exit == 0:
            return "valid"
        if self.special or self.base.startswith("cut:"):
            return "file"
        if self.base.startswith("raw:"):
            return "syntax"
        if self.command == "run":
            return "command line"
        tables = [ln.strip("[] ") for ln in self.toml.splitlines() if ln.startswith("[")]
        first = tables[-1] if tables else "?"  # the last table: e.g. [simulation] controller, then [controller.x]
        return "controller" if first.startswith("controller") else first.split(".")[0]


def load_cases(path: Path = CASES_FILE) -> list[Case]:
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    cases = [Case(**{**c, "args": tuple(c.get("args", ()))}) for c in data["case"]]
    ids = [c.id for c in cases]
    dupes = sorted(i for i, n in Counter(ids).items() if n > 1)
    if dupes:
        raise ValueError(f"{path}: case ids twice: {dupes}")
    return cases


# --------------------------------------------------------------------------- files


def _scenario_text(name: str) -> str:
    return (SCENARIOS / f"{name}.toml").read_text(encoding="utf-8")


def _without_table(text: str, table: str) -> str:
    out, skip = [], False
    for line in text.splitlines(keepends=True):
        if line.startswith("["):
            skip = line.strip() == f"[{table}]"
        if not skip:
            out.append(line)
    return "".join(out)


def _variant(case: Case) -> str:
    if case.base.startswith("raw:"):
        return case.base[4:]
    if case.base.startswith("cut:"):
        _, name, table = case.base.split(":")
        return _without_table(_scenario_text(name), table)
    return f'extends = "{SCENARIOS / (case.base + ".toml")}"\n' + case.toml


@contextlib.contextmanager
def _refused_open(path: Path) -> Iterator[None]:
    """As root, a mode-000 file is still readable: make opening it fail as it would for a user."""
    if os.geteuid() != 0:
        yield
        return
    real_open = os.open

    def fake_open(p, *args, **kw):
        if Path(p) == path:
            raise PermissionError(13, "Permission denied", str(p))
        return real_open(p, *args, **kw)

    os.open = fake_open
    try:
        yield
    finally:
        os.open = real_open


def _base_file(kind: str, folder: Path) -> str:
    """The ``extends`` target of the special cases ``extends_<kind>``."""
    target = folder / "base.toml"
    if kind == "missing":
        return "missing.toml"
    if kind == "directory":
        target.mkdir()
    elif kind == "fifo":
        os.mkfifo(target)
    elif kind == "dev_zero":
        return "/dev/zero"
    elif kind == "cycle":
        target.write_text('extends = "case.toml"\n')
    elif kind == "self":
        return "case.toml"
    elif kind == "too_deep":
        for i in range(20):
            nxt = f"base{i + 1}.toml" if i < 19 else str(SCENARIOS / f"{DEFAULT_BASE}.toml")
            (folder / f"base{i}.toml").write_text(f'extends = "{nxt}"\n')
        return "base0.toml"
    elif kind == "latin1":
        target.write_bytes(b"[meta]\nname = '\xe9'\n")
    elif kind == "invalid_toml":
        target.write_text("[simulation\n")
    elif kind == "too_large":
        target.write_text(_scenario_text(DEFAULT_BASE) + ("#" * 99 + "\n") * 11000)
    else:
        raise ValueError(f"unknown special case extends_{kind}")
    return "base.toml"


def materialise(case: Case, folder: Path) -> tuple[Path, contextlib.AbstractContextManager]:
    """Write the case's file(s) into the empty ``folder``; returns the path to give the command and
    a context to run it in."""
    path = folder / "case.toml"
    ctx: contextlib.AbstractContextManager = contextlib.nullcontext()
    sp = case.special
    if sp is None:
        path.write_text(_variant(case), encoding="utf-8")
    elif sp == "missing":
        pass
    elif sp == "directory":
        path.mkdir()
    elif sp == "fifo":
        os.mkfifo(path)
    elif sp == "dev_zero":
        path = Path("/dev/zero")
    elif sp == "unreadable":
        path.write_text(_scenario_text(DEFAULT_BASE))
        path.chmod(0)
        ctx = _refused_open(path)
    elif sp == "too_large":
        path.write_text(_scenario_text(DEFAULT_BASE) + ("#" * 99 + "\n") * 11000)
    elif sp == "latin1":
        path.write_bytes(_scenario_text(DEFAULT_BASE).encode() + b"\n[meta]\nname = '\xe9'\n")
    elif sp == "empty":
        path.write_text("")
    elif sp == "nul_bytes":
        path.write_bytes(b'[meta]\nname = "a\x00b"\n')
    elif sp == "utf8_bom":
        path.write_bytes(b"\xef\xbb\xbf" + _scenario_text(DEFAULT_BASE).encode())
    elif sp == "symlink_to_fifo":
        os.mkfifo(folder / "pipe")
        path.symlink_to(folder / "pipe")
    elif sp == "symlink_loop":
        path.symlink_to(folder / "other.toml")
        (folder / "other.toml").symlink_to(path)
    elif sp == "not_a_dir_component":
        (folder / "file.toml").write_text(_scenario_text(DEFAULT_BASE))
        path = folder / "file.toml" / "case.toml"
    elif sp.startswith("extends_"):
        base = _base_file(sp.removeprefix("extends_"), folder)
        path.write_text(f'extends = "{base}"\n[meta]\nname = "variant"\n')
    else:
        raise ValueError(f"{case.id}: unknown special {sp!r}")
    return path, ctx


# --------------------------------------------------------------------------- running


@contextlib.contextmanager
def manifest_read_once() -> Iterator[None]:
    """Every CLI call reads the manifest; ``read_manifest`` verifies and parses a generated folder once
    per process (again only if one of its files changes), so the ~360 calls of the corpus hash the
    generated files once: read it here, before the first call is timed."""
    from rpo.runtime.model.manifest import read_manifest

    read_manifest()
    yield


@dataclass
class Outcome:
    """A command's exit code (None: an exception escaped ``main``), stdout and stderr."""

    command: str
    code: int | None
    stdout: str
    stderr: str
    created: list[str] = field(default_factory=list)  # files the command left in the case's folder


def invoke(argv: list[str]) -> tuple[int | None, str, str]:
    """``rpo ARGV`` in this process (the entry point's ``main``), stdout and stderr captured."""
    from rpo.runtime.cli.main import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code: int | None = main(argv)
        except BaseException:  # noqa: BLE001 - a traceback is what the corpus must never see
            traceback.print_exc(file=err)
            code = None
    return code, out.getvalue(), err.getvalue()


def outcomes(case: Case, folder: Path) -> list[Outcome]:
    """Run the case (validate and/or run) in ``folder`` (empty; one sub-folder per command)."""
    commands = ["validate", "run"] if case.command == "both" else [case.command]
    results = []
    for command in commands:
        sub = folder / command
        sub.mkdir()
        path, ctx = materialise(case, sub)
        before = set(os.listdir(sub))
        argv = [command, str(path)]
        if command == "run":
            argv += ["--out", str(sub / "out"), "--no-plots", "--quiet", *case.args]
        with ctx:
            code, stdout, stderr = invoke(argv)
        created = sorted(set(os.listdir(sub)) - before)
        results.append(Outcome(command, code, stdout, stderr, created))
    return results


def expected_code(case: Case, command: str) -> int:
    return case.run_exit if command == "run" and case.run_exit is not None else case.exit


def main() -> int:
    import tempfile

    os.environ.setdefault("COLUMNS", "100")
    cases = load_cases()
    by_code: Counter = Counter()
    by_group: Counter = Counter()
    failures = 0
    with tempfile.TemporaryDirectory() as tmp, manifest_read_once():
        for i, case in enumerate(cases):
            folder = Path(tmp) / str(i)
            folder.mkdir()
            for o in outcomes(case, folder):
                ok = o.code == expected_code(case, o.command) and case.fragment in o.stderr \
                    and "Traceback" not in o.stderr
                failures += not ok
                by_code[(o.command, o.code)] += 1
                line = o.stderr.strip().splitlines()[0] if o.stderr.strip() else ""
                print(f"{'ok  ' if ok else 'FAIL'} {o.command:<8s} exit {o.code}  {case.id:<34s} {line[:150]}")
            by_group[case.group] += 1
    malformed = sum(1 for c in cases if c.exit != 0)
    print(f"\n{len(cases)} cases ({malformed} malformed, {len(cases) - malformed} valid), "
          f"{sum(by_code.values())} commands, {failures} not as expected")
    print("exit codes: " + ", ".join(f"{cmd} {code}: {n}" for (cmd, code), n in sorted(by_code.items(), key=str)))
    print("groups: " + ", ".join(f"{g} {n}" for g, n in sorted(by_group.items())))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
