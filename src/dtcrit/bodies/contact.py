"""Inverse-inertia coefficients of a contact between two particles (run time; no SymPy).

Peng, Burns & Hanley (2020), Sections 2, 3 and 5.  With force ``F`` on particle 2 (``-F`` on 1)
at the contact arms ``r1, r2`` and no angular velocity, the relative acceleration of the contact
points is ``xdd_c = A F`` with the symmetric positive definite coefficient matrix

    A = (1/m1 + 1/m2) 1 + sum_i [r_i]x^T W_i [r_i]x,   W_i = Q_i I_i^-1 Q_i^T

(derived from Eqs 1-19 in ``dtcrit.symbolic.kinematics``; the paper keeps its diagonal in three
special configurations, Eqs 22-25).  The functions here:

* :func:`a_max` -- Eq (26) as printed.  It bounds ``A`` for the ellipsoids of the paper but *not*
  for boxes, polyhedra or box-like superquadrics (see ``derivations/records/sec2_3_kinematics.md``).
* :func:`a_bound` -- an upper bound on ``lambda_max(A)`` valid for every admissible contact of the
  two shapes: ``1/m1 + 1/m2 + S1 + S2`` with ``S_i`` the supremum over the body of
  ``lambda_max([p]x^T I_i^-1 [p]x)`` (:func:`dtcrit.bodies.arm_supremum.arm_term_supremum`).  It is
  attained for identical particles and, whenever the top eigenvectors can be aligned, for others.
* :func:`b_max` -- Eq (54); :func:`b_bound` -- the tight constant of the gyroscopic term.
* :func:`coefficient_matrix` -- ``A`` for given arms and orientations (``body_to_world=(R1, R2)``).

Rotation convention (the one used wherever dtcrit carries a quaternion): an orientation is
*body-to-world*.  The unit quaternion ``q = (qw, qx, qy, qz)`` of a particle gives, through the
matrix printed as Eq (7), ``Q = R(q)`` with ``v_world = Q v_body`` (the columns of ``Q`` are the
body axes in world components).  The paper's Eq (5) matrix, world to body (``M_L = R M_G``), is
``Q^T``, the matrix of the conjugate quaternion.

Units: SI throughout; ``A`` in 1/kg, ``B`` dimensionless.
"""
from __future__ import annotations

import math

import numpy as np

from dtcrit._generated import contact as _k
from dtcrit.bodies.arm_supremum import arm_term_supremum
from dtcrit.bodies.arm_terms import arm_terms_local
from dtcrit.errors import InputError, MisuseError

__all__ = ["a_max", "a_bound", "b_max", "b_bound", "coefficient_matrix"]


# ============================================================================================
# Input checks
# ============================================================================================
def _shape(key: str, p):
    """Accept anything with the dtcrit shape interface: positive finite ``mass``, ``inertia`` (3),
    ``half_lengths`` (3) and ``max_arm``.
    """
    try:
        mass = float(p.mass)
        inertia = tuple(float(i) for i in p.inertia)
        half = tuple(float(h) for h in p.half_lengths)
        arm = float(p.max_arm)
    except (AttributeError, TypeError, ValueError):
        raise InputError(key, f"must be a dtcrit shape (Sphere, Ellipsoid, Superquadric, Box, ConvexPolyhedron); got {type(p).__name__}") from None
    values = (mass, *inertia, *half, arm)
    if len(inertia) != 3 or len(half) != 3 or not all(math.isfinite(v) and v > 0 for v in values):
        raise InputError(key, "mass, principal moments, half-lengths and max_arm must be positive and finite")
    return p


def _vector(key: str, v) -> np.ndarray:
    try:
        x = np.asarray(v, dtype=float)
    except (TypeError, ValueError):
        raise InputError(key, f"must be a 3-vector of real numbers (got {v!r})") from None
    if x.shape != (3,):
        raise InputError(key, f"must be a 3-vector (got shape {x.shape})")
    if not np.all(np.isfinite(x)):
        raise InputError(key, "must be finite")
    return x


def _rotation(key: str, R) -> np.ndarray:
    """A particle's orientation ``Q``, body to world (``v_world = Q v_body``), from ``None`` (identity), a
    unit quaternion ``(qw, qx, qy, qz)`` (normalised here; ``Q`` is its Eq (7) matrix) or a proper
    orthogonal 3x3 body-to-world matrix.
    """
    if R is None:
        return np.eye(3)
    try:
        x = np.asarray(R, dtype=float)
    except (TypeError, ValueError):
        raise InputError(key, f"must be a quaternion (qw, qx, qy, qz) or a 3x3 rotation matrix (got {R!r})") from None
    if not np.all(np.isfinite(x)):
        raise InputError(key, "must be finite")
    if x.shape == (4,):
        norm = float(np.linalg.norm(x))
        if norm == 0.0:
            raise InputError(key, "quaternion must be non-zero")
        q = x / norm
        return np.array([float(e) for e in _k.rotation_matrix(*q)]).reshape(3, 3)
    if x.shape != (3, 3):
        raise InputError(key, f"must be a quaternion (4,) or a rotation matrix (3, 3) (got shape {x.shape})")
    if np.max(np.abs(x @ x.T - np.eye(3))) > 1e-9 or np.linalg.det(x) <= 0:
        raise InputError(key, "must be a proper rotation matrix (R R^T = 1 within 1e-9, det R = +1)")
    return x


# ============================================================================================
# Eq (26), the valid bound, Eq (54) and the coefficient matrix
# ============================================================================================
def a_max(p1, p2=None) -> float:
    """Peng et al. 2020, Eq (26) as printed: ``a1^2/Ixx1 + a2^2/Ixx2 + 1/m1 + 1/m2`` [1/kg].

    ``a`` is the largest half-length and ``Ixx`` the first principal moment of each particle;
    ``p2=None`` means two identical particles.  Not an upper bound on ``lambda_max(A)`` for boxes,
    polyhedra and box-like superquadrics (use :func:`a_bound`).

    Parameters
    ----------
    p1 : object
        The first shape.
    p2 : object, optional
        The second shape (None: identical to ``p1``).

    Returns
    -------
    float
        ``A_max`` [1/kg].

    Examples
    --------
    >>> from dtcrit import Sphere, a_max
    >>> a_max(Sphere(1.0, mass=1.0))   # 1/m + R^2/I = 1 + 1/0.4 for each of the two spheres
    7.0
    """
    p1 = _shape("p1", p1)
    p2 = p1 if p2 is None else _shape("p2", p2)
    return float(_k.a_max(p1.mass, p1.inertia[0], p1.half_lengths[0], p2.mass, p2.inertia[0], p2.half_lengths[0]))


def a_bound(p1, p2=None) -> float:
    """Upper bound on ``lambda_max(A)`` over every admissible contact of the two shapes [1/kg].

    ``1/m1 + 1/m2 + S1 + S2`` where ``S_i >= sup over the body of lambda_max([p]x^T I_i^-1 [p]x)``:
    exact for polyhedra (vertex maximum) and isotropic inertia, within ``SUP_RTOL`` (1e-7) of the
    best surface value for smooth bodies (outer support polytopes; the returned value is an upper
    bound in every case).  Holds because ``lambda_max`` is subadditive; equality for identical
    particles (``dtcrit.bodies.contact_search.mirror_contact``).  ``p2=None``: identical particles.

    Parameters
    ----------
    p1 : object
        The first shape.
    p2 : object, optional
        The second shape (None: identical to ``p1``).

    Returns
    -------
    float
        The bound [1/kg].

    Examples
    --------
    >>> from dtcrit import Ellipsoid, a_max, a_bound
    >>> e = Ellipsoid(3.0, 2.0, 1.0, density=1000.0)
    >>> a_bound(e) <= a_max(e)   # the paper's Eq. (26) bound against the exact supremum
    True
    """
    p1 = _shape("p1", p1)
    p2 = p1 if p2 is None else _shape("p2", p2)
    s1 = arm_term_supremum(p1).upper
    s2 = s1 if p2 is p1 else arm_term_supremum(p2).upper
    return float(1.0 / p1.mass + 1.0 / p2.mass + s1 + s2)


B_ROUNDING = 64 * 2.220446049250313e-16
"""Differences of principal moments at the rounding level of their computation (a cube built from its
corners has ``B ~ 3e-16``) are equal moments: ``b_max`` below this is 0, not a rotation step of 1e13 s."""


def b_max(p) -> float:
    """Peng et al. 2020, Eq (54): ``max(|Ixx-Iyy|/Izz, |Ixx-Izz|/Iyy, |Iyy-Izz|/Ixx)`` (dimensionless),
    0 below ``B_ROUNDING``.

    Parameters
    ----------
    p : object
        The shape (its principal moments).

    Returns
    -------
    float
        ``B_max``.

    Examples
    --------
    >>> from dtcrit import Ellipsoid, b_max, b_bound
    >>> e = Ellipsoid(3.0, 2.0, 1.0, density=1000.0)
    >>> round(b_max(e), 12), round(b_bound(e), 12)   # the exact supremum and the paper's bound
    (0.8, 0.4)
    """
    p = _shape("p", p)
    b = float(_k.b_max(*p.inertia))
    return b if b > B_ROUNDING else 0.0


def b_bound(p) -> float:
    """Tight constant ``G = max over unit w of |I^-1 (w x I w)|`` of the gyroscopic term.

    Euler's equations (Eqs 11-12, ``M_L = 0``) give ``|wdot| <= G |w|^2`` with equality for some
    ``w``, so for any orientation every global component satisfies ``|wdot_k| <= G w_max^2`` and the
    bound is attained.  ``B_max/2 <= G <= B_max/sqrt(3)`` (derivations/records/sec5_rotation.md).

    With ``x_i = w_i^2`` on the simplex, ``|wdot|^2 = c_x^2 x_y x_z + c_y^2 x_z x_x + c_z^2 x_x x_y`` is
    a quadratic form; its maximum is at an edge midpoint (``c_i^2/4``) or at the interior stationary
    point, both evaluated here in closed form.

    Parameters
    ----------
    p : object
        The shape (its principal moments).

    Returns
    -------
    float
        ``G`` (dimensionless).

    Examples
    --------
    >>> from dtcrit import Ellipsoid, b_bound
    >>> round(b_bound(Ellipsoid(3.0, 2.0, 1.0, density=1000.0)), 12)
    0.4
    """
    p = _shape("p", p)
    c = np.array([float(x) for x in _k.gyroscopic_coefficients(*p.inertia)])
    a, b, g = c**2
    best = max(a, b, g) / 4.0
    Q = np.array([[0.0, g, b], [g, 0.0, a], [b, a, 0.0]])
    det = 2.0 * a * b * g
    if det > 1e-300:
        y = np.linalg.solve(Q, np.ones(3))
        if np.all(y > 0):
            x = y / np.sum(y)
            best = max(best, 0.5 * float(x @ Q @ x))
    return math.sqrt(best)


_OLD_ROTATIONS = object()  # the default of the retired R1, R2 parameters: given at all, they are refused
OLD_ROTATION_CALL = (
    "coefficient_matrix takes the orientations as body_to_world=(R1, R2), keyword only: R_i maps body to world "
    "components (v_world = R_i v_body; the unit quaternion (qw, qx, qy, qz) of Eq (7), or that matrix); the paper's "
    "Eq (5) matrix, world to body, is its transpose.  A rotation passed positionally or as R1=/R2= is refused: an "
    "older dtcrit read it as world to body, so the same call would now silently use its inverse")


def coefficient_matrix(p1, p2, r1, r2, *rotations, body_to_world=None, R1=_OLD_ROTATIONS,
                       R2=_OLD_ROTATIONS) -> np.ndarray:
    """The 3x3 coefficient matrix ``A`` of the contact force in ``xdd_c = A F + Omega`` (global frame).

    Parameters
    ----------
    p1, p2 : object
        The two ``dtcrit.bodies`` shapes.
    r1, r2 : array_like, shape (3,)
        Contact arms ``x_c - x_i`` in global components (Peng et al. 2020, Eqs 1-2).  They need not lie
        on the surfaces (pure kinematics).
    body_to_world : pair ``(R1, R2)``, keyword only, optional
        The particles' orientations, body to world (``v_world = R_i v_body``): each a unit quaternion
        ``(qw, qx, qy, qz)`` whose Eq (7) matrix is that rotation, the rotation matrix itself, or
        ``None`` (axis aligned); ``None`` for the pair means both axis aligned.  The paper's Eq (5)
        rotation, world to body, is ``R_i^T``.
    *rotations, R1, R2
        Retired positional or ``R1=``/``R2=`` rotations (read as world to body by an older dtcrit):
        passing any raises ``TypeError`` saying so.

    Returns
    -------
    ndarray, shape (3, 3)
        ``A = (1/m1 + 1/m2) 1 + sum_i R_i T_i(R_i^T r_i) R_i^T`` with the generated per-particle term
        ``T(p) = [p]x^T I^-1 [p]x`` in body components (Eqs 3-19), symmetrised.

    Examples
    --------
    >>> from dtcrit import Sphere, coefficient_matrix
    >>> s = Sphere(1.0, mass=1.0)   # two unit spheres touching along x
    >>> coefficient_matrix(s, s, (1.0, 0.0, 0.0), (-1.0, 0.0, 0.0)).round(12).tolist()
    [[2.0, 0.0, 0.0], [0.0, 7.0, 0.0], [0.0, 0.0, 7.0]]
    """
    if rotations or R1 is not _OLD_ROTATIONS or R2 is not _OLD_ROTATIONS:
        raise MisuseError(OLD_ROTATION_CALL)  # a TypeError: the retired calling convention
    p1, p2 = _shape("p1", p1), _shape("p2", p2)
    r1, r2 = _vector("r1", r1), _vector("r2", r2)
    Q1, Q2 = _rotation_pair(body_to_world)
    T1 = Q1 @ arm_terms_local((Q1.T @ r1)[None, :], p1.inertia)[0] @ Q1.T
    T2 = Q2 @ arm_terms_local((Q2.T @ r2)[None, :], p2.inertia)[0] @ Q2.T
    A = (1.0 / p1.mass + 1.0 / p2.mass) * np.eye(3) + T1 + T2
    return 0.5 * (A + A.T)


def _rotation_pair(pair) -> tuple[np.ndarray, np.ndarray]:
    """``body_to_world``: ``None`` or a pair of orientations (``_rotation``), keys ``body_to_world[1|2]``."""
    if pair is None:
        return np.eye(3), np.eye(3)
    if isinstance(pair, (str, bytes, dict)) or not hasattr(pair, "__len__") or len(pair) != 2:
        raise InputError("body_to_world", "must be a pair (R1, R2) of orientations, body to world: quaternions "
                         f"(qw, qx, qy, qz), 3x3 matrices or None (got {type(pair).__name__} "
                         f"of length {len(pair) if hasattr(pair, '__len__') else '-'})")
    return _rotation("body_to_world[1]", pair[0]), _rotation("body_to_world[2]", pair[1])
