"""The time-stepped 1-D impact in closed form: the position recurrences of the integrators through a
switched contact, the central-difference invariant and exit ratio, unit-ratio steps, and the forward
Euler map.
"""
from __future__ import annotations

from functools import lru_cache

import sympy as sp

from dtcrit.integrators.schemes import INTEGRATORS, LinearForce
from dtcrit.symbolic.impact_contact import N, n, phi, psi, v, x
from dtcrit.symbolic.integrators import tau

# ---------------------------------------------------------------------------------------------
# 2. Time-stepped undamped impact: central-difference family and forward Euler
# ---------------------------------------------------------------------------------------------

def position_recurrence_residual(name: str) -> sp.Expr:
    """x_2 - 2 x_1 + x_0 + tau^2 x_1 after two contact steps of ``name`` from a generic state.

    Zero for the central-difference family (undamped, omega = 1): positions obey the Stoermer
    recurrence whatever the stored velocity or acceleration.

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).

    Returns
    -------
    sympy.Expr
        The residual, expanded.
    """
    integ = INTEGRATORS[name]
    state = sp.symbols(f"q0:{len(integ.state)}", real=True)
    f = LinearForce(sp.Integer(1), sp.Integer(0))
    s1 = integ.step(state, tau, f)
    s2 = integ.step(s1, tau, f)
    return sp.simplify(s2[0] - 2 * s1[0] + state[0] + tau**2 * s1[0])


class _SwitchedForce:
    """Undamped unit contact force ``-x``, or 0 where the position is known to be out of contact.

    Symbolic stand-in for the simulation's sign test (SymPy cannot test the sign of a symbol):
    ``contact(x)`` says whether the position at which a force is evaluated is in contact.
    """

    dv = sp.Integer(0)

    def __init__(self, contact):
        self.contact = contact

    def __call__(self, xq, vq):
        return -xq if self.contact(xq) else sp.Integer(0)


def _same(a, b) -> bool:
    return sp.simplify(a - b) == 0


def _family_state(name: str, xq, vq, contact: bool):
    """Scheme state with overlap xq and velocity vq; stored acceleration -xq in contact, else 0."""
    if len(INTEGRATORS[name].state) == 2:
        return (xq, vq)
    return (xq, vq, -xq if contact else sp.Integer(0))


def free_flight_entry_residual(name: str) -> tuple[sp.Expr, sp.Expr]:
    """(x_0 - phi tau, x_1 - 2 x_0 + x_(-1) + tau^2 x_0) across the entry into contact.

    The state at x_(-1) = (phi - 1) tau < 0 is in free flight (speed 1, stored acceleration 0); a
    force evaluated at x_(-1) is zero, one evaluated at any later position (x_0 >= 0, x_1) is the
    contact force.  Both zero for the central-difference family: the Stoermer recurrence starts
    from the free-flight history.

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).

    Returns
    -------
    tuple of sympy.Expr
        The two residuals.
    """
    xm1 = (phi - 1) * tau
    integ = INTEGRATORS[name]
    f = _SwitchedForce(lambda xq: not _same(xq, xm1))
    s0 = integ.step(_family_state(name, xm1, sp.Integer(1), False), tau, f)
    s1 = integ.step(s0, tau, f)
    return sp.simplify(s0[0] - phi * tau), sp.simplify(s1[0] - 2 * s0[0] + xm1 + tau**2 * s0[0])


def exit_velocity_residual(name: str) -> sp.Expr:
    """Velocity two steps after leaving contact minus (x_m - x_(m-1))/tau.

    From a generic in-contact state at x_(m-1) (stored acceleration consistent), forces evaluated at
    x_(m-1) are contact forces and those at x_m and later positions are zero.  Zero for the family:
    the exit speed is the free-flight difference quotient, the quantity the invariant Q controls.

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).

    Returns
    -------
    sympy.Expr
        The residual.
    """
    integ = INTEGRATORS[name]
    xa, va = sp.symbols("x_a v_a", real=True)
    f = _SwitchedForce(lambda xq: _same(xq, xa))
    s_m = integ.step(_family_state(name, xa, va, True), tau, f)
    s_m2 = integ.step(integ.step(s_m, tau, f), tau, f)
    return sp.simplify(s_m2[1] - (s_m[0] - xa) / tau)


@lru_cache(maxsize=None)
def central_difference_invariant() -> sp.Expr:
    """Quadratic Q = v^2 + p x v + q x^2 left unchanged by one undamped symplectic-Euler step.

    Solved for (p, q) from Q(step(x, v)) - Q(x, v) = 0 identically in (x, v): Q = v^2 + x^2 - tau x v.
    """
    p, q = sp.symbols("p q")
    Q = v**2 + p * x * v + q * x**2
    x1, v1 = INTEGRATORS["symplectic-euler"].step((x, v), tau, LinearForce(sp.Integer(1), sp.Integer(0)))
    diff = sp.Poly(sp.expand(Q.subs({x: x1, v: v1}, simultaneous=True) - Q), x, v)
    sol = sp.solve(diff.coeffs(), [p, q], dict=True)
    if len(sol) != 1:
        raise AssertionError(f"invariant not unique: {sol}")
    return Q.subs(sol[0])


def central_difference_angle_expr() -> sp.Expr:
    """The angle theta with cos theta = 1 - tau^2/2: roots of lambda^2 - (2 - tau^2) lambda + 1 are exp(+-i theta).

    Returns
    -------
    sympy.Expr
        ``theta(tau)``.
    """
    return 2 * sp.asin(tau / 2)


@lru_cache(maxsize=None)
def central_difference_position_expr() -> sp.Expr:
    """x_n = A cos(n theta) + B sin(n theta) with x_0 = phi tau, x_{-1} = (phi - 1) tau."""
    th = central_difference_angle_expr()
    A, B = sp.symbols("A B")
    sol = sp.solve(
        [sp.Eq(A, phi * tau), sp.Eq(A * sp.cos(th) - B * sp.sin(th), (phi - 1) * tau)], [A, B], dict=True
    )[0]
    a_c = sp.simplify(sol[A])
    b_c = sp.simplify(sp.expand_trig(sol[B]))
    return a_c * sp.cos(n * th) + b_c * sp.sin(n * th)


def central_difference_ratio_expr() -> sp.Expr:
    """v_exit/v0 from Q at entry (x = phi tau, v = 1) and at exit (x = -psi tau r, v = -r).

    Returns
    -------
    sympy.Expr
        ``r(tau, phi, psi)``.
    """
    Q = central_difference_invariant()
    r = sp.Symbol("r", positive=True)
    q_in = Q.subs({x: phi * tau, v: 1})
    q_out = Q.subs({x: -psi * tau * r, v: -r})
    sample = {tau: 1, phi: sp.Rational(1, 3), psi: sp.Rational(1, 2)}
    sol = [e for e in sp.solve(sp.Eq(q_in, q_out), r) if e.subs(sample) > 0]
    if len(sol) != 1:
        raise AssertionError(f"ratio not unique: {sol}")
    return sp.sqrt(sp.factor(sol[0] ** 2))


def central_difference_unit_steps_expr() -> sp.Expr:
    """tau_N = 2 sin(pi/(2N)): theta = pi/N, where v_exit = v0 for every entry phase.

    Returns
    -------
    sympy.Expr
        ``tau_N`` in the symbol ``N``.
    """
    # 1 - tau^2/2 = cos(pi/N) with tau > 0: tau = sqrt(2 - 2 cos(pi/N)) = 2 sin(pi/(2N))
    half_angle = 2 * sp.sin(sp.pi / (2 * N))
    if sp.simplify(sp.cos(sp.pi / N) - (1 - half_angle**2 / 2)) != 0:
        raise AssertionError("unit-ratio steps")
    return half_angle


def unit_step_exit_phase_equals_entry() -> sp.Expr:
    """The difference psi - phi when theta = pi/N and the exit is at step N (0: the exit mirrors the entry).

    With x_n = A cos(n theta) + B sin(n theta): x_N = A cos(pi) + B sin(pi) = -x_0 and
    x_(N-1) = A cos(pi - theta) + B sin(pi - theta) = -x_(-1), so psi = x_0/(x_0 - x_(-1)) = phi.

    Returns
    -------
    sympy.Expr
        ``psi - phi``, simplified.
    """
    xn = central_difference_position_expr()
    th = central_difference_angle_expr()
    a_c = sp.simplify(xn.subs(n, 0))
    b_c = sp.simplify(xn.coeff(sp.sin(n * th)))
    x_N = a_c * sp.cos(sp.pi) + b_c * sp.sin(sp.pi)
    x_Nm1 = a_c * sp.cos(sp.pi - th) + b_c * sp.sin(sp.pi - th)
    psi_N = -x_N / (x_Nm1 - x_N)
    return sp.simplify(sp.expand_trig(psi_N) - phi)


@lru_cache(maxsize=None)
def forward_euler_map() -> tuple[sp.Expr, sp.Expr, sp.Matrix]:
    """(rho, alpha, M): one undamped forward-Euler step M = rho * rotation(alpha)."""
    x1, v1 = INTEGRATORS["forward-euler"].step((x, v), tau, LinearForce(sp.Integer(1), sp.Integer(0)))
    M = sp.Matrix([[sp.diff(e, q) for q in (x, v)] for e in (x1, v1)])
    rho = sp.sqrt(1 + tau**2)
    alpha = sp.atan(tau)
    R = sp.Matrix([[sp.cos(alpha), sp.sin(alpha)], [-sp.sin(alpha), sp.cos(alpha)]])
    if sp.simplify(M - rho * R) != sp.zeros(2, 2):
        raise AssertionError("forward Euler step is not a scaled rotation")
    return rho, alpha, M


def forward_euler_motion_expr() -> tuple[sp.Expr, sp.Expr]:
    """(x_n, v_n) from (x_0, v_0) = (phi tau, 1): rho^n rotation(n alpha) applied.

    Returns
    -------
    tuple of sympy.Expr
        ``x_n`` and ``v_n`` in the symbols ``n``, ``tau``, ``phi``.
    """
    rho, alpha, _ = forward_euler_map()
    x0 = phi * tau
    g = (1 + tau**2) ** (n / 2)
    return (
        g * (x0 * sp.cos(n * alpha) + sp.sin(n * alpha)),
        g * (-x0 * sp.sin(n * alpha) + sp.cos(n * alpha)),
    )
