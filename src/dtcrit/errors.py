"""The errors dtcrit raises: bad input, a solver that did not converge, and misuse of the API.

All derive from :class:`DtcritError`, so ``except DtcritError`` catches every error dtcrit raises on
purpose; each also derives from the built-in error a Python user expects for its kind:

* :class:`InputError` (a ``ValueError``): a bad argument, scene entry or file content.  It carries a
  :class:`Location` -- the ``source`` (a file), the ``line`` in it and the ``key`` of the entry -- so
  that the command line can print the one-line form ``SOURCE:key: reason`` and exit with status 2;
* :class:`NotConvergedError` (an ``ArithmeticError``): an iterative solver stopped before its
  tolerance; it carries the bracket known to hold the answer;
* :class:`MisuseError` (a ``TypeError``): the API called in a way it does not support (a wrong type
  or an outdated calling convention), a programming error rather than bad data.
"""
from __future__ import annotations

from dataclasses import dataclass


class DtcritError(Exception):
    """The base of every error dtcrit raises on purpose (bad input, no convergence, misuse).

    Examples
    --------
    >>> from dtcrit import DtcritError, InputError, MisuseError, NotConvergedError
    >>> all(issubclass(e, DtcritError) for e in (InputError, MisuseError, NotConvergedError))
    True
    """


@dataclass(frozen=True)
class Location:
    """Where a bad input lies: any of a ``source``, a ``line`` in it and the ``key`` of an entry.

    Parameters
    ----------
    source : str or None
        The file (or other named source) the value came from, as the user gave it.
    line : int or None
        The 1-based line number in ``source``.
    key : str or None
        The path of the entry: a scene key (``contact.kn``, ``particle[2].semi_axes``), a JSON entry
        (``bodies[3].position``) or a flag (``--kn``).
    """

    source: str | None = None
    line: int | None = None
    key: str | None = None

    def __str__(self) -> str:
        """The location as messages print it: ``SOURCE:LINE``, ``SOURCE: key``, ``line N`` or ``key``."""
        parts = []
        if self.source is not None:
            parts.append(self.source if self.line is None else f"{self.source}:{self.line}")
        elif self.line is not None:
            parts.append(f"line {self.line}")
        if self.key is not None:
            parts.append(self.key)
        return ": ".join(parts)


class InputError(DtcritError, ValueError):
    """A bad argument, scene entry or file content: where it lies and what is wrong.

    ``InputError(key, reason)`` names the entry by ``key`` alone (the form used since the first
    release); ``source`` and ``line`` add the file and its line.  ``str(exc)`` is
    ``"{location}: {reason}"`` with the location as :class:`Location` prints it.

    Parameters
    ----------
    key : str or None
        The path of the entry (``contact.kn``, ``bodies[3].shape``, ``--kn``), or None when the
        source and line say everything.
    reason : str
        What is wrong, one line.
    source : str or os.PathLike or None
        The file the value came from.
    line : int or None
        The 1-based line in ``source`` (or in the text read, when ``source`` is None).

    Attributes
    ----------
    location : Location
        The structured location (``source``, ``line``, ``key``).
    key : str
        The location as printed (``str(location)``): the entry's key when there is neither a source
        nor a line, as callers that rename keys to command-line flags expect.
    reason : str
        What is wrong.

    Examples
    --------
    >>> from dtcrit import InputError, parse_scene
    >>> try:
    ...     parse_scene("integrator = 'no-such-scheme'")
    ... except InputError as exc:
    ...     exc.key
    'integrator'
    """

    def __init__(self, key: str | None, reason: str, *, source: object = None, line: int | None = None):
        self.location = Location(None if source is None else str(source), line, key)
        self.key = str(self.location)
        self.reason = reason
        super().__init__(f"{self.key}: {reason}")

    def within(self, source: object) -> InputError:
        """The same error located in ``source`` (a file), for a reader that learns the file's name
        only after the line failed (``line 7`` becomes ``FILE:7``).

        Parameters
        ----------
        source : str or os.PathLike
            The file the located text came from.

        Returns
        -------
        InputError
            A new error with ``location.source`` set (and ``line`` and ``key`` kept).
        """
        return InputError(self.location.key, self.reason, source=source, line=self.location.line)

    @classmethod
    def at(cls, location: Location, reason: str) -> InputError:
        """An error at a given :class:`Location`.

        Parameters
        ----------
        location : Location
            Where the bad input lies.
        reason : str
            What is wrong, one line.

        Returns
        -------
        InputError
            The error, ``str(exc) == f"{location}: {reason}"``.
        """
        return cls(location.key, reason, source=location.source, line=location.line)

    def __reduce__(self):
        return _input_error, (self.location.key, self.reason, self.location.source, self.location.line)


def _input_error(key: str | None, reason: str, source: str | None, line: int | None) -> InputError:
    """Rebuild a pickled :class:`InputError` (its constructor takes more than the message)."""
    return InputError(key, reason, source=source, line=line)


class NotConvergedError(DtcritError, ArithmeticError):
    """An iterative solver stopped before its tolerance: the answer is only known to lie in a bracket.

    The command line prints it as one line with the bracket, exit status 2.

    Parameters
    ----------
    quantity : str
        The quantity solved for, with its unit (``"dt_crit [s]"``).
    lower, upper : float
        The bracket ``[lower, upper]`` known to hold the answer; either end may be ``0`` or ``inf``
        when nothing better is known.
    solver : str
        The solver that stopped (``"ARPACK eigsh"``).
    reason : str
        What happened (iterations exhausted, residual not reached, ...).

    Attributes
    ----------
    quantity, lower, upper, solver, reason
        The parameters as given (``lower`` and ``upper`` as floats).

    Examples
    --------
    >>> from dtcrit import NotConvergedError
    >>> exc = NotConvergedError("dt_crit", 1e-6, 2e-6, "bisection", "the budget ran out")
    >>> exc.bracket
    (1e-06, 2e-06)
    """

    def __init__(self, quantity: str, lower: float, upper: float, solver: str, reason: str):
        self.quantity = quantity
        self.lower = float(lower)
        self.upper = float(upper)
        self.solver = solver
        self.reason = reason
        super().__init__(f"{solver} did not converge ({reason}); {quantity} lies in "
                         f"[{self.lower:.6g}, {self.upper:.6g}]")

    @property
    def bracket(self) -> tuple[float, float]:
        """``(lower, upper)``: the interval known to hold the answer."""
        return self.lower, self.upper


class MisuseError(DtcritError, TypeError):
    """The API called in a way it does not support (a wrong type, an outdated calling convention).

    A programming error, not bad data: the message says how to call it instead.

    Examples
    --------
    >>> from dtcrit import MisuseError
    >>> issubclass(MisuseError, TypeError)
    True
    """
