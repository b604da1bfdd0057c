"""Explicit DEM integrators, each written once as its update rule.

This is a leaf module: plain arithmetic, no imports from the rest of dtcrit, no SymPy.  The same
update rule is

* applied to SymPy symbols by ``dtcrit.symbolic.integrators`` to build the amplification matrix
  (the rule is linear in the state, so its Jacobian *is* the amplification matrix), and
* applied to floats / NumPy arrays / mpmath numbers by ``dtcrit.integrators.simulate`` to time-step the
  contact system itself, an independent check of every bound.

The contact law is Peng et al. 2020, Eq. (29)-(30): a contact coordinate ``x`` with inverse-inertia
coefficient ``A`` under ``F = -k x - c xdot`` obeys ``xddot = f(x, v) = -K x - C v`` with
``K = k A`` and ``C = c A``.  ``force`` below is that ``f``; ``force.dv`` is ``df/dv = -C``, needed
only by the scheme that is implicit in the (linear) damping term and solved exactly.

Adding an integrator is one new ``Integrator(...)`` entry in ``INTEGRATORS``.  A scheme written by a
user in a scene is parsed into the same ``Integrator`` by ``dtcrit.integrators.user_rules``.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Sequence


class LinearForce:
    """``f(x, v) = -K x - C v`` with ``K = k A`` and ``C = c A`` (Peng et al. 2020, Eq. (30)).

    One contact coordinate: ``K`` and ``C`` are scalars (float, mpmath or SymPy) and ``x``, ``v`` scalars
    or arrays of independent contacts.

    Parameters
    ----------
    K : scalar
        Stiffness rate ``k A`` [1/s^2].
    C : scalar
        Damping rate ``c A`` [1/s].

    Attributes
    ----------
    dv : scalar
        ``df/dv = -C``, read by the scheme that is implicit in the damping term (``leapfrog-centred``).
    """

    def __init__(self, K, C):
        self.K = K
        self.C = C
        self.dv = -C

    def __call__(self, x, v):
        """The acceleration ``-K x - C v``.

        Parameters
        ----------
        x : scalar or array_like
            Contact coordinate (overlap).
        v : scalar or array_like
            Its velocity.

        Returns
        -------
        scalar or array_like
            ``-K x - C v``.
        """
        return -self.K * x - self.C * v


class MatrixForce:
    """``f(x, v) = -K x - C v`` with matrices ``K``, ``C``: coupled degrees of freedom (Peng et al. 2020,
    Eq. (30) for a block of modes, or a whole packing's ``M^-1 K``, ``M^-1 C``).

    Parameters
    ----------
    K : array_like, shape (n, n)
        Stiffness matrix per unit mass [1/s^2].
    C : array_like, shape (n, n)
        Damping matrix per unit mass [1/s].

    Attributes
    ----------
    dv : None
        ``df/dv = -C`` is a matrix here; the scheme implicit in the damping term (``leapfrog-centred``)
        needs a scalar, so it fails with ``TypeError`` on this force instead of dividing by a matrix.
    """

    def __init__(self, K, C):
        self.K, self.C, self.dv = K, C, None

    def __call__(self, x, v):
        """The accelerations ``-K x - C v``.

        Parameters
        ----------
        x : numpy.ndarray, shape (n,)
            Coordinates.
        v : numpy.ndarray, shape (n,)
            Their velocities.

        Returns
        -------
        numpy.ndarray, shape (n,)
            ``-(K @ x) - C @ v``.
        """
        return -(self.K @ x) - self.C @ v


Step = Callable[[Sequence, Any, Any], tuple]  # (state, h, force: LinearForce, MatrixForce or any f(x, v) with .dv)


@dataclass(frozen=True)
class Integrator:
    """An explicit scheme: its state variables and one step of its update rule.

    Parameters
    ----------
    name : str
        The scheme key (``"velocity-verlet"``).
    state : tuple of str
        Names of the state variables, e.g. ``("x_n", "v_n", "a_n")``.
    step : callable
        ``step(state, h, force) -> new state``: one step of size ``h`` under ``force(x, v)``
        (a :class:`LinearForce` or :class:`MatrixForce`).
    summary : str
        One line on what the rule does.
    damping_velocity : str
        The velocity the dashpot force reads (``"v_{n+1/2}"``).
    used_by : str
        Codes that integrate with this scheme ("" when none is known).
    """

    name: str
    state: tuple[str, ...]
    step: Step
    summary: str
    damping_velocity: str
    used_by: str = ""


def _paper_eq40(s, h, f):
    # Peng et al. 2020, Eqs (38)-(40) as printed: x and v advance with the old v and a, and the
    # acceleration row is evaluated from the *previous* state (x_n, v_n).
    x, v, a = s
    return x + h * v, v + h * a, f(x, v)


def _forward_euler(s, h, f):
    x, v = s
    a = f(x, v)
    return x + h * v, v + h * a


def _symplectic_euler(s, h, f):
    x, v = s
    v_new = v + h * f(x, v)
    return x + h * v_new, v_new


def _leapfrog(s, h, f):
    # state (x_n, v_{n-1/2}); the damping force uses the lagged half-step velocity v_{n-1/2}.
    x, v_half = s
    v_next = v_half + h * f(x, v_half)
    return x + h * v_next, v_next


def _leapfrog_centred(s, h, f):
    # state (x_n, v_{n-1/2}); damping uses (v_{n-1/2} + v_{n+1/2})/2.  The update
    #   v' = v + h f(x, (v + v')/2)
    # is linear in v', solved exactly:  v' (1 - h f_v / 2) = v + h f(x, v/2).
    x, v_half = s
    v_next = (v_half + h * f(x, v_half / 2)) / (1 - h * f.dv / 2)
    return x + h * v_next, v_next


def _velocity_verlet(s, h, f):
    # state (x_n, v_n, a_n); the damping force at n+1 uses the half-step velocity v_{n+1/2}.
    x, v, a = s
    v_half = v + h / 2 * a
    x_next = x + h * v_half
    a_next = f(x_next, v_half)
    return x_next, v_half + h / 2 * a_next, a_next


def _velocity_verlet_predicted(s, h, f):
    # as velocity Verlet, but the damping force uses the predicted full-step velocity v_n + h a_n.
    x, v, a = s
    v_half = v + h / 2 * a
    x_next = x + h * v_half
    a_next = f(x_next, v + h * a)
    return x_next, v_half + h / 2 * a_next, a_next


def _extended_taylor(s, h, f):
    # Chrono DEM-Engine's default EXTENDED_TAYLOR (src/kernel/DEMIntegrationKernels.cu with
    # DEMCustomizablePolicies/IntegrationVelPassOnExtendedTaylor.cu: v += h a, then x += h (v_old + h a/2))
    # and Kratos DEM's TaylorScheme: the force, dashpot included, is evaluated at (x_n, v_n).
    x, v = s
    a = f(x, v)
    return x + h * v + h * h / 2 * a, v + h * a


def _adams_bashforth_2(s, h, f):
    # MFiX DEM (model/des/cfnewvalues.f, INTG_ADAMS_BASHFORTH): second-order Adams-Bashforth for v,
    # trapezoidal rule for x; state (x_n, v_n, a_{n-1}), the force (dashpot included) at (x_n, v_n).
    x, v, a_old = s
    a = f(x, v)
    v_next = v + h / 2 * (3 * a - a_old)
    return x + h / 2 * (v + v_next), v_next, a


INTEGRATORS: dict[str, Integrator] = {
    i.name: i
    for i in (
        Integrator(
            "paper-eq40", ("x_n", "v_n", "a_n"), _paper_eq40,
            "the scheme exactly as printed in Peng et al. 2020, Eq. (40): the acceleration row uses the previous state",
            "v_n (one step old)",
        ),
        Integrator(
            "forward-euler", ("x_n", "v_n"), _forward_euler,
            "a_n = f(x_n, v_n); x and v advance with the old values",
            "v_n",
        ),
        Integrator(
            "symplectic-euler", ("x_n", "v_n"), _symplectic_euler,
            "v advances with the force at (x_n, v_n) first, then x with the new v",
            "v_n",
        ),
        Integrator(
            "leapfrog", ("x_n", "v_{n-1/2}"), _leapfrog,
            "central difference; damping uses the lagged half-step velocity v_{n-1/2}",
            "v_{n-1/2}",
            "PFC/YADE-style central difference with lagged viscous damping",
        ),
        Integrator(
            "leapfrog-centred", ("x_n", "v_{n-1/2}"), _leapfrog_centred,
            "central difference; damping uses (v_{n-1/2} + v_{n+1/2})/2, solved exactly (it is linear)",
            "(v_{n-1/2} + v_{n+1/2})/2",
        ),
        Integrator(
            "velocity-verlet", ("x_n", "v_n", "a_n"), _velocity_verlet,
            "velocity Verlet; damping force from the half-step velocity v_{n+1/2}",
            "v_{n+1/2}",
            "LAMMPS, LIGGGHTS, PFC",
        ),
        Integrator(
            "velocity-verlet-predicted", ("x_n", "v_n", "a_n"), _velocity_verlet_predicted,
            "velocity Verlet; damping force from the predicted full-step velocity v_n + dt a_n",
            "v_n + dt a_n",
        ),
        Integrator(
            "extended-taylor", ("x_n", "v_n"), _extended_taylor,
            "second-order Taylor position update x + dt v + dt^2 a/2 with the old v, then v + dt a; "
            "a = f(x_n, v_n); unstable for every dt when undamped (det G = 1 + (omega dt)^2/2)",
            "v_n",
            "Chrono DEM-Engine (default EXTENDED_TAYLOR), Kratos DEM TaylorScheme",
        ),
        Integrator(
            "adams-bashforth-2", ("x_n", "v_n", "a_{n-1}"), _adams_bashforth_2,
            "v by second-order Adams-Bashforth (3 a_n - a_{n-1})/2, x by the trapezoidal rule (v_n + v_{n+1})/2; "
            "unstable for every dt when undamped",
            "v_n",
            "MFiX DEM (INTG_ADAMS_BASHFORTH)",
        ),
    )
}

NAMES: tuple[str, ...] = tuple(INTEGRATORS)

USER_INTEGRATORS: dict[str, Integrator] = {}
"""Schemes a user wrote in a scene (``dtcrit.integrators.user_rules.register``), by name."""


def lookup(name) -> Integrator:
    """The built-in or registered user scheme called ``name`` (an ``Integrator`` is returned as is).

    Parameters
    ----------
    name : str or Integrator
        A key of ``INTEGRATORS`` or ``USER_INTEGRATORS``.

    Returns
    -------
    Integrator
        The scheme; ``KeyError`` when no scheme has that name.
    """
    if isinstance(name, Integrator):
        return name
    return INTEGRATORS[name] if name in INTEGRATORS else USER_INTEGRATORS[name]
