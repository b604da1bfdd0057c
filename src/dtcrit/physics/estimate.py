"""One estimate of a critical time step, and its rating against the verified ``dt_crit``.

``dtcrit step``, ``dtcrit packing`` and ``dtcrit audit`` all set cheap estimates (the codes' rules
of thumb, per-body and Gershgorin bounds, Rayleigh quotients) beside the critical step.  Each is an
:class:`Estimate`; :class:`RatedEstimate` compares it with ``dt_crit`` using one tolerance,
``SAFE_RTOL``: an estimate equal to ``dt_crit`` up to rounding (e.g. the exact two-sphere bound) is
safe, not a violation.  :meth:`RatedEstimate.to_json` is the one JSON shape; each command maps it to
its published schema where they differ.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["SAFE_RTOL", "Estimate", "RatedEstimate", "is_safe"]

SAFE_RTOL = 1e-9
"""An estimate is safe when ``dt <= dt_crit (1 + SAFE_RTOL)``."""


def is_safe(dt: float, dt_crit: float) -> bool:
    """Whether a step ``dt`` is within the critical step, ``dt <= dt_crit (1 + SAFE_RTOL)``.

    Parameters
    ----------
    dt : float
        The estimate [s].
    dt_crit : float
        The verified critical step [s].

    Returns
    -------
    bool
        True when safe (a nan ``dt`` is not).
    """
    return bool(dt <= dt_crit * (1.0 + SAFE_RTOL))


@dataclass(frozen=True)
class Estimate:
    """One labelled estimate of the critical step.

    Parameters
    ----------
    name : str
        Its key in the documents (``rayleigh``, ``gershgorin``, ...).
    dt : float or None
        The step [s]; None when it does not apply to this input (``detail`` says why).
    kind : str
        What kind of statement it is ("lower bound on dt", "heuristic", "rule of thumb", ...).
    detail : str
        Where it is attained, or why it does not apply.
    label : str
        What it is, in words (the formula and the codes that use it).
    omega2 : float or None
        The squared angular frequency [1/s^2] it stands for, ``dt = 2/omega``, when it is one.
    """

    name: str
    dt: float | None
    kind: str = ""
    detail: str = ""
    label: str = ""
    omega2: float | None = None

    @classmethod
    def from_omega2(cls, name: str, omega2: float, kind: str, detail: str = "") -> "Estimate":
        """An estimate given by its ``omega^2``: ``dt = 2/omega`` (infinite for ``omega2 <= 0``).

        Parameters
        ----------
        name : str
            Its key.
        omega2 : float
            Squared angular frequency [1/s^2].
        kind : str
            What kind of statement it is.
        detail : str
            Where it is attained.

        Returns
        -------
        Estimate
            The estimate with ``dt = 2/sqrt(omega2)``.
        """
        dt = float(2.0 / math.sqrt(omega2)) if omega2 > 0 else float("inf")
        return cls(name, dt, kind, detail, omega2=float(omega2))


@dataclass(frozen=True)
class RatedEstimate:
    """An estimate beside the critical step it is rated against.

    Parameters
    ----------
    estimate : Estimate
        The estimate.
    dt_crit : float
        The verified critical step [s].
    """

    estimate: Estimate
    dt_crit: float

    @property
    def ratio(self) -> float | None:
        """``dt/dt_crit`` (nan when ``dt_crit`` is not positive and finite; None without ``dt``)."""
        dt = self.estimate.dt
        if dt is None:
            return None
        return dt / self.dt_crit if self.dt_crit > 0 and math.isfinite(self.dt_crit) else float("nan")

    @property
    def safe(self) -> bool | None:
        """Whether ``dt <= dt_crit (1 + SAFE_RTOL)``; None when the estimate does not apply."""
        return None if self.estimate.dt is None else is_safe(self.estimate.dt, self.dt_crit)

    @property
    def unsafe(self) -> bool | None:
        """The negation of :attr:`safe` (None when the estimate does not apply)."""
        return None if self.estimate.dt is None else not is_safe(self.estimate.dt, self.dt_crit)

    def to_json(self) -> dict:
        """The common JSON shape of a rated estimate.

        Returns
        -------
        dict
            ``name``, ``dt``, ``ratio``, ``safe``, ``kind``, ``detail``, ``label`` (numbers as given;
            apply :func:`dtcrit.physics.json_numbers.json_safe` before writing).
        """
        e = self.estimate
        return {"name": e.name, "dt": e.dt, "ratio": self.ratio, "safe": self.safe, "kind": e.kind,
                "detail": e.detail, "label": e.label}
