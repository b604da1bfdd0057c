"""Errors raised for bad user input.

``InputError`` carries the offending key so that the command line can print the one-line form
``SOURCE:key: reason`` and exit with status 2.  It subclasses ``ValueError`` so that library users
can catch it as the ordinary Python error for a bad argument.
"""
from __future__ import annotations


class InputError(ValueError):
    """A bad argument or scene entry: ``key`` names it, ``reason`` says what is wrong."""

    def __init__(self, key: str, reason: str):
        self.key = key
        self.reason = reason
        super().__init__(f"{key}: {reason}")


class NotConvergedError(ArithmeticError):
    """An iterative solver stopped before its tolerance: the answer is only known to lie in
    ``[lower, upper]`` (``quantity`` names it, with its unit; either end may be ``0`` or ``inf`` when
    nothing better is known).  ``solver`` names the solver, ``reason`` says what happened.  The
    command line prints it as one line with the bracket, exit status 2.
    """

    def __init__(self, quantity: str, lower: float, upper: float, solver: str, reason: str):
        self.quantity = quantity
        self.lower = float(lower)
        self.upper = float(upper)
        self.solver = solver
        self.reason = reason
        super().__init__(f"{solver} did not converge ({reason}); {quantity} lies in "
                         f"[{self.lower:.6g}, {self.upper:.6g}]")
