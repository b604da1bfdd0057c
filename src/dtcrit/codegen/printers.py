"""SymPy printers for the emitted languages (C99, Fortran 2008, NumPy).

Common rules: the root of a sum of two squares is printed as ``hypot`` (no overflow, no
cancellation); small integer powers are multiplications in C; the cubic-root helper is printed as
a call to the helper emitted next to the kernel.
"""
from __future__ import annotations

import sympy as sp
from sympy.printing.c import C99CodePrinter
from sympy.printing.fortran import FCodePrinter

from dtcrit.symbolic.emit import NumPyHypotPrinter as _NumPyBase
from dtcrit.symbolic.emit import hypot_arguments as _hypot_args


def nested_branches(printer, expr: sp.Piecewise, template: str) -> str:
    """A Piecewise with a default branch as nested inline choices, ``template`` with the fields
    ``cond``, ``then`` and ``other`` (C ternary, ``np.where``)."""
    if expr.args[-1].cond != sp.true:
        raise ValueError("Piecewise without a default branch")
    text = printer._print(expr.args[-1].expr)
    for e, c in reversed(expr.args[:-1]):
        text = template.format(cond=printer._print(c), then=printer._print(e), other=text)
    return text


class _CompiledCalls:
    """Calls shared by the compiled languages: the ``hypot`` function and the cubic-root helper
    ``helper_name`` (its last argument a logical, spelled ``LOGICAL[False]`` / ``LOGICAL[True]``)."""

    LOGICAL = ("0", "1")
    helper_name = ""

    def _print_cubic_positive_root(self, expr):
        a2, a1, a0, largest = expr.args
        flag = self.LOGICAL[1 if largest else 0]
        return f"{self.helper_name}({self._print(a2)}, {self._print(a1)}, {self._print(a0)}, {flag})"

    def _print_hypot(self, expr):
        return f"hypot({self._print(expr.args[0])}, {self._print(expr.args[1])})"


class CPrinter(_CompiledCalls, C99CodePrinter):
    """C99 with ``hypot``, ``x*x`` for squares and the cubic helper ``<prefix>_cubic_positive_root``."""

    def __init__(self, helper_name: str):
        super().__init__()
        self.helper_name = helper_name

    def _print_Pow(self, expr):
        roots = _hypot_args(expr)
        if roots is not None:
            text = f"hypot({self._print(roots[0])}, {self._print(roots[1])})"
            return text if expr.exp == sp.S.Half else f"(1.0/{text})"
        base, exp = expr.args
        if exp == 2:
            b = self.parenthesize(base, sp.printing.precedence.PRECEDENCE["Mul"], strict=True)
            return f"({b}*{b})"
        if exp == -1:
            return f"(1.0/{self.parenthesize(base, sp.printing.precedence.PRECEDENCE['Mul'], strict=True)})"
        if exp == -2:
            b = self.parenthesize(base, sp.printing.precedence.PRECEDENCE["Mul"], strict=True)
            return f"(1.0/({b}*{b}))"
        if exp == 4:
            b = self.parenthesize(base, sp.printing.precedence.PRECEDENCE["Mul"], strict=True)
            return f"(({b}*{b})*({b}*{b}))"
        if exp == -4:
            b = self.parenthesize(base, sp.printing.precedence.PRECEDENCE["Mul"], strict=True)
            return f"(1.0/(({b}*{b})*({b}*{b})))"
        return super()._print_Pow(expr)

    def _print_Piecewise(self, expr):
        return nested_branches(self, expr, "(({cond}) ? ({then}) : ({other}))")


class FortranPrinter(_CompiledCalls, FCodePrinter):
    """Fortran 2008 free form (``hypot`` intrinsic, ``merge`` for inline branches).

    Every real literal carries the kind ``c_double`` of the variables (``0.5_c_double``), not
    SymPy's ``d0``: a ``d0`` literal is DOUBLE PRECISION, which compilers can widen on their own
    (gfortran's ``-fdefault-real-8`` makes it quad precision), and then ``merge``, ``max`` and
    ``sign`` refuse the mixed kinds, or the arithmetic silently leaves IEEE double.
    """

    KIND = "c_double"
    LOGICAL = (".false.", ".true.")

    def __init__(self, helper_name: str):
        super().__init__({"standard": 2008, "source_format": "free"})
        self.helper_name = helper_name

    def _real(self, integer: int) -> str:
        return f"{integer}.0_{self.KIND}"

    def _print_Float(self, expr):
        text = super()._print_Float(expr)  # 1.5d0, 1.5d-3: the d exponent becomes e and a kind
        mantissa, _, exponent = text.partition("d")
        return f"{mantissa}{'e' + exponent if exponent not in ('', '0') else ''}_{self.KIND}"

    def _print_Rational(self, expr):
        return f"{self._real(expr.p)}/{self._real(expr.q)}"

    def _print_Pow(self, expr):
        roots = _hypot_args(expr)
        if roots is not None:
            text = f"hypot({self._print(roots[0])}, {self._print(roots[1])})"
            return text if expr.exp == sp.S.Half else f"({self._real(1)}/{text})"
        base, exp = expr.args
        prec = sp.printing.precedence.precedence(expr)
        if exp == -1:
            return f"{self._real(1)}/{self.parenthesize(base, prec)}"
        if exp == sp.S.Half and base.is_Integer:
            return f"sqrt({self._real(base)})"
        return super()._print_Pow(expr)


class NumPyPrinter(_NumPyBase):
    """NumPy (vectorised): ``np.hypot``, elementwise ``np.minimum``/``np.maximum``, ``np.where``."""

    def __init__(self, helper_name: str):
        super().__init__({"fully_qualified_modules": True, "inline": True})
        self.helper_name = helper_name

    def _print_Pow(self, expr, rational=False):
        base, exp = expr.args
        if exp == -1:
            return f"(1/{self.parenthesize(base, sp.printing.precedence.PRECEDENCE['Mul'], strict=True)})"
        return super()._print_Pow(expr, rational=rational)

    def _nested(self, fn, args):
        args = [self._print(a) for a in args]
        text = args[-1]
        for a in reversed(args[:-1]):
            text = f"{fn}({a}, {text})"
        return text

    def _print_Min(self, expr):
        return self._nested("np.minimum", expr.args)

    def _print_Max(self, expr):
        return self._nested("np.maximum", expr.args)

    def _print_Piecewise(self, expr):
        return nested_branches(self, expr, "np.where({cond}, {then}, {other})")

    def _print_cubic_positive_root(self, expr):
        a2, a1, a0, largest = expr.args
        return f"{self.helper_name}({self._print(a2)}, {self._print(a1)}, {self._print(a0)}, {bool(largest)})"

    def _print_hypot(self, expr):
        return f"np.hypot({self._print(expr.args[0])}, {self._print(expr.args[1])})"
