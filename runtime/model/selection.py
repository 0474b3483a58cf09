"""Which generated C files a call needs: the function's own file, the files of the functions a
composed step calls, and of a specialised callee only the copies the parameters select; and the stub
file that stands in for every callee left out."""

from __future__ import annotations

import re
from collections.abc import Iterable

import numpy as np

from rpo.runtime.errors import ModelError
from rpo.runtime.model.manifest import Manifest

#: a callee's declaration in a composed step (symbolic/codegen/c_composition.py writes one per callee)
_RE_DECL = re.compile(r"^int ([A-Za-z_]\w*)\(const casadi_real\*\* arg, casadi_real\*\* res, casadi_int\* iw, "
                      r"casadi_real\* w, int mem\);$", re.M)

#: the return code of a stub: a composed step passes it on as its own error (never 0)
STUB_RETURN = 1


def callees(text: str) -> list[str]:
    """The functions a generated C file calls (only composed steps call any), in order."""
    return list(dict.fromkeys(_RE_DECL.findall(text)))


def variant_choice(manifest: Manifest, p_offsets: dict[str, slice], base: str, P: np.ndarray) -> list[str]:
    """The copies of ``base`` (itself or its specialised copies) that the rows of ``P`` select, by the
    rule of the composed step's dispatch (c_composition.py): the first specialised copy whose
    ``zero`` fields of p are all 0, else ``base``."""
    specs = manifest.specialised.get(base, ())
    left = np.ones(P.shape[0], dtype=bool)
    chosen = []
    for s in specs:
        idx = np.concatenate([np.arange(p_offsets[f].start, p_offsets[f].stop) for f in s.zero])
        hit = left & np.all(P[:, idx] == 0.0, axis=1)
        if hit.any():
            chosen.append(s.function)
        left &= ~hit
    if left.any():
        chosen.append(base)
    return chosen


def needed_functions(manifest: Manifest, texts: dict[str, str], names: Iterable[str],
                     P: np.ndarray | None, p_offsets: dict[str, slice]) -> set[str]:
    """Every function a call of ``names`` may reach with parameters ``P`` (rows; None: any
    parameters, so every specialised copy).  ``texts``: source file -> its C text."""
    variant_of = {s.function: base for base, specs in manifest.specialised.items() for s in specs}
    chosen: dict[str, list[str]] = {}
    out: set[str] = set()
    todo = list(names)
    while todo:
        name = todo.pop()
        if name in out:
            continue
        desc = manifest.functions.get(name)
        if desc is None:
            raise ModelError(f"no generated function {name!r}")
        out.add(name)
        for c in callees(texts[desc.source]):
            base = variant_of.get(c, c)
            if P is not None and base in manifest.specialised:
                if base not in chosen:
                    chosen[base] = variant_choice(manifest, p_offsets, base, P)
                if c not in chosen[base]:
                    continue
            todo.append(c)
    return out


def stub_source(missing: Iterable[str], lanes: bool) -> bytes:
    """C text defining each ``missing`` callee (or its lane form) as a function that returns an error:
    a library linked for some parameters leaves out the specialised copies they never select."""
    names = sorted(set(missing))
    lines = ["/* rpo: callees this library was linked without (runtime/model/selection.py): the runs it was",
             " * selected for never reach them; a call returns an error (the step fails, nothing is computed). */"]
    if lanes:
        lines.append('#include "rpo_lanes.h"')
        sig = "(const rpo_v** arg, rpo_v** res, long long* iw, rpo_v* w, int mem)"
    else:
        sig = "(const double** arg, double** res, long long* iw, double* w, int mem)"
    for n in names:
        fn = f"{n}_lanes" if lanes else n
        lines.append(f"int {fn}{sig} {{ (void) arg; (void) res; (void) iw; (void) w; (void) mem; "
                     f"return {STUB_RETURN}; }}")
    return ("\n".join(lines) + "\n").encode()
