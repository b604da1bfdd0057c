"""The paper's printed forms (and the CFL note's) evaluated in float64 exactly as printed.

Each function takes float arrays (k, c, A, m) and returns dt [s].  They are compared with the
same form at 50 digits (``dtcrit.bench.reference.paper_form_reference``) to show where a *form*
loses digits in float64 -- cancellation (28 - 49 beta^2 at the pole of Eq. (58);
sqrt(zeta^2 + 1) - zeta in the CFL note for heavy damping) or overflow (c^2 A^2 in Eq. (46)).
Whether the form is the right *bound* is a different question, answered by the ratio to the
verified critical step in the report.  dtcrit's own evaluations of Eq. (46) are included:
``dtcrit._generated.critical_steps.paper_eq46`` and ``dtcrit.integrators.stability.paper_eq46`` (hypot form).
"""
from __future__ import annotations

import math

import numpy as np

from dtcrit._generated import critical_steps as _gen
from dtcrit.integrators.stability import paper_eq46 as _eq46_dtcrit


def eq46_printed(k, c, A, m):
    """Peng et al. 2020, Eq. (46): (sqrt(4 k A + c^2 A^2) + c A) / (k A).

    Parameters
    ----------
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].
    m : array_like or None
        Particle mass [kg] (two identical spheres: A = 7/m); unused by the forms written in A.

    Returns
    -------
    numpy.ndarray
        The printed step [s] (NaN where it is not real).
    """
    return (np.sqrt(4 * k * A + c * c * A * A) + c * A) / (k * A)


def eq46_generated(k, c, A, m):
    """``dtcrit._generated.critical_steps.paper_eq46`` (SymPy's simplified Eq. (46)).

    Parameters
    ----------
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].
    m : array_like or None
        Particle mass [kg] (two identical spheres: A = 7/m); unused by the forms written in A.

    Returns
    -------
    numpy.ndarray
        The printed step [s] (NaN where it is not real).
    """
    return _gen.paper_eq46(k, c, A)


def eq46_dtcrit(k, c, A, m):
    """``dtcrit.integrators.stability.paper_eq46``: 2 (gamma + hypot(gamma, omega)) / omega^2, scaled.

    Parameters
    ----------
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].
    m : array_like or None
        Particle mass [kg] (two identical spheres: A = 7/m); unused by the forms written in A.

    Returns
    -------
    numpy.ndarray
        The printed step [s] (NaN where it is not real).
    """
    return np.array([_eq46_dtcrit(*x) for x in zip(np.atleast_1d(k), np.atleast_1d(c), np.atleast_1d(A))])


def eq34_printed(k, c, A, m):
    """Peng et al. 2020, Eq. (34): 4 / sqrt(4 k A - c^2 A^2) (NaN beyond critical damping).

    Parameters
    ----------
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].
    m : array_like or None
        Particle mass [kg] (two identical spheres: A = 7/m); unused by the forms written in A.

    Returns
    -------
    numpy.ndarray
        The printed step [s] (NaN where it is not real).
    """
    return 4 / np.sqrt(4 * k * A - c * c * A * A)


def eq36_printed(k, c, A, m):
    """Peng et al. 2020, Eq. (36): pi / sqrt(2 k/m - c^2/(4 m^2)), m the particle mass.

    Parameters
    ----------
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].
    m : array_like or None
        Particle mass [kg] (two identical spheres: A = 7/m); unused by the forms written in A.

    Returns
    -------
    numpy.ndarray
        The printed step [s] (NaN where it is not real).
    """
    return math.pi / np.sqrt(2 * k / m - c * c / (4 * m * m))


def _beta(k, c, m):
    return c / np.sqrt(m * k)


def eq58_printed(k, c, A, m):
    """Peng et al. 2020, Eq. (58): dt = 4 / sqrt(28 - 49 beta^2) * sqrt(m/k), beta = c/sqrt(m k).

    Parameters
    ----------
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].
    m : array_like or None
        Particle mass [kg] (two identical spheres: A = 7/m); unused by the forms written in A.

    Returns
    -------
    numpy.ndarray
        The printed step [s] (NaN where it is not real).
    """
    b = _beta(k, c, m)
    return 4 / np.sqrt(28 - 49 * b * b) * np.sqrt(m / k)


def eq59_printed(k, c, A, m):
    """Peng et al. 2020, Eq. (59): dt = pi / sqrt(2 - beta^2/4) * sqrt(m/k).

    Parameters
    ----------
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].
    m : array_like or None
        Particle mass [kg] (two identical spheres: A = 7/m); unused by the forms written in A.

    Returns
    -------
    numpy.ndarray
        The printed step [s] (NaN where it is not real).
    """
    b = _beta(k, c, m)
    return math.pi / np.sqrt(2 - b * b / 4) * np.sqrt(m / k)


def eq60_printed(k, c, A, m):
    """Peng et al. 2020, Eq. (60): dt = (beta + sqrt(beta^2 + 4/7)) * sqrt(m/k).

    Parameters
    ----------
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].
    m : array_like or None
        Particle mass [kg] (two identical spheres: A = 7/m); unused by the forms written in A.

    Returns
    -------
    numpy.ndarray
        The printed step [s] (NaN where it is not real).
    """
    b = _beta(k, c, m)
    return (b + np.sqrt(b * b + 4.0 / 7.0)) * np.sqrt(m / k)


def cfl_note_printed(k, c, A, m):
    """CFL note (seed 004): dt = 2 sqrt(m/k) (sqrt(c^2/(4 k m) + 1) - c/(2 sqrt(k m))), m = 1/A.

    Parameters
    ----------
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].
    m : array_like or None
        Particle mass [kg] (two identical spheres: A = 7/m); unused by the forms written in A.

    Returns
    -------
    numpy.ndarray
        The printed step [s] (NaN where it is not real).
    """
    mm = 1.0 / A
    return 2 * np.sqrt(mm / k) * (np.sqrt(c * c / (4 * k * mm) + 1) - c / (2 * np.sqrt(k * mm)))


# (route name, reference form key, function, needs the sphere mass m)
PAPER_FORMS = (
    ("eq46-printed", "eq46", eq46_printed, False),
    ("eq46-generated", "eq46", eq46_generated, False),
    ("eq46-dtcrit", "eq46", eq46_dtcrit, False),
    ("eq34-printed", "eq34", eq34_printed, False),
    ("eq36-printed", "eq36", eq36_printed, True),
    ("eq58-printed", "eq58", eq58_printed, True),
    ("eq59-printed", "eq59", eq59_printed, True),
    ("eq60-printed", "eq60", eq60_printed, True),
    ("cfl-note-printed", "cfl-note", cfl_note_printed, False),
)
