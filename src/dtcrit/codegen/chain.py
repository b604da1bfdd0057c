"""Reduction and ordering of a SymPy assignment chain before it is printed (``dtcrit.codegen.kernel``)."""
from __future__ import annotations

import sympy as sp


def cse_chain(args, steps) -> tuple[list, list]:
    """Common-subexpression elimination of an assignment chain, keeping divisions as divisions.

    A shared reciprocal ``1/y`` would turn every ``u/y`` into ``u*(1/y)`` (two roundings instead of
    one), so such temporaries are put back into the expressions.

    Parameters
    ----------
    args : sequence of sympy.Symbol
        The chain's arguments (unused; kept for the call's symmetry with :func:`dependency_order`).
    steps : sequence of (sympy.Symbol, sympy.Expr)
        The named assignments.

    Returns
    -------
    tuple of list
        ``(temporaries, reduced)``: the kept ``(x_i, expr)`` temporaries and the named assignments rewritten in them.
    """
    names = [s for s, _ in steps]
    exprs = [e for _, e in steps]
    temps, reduced = sp.cse(exprs, symbols=sp.numbered_symbols("x", real=True), order="canonical")
    # A shared reciprocal 1/y would turn every u/y into u*(1/y): two roundings instead of one.
    # Such temporaries are put back, so divisions stay divisions.
    inline: dict[sp.Symbol, sp.Expr] = {}
    kept = []
    for sym, expr in temps:
        expr = expr.xreplace(inline)
        if expr.is_Pow and expr.exp == -1 and expr.base.is_Atom:
            inline[sym] = expr
        else:
            kept.append((sym, expr))
    reduced = [e.xreplace(inline) for e in reduced]
    return kept, list(zip(names, reduced))


def dependency_order(args, items, result) -> list:
    """Order assignments so each comes after the names it uses (stable: earliest ready first).

    Parameters
    ----------
    args : sequence of sympy.Symbol
        The chain's arguments (defined from the start).
    items : sequence of (sympy.Symbol, sympy.Expr)
        The assignments, in any order.
    result : sympy.Symbol
        The name assigned last.

    Returns
    -------
    list of (sympy.Symbol, sympy.Expr)
        The assignments in an order that evaluates.
    """
    defined = set(args)
    pending = list(items)
    out = []
    while pending:
        for n, (sym, expr) in enumerate(pending):
            if expr.free_symbols <= defined and (sym != result or len(pending) == 1):
                out.append((sym, expr))
                defined.add(sym)
                del pending[n]
                break
        else:  # pragma: no cover - the chain is acyclic by construction
            raise RuntimeError("cyclic assignment chain")
    return out
