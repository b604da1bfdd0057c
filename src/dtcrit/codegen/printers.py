"""SymPy printers for the emitted languages (C99, Fortran 2008, NumPy).

Every printer's ``doprint`` first applies the shared expression rewrites once
(``dtcrit.symbolic.emit.rewrite_for_printing``: the root of a sum of two squares becomes ``hypot``,
no overflow, no cancellation); the printers then only print: small integer powers are
multiplications in C, the cubic-root helper and the floating-point primitives are calls to the
helpers emitted next to the kernel.
"""
from __future__ import annotations

import sympy as sp
from sympy.printing.c import C99CodePrinter
from sympy.printing.fortran import FCodePrinter

from dtcrit.symbolic.emit import NumPyHypotPrinter as _NumPyBase
from dtcrit.symbolic.emit import rewrite_for_printing


def nested_branches(printer, expr: sp.Piecewise, template: str) -> str:
    """A Piecewise with a default branch as nested inline choices, ``template`` with the fields
    ``cond``, ``then`` and ``other`` (C ternary, ``np.where``).

    Parameters
    ----------
    printer : sympy.printing.codeprinter.CodePrinter
        The printer of the branches' expressions and conditions.
    expr : sympy.Piecewise
        The Piecewise, with a default branch.
    template : str
        Format string with the fields ``cond``, ``then`` and ``other``.

    Returns
    -------
    str
        The nested choice.
    """
    if expr.args[-1].cond != sp.true:
        raise ValueError("Piecewise without a default branch")
    text = printer._print(expr.args[-1].expr)
    for e, c in reversed(expr.args[:-1]):
        text = template.format(cond=printer._print(c), then=printer._print(e), other=text)
    return text


class _Primitives:
    """The floating-point primitives of ``dtcrit.symbolic.careful_forms`` and the careful step
    ``critical_step(k, c, A)``, printed as calls to helpers emitted beside the kernel
    (``dtcrit.codegen.helpers``): ``PRIMITIVE`` maps a primitive to the helper's name pattern, with
    ``{p}`` the prefix of the file's helpers.
    """

    PRIMITIVE: dict = {}
    prefix = ""

    def doprint(self, expr, assign_to=None):
        """Source text of ``expr`` (assigned to ``assign_to`` when given), after the shared rewrites.

        Parameters
        ----------
        expr : sympy.Basic
            Expression to print.
        assign_to : sympy.Symbol or str, optional
            Variable the value is assigned to (Fortran and C statements).

        Returns
        -------
        str
            The code, ``dtcrit.symbolic.emit.rewrite_for_printing`` applied once to ``expr`` first.
        """
        return super().doprint(rewrite_for_printing(expr), assign_to=assign_to)

    def _call(self, key, expr):
        return f"{self.PRIMITIVE[key].format(p=self.prefix)}({', '.join(self._print(a) for a in expr.args)})"

    def _print_mantissa(self, expr):
        return self._call("mantissa", expr)

    def _print_exponent(self, expr):
        return self._call("exponent", expr)

    def _print_ldexp(self, expr):
        return self._call("ldexp", expr)

    def _print_two_product_error(self, expr):
        return self._call("two_product_error", expr)

    def _print_two_sum_error(self, expr):
        return self._call("two_sum_error", expr)

    def _print_is_nan(self, expr):
        return self._call("is_nan", expr)

    def _print_critical_step(self, expr):
        return self._call("critical_step", expr)

    def _print_critical_step_undamped(self, expr):
        return self._call("critical_step", expr).replace("critical_step(", "critical_step_undamped(")

    def _print_is_negative(self, expr):
        return f"({self._print(expr.args[0])} < 0)"


class _CompiledCalls(_Primitives):
    """Calls shared by the compiled languages: the ``hypot`` function and the cubic-root helper
    ``helper_name`` (its last argument a logical, spelled ``LOGICAL[False]`` / ``LOGICAL[True]``).
    """

    LOGICAL = ("0", "1")
    helper_name = ""

    def _print_cubic_positive_root(self, expr):
        a2, a1, a0, largest = expr.args
        flag = self.LOGICAL[1 if largest else 0]
        return f"{self.helper_name}({self._print(a2)}, {self._print(a1)}, {self._print(a0)}, {flag})"

    def _print_hypot(self, expr):
        return f"hypot({self._print(expr.args[0])}, {self._print(expr.args[1])})"


class CPrinter(_CompiledCalls, C99CodePrinter):
    """C99 with ``hypot``, ``x*x`` for squares and the cubic helper ``<prefix>_cubic_positive_root``.

    Parameters
    ----------
    helper_name : str
        Name of the emitted cubic-root helper.
    prefix : str, optional
        Prefix of the emitted primitive helpers (``<prefix>_mantissa``, ...).
    """

    PRIMITIVE = {"mantissa": "{p}_mantissa", "exponent": "{p}_exponent", "ldexp": "{p}_ldexp",
                 "two_product_error": "{p}_two_product_error", "two_sum_error": "{p}_two_sum_error",
                 "is_nan": "isnan", "critical_step": "{p}_critical_step"}

    def __init__(self, helper_name: str, prefix: str = ""):
        super().__init__()
        self.helper_name = helper_name
        self.prefix = prefix

    def _print_floor(self, expr):
        return f"floor({self._print(expr.args[0])})"

    def _logical(self, expr, op):
        return f" {op} ".join(f"({self._print(a)})" if isinstance(a, (sp.And, sp.Or)) else self._print(a)
                              for a in expr.args)

    def _print_And(self, expr):
        return self._logical(expr, "&&")

    def _print_Or(self, expr):
        return self._logical(expr, "||")

    def _print_Pow(self, expr):
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

    Parameters
    ----------
    helper_name : str
        Name of the emitted cubic-root helper.
    prefix : str, optional
        Prefix of the emitted primitive helpers (unused: Fortran's helpers are private module procedures).
    """

    KIND = "c_double"
    LOGICAL = (".false.", ".true.")

    PRIMITIVE = {"mantissa": "frexp_mantissa", "exponent": "frexp_exponent", "ldexp": "times_power_of_two",
                 "two_product_error": "two_product_error", "two_sum_error": "two_sum_error",
                 "is_nan": "ieee_is_nan", "critical_step": "critical_step"}

    def __init__(self, helper_name: str, prefix: str = ""):
        super().__init__({"standard": 2008, "source_format": "free"})
        self.helper_name = helper_name

    def _print_NaN(self, expr):
        return f"ieee_value(0.0_{self.KIND}, ieee_quiet_nan)"

    def _print_floor(self, expr):
        return f"real(floor({self._print(expr.args[0])}), {self.KIND})"

    def _call(self, key, expr):
        args = [self._real(int(a)) if a.is_Integer else self._print(a) for a in expr.args]
        return f"{self.PRIMITIVE[key]}({', '.join(args)})"

    def _extremum(self, fn, expr):
        args = [self._real(int(a)) if a.is_Integer else self._print(a) for a in expr.args]
        return f"{fn}({', '.join(args)})"

    def _print_Max(self, expr):
        return self._extremum("max", expr)

    def _print_cubic_positive_root(self, expr):
        # the helper's coefficients are real(c_double) dummies: an integer literal coefficient (the y-cubic
        # of adams-bashforth-2 has a2 = 1) must be passed as a real one, or gfortran refuses the call
        *coeffs, largest = expr.args
        args = [self._real(int(a)) if a.is_Integer else self._print(a) for a in coeffs]
        return f"{self.helper_name}({', '.join(args)}, {self.LOGICAL[1 if largest else 0]})"

    def _print_Min(self, expr):
        return self._extremum("min", expr)


    def _real(self, integer: int) -> str:
        return f"{integer}.0_{self.KIND}"

    def _print_Float(self, expr):
        text = super()._print_Float(expr)  # 1.5d0, 1.5d-3: the d exponent becomes e and a kind
        mantissa, _, exponent = text.partition("d")
        return f"{mantissa}{'e' + exponent if exponent not in ('', '0') else ''}_{self.KIND}"

    def _print_Rational(self, expr):
        return f"{self._real(expr.p)}/{self._real(expr.q)}"

    def _print_Pow(self, expr):
        base, exp = expr.args
        prec = sp.printing.precedence.precedence(expr)
        if exp == -1:
            return f"{self._real(1)}/{self.parenthesize(base, prec)}"
        if exp == sp.S.Half and base.is_Integer:
            return f"sqrt({self._real(base)})"
        return super()._print_Pow(expr)


class NumPyPrinter(_Primitives, _NumPyBase):
    """NumPy (vectorised): ``np.hypot``, elementwise ``np.minimum``/``np.maximum``, ``np.where``.

    Parameters
    ----------
    helper_name : str
        Name of the emitted cubic-root helper.
    prefix : str, optional
        Prefix of the emitted primitive helpers (unused: the NumPy helpers carry fixed names).
    """

    PRIMITIVE = {"mantissa": "_mantissa", "exponent": "_exponent", "ldexp": "_ldexp",
                 "two_product_error": "_two_product_error", "two_sum_error": "_two_sum_error",
                 "is_nan": "np.isnan", "critical_step": "_critical_step"}

    def __init__(self, helper_name: str, prefix: str = ""):
        super().__init__({"fully_qualified_modules": True, "inline": True})
        self.helper_name = helper_name

    def _print_Pow(self, expr, rational=False):
        base, exp = expr.args
        if exp == -1:
            return f"(1/{self.parenthesize(base, sp.printing.precedence.PRECEDENCE['Mul'], strict=True)})"
        if exp == sp.Rational(1, 3):  # x**(1/3) would raise x to the rounded 1/3
            return f"np.cbrt({self._print(base)})"
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
