"""Common subexpressions by structural identity: a fast ``cse`` for ``sympy.lambdify``.

``sympy.lambdify(..., cse=True)`` runs SymPy's full ``cse``, which also searches Adds and Muls
for common argument subsets; on the model's larger pieces that search took minutes (c001's law:
~3 minutes) and dominated the test suite.  The NumPy reference only needs the sharing that is
already in the expression graph (the plant's and laws' expressions are built as DAGs: one node
used in many places), so this extracts exactly the nodes that occur more than once, in one
post-order walk, and leaves every node's own form to SymPy's NumPy printer.  It shares no code
with the CasADi translation, so the reference stays independent of the C path.
"""

from __future__ import annotations

from collections.abc import Iterable

import sympy as sp


def _rebuild(node: sp.Basic, args: list) -> sp.Basic:
    if args == list(node.args):
        return node
    try:
        return node.func(*args, evaluate=False)
    except TypeError:  # constructors without an evaluate flag (ExprCondPair, Tuple, ...)
        return node.func(*args)


def _cse_flat(exprs: list[sp.Basic]) -> tuple[list[tuple[sp.Symbol, sp.Basic]], list[sp.Basic]]:
    count: dict[sp.Basic, int] = {}
    order: list[sp.Basic] = []  # post-order (children first), each node once
    stack: list[tuple[sp.Basic, bool]] = [(e, False) for e in reversed(exprs)]
    while stack:
        node, done = stack.pop()
        if done:
            order.append(node)
            continue
        if node.is_Atom or not node.args:
            continue
        seen = count.get(node, 0)
        count[node] = seen + 1
        if seen:
            continue
        stack.append((node, True))
        stack.extend((a, False) for a in reversed(node.args))
    names = sp.numbered_symbols("_cse")
    new: dict[sp.Basic, sp.Basic] = {}  # node -> its rebuilt form (or the symbol that replaces it)
    subs: list[tuple[sp.Symbol, sp.Basic]] = []
    for node in order:
        built = _rebuild(node, [new.get(a, a) for a in node.args])
        # a repeated node worth naming: not a relational or condition pair (printed inside np.select)
        if count[node] > 1 and isinstance(node, sp.Expr):
            sym = next(names)
            subs.append((sym, built))
            new[node] = sym
        else:
            new[node] = built
    return subs, [new.get(e, e) for e in exprs]


def structural_cse(exprs: Iterable) -> tuple[list[tuple[sp.Symbol, sp.Basic]], list]:
    """``(replacements, reduced)`` as ``sympy.cse`` returns them, for expressions and matrices."""
    flat: list[sp.Basic] = []
    shapes: list[tuple[int, int] | None] = []
    for e in exprs:
        if isinstance(e, sp.MatrixBase):
            shapes.append(e.shape)
            flat.extend(list(e))
        else:
            shapes.append(None)
            flat.append(sp.sympify(e))
    subs, reduced = _cse_flat(flat)
    out: list = []
    i = 0
    for shape in shapes:
        if shape is None:
            out.append(reduced[i])
            i += 1
        else:
            n = shape[0] * shape[1]
            out.append(sp.Matrix(shape[0], shape[1], reduced[i:i + n]))
            i += n
    return subs, out
