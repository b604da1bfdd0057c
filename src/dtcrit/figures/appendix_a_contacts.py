"""The records of Appendix A's search: one evaluated contact (``ContactConfig``) and the maxima found.

A contact of particle 2 on particle 1 (global frame = particle 1's frame), its coefficient matrix ``A``
(Peng et al. 2020, Eqs. 3-19), ``|A F|`` and the largest eigenvalue; orientations are body to world
and are also reported as Eq. (7) quaternions.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from dtcrit.figures._rotations import matrix_quaternion

QUATERNION_KEY = "quaternion_2_body_to_world_wxyz"
"""JSON key of particle 2's orientation: (qw, qx, qy, qz), body to world (Eq. (7) gives v_world = R(q) v_body)."""


@dataclass(frozen=True)
class ContactConfig:
    """One contact of particle 2 on particle 1 (global frame = particle 1's frame).

    Parameters
    ----------
    normal : tuple of float
        Outward normal of particle 1 at the contact (global).
    orientation : tuple of tuple of float
        Rows of ``Q2``, body to world.
    contact_point : tuple of float
        The contact point [m].
    r1, r2 : tuple of float
        Contact arms [m].
    centre2 : tuple of float
        Centre of particle 2 [m].
    matrix : tuple of tuple of float
        Rows of the coefficient matrix ``A`` [1/kg].
    accel : float
        ``|A F|`` [m/s^2].
    lam : float
        Largest eigenvalue of ``A`` [1/kg].
    label : str
        Name of the configuration.
    """

    normal: tuple[float, float, float]  # outward normal of particle 1 at the contact (global)
    orientation: tuple[tuple[float, ...], ...]  # Q2, body to world (v_world = Q2 v_body), rows
    contact_point: tuple[float, float, float]
    r1: tuple[float, float, float]
    r2: tuple[float, float, float]
    centre2: tuple[float, float, float]
    matrix: tuple[tuple[float, ...], ...]
    accel: float  # |A F|
    lam: float  # largest eigenvalue of A
    label: str = ""

    @property
    def quaternion(self) -> tuple[float, float, float, float]:
        """(qw, qx, qy, qz) of particle 2, body to world: its Eq. (7) matrix is ``Q2`` (qw >= 0).  Passed as
        ``body_to_world=(None, q)`` to ``dtcrit.bodies.contact.coefficient_matrix`` it gives ``matrix``.
        """
        return matrix_quaternion(np.array(self.orientation))

    def describe(self, digits: int = 6) -> dict:
        """Rounded, JSON-ready description.

        Parameters
        ----------
        digits : int
            Significant digits kept.

        Returns
        -------
        dict
            The configuration's vectors and matrices as rounded lists.
        """
        def rnd(v):
            if isinstance(v, (tuple, list, np.ndarray)):
                return [rnd(x) for x in v]
            return float(f"{float(v):.{digits}g}") + 0.0

        Q = np.array(self.orientation)
        long2 = Q[:, 0]
        return {
            "label": self.label,
            "accel": rnd(self.accel),
            "lambda_max": rnd(self.lam),
            "normal_1": rnd(self.normal),
            "contact_point": rnd(self.contact_point),
            "r1": rnd(self.r1),
            "r2": rnd(self.r2),
            "centre_2": rnd(self.centre2),
            QUATERNION_KEY: rnd(self.quaternion),
            "long_axis_2": rnd(long2 * (1 if long2[np.argmax(np.abs(long2))] > 0 else -1)),
            "angle_between_long_axes_deg": rnd(math.degrees(math.acos(min(1.0, abs(float(long2[0])))))),
            "matrix": rnd(self.matrix),
        }


def _config(body1, body2, n, Q2, r1, r2, A, force, label="") -> ContactConfig:
    def tup(v) -> tuple[float, float, float]:
        x, y, z = (float(t) for t in np.ravel(v))
        return x, y, z

    A = np.asarray(A, dtype=float)
    return ContactConfig(
        tup(n), tuple(tup(row) for row in Q2), tup(r1), tup(r1), tup(r2), tup(np.asarray(r1) - np.asarray(r2)),
        tuple(tup(row) for row in A), float(np.linalg.norm(A @ force)), float(np.linalg.eigvalsh(A)[-1]), label,
    )


# ============================================================================================
# The search
# ============================================================================================
@dataclass
class SearchResult:
    """Maxima over all admissible contacts found by :meth:`PairSearch.search`.

    Parameters
    ----------
    best_accel : ContactConfig
        Largest ``|A F|`` found.
    best_lam : ContactConfig
        Largest eigenvalue found.
    grid_accel : float
        Best ``|A F|`` on the grid, before polishing.
    grid_lam : float
        Best eigenvalue on the grid, before polishing.
    evaluated : int
        Number of grid contacts.
    polished : list of ContactConfig
        Every polished end point.
    """

    best_accel: ContactConfig
    best_lam: ContactConfig
    grid_accel: float  # best on the grid, before polishing
    grid_lam: float
    evaluated: int  # number of grid contacts
    polished: list[ContactConfig] = field(default_factory=list)
