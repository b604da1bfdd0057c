"""The functions the emitted code calls, as SymPy function classes (printed by ``dtcrit.codegen.printers``)."""
from __future__ import annotations

import sympy as sp

import dtcrit.symbolic.emit as _emit


class cubic_positive_root(sp.Function):
    """Smallest (largest when the fourth argument is true) positive real root of
    t^3 + a2 t^2 + a1 t + a0 (0 when there is none); emitted as a helper function.

    Parameters
    ----------
    *args : sympy.Expr
        ``a2, a1, a0, largest``: the cubic's coefficients and the flag choosing the largest root.
    """

    nargs = 4
    is_real = True
    is_nonnegative = True


class critical_step(sp.Function):
    """The careful critical step of one mode, dt(k, c, A) (``dtcrit.symbolic.careful_forms``),
    emitted as a helper function beside the kernel (``dtcrit.codegen.step``).

    Parameters
    ----------
    *args : sympy.Expr
        ``k, c, A``: stiffness [N/m], viscous coefficient [N s/m] and the mode's inverse mass [1/kg].
    """

    nargs = 3
    is_real = True


class critical_step_undamped(sp.Function):
    """``critical_step`` of an undamped mode, dt(k, A).

    Parameters
    ----------
    *args : sympy.Expr
        ``k, A``: stiffness [N/m] and the mode's inverse mass [1/kg].
    """

    nargs = 2
    is_real = True


hypot = _emit.hypot  # sqrt(x^2 + y^2) without overflow: the class the shared rewrite emits
