"""The call graph gcc writes with -fcallgraph-info=su (one VCG ``.ci`` file per object), merged over a
package's objects: the worst-case stack of one call and the recursion cycles.

A ``.ci`` file holds one ``node:`` per function: a function defined in that source has a label ending
in ``N bytes (static)`` (or ``(dynamic)``, ``(dynamic,bounded)``: alloca or a VLA), a function only
called there is an ``ellipse`` without a size; an ``edge:`` is one call site.  Global functions are
titled by their name, file-local (static) ones ``file.c:name``, so merging the files joins a call to a
global function with its definition in another source; a callee defined in no source of the package
(libm, libgcc) is *not counted*: its frames are outside the bound.  An indirect call is the node
``__indirect_call``: its callee is unknown, so is the bound.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from rpo.runtime.flight.tools import Finding

INDIRECT = "__indirect_call"

_NODE = re.compile(r'^node: \{ title: "([^"]*)" label: "([^"]*)"')
_EDGE = re.compile(r'^edge: \{ sourcename: "([^"]*)" targetname: "([^"]*)"')
_SIZE = re.compile(r"\\n(\d+) bytes \(([^)]*)\)")


@dataclass(frozen=True)
class Frame:
    """A function defined in the package: its frame [bytes], whether gcc could size it statically
    (``static``; else ``dynamic`` or ``dynamic,bounded``) and where it is (file:line)."""

    name: str
    size: int
    qualifier: str
    file: str
    line: int


@dataclass
class CallGraph:
    frames: dict[str, Frame] = field(default_factory=dict)
    calls: dict[str, list[str]] = field(default_factory=dict)

    def callees(self, title: str) -> list[str]:
        return self.calls.get(title, [])


def _where(label: str) -> tuple[str, str, int]:
    """(name, file, line) from a node label ``name\\nfile:line:col\\n...``."""
    parts = label.split("\\n")
    name = parts[0]
    loc = parts[1].split(":") if len(parts) > 1 else []
    line = int(loc[1]) if len(loc) > 2 and loc[1].isdigit() else 0
    return name, (loc[0] if loc else ""), line


def read_callgraph(files: list[Path]) -> CallGraph:
    """The call graph of a package: its ``.ci`` files merged (a node's definition wins over a mention)."""
    g = CallGraph()
    for ci in files:
        for raw in ci.read_text(encoding="utf-8", errors="replace").splitlines():
            line = raw.strip()
            m = _NODE.match(line)
            if m:
                title, label = m.groups()
                size = _SIZE.search(label)
                if size is not None:
                    name, file, lineno = _where(label)
                    g.frames[title] = Frame(name, int(size.group(1)), size.group(2), file, lineno)
                continue
            e = _EDGE.match(line)
            if e:
                src, dst = e.groups()
                callees = g.calls.setdefault(src, [])
                if dst not in callees:
                    callees.append(dst)
    return g


@dataclass
class StackBound:
    """The worst-case stack of one call of ``entry``: ``bytes`` (None when unknown: a dynamic frame, an
    indirect call, recursion, or no such function), the worst path, the callees outside the package."""

    entry: str
    bytes: int | None
    path: list[str]
    not_counted: list[str]
    findings: list[Finding]


def stack_bound(g: CallGraph, entry: str, where: str = "") -> StackBound:
    """The maximum over the call paths from ``entry`` of the sum of their frames."""
    findings: list[Finding] = []
    outside: set[str] = set()
    if entry not in g.frames:
        findings.append(Finding("stack", f"{entry} is not defined in the package", rule="entry", where=where))
        return StackBound(entry, None, [], [], findings)
    memo: dict[str, tuple[int, list[str]]] = {}
    active: list[str] = []
    reported: set[str] = set()

    def once(key: str, finding: Finding) -> None:
        if key not in reported:
            reported.add(key)
            findings.append(finding)

    def worst(title: str) -> tuple[int, list[str]]:
        if title in memo:
            return memo[title]
        f = g.frames[title]
        if f.qualifier != "static":
            once("dyn:" + title, Finding("stack", f"{f.name} has a {f.qualifier} stack frame (alloca or a VLA): "
                                         "the bound is unknown", file=f.file, line=f.line, rule="dynamic",
                                         where=where))
        active.append(title)
        best: tuple[int, list[str]] = (0, [])
        for callee in g.callees(title):
            if callee == INDIRECT:
                once("ind:" + title, Finding("stack", f"{f.name} makes an indirect call: the bound is unknown",
                                             file=f.file, line=f.line, rule="indirect", where=where))
            elif callee in active:
                cycle = [*active[active.index(callee):], callee]
                once("rec:" + callee, Finding("stack", "recursion: " + " -> ".join(cycle)
                                              + ": the bound is unknown", file=f.file, line=f.line,
                                              rule="recursion", where=where))
            elif callee in g.frames:
                sub = worst(callee)
                if sub[0] > best[0] or not best[1]:
                    best = sub
            else:
                outside.add(callee)
        active.pop()
        memo[title] = (f.size + best[0], [title, *best[1]])
        return memo[title]

    total, path = worst(entry)
    return StackBound(entry, None if findings else total, path, sorted(outside), findings)


def cycles(g: CallGraph) -> list[list[str]]:
    """The recursion in the whole graph: each strongly connected component of more than one function,
    or one function that calls itself (Tarjan's algorithm)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in g.callees(v):
            if w not in g.frames:
                continue
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp: list[str] = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1 or v in g.callees(v):
                out.append(sorted(comp))

    for v in sorted(g.frames):
        if v not in index:
            visit(v)
    return sorted(out)
