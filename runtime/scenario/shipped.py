"""The scenarios shipped with rpo: the package data of ``rpo.scenarios``, in every install mode.

The repository's top-level ``scenarios/`` folder is installed as the package ``rpo.scenarios``
(setup.py maps it; ``scenarios/__init__.py``).  :mod:`importlib.resources` finds it wherever rpo is
installed: the checkout's ``scenarios/`` after ``pip install -e .``, ``site-packages/rpo/scenarios``
after ``pip install .`` or from a wheel.  Nothing here looks for a folder next to the sources.

A shipped scenario is named by its path under that folder without ``.toml``: ``000_scenario_III``,
``campaigns/000_III_mc`` (a campaign may also be named by its file name alone, ``000_III_mc``).
``rpo scenarios`` lists them (:func:`shipped`) and copies one out for editing (:func:`copy_out`).
"""

from __future__ import annotations

import difflib
import os
import re
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from rpo.runtime.errors import OutputError, RpoError, ScenarioError
from rpo.runtime.scenario.loader import parse_toml, read_scenario, read_text

#: The package whose data the shipped scenario files are.
PACKAGE = "rpo.scenarios"
#: The top-level ``extends = "..."`` line of a scenario (the key precedes every table in TOML).
_EXTENDS = re.compile(r"""^(?P<head>extends[ \t]*=[ \t]*)(?P<q>["'])(?P<value>[^"'\n]*)(?P=q)""", re.MULTILINE)


def folder() -> Path:
    """The folder of the shipped scenarios, as found by :mod:`importlib.resources`.

    Every install pip makes (editable, ``pip install .``, a wheel) puts it on disk, where ``extends``
    can resolve a base file next to a variant; anything else is an error naming the package.
    """
    try:
        root = resources.files(PACKAGE)
    except ModuleNotFoundError:
        raise RpoError(f"the shipped scenarios ({PACKAGE}) are not installed: reinstall rpo") from None
    path = Path(str(root))
    if not isinstance(root, Path) or not path.is_dir():
        raise RpoError(f"the shipped scenarios ({PACKAGE}) are not a folder on disk ({root}): reinstall rpo "
                       "from a wheel or a checkout")
    return path


@dataclass(frozen=True)
class Shipped:
    """One shipped file: its ``name`` (path under :func:`folder` without ``.toml``), ``path``, ``kind``
    (``"scenario"`` or ``"campaign"``) and a one-line ``description`` from its own header."""

    name: str
    path: Path
    kind: str
    description: str


def _description(path: Path) -> tuple[str, str]:
    """(kind, one line) from the file's own tables (not its base's): ``[campaign]`` or ``[meta]``
    ``description``, else their ``name``, else the first line of the header comment."""
    text = read_text(path)
    own = parse_toml(text, str(path))
    kind = "campaign" if isinstance(own.get("campaign"), dict) else "scenario"
    table = own.get(kind if kind == "campaign" else "meta")
    table = table if isinstance(table, dict) else {}
    for key in ("description", "name"):
        if isinstance(table.get(key), str) and table[key].strip():
            return kind, " ".join(table[key].split())
    for line in text.splitlines():
        if line.startswith("#") and line.strip("# \t"):
            return kind, " ".join(line.strip("# \t").split())
    return kind, ""


def shipped() -> list[Shipped]:
    """Every shipped scenario and campaign (``*.toml`` under :func:`folder`), scenarios first, by name."""
    root = folder()
    out = []
    for path in sorted(root.rglob("*.toml")):
        rel = path.relative_to(root).with_suffix("").as_posix()
        out.append(Shipped(rel, path, *_description(path)))
    return sorted(out, key=lambda s: (s.name.count("/"), s.name))


def find(name: str) -> Shipped:
    """The shipped file called ``name`` (``.toml`` optional; a file name alone if only one has it);
    an unknown name is a one-line :class:`ScenarioError` with the nearest names."""
    key = name.removesuffix(".toml").strip("/")
    every = shipped()
    hits = [s for s in every if s.name == key] or [s for s in every if s.name.rsplit("/", 1)[-1] == key]
    if len(hits) == 1:
        return hits[0]
    if hits:
        raise ScenarioError(f"shipped scenario {name!r} is ambiguous: {', '.join(s.name for s in hits)}")
    near = difflib.get_close_matches(key, [s.name for s in every], n=3, cutoff=0.5)
    hint = f"; did you mean {' or '.join(near)}?" if near else ""
    raise ScenarioError(f"no shipped scenario {name!r}{hint} (`rpo scenarios` lists them)")


def _with_extends(text: str, source: Path, value: str) -> str:
    """``text`` with its ``extends`` value replaced by ``value`` (the rest byte for byte)."""
    m = _EXTENDS.search(text)
    if m is None:
        raise ScenarioError(f"{source}: extends: not a one-line string, cannot point the copy at its base")
    new = f"{text[:m.start('value')]}{value}{text[m.end('value'):]}"
    if parse_toml(new, str(source)).get("extends") != value:
        raise ScenarioError(f"{source}: extends: not a one-line string, cannot point the copy at its base")
    return new


@dataclass(frozen=True)
class Copied:
    """One file of :func:`copy_out`: where it went, the shipped file, and whether it was written
    (``False``: an identical file was there already and is used as it is)."""

    path: Path
    source: Path
    written: bool


def copy_out(name: str, to: str | Path) -> list[Copied]:
    """Copy the shipped scenario ``name`` to the file ``to`` (or into the folder ``to``) for editing.

    A variant needs its base: the files it ``extends`` are copied next to it under their own names,
    and ``extends`` points at those copies (``"../000_scenario_III.toml"`` becomes
    ``"000_scenario_III.toml"``), so the copy reads as the shipped file does.  Nothing is ever
    overwritten: an existing ``to`` is refused, and so is an existing base that differs from the
    shipped one (an identical one is used as it is); the check comes before anything is written.
    """
    item = find(name)
    target = Path(to)
    if target.is_dir() or str(to).endswith(("/", os.sep)):  # "into/": a folder, even one that is missing
        target = target / item.path.name
    where = target.parent
    if not where.is_dir():
        raise OutputError(f"{target}: cannot copy {item.name} there: the folder {where} does not exist")
    if os.path.lexists(target):
        raise OutputError(f"{target} exists; not overwritten (choose another --to, or delete it first)")
    chain = [item.path, *read_scenario(item.path).bases]
    dests = [target, *(where / base.name for base in chain[1:])]
    if len({d.name for d in dests}) < len(dests):
        raise OutputError(f"{target}: the copy of {item.name} would have the name of its base "
                          f"{chain[1].name} (choose another --to)")
    plan: list[tuple[Copied, str | None]] = []  # (file, text to write; None: there already)
    for i, (src, dest) in enumerate(zip(chain, dests, strict=True)):
        text = read_text(src)
        if i + 1 < len(chain):
            text = _with_extends(text, src, dests[i + 1].name)
        if i and os.path.lexists(dest):
            if not dest.is_file() or dest.read_bytes() != text.encode():
                raise OutputError(f"{dest} exists and is not the shipped {src.name} that {item.name} extends; "
                                  "not overwritten (copy into another folder)")
            plan.append((Copied(dest, src, False), None))
        else:
            plan.append((Copied(dest, src, True), text))
    done: list[Path] = []
    try:
        for copied, text in plan:
            if text is not None:
                with open(copied.path, "x", encoding="utf-8", newline="") as f:  # "x": never replaces a file
                    done.append(copied.path)
                    f.write(text)
    except OSError as exc:
        for p in done:
            p.unlink(missing_ok=True)
        raise OutputError(f"{target}: cannot copy {item.name}: {exc.strerror or exc}") from None
    return [copied for copied, _ in plan]
