"""C for a function composed of other generated functions: calls in sequence, CasADi's API.

A controller's closed-loop step is ``measure`` -> ``control_<name>`` -> ``plant_advance``.  The
two large pieces are generated once each (the plant's in the plant family), and the step itself
is this thin glue: it calls them through their C entry points, with its intermediate vectors and
the callees' work space in the caller's ``w``.  So a controller edit recompiles the controller's
own code, not the plant's integration (as acados wraps its generated functions).

The glue has the calling convention and API of CasADi's generated functions (``<name>``,
``<name>_work``, ``_n_in``, ``_n_out``, ``_sparsity_in``, ``_sparsity_out``, ``_name_in``,
``_name_out``, ...), so the runtime and its loop driver call it like any generated function.
Inputs must be non-NULL (the step has no meaning for an omitted state); a NULL output is skipped.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

EXPORT = """#ifndef casadi_real
#define casadi_real double
#endif

#ifndef casadi_int
#define casadi_int long long int
#endif

#ifndef CASADI_SYMBOL_EXPORT
  #if defined(_WIN32) || defined(__WIN32__) || defined(__CYGWIN__)
    #if defined(STATIC_LINKED)
      #define CASADI_SYMBOL_EXPORT
    #else
      #define CASADI_SYMBOL_EXPORT __declspec(dllexport)
    #endif
  #elif defined(__GNUC__) && defined(GCC_HASCLASSVISIBILITY)
    #define CASADI_SYMBOL_EXPORT __attribute__ ((visibility ("default")))
  #else
    #define CASADI_SYMBOL_EXPORT
  #endif
#endif
"""


@dataclass(frozen=True)
class Callee:
    """A generated function called by the glue, with its work sizes (``casadi.Function.sz_*``)."""

    name: str
    sz_arg: int
    sz_res: int
    sz_iw: int
    sz_w: int
    #: numbers of entries of each (dense) input and output
    in_sizes: tuple[int, ...] = ()
    out_sizes: tuple[int, ...] = ()

    @classmethod
    def of(cls, fn) -> Callee:
        return cls(fn.name(), int(fn.sz_arg()), int(fn.sz_res()), int(fn.sz_iw()), int(fn.sz_w()),
                   tuple(int(fn.nnz_in(i)) for i in range(fn.n_in())),
                   tuple(int(fn.nnz_out(i)) for i in range(fn.n_out())))


@dataclass(frozen=True)
class Call:
    """``callee(args...) -> results...``; each argument and result is ``(vector, offset)`` where the
    vector is an input, an output or a buffer name.

    ``variants``: specialised copies of the callee (same signature), each with the entries of the
    input ``on`` it requires to be 0 (:mod:`rpo.symbolic.codegen.specialisation`): the glue calls the
    first whose entries are all 0, else ``callee``.  The lane form (``rpo.runtime.lanes``) makes
    the same choice per lane."""

    callee: Callee
    args: Sequence[tuple[str, int]]
    results: Sequence[str]
    variants: Sequence[tuple[Callee, Sequence[int]]] = ()
    on: str = "p"


def _check(name: str, in_size: dict[str, int], size: dict[str, int],
           outputs: Sequence[tuple[str, Sequence[str]]], calls: Sequence[Call]) -> None:
    """Every call matches its callee's signature: argument and result counts, each argument slice
    inside its vector, each result buffer exactly the callee's output size, each buffer written once.
    The glue's C is only generated from a composition that passes (no hand-kept sizes can drift)."""
    written: set[str] = set()
    for c in calls:
        ce = c.callee
        for v, idx in c.variants:
            if (v.in_sizes, v.out_sizes) != (ce.in_sizes, ce.out_sizes):
                raise ValueError(f"{name}: {v.name} is a variant of {ce.name} with another signature")
            if c.on not in in_size or not idx or min(idx) < 0 or max(idx) >= in_size[c.on]:
                raise ValueError(f"{name}: {v.name} tests entries {list(idx)[:3]}... of {c.on}, outside the input")
        if len(c.args) != len(ce.in_sizes) or len(c.results) != len(ce.out_sizes):
            raise ValueError(f"{name}: {ce.name} takes {len(ce.in_sizes)} inputs and gives {len(ce.out_sizes)} "
                             f"outputs; the call passes {len(c.args)} and takes {len(c.results)}")
        for (vec, off), n in zip(c.args, ce.in_sizes, strict=True):
            have = in_size.get(vec, size.get(vec))
            if have is None or (vec in size and vec not in written):
                raise ValueError(f"{name}: {ce.name} reads {vec}, which is not an input or an earlier result")
            if off < 0 or off + n > have:
                raise ValueError(f"{name}: {ce.name} reads {vec}[{off}:{off + n}] of a vector of {have}")
        for b, n in zip(c.results, ce.out_sizes, strict=True):
            if size.get(b) != n or b in written:
                raise ValueError(f"{name}: {ce.name} writes {n} entries into buffer {b} "
                                 f"({size.get(b)} entries{', already written' if b in written else ''})")
            written.add(b)
    for o_name, parts in outputs:
        missing = [b for b in parts if b not in written]
        if missing:
            raise ValueError(f"{name}: output {o_name} uses buffers no call writes: {', '.join(missing)}")


def composed_c(name: str, inputs: Sequence[tuple[str, int]], outputs: Sequence[tuple[str, Sequence[str]]],
               buffers: Sequence[tuple[str, int]], calls: Sequence[Call]) -> tuple[str, str]:
    """(C source, header) of ``name(inputs) -> outputs``.

    ``inputs``: (name, size) of dense column inputs; ``buffers``: (name, size) of intermediate
    vectors, each written by one call; ``outputs``: (name, [buffer, ...]): an output is the
    concatenation of those buffers, copied out after the last call.
    """
    size = dict(buffers)
    in_size = dict(inputs)
    _check(name, in_size, size, outputs, calls)
    offsets, o = {}, 0
    for b, n in buffers:
        offsets[b] = o
        o += n
    n_buf = o
    every = [ce for c in calls for ce in (c.callee, *(v for v, _ in c.variants))]
    max_arg = max(ce.sz_arg for ce in every)
    max_res = max(ce.sz_res for ce in every)
    sz_iw = max(ce.sz_iw for ce in every)
    sz_w = n_buf + max(ce.sz_w for ce in every)
    out_size = {o_name: sum(size[b] for b in parts) for o_name, parts in outputs}

    def ptr(vec: str, off: int) -> str:
        if vec in in_size:
            i = [n for n, _ in inputs].index(vec)
            return f"arg[{i}] + {off}" if off else f"arg[{i}]"
        return f"w + {offsets[vec] + off}"

    lines = []
    for ce in {ce.name: ce for ce in every}.values():
        lines.append(f"int {ce.name}(const casadi_real** arg, casadi_real** res, casadi_int* iw, "
                     "casadi_real* w, int mem);")
    tables = []
    for k, c in enumerate(c for c in calls if c.variants):
        for j, (v, idx) in enumerate(c.variants):
            tables.append(f"static const casadi_int {name}_z{k}_{j}[{len(idx)}] = {{{', '.join(map(str, idx))}}};"
                          f"  /* {v.name}: these entries of {c.on} are 0 */")
        tables.append(f"static const casadi_int {name}_n{k}[{len(c.results)}] = "
                      f"{{{', '.join(str(n) for n in c.callee.out_sizes)}}};  /* sizes of {c.callee.name}'s results */")
    if tables:
        lines.append("")
        lines.extend(tables)
        lines.append("")
        lines.append(f"/* 1 when the n entries idx of x are all 0 (a specialised callee applies) */\n"
                     f"static int {name}_all_zero(const casadi_real* x, const casadi_int* idx, casadi_int n) {{\n"
                     "  casadi_int i;\n"
                     "  for (i = 0; i < n; ++i) if (x[idx[i]] != 0) return 0;\n"
                     "  return 1;\n"
                     "}")
    decls = "\n".join(lines)
    body = []
    body.append(f"  const casadi_real* a[{max_arg}];")
    body.append(f"  casadi_real* r[{max_res}];")
    body.append("  casadi_int i;")
    for i, (n_name, n) in enumerate(inputs):
        if n:  # an empty input may be NULL (CasADi passes NULL for 0x1): it is never read
            body.append(f"  if (!arg[{i}]) return 1;  /* {n_name} */")
    k_var = 0
    for c in calls:
        args = ", ".join(f"{v}{'+' + str(o) if o else ''}" for v, o in c.args)
        res = ", ".join(c.results)
        body.append(f"  /* ({res}) = {c.callee.name}({args}) */")
        for i, (v, off) in enumerate(c.args):
            body.append(f"  a[{i}] = {ptr(v, off)};")
        for i, b in enumerate(c.results):
            body.append(f"  r[{i}] = {ptr(b, 0)};")
        call = f"if ({{}}(a, r, iw, w + {n_buf}, 0)) return 1;"
        if not c.variants:
            body.append("  " + call.format(c.callee.name))
            continue
        body.append(f"  /* or the first specialised copy whose entries {name}_z{k_var}_<j> of {c.on} are all 0 */")
        on = ptr(c.on, 0)
        for j, (v, idx) in enumerate(c.variants):
            body.append(f"  {'} else ' if j else ''}if ({name}_all_zero({on}, {name}_z{k_var}_{j}, {len(idx)})) {{")
            body.append("    " + call.format(v.name))
        body.append("  } else {")
        body.append("    " + call.format(c.callee.name))
        body.append("  }")
        k_var += 1
    for k, (o_name, parts) in enumerate(outputs):
        body.append(f"  /* {o_name} = [{', '.join(parts)}] */")
        body.append(f"  if (res[{k}]) {{")
        o = 0
        for b in parts:
            if size[b]:
                body.append(f"    for (i = 0; i < {size[b]}; ++i) res[{k}][{o} + i] = w[{offsets[b]} + i];")
            o += size[b]
        body.append("  }")
    sparsities = [n for _, n in inputs] + [out_size[o_name] for o_name, _ in outputs]
    sp_lines = [f"static const casadi_int {name}_s{i}[3] = {{{n}, 1, 1}};" for i, n in enumerate(sparsities)]
    n_in, n_out = len(inputs), len(outputs)
    names_in = "".join(f"    case {i}: return \"{n}\";\n" for i, (n, _) in enumerate(inputs))
    names_out = "".join(f"    case {i}: return \"{n}\";\n" for i, (n, _) in enumerate(outputs))
    sp_in = "".join(f"    case {i}: return {name}_s{i};\n" for i in range(n_in))
    sp_out = "".join(f"    case {i}: return {name}_s{n_in + i};\n" for i in range(n_out))
    c = f"""#ifdef __cplusplus
extern "C" {{
#endif

{EXPORT}
{decls}

{chr(10).join(sp_lines)}

CASADI_SYMBOL_EXPORT int {name}_casadi_int_size(void) {{ return (int) sizeof(casadi_int); }}
CASADI_SYMBOL_EXPORT int {name}_casadi_real_size(void) {{ return (int) sizeof(casadi_real); }}

/* w: [{', '.join(f'{b} ({n})' for b, n in buffers)}] then the callees' work space */
CASADI_SYMBOL_EXPORT int {name}(const casadi_real** arg, casadi_real** res, casadi_int* iw, casadi_real* w, int mem) {{
  (void) mem;
{chr(10).join(body)}
  return 0;
}}

CASADI_SYMBOL_EXPORT int {name}_alloc_mem(void) {{ return 0; }}
CASADI_SYMBOL_EXPORT int {name}_init_mem(int mem) {{ (void) mem; return 0; }}
CASADI_SYMBOL_EXPORT void {name}_free_mem(int mem) {{ (void) mem; }}
CASADI_SYMBOL_EXPORT int {name}_checkout(void) {{ return 0; }}
CASADI_SYMBOL_EXPORT void {name}_release(int mem) {{ (void) mem; }}
CASADI_SYMBOL_EXPORT void {name}_incref(void) {{}}
CASADI_SYMBOL_EXPORT void {name}_decref(void) {{}}
CASADI_SYMBOL_EXPORT casadi_int {name}_n_in(void) {{ return {n_in}; }}
CASADI_SYMBOL_EXPORT casadi_int {name}_n_out(void) {{ return {n_out}; }}
CASADI_SYMBOL_EXPORT casadi_real {name}_default_in(casadi_int i) {{ (void) i; return 0; }}

CASADI_SYMBOL_EXPORT const char* {name}_name_in(casadi_int i) {{
  switch (i) {{
{names_in}    default: return 0;
  }}
}}

CASADI_SYMBOL_EXPORT const char* {name}_name_out(casadi_int i) {{
  switch (i) {{
{names_out}    default: return 0;
  }}
}}

CASADI_SYMBOL_EXPORT const casadi_int* {name}_sparsity_in(casadi_int i) {{
  switch (i) {{
{sp_in}    default: return 0;
  }}
}}

CASADI_SYMBOL_EXPORT const casadi_int* {name}_sparsity_out(casadi_int i) {{
  switch (i) {{
{sp_out}    default: return 0;
  }}
}}

CASADI_SYMBOL_EXPORT int {name}_work(casadi_int *sz_arg, casadi_int* sz_res, casadi_int *sz_iw, casadi_int *sz_w) {{
  if (sz_arg) *sz_arg = {n_in};
  if (sz_res) *sz_res = {n_out};
  if (sz_iw) *sz_iw = {sz_iw};
  if (sz_w) *sz_w = {sz_w};
  return 0;
}}

CASADI_SYMBOL_EXPORT int {name}_work_bytes(casadi_int *sz_arg, casadi_int* sz_res, casadi_int *sz_iw,
                                          casadi_int *sz_w) {{
  if (sz_arg) *sz_arg = {n_in}*sizeof(const casadi_real*);
  if (sz_res) *sz_res = {n_out}*sizeof(casadi_real*);
  if (sz_iw) *sz_iw = {sz_iw}*sizeof(casadi_int);
  if (sz_w) *sz_w = {sz_w}*sizeof(casadi_real);
  return 0;
}}

#ifdef __cplusplus
}} /* extern "C" */
#endif
"""
    h = f"""#ifdef __cplusplus
extern "C" {{
#endif

#ifndef casadi_real
#define casadi_real double
#endif

#ifndef casadi_int
#define casadi_int long long int
#endif

int {name}(const casadi_real** arg, casadi_real** res, casadi_int* iw, casadi_real* w, int mem);
int {name}_work(casadi_int *sz_arg, casadi_int* sz_res, casadi_int *sz_iw, casadi_int *sz_w);
casadi_int {name}_n_in(void);
casadi_int {name}_n_out(void);
const casadi_int* {name}_sparsity_in(casadi_int i);
const casadi_int* {name}_sparsity_out(casadi_int i);

#ifdef __cplusplus
}} /* extern "C" */
#endif
"""
    return c, h
