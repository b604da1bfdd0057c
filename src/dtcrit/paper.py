"""The paper's printed formulas, labelled as printed, next to the verified ones dtcrit uses.

Peng, Burns & Hanley 2020 (Int J Numer Methods Eng, doi:10.1002/nme.6568) print three formulas that
dtcrit does not use as they stand; they are kept here, for comparison only, each beside the form
dtcrit verified (derivations/records):

* Eq. (26), ``A_max = a1^2/Ixx1 + a2^2/Ixx2 + 1/m1 + 1/m2``: not an upper bound on ``lambda_max(A)``
  for boxes, polyhedra and box-like superquadrics.  Verified: :func:`a_bound`, a bound for every
  admissible contact of the two shapes.
* Eq. (46), ``dt = (c A + sqrt(c^2 A^2 + 4 k A)) / (k A)``: where a *real* eigenvalue of the Eq. (40)
  scheme's amplification matrix reaches -1, not that scheme's stability bound.  Verified:
  :func:`eq40_critical_dt`, the exact boundary of the scheme as printed (``paper-eq40``).
* Eq. (54), ``B_max = max(|Ixx-Iyy|/Izz, |Ixx-Izz|/Iyy, |Iyy-Izz|/Ixx)``: the constant of the
  rotation bound Eq. (56) as printed.  Verified: :func:`b_bound`, the tight gyroscopic constant
  ``G = max |I^-1 (w x I w)|`` over unit ``w`` (``B_max/2 <= G <= B_max/sqrt(3)``).

``FORMS`` lists the pairs.  Nothing here imports SymPy.

Examples
--------
>>> from dtcrit import paper
>>> [(f.equation, f.printed, f.verified) for f in paper.FORMS][1]
('Eq. (46)', 'eq46_dt', 'eq40_critical_dt')
>>> paper.eq46_dt(1.0, 0.0, 1.0), paper.eq40_critical_dt(1.0, 0.0, 1.0)  # undamped, Eq. (40) has no stable step
(2.0, 0.0)
"""
from __future__ import annotations

from dataclasses import dataclass

__all__ = ["FORMS", "PaperForm", "a_bound", "b_bound", "eq26_a_max", "eq40_critical_dt", "eq46_dt",
           "eq54_b_max"]


@dataclass(frozen=True)
class PaperForm:
    """One of the paper's printed formulas and the verified form beside it.

    Parameters
    ----------
    equation : str
        The equation number in Peng et al. 2020.
    printed : str
        The name of the function in this module computing the formula as printed.
    verified : str
        The name of the function in this module computing the verified form.
    note : str
        Where the printed form falls short.
    """

    equation: str
    printed: str
    verified: str
    note: str


FORMS = (
    PaperForm("Eq. (26)", "eq26_a_max", "a_bound",
              "not an upper bound on lambda_max(A) for boxes, polyhedra and box-like superquadrics"),
    PaperForm("Eq. (46)", "eq46_dt", "eq40_critical_dt",
              "where a real eigenvalue of the Eq. (40) scheme reaches -1, not its stability bound"),
    PaperForm("Eq. (54)", "eq54_b_max", "b_bound",
              "B_max as printed; the tight gyroscopic constant G lies in [B_max/2, B_max/sqrt(3)]"),
)
"""The printed formulas and their verified counterparts."""


def eq26_a_max(p1, p2=None) -> float:
    """Peng et al. 2020, Eq. (26) as printed: ``a1^2/Ixx1 + a2^2/Ixx2 + 1/m1 + 1/m2`` [1/kg].

    Parameters
    ----------
    p1 : shape
        The first particle (``dtcrit.Sphere``, ``dtcrit.Ellipsoid``, ...): ``a`` is its largest
        half-length, ``Ixx`` its first principal moment.
    p2 : shape, optional
        The second particle (None: identical to the first).

    Returns
    -------
    float
        ``A_max`` as printed [1/kg]; not a bound for box-like shapes (use :func:`a_bound`).

    Examples
    --------
    >>> from dtcrit import Sphere
    >>> from dtcrit.paper import eq26_a_max
    >>> s = Sphere(1.0, mass=1.0)
    >>> round(eq26_a_max(s), 12)  # 2 (1/m + a^2/I) = 2 (1 + 1/0.4)
    7.0
    """
    from dtcrit.bodies.contact import a_max

    return a_max(p1, p2)


def a_bound(p1, p2=None) -> float:
    """The verified form of Eq. (26): an upper bound on ``lambda_max(A)`` over every contact [1/kg].

    ``1/m1 + 1/m2 + S1 + S2`` with ``S_i`` the supremum of ``lambda_max([p]x^T I_i^-1 [p]x)`` over
    the body (``dtcrit.bodies.contact.a_bound``).

    Parameters
    ----------
    p1 : shape
        The first particle.
    p2 : shape, optional
        The second particle (None: identical to the first).

    Returns
    -------
    float
        The bound [1/kg].

    Examples
    --------
    >>> from dtcrit import Box
    >>> from dtcrit.paper import a_bound, eq26_a_max
    >>> box = Box(1.0, 1.0, 1.0, density=1.0)
    >>> a_bound(box) > eq26_a_max(box)  # the printed form falls short for a box
    True
    """
    from dtcrit.bodies.contact import a_bound as bound

    return bound(p1, p2)


def eq46_dt(k: float, c: float, A: float) -> float:
    """Peng et al. 2020, Eq. (46) as printed: ``(c A + sqrt(c^2 A^2 + 4 k A)) / (k A)`` [s].

    Parameters
    ----------
    k : float
        Contact stiffness [N/m] (> 0).
    c : float
        Viscous damping [N s/m] (>= 0).
    A : float
        Inverse inertia coefficient [1/kg] (> 0).

    Returns
    -------
    float
        The printed step [s]: where a real eigenvalue of the Eq. (40) scheme reaches -1.

    Examples
    --------
    >>> from dtcrit.paper import eq46_dt
    >>> eq46_dt(4.0, 0.0, 1.0)  # undamped: 2 / sqrt(k A)
    1.0
    """
    from dtcrit.integrators.stability import paper_eq46

    return paper_eq46(k, c, A)


def eq40_critical_dt(k: float, c: float, A: float) -> float:
    """The verified step of the Eq. (40) scheme as printed: its exact stability boundary [s].

    Parameters
    ----------
    k : float
        Contact stiffness [N/m] (> 0).
    c : float
        Viscous damping [N s/m] (>= 0).
    A : float
        Inverse inertia coefficient [1/kg] (> 0).

    Returns
    -------
    float
        The critical step of the ``paper-eq40`` integrator for ``xddot = -k A x - c A xdot`` [s].

    Examples
    --------
    >>> from dtcrit.paper import eq40_critical_dt, eq46_dt
    >>> eq40_critical_dt(1.0, 0.5, 1.0) < eq46_dt(1.0, 0.5, 1.0)  # with damping, Eq. (46) is too large
    True
    """
    from dtcrit.integrators.stability import critical_dt

    return float(critical_dt("paper-eq40", k, c, A).dt)


def eq54_b_max(p) -> float:
    """Peng et al. 2020, Eq. (54) as printed: ``max(|Ixx-Iyy|/Izz, |Ixx-Izz|/Iyy, |Iyy-Izz|/Ixx)``.

    Parameters
    ----------
    p : shape
        The particle.

    Returns
    -------
    float
        ``B_max`` (dimensionless; 0 below rounding).

    Examples
    --------
    >>> from dtcrit import Ellipsoid
    >>> from dtcrit.paper import eq54_b_max
    >>> eq54_b_max(Ellipsoid(1.0, 1.0, 1.0, density=1.0))
    0.0
    """
    from dtcrit.bodies.contact import b_max

    return b_max(p)


def b_bound(p) -> float:
    """The verified form of Eq. (54): the tight gyroscopic constant ``G = max |I^-1 (w x I w)|``.

    Parameters
    ----------
    p : shape
        The particle.

    Returns
    -------
    float
        ``G`` over unit ``w`` (dimensionless), with ``B_max/2 <= G <= B_max/sqrt(3)``.

    Examples
    --------
    >>> from dtcrit import Ellipsoid
    >>> from dtcrit.paper import b_bound, eq54_b_max
    >>> e = Ellipsoid(3.0, 2.0, 1.0, density=1.0)
    >>> eq54_b_max(e) / 2 <= b_bound(e) <= eq54_b_max(e) / 3 ** 0.5
    True
    """
    from dtcrit.bodies.contact import b_bound as bound

    return bound(p)
