"""Emit Python/NumPy modules from SymPy expressions, with a deterministic provenance header.

Every file under ``dtcrit/_generated`` is produced here.  The header names the producing module,
the equations, and a hash of the emitted expressions (``srepr``), and carries no timestamp or
version, so regeneration is byte-for-byte reproducible and a test can diff it.
"""
from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from typing import Sequence

import sympy as sp
from sympy.codegen.rewriting import ReplaceOptim, optimize
from sympy.printing.numpy import NumPyPrinter

REGENERATE_COMMAND = "python3 dev.py generate"


@dataclass
class Kernel:
    """One emitted function: ``name(args...) -> expr`` (or a tuple for several outputs).

    Parameters
    ----------
    name : str
        Name of the emitted function.
    args : sequence of (sympy.Symbol, str)
        The arguments in order, each with its meaning and unit.
    expr : sympy.Expr or sequence of sympy.Expr
        The value returned (a tuple for several outputs).
    doc : str
        The function's docstring.
    cse : bool
        Eliminate common subexpressions before printing.
    returns : str
        What the function returns, for its docstring.
    extra_lines : sequence of str
        Lines emitted at the start of the body.
    as_arrays : bool
        Convert the arguments to float arrays and silence IEEE warnings.
    """

    name: str
    args: Sequence[tuple[sp.Symbol, str]]  # (symbol, "meaning [unit]")
    expr: sp.Expr | Sequence[sp.Expr]
    doc: str
    cse: bool = True
    returns: str = ""
    extra_lines: Sequence[str] = field(default_factory=tuple)
    as_arrays: bool = False  # convert the arguments to float arrays and silence IEEE warnings


def square_root_of_term(term: sp.Expr) -> sp.Expr | None:
    """``r`` with ``r**2 == term`` and no radical in ``r``, or None.

    Parameters
    ----------
    term : sympy.Expr
        One term of a sum.

    Returns
    -------
    sympy.Expr or None
        ``r`` with ``r**2 == term`` and no radical in it, else None.
    """
    if term.could_extract_minus_sign():
        return None
    r = sp.sqrt(term)
    if r.has(sp.I) or any(not p.exp.is_integer for p in r.atoms(sp.Pow)):
        return None
    return r


def hypot_arguments(expr: sp.Basic) -> list[sp.Expr] | None:
    """The two legs of a root of a sum of two squares, the pattern the ``hypot`` rewrite replaces.

    Parameters
    ----------
    expr : sympy.Basic
        Any expression.

    Returns
    -------
    list of sympy.Expr or None
        ``[x, y]`` when ``expr`` is ``sqrt(x^2 + y^2)`` or ``1/sqrt(x^2 + y^2)`` with ``x``, ``y`` free of
        radicals, else None.
    """
    if not expr.is_Pow:
        return None
    base, exp = expr.args
    if exp in (sp.S.Half, -sp.S.Half) and base.is_Add and len(base.args) == 2:
        roots = [square_root_of_term(t) for t in base.args]
        if all(r is not None for r in roots):
            return [r for r in roots if r is not None]
    return None


class hypot(sp.Function):
    """``sqrt(x^2 + y^2)`` without overflow or underflow (C99/Fortran 2008 ``hypot``, ``np.hypot``).

    Parameters
    ----------
    *args : sympy.Expr
        The legs ``x`` and ``y``.
    """

    nargs = 2
    is_real = True
    is_nonnegative = True


def _as_hypot(expr: sp.Pow) -> sp.Expr:
    x, y = hypot_arguments(expr) or (None, None)
    h = hypot(x, y)
    return h if expr.exp == sp.S.Half else 1 / h


HYPOT_REWRITE = ReplaceOptim(lambda e: hypot_arguments(e) is not None, _as_hypot)
"""``sqrt(x^2 + y^2) -> hypot(x, y)`` (and its reciprocal): no overflow of the squares, no cancellation."""


def rewrite_for_printing(expr: sp.Basic) -> sp.Basic:
    """Apply the expression rewrites every emitted language shares, once, before printing.

    Parameters
    ----------
    expr : sympy.Basic
        Expression (or Boolean) to print.

    Returns
    -------
    sympy.Basic
        ``expr`` with every root of a sum of two squares written as :class:`hypot` (``HYPOT_REWRITE``,
        a ``sympy.codegen.rewriting.ReplaceOptim``); the printers only print.
    """
    return optimize(expr, [HYPOT_REWRITE])


class NumPyHypotPrinter(NumPyPrinter):
    """NumPy printer of the generated modules: ``np.`` prefix, :class:`hypot` as ``np.hypot``.

    Parameters
    ----------
    settings : dict, optional
        SymPy printer settings (unknown functions are allowed by default).
    """

    def __init__(self, settings=None):
        settings = dict(settings or {})
        settings.setdefault("allow_unknown_functions", True)
        super().__init__(settings)
        self._module = "np"

    def _module_format(self, fqn, register=True):
        text = super()._module_format(fqn, register)
        return text.replace("numpy.", "np.")

    def _print_hypot(self, expr):
        return f"np.hypot({self._print(expr.args[0])}, {self._print(expr.args[1])})"


def expr_code(expr: sp.Expr) -> str:
    """NumPy source text for one expression, after :func:`rewrite_for_printing`.

    Parameters
    ----------
    expr : sympy.Expr
        Expression in the kernel's arguments.

    Returns
    -------
    str
        One line of NumPy code.
    """
    return NumPyHypotPrinter({"fully_qualified_modules": True, "inline": True}).doprint(rewrite_for_printing(expr))


def derivation_hash(exprs: Sequence[sp.Basic]) -> str:
    """A short, stable hash of the emitted expressions (their ``srepr``).

    Parameters
    ----------
    exprs : sequence of sympy.Basic
        The emitted expressions.

    Returns
    -------
    str
        The first 16 hexadecimal digits of the SHA-256 of their ``srepr``.
    """
    digest = hashlib.sha256()
    for e in exprs:
        digest.update(sp.srepr(e).encode())
        digest.update(b"\0")
    return digest.hexdigest()[:16]


def kernel_source(k: Kernel) -> str:
    """Source text of one emitted NumPy function (docstring, optional CSE, return).

    Parameters
    ----------
    k : Kernel
        The function to emit.

    Returns
    -------
    str
        Its Python source, the expressions printed by :func:`expr_code`.
    """
    outputs = list(k.expr) if isinstance(k.expr, (list, tuple)) else [k.expr]
    names = [str(s) for s, _ in k.args]
    lines = [f"def {k.name}({', '.join(names)}):"]
    doc = [k.doc.strip(), "", "Arguments:"]
    doc += [f"    {s}: {meaning}" for s, meaning in k.args]
    if k.returns:
        doc += ["", f"Returns: {k.returns}"]
    lines.append('    """' + "\n    ".join(doc[:1]) + ("\n\n    " + "\n    ".join(doc[2:]) if len(doc) > 2 else ""))
    lines[-1] += '\n    """'
    lines += [f"    {line}" for line in k.extra_lines]
    indent = "    "
    if k.as_arrays:
        lines += [f"    {n} = np.asarray({n}, dtype=float)" for n in names]
        lines.append('    with np.errstate(all="ignore"):  # unused Piecewise branches may divide by zero')
        indent = "        "
    if k.cse:
        repl, reduced = sp.cse(outputs, symbols=sp.numbered_symbols("_t"), optimizations="basic")
    else:
        repl, reduced = [], outputs
    for sym, sub in repl:
        lines.append(f"{indent}{sym} = {expr_code(sub)}")
    if len(reduced) == 1 and not isinstance(k.expr, (list, tuple)):
        lines.append(f"{indent}return {expr_code(reduced[0])}")
    else:
        lines.append(f"{indent}return (" + ", ".join(expr_code(r) for r in reduced) + ",)")
    return "\n".join(lines) + "\n"


def python_module(
    producer: str, summary: str, kernels: Sequence[Kernel], preamble: str = "", postamble: str = ""
) -> str:
    """Full text of a generated module.  ``producer`` is the dotted name of the generating module.

    Parameters
    ----------
    producer : str
        Dotted name of the producing module (named in the header).
    summary : str
        The module docstring.
    kernels : sequence of Kernel
        The functions emitted.
    preamble : str, optional
        Text placed after ``import numpy as np`` (e.g. imports from ``dtcrit.numerics``).
    postamble : str, optional
        Text placed after the functions (tables of kernels).

    Returns
    -------
    str
        The module's text, byte for byte reproducible.
    """
    exprs: list[sp.Basic] = []
    for k in kernels:
        exprs += list(k.expr) if isinstance(k.expr, (list, tuple)) else [k.expr]
    head = [
        f"# GENERATED by {producer} -- do not edit by hand.",
        f"# Regenerate with: {REGENERATE_COMMAND}",
        f"# Derivation hash: {derivation_hash(exprs)}",
        '"""' + summary.strip() + '\n"""',
    ]
    body = "\n\n".join(kernel_source(k) for k in kernels)
    tail = ("\n\n" + postamble.rstrip() + "\n") if postamble else ""
    head += ["import numpy as np", ""] if "np." in preamble + body + tail else [""]  # no unused import
    if preamble:
        head += [preamble.rstrip(), ""]
    return "\n".join(head) + "\n" + body + tail
