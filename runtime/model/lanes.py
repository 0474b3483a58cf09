"""The lane form of a generated C file: the same straight-line code over K runs at once.

CasADi's generated body is straight-line code with one operation per line (``a3=(a1*a2);``,
``a4=sin(a3);``, ``a5=(a1<=a2);``, ``a6=(a5?a4:0);``, ``if (res[0]!=0) res[0][2]=a6;`` ...).
:func:`lane_source` rewrites it line by line over the element type ``rpo_v`` of
``runtime/csrc/rpo_lanes.h`` (K doubles in a GCC vector, K = the target's vector width, or one
double): arithmetic stays as written; comparisons, logic and ``?:`` become mask operations of
rpo_math.h with the scalar code's values (1.0 / 0.0, +0.0 for a false ``?:``); math calls become
rpo_math.h's functions, which the scalar compile of the same file also calls (it is compiled
with ``-include rpo_math_scalar.h``), so that a lane's result is bit-identical to the scalar
result.  A ``sin`` and a ``cos`` of the same value become one ``rpo_sincos``.

Every line must match a known form: an unknown construct raises :class:`LaneError` naming the
file and the line, so a CasADi upgrade or a new operation can never be translated silently
wrong.  The C glue of the composed steps (``step_<ctrl>``, written by
``rpo.symbolic.codegen.c_composition``) is translated by type and callee name.

Pure text work (no SymPy, no CasADi): the runtime transforms the verified bytes of
``generated/`` when it builds the lane library.
"""

from __future__ import annotations

import re

#: Bump when the translation changes: it is part of the lane objects' cache key.
LANES_VERSION = 2


class LaneError(ValueError):
    """A generated file has a construct the lane translation does not know."""


_V = r"a\d+"
_NUM = r"-?(?:\d+\.\d*(?:e[+-]?\d+)?|\d+e[+-]?\d+|\d+)"
_ATOM = rf"(?:{_V}|{_NUM})"

#: CasADi helper or C math call -> rpo_math.h function (one or two arguments).
MATH = {
    "sin": "rpo_sin", "cos": "rpo_cos", "tan": "rpo_tan", "exp": "rpo_exp", "log": "rpo_log",
    "atan": "rpo_atan", "atan2": "rpo_atan2", "asin": "rpo_asin", "acos": "rpo_acos",
    "sinh": "rpo_sinh", "cosh": "rpo_cosh", "tanh": "rpo_tanh", "sqrt": "rpo_sqrt", "floor": "rpo_floor",
    "ceil": "rpo_ceil", "fabs": "rpo_fabs", "casadi_fabs": "rpo_fabs", "casadi_fmax": "rpo_fmax",
    "casadi_fmin": "rpo_fmin", "fmax": "rpo_fmax", "fmin": "rpo_fmin", "casadi_sign": "rpo_sign",
}

_CMP = {"<": "RPO_LT", "<=": "RPO_LE", "==": "RPO_EQ", "!=": "RPO_NE", ">": "RPO_GT", ">=": "RPO_GE"}

_RE_DECL = re.compile(r"^\s*casadi_real ((?:a\d+, )*a\d+);$")
_RE_ARG = re.compile(rf"^\s*({_V})=arg\[(\d+)\]\? arg\[\2\]\[(\d+)\] : 0;$")
_RE_RES = re.compile(rf"^\s*if \(res\[(\d+)\]!=0\) res\[\1\]\[(\d+)\]=({_V});$")
_RE_CONST = re.compile(rf"^\s*({_V})=({_NUM});$")
_RE_BIN = re.compile(rf"^\s*({_V})=\(({_ATOM})(\*|\+|-|/|<=|<|==|!=|>=|>|&&|\|\|)({_ATOM})\);$")
_RE_NEG = re.compile(rf"^\s*({_V})=\(-({_V})\);$")
_RE_NOT = re.compile(rf"^\s*({_V})=\(!({_V})\);$")
_RE_SEL = re.compile(rf"^\s*({_V})=\(({_V})\?({_V}):0\);$")
_RE_CALL1 = re.compile(rf"^\s*({_V})=([a-z_0-9]+)\(({_V})\);$")
_RE_CALL2 = re.compile(rf"^\s*({_V})=([a-z_0-9]+)\(({_ATOM}),({_ATOM})\);$")
_RE_SQ = re.compile(rf"^\s*({_V})=casadi_sq\(({_V})\);$")


def _atom(a: str) -> str:
    """An operand: a variable as is, a literal broadcast to every lane."""
    return a if a[0] == "a" else f"RPO_SPLAT({a})"


def _nz(a: str) -> str:
    return f"RPO_NE({_atom(a)},RPO_SPLAT(0.))"


def _kernel_body(lines: list[str], where: str) -> list[str]:
    """Translate the body of a ``casadi_fN`` kernel (the lines between its braces)."""
    # pass 1: value numbering of the variables (CasADi reuses names), to pair sin/cos of one value
    version: dict[str, int] = {}
    trig: dict[tuple[str, int], dict[str, int]] = {}
    for i, line in enumerate(lines):
        m = _RE_CALL1.match(line)
        if m and m.group(2) in ("sin", "cos"):
            key = (m.group(3), version.get(m.group(3), 0))
            trig.setdefault(key, {}).setdefault(m.group(2), i)
        m2 = re.match(rf"^\s*({_V})=", line)
        if m2:
            version[m2.group(1)] = version.get(m2.group(1), 0) + 1
    fused: dict[int, tuple[str, int]] = {}   # line -> ("first", pair id) or ("second", pair id)
    for n, (_key, found) in enumerate(sorted(trig.items(), key=lambda kv: min(kv[1].values()))):
        if len(found) == 2:
            first, second = sorted(found.values())
            fused[first], fused[second] = ("first", n), ("second", n)
    out: list[str] = []
    temps: list[str] = []
    for i, line in enumerate(lines):
        if not line.strip():
            continue
        if m := _RE_DECL.match(line):
            out.append(f"  rpo_v {m.group(1)};")
        elif m := _RE_ARG.match(line):
            out.append(f"  {m.group(1)}=arg[{m.group(2)}] ? arg[{m.group(2)}][{m.group(3)}] : RPO_SPLAT(0.);")
        elif m := _RE_RES.match(line):
            out.append(line.rstrip())
        elif m := _RE_CONST.match(line):
            out.append(f"  {m.group(1)}=RPO_SPLAT({m.group(2)});")
        elif m := _RE_BIN.match(line):
            d, x, op, y = m.groups()
            if op in "*+-/":
                # a literal operand stays a C scalar: GCC broadcasts it in vector arithmetic
                out.append(f"  {d}=({x}{op}{y});" if (x[0] == "a" or y[0] == "a") else f"  {d}=RPO_SPLAT({x}{op}{y});")
            elif op in _CMP:
                out.append(f"  {d}=RPO_B2D({_CMP[op]}({_atom(x)},{_atom(y)}));")
            elif op == "&&":
                out.append(f"  {d}=RPO_B2D(RPO_MAND({_nz(x)},{_nz(y)}));")
            else:
                out.append(f"  {d}=RPO_B2D(RPO_MOR({_nz(x)},{_nz(y)}));")
        elif m := _RE_NEG.match(line):
            out.append(f"  {m.group(1)}=(-{m.group(2)});")
        elif m := _RE_NOT.match(line):
            out.append(f"  {m.group(1)}=RPO_B2D(RPO_EQ({m.group(2)},RPO_SPLAT(0.)));")
        elif m := _RE_SEL.match(line):
            d, c, v = m.groups()
            out.append(f"  {d}=RPO_SELECT({_nz(c)},{v},RPO_SPLAT(0.));")
        elif m := _RE_SQ.match(line):
            out.append(f"  {m.group(1)}=({m.group(2)}*{m.group(2)});")
        elif (m := _RE_CALL1.match(line)) and m.group(2) in MATH:
            d, f, x = m.groups()
            if i in fused:
                role, n = fused[i]
                if role == "first":
                    s, c = (d, f"rpo_t{n}") if f == "sin" else (f"rpo_t{n}", d)
                    temps.append(f"rpo_t{n}")
                    out.append(f"  rpo_sincos({x},&{s},&{c});")
                else:
                    out.append(f"  {d}=rpo_t{n};")
            else:
                out.append(f"  {d}={MATH[f]}({x});")
        elif (m := _RE_CALL2.match(line)) and m.group(2) in MATH:
            d, f, x, y = m.groups()
            out.append(f"  {d}={MATH[f]}({_atom(x)},{_atom(y)});")
        elif line.strip() == "return 0;":
            out.append("  return 0;")
        else:
            raise LaneError(f"{where}: no lane form for the line {line.strip()!r} (runtime/model/lanes.py knows "
                            "CasADi's one-operation lines and the math of runtime/csrc/rpo_math.h)")
    if temps:
        out.insert(0, "  rpo_v " + ", ".join(temps) + ";")
    return out


_RE_KERNEL = re.compile(r"^static int (casadi_f\d+)\(const casadi_real\*\* arg, casadi_real\*\* res, "
                        r"casadi_int\* iw, casadi_real\* w, int mem\) \{$")
_RE_PUBLIC = re.compile(r"^CASADI_SYMBOL_EXPORT int ([A-Za-z_]\w*)\(const casadi_real\*\* arg, "
                        r"casadi_real\*\* res, casadi_int\* iw, casadi_real\* w, int mem\)\s*\{$")
_RE_WORK = re.compile(r"^\s*if \(sz_w\) \*sz_w = (\d+)\*sizeof\(casadi_real\);$")


_RE_TABLE = re.compile(r"^static const casadi_int (\w+_(?:z\d+_\d+|n\d+))\[(\d+)\] = \{([\d, ]+)\};(  /\*.*\*/)?$")
_RE_VARIANT = re.compile(r"^(?:\} else )?if \((\w+)_all_zero\((arg\[\d+\]), (\w+_z(\d+)_\d+), (\d+)\)\) \{$")
_RE_CALL = re.compile(r"^if \(([A-Za-z_]\w*)\(a, r, iw, w \+ (\d+), 0\)\) return 1;$")


def _dispatch(lines: list[str], i: int, tables: dict[str, list[int]], where: str) -> tuple[int, list[str], list[str]]:
    """The lane form of a call with specialised variants (c_composition's ``if (<f>_all_zero(...))
    { call } else if ... else { call }`` block starting at line ``i``): one ``rpo_dispatch``, which
    chooses per lane.  Returns (the index after the block, the lines, the callees)."""
    alts: list[tuple[str, str, int]] = []  # (callee, zero table, entries)
    on = glue = k = None
    work = None
    general = None
    j = i
    while True:
        s = lines[j].strip()
        if m := _RE_VARIANT.match(s):
            glue, on, table, k, n = m.group(1), m.group(2), m.group(3), m.group(4), int(m.group(5))
            if tables.get(table) is None or len(tables[table]) != n:
                raise LaneError(f"{where}: {table} is not a table of {n} entries")
            c = _RE_CALL.match(lines[j + 1].strip())
            if not c:
                raise LaneError(f"{where}: no call after {s!r}")
            alts.append((c.group(1), table, n))
            work = c.group(2)
            j += 2
        elif s == "} else {":
            c = _RE_CALL.match(lines[j + 1].strip())
            if not c or lines[j + 2].strip() != "}" or c.group(2) != work:
                raise LaneError(f"{where}: the general call of a dispatch is not '{{ call }}' at {s!r}")
            general = c.group(1)
            j += 3
            break
        else:
            raise LaneError(f"{where}: no lane form for the line {s!r} in a dispatch")
    sizes = tables.get(f"{glue}_n{k}")
    if sizes is None or not alts or general is None:
        raise LaneError(f"{where}: a dispatch without its result sizes {glue}_n{k} or its general call")
    fns = [a for a, _t, _n in alts] + [general]
    out = ["  {",
           # rpo_lanes.h's scratch bounds, checked by the compiler against the header itself
           f"    _Static_assert({len(sizes)} <= RPO_DISPATCH_MAX_RES && {sum(sizes)} <= RPO_DISPATCH_MAX_ENTRIES, "
           f"\"{glue}: a dispatched call's results exceed rpo_lanes.h's scratch\");",
           f"    static const rpo_lane_fn fns[{len(fns)}] = {{{', '.join(f + '_lanes' for f in fns)}}};",
           f"    static const long long* const zero[{len(alts)}] = {{{', '.join(t for _f, t, _n in alts)}}};",
           f"    static const long long n_zero[{len(alts)}] = {{{', '.join(str(n) for _f, _t, n in alts)}}};",
           f"    if (rpo_dispatch({len(fns)}, fns, zero, n_zero, {on}, a, r, {len(sizes)}, {glue}_n{k}, iw, "
           f"w + {work})) return 1;",
           "  }"]
    return j, out, fns


def _public_body(lines: list[str], kernels: set[str], where: str,
                 tables: dict[str, list[int]] | None = None) -> tuple[list[str], list[str]]:
    """Translate a public function's body: a call of one kernel, or the glue of a composed step."""
    out = []
    callees = []
    i = 0
    while i < len(lines):
        line = lines[i]
        i += 1
        s = line.strip()
        if _RE_VARIANT.match(s) and not s.startswith("}"):
            i, block, fns = _dispatch(lines, i - 1, tables or {}, where)
            out.extend(block)
            callees.extend(fns)
            continue
        if not s or s.startswith("/*") or s == "(void) mem;":
            out.append(line.rstrip())
            continue
        m = re.match(r"^return (casadi_f\d+)\(arg, res, iw, w, mem\);$", s)
        if m and m.group(1) in kernels:
            out.append(f"  return {m.group(1)}(arg, res, iw, w, mem);")
            continue
        if re.fullmatch(r"const casadi_real\* a\[\d+\];", s):
            out.append("  " + s.replace("casadi_real", "rpo_v"))
        elif re.fullmatch(r"casadi_real\* r\[\d+\];", s):
            out.append("  " + s.replace("casadi_real", "rpo_v"))
        elif s == "casadi_int i;":
            out.append("  long long i;")
        elif re.fullmatch(r"if \(!arg\[\d+\]\) return 1;.*", s) \
                or re.fullmatch(r"a\[\d+\] = arg\[\d+\]( \+ \d+)?;", s) \
                or re.fullmatch(r"[ar]\[\d+\] = w \+ \d+;", s) \
                or re.fullmatch(r"if \(res\[\d+\]\) \{", s) or s == "}" or s == "return 0;" \
                or re.fullmatch(r"for \(i = 0; i < \d+; \+\+i\) res\[\d+\]\[\d+ \+ i\] = w\[\d+ \+ i\];", s):
            out.append(line.rstrip())
        elif m := re.fullmatch(r"if \(([A-Za-z_]\w*)\(a, r, iw, w \+ (\d+), 0\)\) return 1;", s):
            callees.append(m.group(1))
            out.append(f"  if ({m.group(1)}_lanes(a, r, iw, w + {m.group(2)}, 0)) return 1;")
        else:
            raise LaneError(f"{where}: no lane form for the line {s!r} of a public function")
    return out, callees


def lane_source(name: str, text: str) -> tuple[str, list[str]]:
    """The lane form of the generated file ``name`` (its C text): C source defining
    ``<fn>_lanes(const rpo_v** arg, rpo_v** res, long long* iw, rpo_v* w, int mem)`` and
    ``<fn>_lanes_work(void)`` (work vector length, in rpo_v), and the names of the functions it calls."""
    lines = text.splitlines()
    out = [f"/* Lane form of {name}, written by rpo.runtime.model.lanes (version {LANES_VERSION}) from the",
           " * verified generated file: the same operations over rpo_v (see runtime/csrc/rpo_lanes.h). */",
           '#include "rpo_lanes.h"', ""]
    kernels: set[str] = set()
    public = None
    callees: list[str] = []
    sz_w = None
    decls: list[str] = []
    tables: dict[str, list[int]] = {}
    i = 0
    while i < len(lines):
        line = lines[i]
        if mt := _RE_TABLE.match(line):
            vals = [int(v) for v in mt.group(3).split(", ")]
            if len(vals) != int(mt.group(2)):
                raise LaneError(f"{name}: table {mt.group(1)} does not hold {mt.group(2)} entries")
            tables[mt.group(1)] = vals
            out.append(f"static const long long {mt.group(1)}[{len(vals)}] = {{{mt.group(3)}}};")
            i += 1
            continue
        m, m2 = _RE_KERNEL.match(line), _RE_PUBLIC.match(line)
        if m or m2:
            j = i + 1
            while lines[j] != "}":
                j += 1
            body = lines[i + 1:j]
            if m:
                kernels.add(m.group(1))
                out.append(f"static int {m.group(1)}(const rpo_v** arg, rpo_v** res, long long* iw, rpo_v* w, "
                           "int mem) {")
                out.extend(_kernel_body(body, f"{name} ({m.group(1)})"))
            else:
                assert m2 is not None
                public = m2.group(1)
                out.append(f"RPO_EXPORT int {public}_lanes(const rpo_v** arg, rpo_v** res, long long* iw, rpo_v* w, "
                           "int mem) {")
                body_out, callees = _public_body(body, kernels, f"{name} ({public})", tables)
                out.extend(body_out)
            out.append("}")
            out.append("")
            i = j + 1
            continue
        if mw := _RE_WORK.match(line):
            sz_w = int(mw.group(1))
        i += 1
    if public is None or sz_w is None:
        raise LaneError(f"{name}: no CasADi public function or work size found")
    for c in dict.fromkeys(callees):
        decls.append(f"int {c}_lanes(const rpo_v** arg, rpo_v** res, long long* iw, rpo_v* w, int mem);")
    out[4:4] = decls + ([""] if decls else [])
    out.append(f"RPO_EXPORT long long {public}_lanes_work(void) {{ return {sz_w}; }}")
    out.append(f"RPO_EXPORT int {public}_lanes_width(void) {{ return RPO_LANES; }}")
    out.append("")
    return "\n".join(out), callees
