"""Translate SymPy expressions into CasADi SX graphs (and into NumPy callables).

The SymPy expressions in :mod:`rpo.symbolic` are the single source of every equation; this
module turns *those objects* into CasADi expressions for code generation, so the C code and the
Lyapunov checks derive from the same expression.  The walk is memoised on the (hashable,
structurally compared) SymPy nodes, so a subexpression shared in SymPy is one node in CasADi.
"""

from __future__ import annotations

from collections.abc import Sequence

import casadi as ca
import numpy as np
import sympy as sp

from ..physics.kepler import KeplerE, solve_kepler
from ..physics.special import Fmax, Step

_UNARY = {
    sp.sin: ca.sin,
    sp.cos: ca.cos,
    sp.tan: ca.tan,
    sp.asin: ca.asin,
    sp.acos: ca.acos,
    sp.atan: ca.atan,
    sp.exp: ca.exp,
    sp.log: ca.log,
    sp.sinh: ca.sinh,
    sp.cosh: ca.cosh,
    sp.tanh: ca.tanh,
    sp.Abs: ca.fabs,
    sp.sign: ca.sign,
    sp.floor: ca.floor,
}


def _children(e: sp.Basic):
    if isinstance(e, sp.Piecewise):
        return [x for pair in e.args for x in pair]  # (expr, cond) pairs
    return e.args


class Translator:
    """Memoising SymPy -> CasADi SX translator for one symbol table."""

    def __init__(self, table: dict[sp.Symbol, ca.SX]):
        self.memo: dict[sp.Basic, ca.SX] = dict(table)

    def __call__(self, e: sp.Basic) -> ca.SX:
        memo = self.memo
        if e in memo:
            return memo[e]
        # iterative post-order walk (expressions can be deep)
        stack = [(e, False)]
        while stack:
            node, done = stack.pop()
            if node in memo:
                continue
            if not done:
                stack.append((node, True))
                for a in _children(node):
                    if a not in memo:
                        stack.append((a, False))
                continue
            memo[node] = self._node(node)
        return memo[e]

    def _node(self, e: sp.Basic) -> ca.SX:
        m = self.memo
        if e.is_Number or e in (sp.pi, sp.E):
            if e is sp.zoo or e is sp.nan or e in (sp.oo, -sp.oo):
                raise ValueError(f"non-finite constant {e} in expression")
            return ca.SX(float(e))
        if isinstance(e, sp.Symbol):
            raise KeyError(f"symbol {e} is not an input of this function")
        if e.is_Add:
            out = m[e.args[0]]
            for a in e.args[1:]:
                out = out + m[a]
            return out
        if e.is_Mul:
            out = m[e.args[0]]
            for a in e.args[1:]:
                out = out * m[a]
            return out
        if e.is_Pow:
            b, x = e.args
            base = m[b]
            if x == 2:
                return base * base
            if x == -1:
                return 1 / base
            if x == sp.Rational(1, 2):
                return ca.sqrt(base)
            if x == sp.Rational(-1, 2):
                return 1 / ca.sqrt(base)
            if x == 3:
                return base * base * base
            if x == -2:
                return 1 / (base * base)
            if x.is_Integer:
                return ca.constpow(base, float(x))
            if x.is_Rational and x.q == 2:  # half-integer: sqrt(b)^n, no pow() call
                rt = ca.sqrt(base)
                n = abs(int(x.p))
                out = rt
                for _ in range(n - 1):
                    out = out * rt
                return 1 / out if x < 0 else out
            return ca.power(base, m[x])
        f = type(e)
        if f in _UNARY:
            return _UNARY[f](m[e.args[0]])
        if f is Step:  # 1 for x >= 0, else 0
            return m[e.args[0]] >= 0
        if f is Fmax:
            return ca.fmax(m[e.args[0]], m[e.args[1]])
        if f is sp.atan2:
            return ca.atan2(m[e.args[0]], m[e.args[1]])
        if f is sp.Max:
            out = m[e.args[0]]
            for a in e.args[1:]:
                out = ca.fmax(out, m[a])
            return out
        if f is sp.Min:
            out = m[e.args[0]]
            for a in e.args[1:]:
                out = ca.fmin(out, m[a])
            return out
        if f is sp.Piecewise:
            out = None
            for expr, cond in reversed(e.args):
                if cond is sp.true:
                    out = m[expr]
                else:
                    if out is None:
                        raise ValueError("Piecewise without a default branch")
                    out = ca.if_else(m[cond], m[expr], out)
            return out
        if isinstance(e, sp.core.relational.Relational):
            a, b = m[e.lhs], m[e.rhs]
            return {
                sp.StrictLessThan: lambda: a < b,
                sp.LessThan: lambda: a <= b,
                sp.StrictGreaterThan: lambda: a > b,
                sp.GreaterThan: lambda: a >= b,
                sp.Equality: lambda: a == b,
                sp.Unequality: lambda: a != b,
            }[f]()
        if f is sp.And:
            out = m[e.args[0]]
            for a in e.args[1:]:
                out = ca.logic_and(out, m[a])
            return out
        if f is sp.Or:
            out = m[e.args[0]]
            for a in e.args[1:]:
                out = ca.logic_or(out, m[a])
            return out
        if f is sp.Not:
            return ca.logic_not(m[e.args[0]])
        if f is KeplerE:
            return solve_kepler(m[e.args[0]], m[e.args[1]], ca)
        if e is sp.true:
            return ca.SX(1.0)
        if e is sp.false:
            return ca.SX(0.0)
        raise NotImplementedError(f"no CasADi translation for {f.__name__}: {e}")


def _flatten(a) -> list[sp.Basic]:
    if isinstance(a, sp.MatrixBase):
        return list(a.T)  # column-major, as CasADi stores dense matrices
    return [sp.sympify(a)]


def _shape(a) -> tuple[int, int]:
    return a.shape if isinstance(a, sp.MatrixBase) else (1, 1)


def sympy_function(
    name: str,
    inputs: Sequence[tuple[str, sp.Basic]],
    outputs: Sequence[tuple[str, sp.Basic]],
) -> ca.Function:
    """A :class:`casadi.Function` evaluating SymPy ``outputs`` of the SymPy ``inputs``.

    ``inputs`` are ``(name, Matrix of Symbols or Symbol)``; ``outputs`` are ``(name, Matrix or
    expression)``.  Matrices keep their shapes (column-major).
    """
    table: dict[sp.Symbol, ca.SX] = {}
    ca_in = []
    for nm, a in inputs:
        r, c = _shape(a)
        s = ca.SX.sym(nm, r, c)
        for i, sym in enumerate(_flatten(a)):
            if not isinstance(sym, sp.Symbol):
                raise TypeError(f"input {nm} must contain only symbols, got {sym}")
            if sym in table:
                raise ValueError(f"symbol {sym} appears twice among the inputs of {name}")
            table[sym] = s.nz[i]
        ca_in.append(s)
    tr = Translator(table)
    ca_out = []
    for _nm, expr in outputs:
        r, c = _shape(expr)
        flat = [tr(x) for x in _flatten(expr)]
        ca_out.append(ca.reshape(ca.vertcat(*flat), r, c) if flat else ca.SX(r, c))
    return ca.Function(name, ca_in, ca_out, [n for n, _ in inputs], [n for n, _ in outputs])


class _NumpyKepler:
    sin, cos, floor, sign = np.sin, np.cos, np.floor, np.sign


def numpy_kepler(M, e):
    """NumPy evaluation of :class:`KeplerE` (the same solver the C code runs)."""
    return solve_kepler(np.asarray(M, float), np.asarray(e, float), _NumpyKepler)


#: Module mapping for ``sympy.lambdify`` so that lambdified expressions evaluate KeplerE.
LAMBDIFY_MODULES = [{"KeplerE": numpy_kepler, "Step": lambda x: np.where(np.asarray(x) >= 0, 1.0, 0.0),
                     "Fmax": np.maximum}, "numpy"]


def numpy_function(inputs: Sequence[sp.Basic], outputs: Sequence[sp.Basic]):
    """``sympy.lambdify`` of the same expressions, for independent NumPy evaluation (with the
    sharing already in the expression graph, :func:`~rpo.symbolic.codegen.structural_cse.structural_cse`)."""
    from .structural_cse import structural_cse

    # use_imps=False: lambdify's search for implemented_function walks the expression as a tree,
    # which is exponential in the depth of shared nodes (the Cholesky factors of the allocation)
    return sp.lambdify(list(inputs), list(outputs), modules=LAMBDIFY_MODULES, cse=structural_cse, use_imps=False)
