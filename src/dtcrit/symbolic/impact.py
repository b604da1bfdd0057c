"""One-dimensional impact of the spring-dashpot contact, derived with SymPy (CFL note; Feng 2005).

The CFL note (seed 004, "One-dimensional equations for impact") reduces a DEM collision to

    m d'' = -c d' - k d   while d >= 0 (contact),     m d'' = 0   while d < 0 (separated),

with ``d`` the overlap (the note calls it the gap, with the sign chosen so that d >= 0 is contact)
and entry state ``d = 0``, ``d' = v0 > 0``.  Everything here is dimensionless: time ``s = omega t``
with ``omega = sqrt(k/m)``, overlap in ``v0/omega``, velocity in ``v0``, ``zeta = c/(2 sqrt(k m))``
and the time step ``tau = omega dt``.  The contact motion is ``d'' + 2 zeta d' + d = 0``,
``d(0) = 0``, ``d'(0) = 1``.

Two meanings of "separation" are handled:

* **geometric** (the note's equation, and what the time-stepped simulation in ``dtcrit.impact``
  uses): the contact lasts while ``d >= 0``; the spring-dashpot force may turn tensile (attractive)
  near the end.  The bodies separate when ``d`` returns to 0: at ``s = pi/sqrt(1 - zeta^2)`` for
  ``zeta < 1``; for ``zeta >= 1`` ``d`` stays positive for all ``s > 0`` and only tends to 0, so
  they never separate (exit velocity 0 in the limit).
* **force-based**: the contact force ``P = k d + c d'`` (compressive when positive) acts only while
  ``P >= 0``; once it would turn tensile it is zero and the bodies coast apart.  ``P = -m d''``,
  so the release is the first zero of ``d''``: ``s_f = 2 g(zeta)`` with
  ``g = arccos(zeta)/sqrt(1 - zeta^2)`` (``zeta < 1``), ``1`` (``zeta = 1``),
  ``arccosh(zeta)/sqrt(zeta^2 - 1)`` (``zeta > 1``) -- one analytic function of ``zeta`` -- and the
  exit speed is ``exp(-zeta s_f)`` for every ``zeta``: the bodies always separate.

For the time-stepped impact (``tau`` fixed, undamped) two closed forms are derived:

* the **central-difference family** (symplectic Euler, leapfrog, leapfrog-centred, velocity Verlet,
  velocity Verlet with predicted damping velocity: identical when undamped): positions obey
  ``x_{n+1} - 2 x_n + x_{n-1} = -tau^2 x_n`` in contact, which conserves
  ``Q = v^2 + x^2 - tau x v`` (``v`` the half-step velocity).  With entry phase ``phi`` (the first
  in-contact step lies ``phi`` of a step after the continuous contact start) and exit phase ``psi``
  (the first out-of-contact position is ``psi`` steps of free flight past ``d = 0``)::

      v_exit / v0 = sqrt((1 - tau^2 phi (1 - phi)) / (1 - tau^2 psi (1 - psi)))

  bounded by ``sqrt(1 - tau^2/4)`` and its reciprocal, and equal to 1 for every phase exactly when
  ``pi/theta`` is an integer ``N`` (``cos theta = 1 - tau^2/2``), i.e. ``tau_N = 2 sin(pi/(2N))``.
* **forward Euler**: one step is ``sqrt(1 + tau^2)`` times a rotation by ``arctan(tau)``.

The Hertz contact ``m d'' = -k_h d^(3/2)`` is reduced to the universal problem in units of the
maximum overlap and of the tangent frequency there.

``generated_files()`` emits ``dtcrit/_generated/impact.py``.
"""
from __future__ import annotations

from functools import lru_cache

import sympy as sp

from dtcrit.integrators.schemes import INTEGRATORS, LinearForce
from dtcrit.symbolic.emit import Kernel, python_module
from dtcrit.symbolic.integrators import tau

PRODUCER = "dtcrit.symbolic.impact"
TARGET = "impact.py"

s = sp.Symbol("s", nonnegative=True)  # omega t
zeta = sp.Symbol("zeta", positive=True)  # damping ratio (zeta = 0 is the "undamped" regime)
w = sp.Symbol("w", positive=True)  # damped frequency / omega, underdamped: sqrt(1 - zeta^2)
mu = sp.Symbol("mu", positive=True)  # overdamped: sqrt(zeta^2 - 1)
phi = sp.Symbol("phi", nonnegative=True)  # entry phase in [0, 1)
psi = sp.Symbol("psi", nonnegative=True)  # exit phase in (0, 1]
n = sp.Symbol("n", integer=True, nonnegative=True)
N = sp.Symbol("N", integer=True, positive=True)
x, v = sp.symbols("x v", real=True)
u = sp.Symbol("u", real=True)  # 1 - zeta near critical damping

# Hertz: F = k_h d^(3/2)
k_h, m, v0 = sp.symbols("k_h m v0", positive=True)

CENTRAL_DIFFERENCE_FAMILY: tuple[str, ...] = (
    "symplectic-euler",
    "leapfrog",
    "leapfrog-centred",
    "velocity-verlet",
    "velocity-verlet-predicted",
)

# |1 - zeta| below which g(zeta) is evaluated from its Taylor series (the closed forms are 0/0 at 1)
SERIES_RADIUS = sp.Rational(1, 1000)
SERIES_ORDER = 6  # terms u^0 .. u^5: truncation error < 1e-18 relative inside SERIES_RADIUS


# ---------------------------------------------------------------------------------------------
# 1. The exact (continuous) impact
# ---------------------------------------------------------------------------------------------

def _solve_contact(stiff: sp.Expr, damp: sp.Expr) -> sp.Expr:
    """d(s) solving d'' + damp d' + stiff d = 0, d(0) = 0, d'(0) = 1 (SymPy's dsolve)."""
    d = sp.Function("d")
    ode = sp.Eq(d(s).diff(s, 2) + damp * d(s).diff(s) + stiff * d(s), 0)
    sol = sp.dsolve(ode, d(s), ics={d(0): 0, d(s).diff(s).subs(s, 0): 1})
    return sp.simplify(sol.rhs)


@lru_cache(maxsize=None)
def contact_motion(regime: str) -> sp.Expr:
    """Overlap d(s) during contact (Feng 2005 / CFL note, one-dimensional impact equation).

    ``regime``: "undamped" (zeta = 0), "underdamped" (in terms of w = sqrt(1 - zeta^2)),
    "critical" (zeta = 1), "overdamped" (in terms of mu = sqrt(zeta^2 - 1)).
    """
    if regime == "undamped":
        return _solve_contact(sp.Integer(1), sp.Integer(0))
    if regime == "underdamped":  # 1 = zeta^2 + w^2
        return _solve_contact(zeta**2 + w**2, 2 * zeta)
    if regime == "critical":
        return _solve_contact(sp.Integer(1), sp.Integer(2))
    if regime == "overdamped":  # 1 = zeta^2 - mu^2
        raw = _solve_contact(zeta**2 - mu**2, 2 * zeta)
        tidy = sp.exp(-zeta * s) * sp.sinh(mu * s) / mu
        if sp.simplify((raw - tidy).rewrite(sp.exp)) != 0:
            raise AssertionError("overdamped solution does not match exp(-zeta s) sinh(mu s)/mu")
        return tidy
    raise ValueError(f"unknown regime {regime!r}")


def _regime_subs(regime: str) -> dict:
    return {
        "undamped": {zeta: 0},
        "underdamped": {w: sp.sqrt(1 - zeta**2)},
        "critical": {zeta: 1},
        "overdamped": {mu: sp.sqrt(zeta**2 - 1)},
    }[regime]


def residual(regime: str) -> sp.Expr:
    """d'' + 2 zeta d' + d for the regime's motion, with its frequency substituted (must be 0)."""
    d = contact_motion(regime)
    z = {"undamped": 0, "critical": 1}.get(regime, zeta)
    expr = (d.diff(s, 2) + 2 * z * d.diff(s) + d).subs(_regime_subs(regime))
    return sp.simplify(expr)


@lru_cache(maxsize=None)
def geometric_separation() -> tuple[sp.Expr, sp.Expr]:
    """(t_d, d'(t_d)): first return of d to 0 and the exit velocity, underdamped (CFL note).

    d = exp(-zeta s) sin(w s)/w vanishes where sin(w s) = 0, first at s = pi/w.
    """
    d = contact_motion("underdamped")
    zeros = sp.solve(sp.sin(w * s), s)
    first = min((z for z in zeros if z.is_positive), key=lambda e: e / (sp.pi / w))
    t_d = first.subs(_regime_subs("underdamped"))
    v_e = sp.simplify(d.diff(s).subs(s, first).subs(_regime_subs("underdamped")))
    return t_d, v_e


def no_geometric_separation() -> dict:
    """Critical and overdamped: d > 0 for every s > 0; {regime: (lim d, lim d', d)} as s -> oo.

    The overdamped d is returned in the decay rates a = zeta - mu > 0 and a + c = zeta + mu:
    (exp(-a s) - exp(-(a + c) s))/c, positive for s > 0.

    d = s exp(-s) (critical) and exp(-zeta s) sinh(mu s)/mu with zeta > mu (overdamped) are positive
    for s > 0, so the overlap never returns to 0: no geometric separation, exit velocity 0 in the limit.
    """
    a_r, c_r = sp.symbols("a c", positive=True)  # overdamped decay rates a = zeta - mu, a + c = zeta + mu
    out = {}
    for regime in ("critical", "overdamped"):
        dd = contact_motion(regime)
        if regime == "overdamped":
            dd = sp.expand(dd.subs({zeta: a_r + c_r / 2, mu: c_r / 2}).rewrite(sp.exp))
        out[regime] = (sp.limit(dd, s, sp.oo), sp.limit(dd.diff(s), s, sp.oo), dd)
    return out


def compressive_force(regime: str) -> sp.Expr:
    """P(s) = d + 2 zeta d' = -d'' (contact force in units of k v0/omega; > 0 is compressive)."""
    d = contact_motion(regime)
    return sp.simplify(-d.diff(s, 2))


def g_underdamped() -> sp.Expr:
    return sp.acos(zeta) / (sp.sqrt(1 - zeta) * sp.sqrt(1 + zeta))


def g_overdamped() -> sp.Expr:
    return sp.acosh(zeta) / (sp.sqrt(zeta - 1) * sp.sqrt(zeta + 1))


def g_ode_residuals() -> tuple[sp.Expr, sp.Expr]:
    """(1 - zeta^2) g' - zeta g + 1 for both closed forms of g (both 0): g solves one linear ODE."""
    p = sp.Symbol("p", positive=True)  # zeta = 1 - p (p < 1) and zeta = 1 + p
    out = []
    for g, z in ((g_underdamped(), 1 - p), (g_overdamped(), 1 + p)):
        res = ((1 - zeta**2) * sp.diff(g, zeta) - zeta * g + 1).subs(zeta, z)
        out.append(sp.simplify(sp.powsimp(sp.expand(res), force=False)))
    return tuple(out)


@lru_cache(maxsize=None)
def g_series() -> sp.Expr:
    """Taylor polynomial of g about zeta = 1 in u = 1 - zeta (terms u^0 .. u^5).

    g is the solution of (1 - zeta^2) g' = zeta g - 1 that is regular at zeta = 1 (both closed
    forms are); with zeta = 1 - u the ODE reads u (2 - u) dg/du + (1 - u) g - 1 = 0, and matching
    powers of u fixes every coefficient (c_0 = 1, c_k = 2k c_(k-1)/(2k + 1)).
    """
    c = sp.symbols(f"c0:{SERIES_ORDER}")
    poly = sum(ck * u**k for k, ck in enumerate(c))
    ode = sp.expand(u * (2 - u) * sp.diff(poly, u) + (1 - u) * poly - 1)
    eqs = [ode.coeff(u, k) for k in range(SERIES_ORDER)]
    sol = sp.solve(eqs, c, dict=True)[0]
    return sp.expand(poly.subs(sol))


@lru_cache(maxsize=None)
def force_release() -> dict:
    """Force-based separation: release time s_f (first zero of P) and exit velocity, per regime.

    Underdamped: P = exp(-zeta s) (2 zeta cos(w s) + (1 - 2 zeta^2) sin(w s)/w) is 2 zeta at s = 0
    and its zeros are pi/w apart; theta = 2 arccos(zeta) in (0, pi] is one (checked below), so it is
    the first: s_f = 2 arccos(zeta)/w.  Overdamped: tanh(mu s) = 2 zeta mu/(2 zeta^2 - 1) has the
    single root s_f = 2 arccosh(zeta)/mu.  Critical: P = (2 - s) exp(-s), s_f = 2.
    Returns {regime: (s_f, d'(s_f), d(s_f), P(s_f))}; the last must be 0.
    """
    out = {}
    for regime, s_f in (
        ("undamped", sp.pi),
        ("underdamped", 2 * sp.acos(zeta) / w),
        ("critical", sp.Integer(2)),
        ("overdamped", 2 * sp.acosh(zeta) / mu),
    ):
        d = contact_motion(regime)
        sub = _regime_subs(regime)
        vals = []
        for e in (d.diff(s), d, compressive_force(regime)):
            e = e.subs(s, s_f).subs(sub)
            vals.append(sp.simplify(sp.expand_trig(sp.simplify(e))))
        out[regime] = (s_f.subs(sub), *vals)
    return out


def force_release_time_expr() -> sp.Expr:
    """s_f = 2 g(zeta), piecewise with the series near zeta = 1 (no 0/0)."""
    series = g_series().subs(u, 1 - zeta)
    g = sp.Piecewise(
        (series, sp.Abs(1 - zeta) < SERIES_RADIUS),
        (g_underdamped(), zeta < 1),
        (g_overdamped(), True),
    )
    return 2 * g


def geometric_duration_expr() -> sp.Expr:
    t_d = geometric_separation()[0]
    t_d = t_d.subs(sp.sqrt(1 - zeta**2), sp.sqrt(1 - zeta) * sp.sqrt(1 + zeta))
    return sp.Piecewise((t_d, zeta < 1), (sp.oo, True))


def geometric_exit_ratio_expr() -> sp.Expr:
    v_e = -geometric_separation()[1]
    v_e = v_e.subs(sp.sqrt(1 - zeta**2), sp.sqrt(1 - zeta) * sp.sqrt(1 + zeta))
    return sp.Piecewise((v_e, zeta < 1), (0, True))


# ---------------------------------------------------------------------------------------------
# 2. Time-stepped undamped impact: central-difference family and forward Euler
# ---------------------------------------------------------------------------------------------

def position_recurrence_residual(name: str) -> sp.Expr:
    """x_2 - 2 x_1 + x_0 + tau^2 x_1 after two contact steps of ``name`` from a generic state.

    Zero for the central-difference family (undamped, omega = 1): positions obey the Stoermer
    recurrence whatever the stored velocity or acceleration.
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
    ``contact(x)`` says whether the position at which a force is evaluated is in contact."""

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
    """theta with cos theta = 1 - tau^2/2: roots of lambda^2 - (2 - tau^2) lambda + 1 are exp(+-i theta)."""
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
    """v_exit/v0 from Q at entry (x = phi tau, v = 1) and at exit (x = -psi tau r, v = -r)."""
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
    """tau_N = 2 sin(pi/(2N)): theta = pi/N, where v_exit = v0 for every entry phase."""
    # 1 - tau^2/2 = cos(pi/N) with tau > 0: tau = sqrt(2 - 2 cos(pi/N)) = 2 sin(pi/(2N))
    half_angle = 2 * sp.sin(sp.pi / (2 * N))
    if sp.simplify(sp.cos(sp.pi / N) - (1 - half_angle**2 / 2)) != 0:
        raise AssertionError("unit-ratio steps")
    return half_angle


def unit_step_exit_phase_equals_entry() -> sp.Expr:
    """psi - phi when theta = pi/N and the exit is at step N (0: the exit mirrors the entry).

    With x_n = A cos(n theta) + B sin(n theta): x_N = A cos(pi) + B sin(pi) = -x_0 and
    x_(N-1) = A cos(pi - theta) + B sin(pi - theta) = -x_(-1), so psi = x_0/(x_0 - x_(-1)) = phi.
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
    """(x_n, v_n) from (x_0, v_0) = (phi tau, 1): rho^n rotation(n alpha) applied."""
    rho, alpha, _ = forward_euler_map()
    x0 = phi * tau
    g = (1 + tau**2) ** (n / 2)
    return (
        g * (x0 * sp.cos(n * alpha) + sp.sin(n * alpha)),
        g * (-x0 * sp.sin(n * alpha) + sp.cos(n * alpha)),
    )


# ---------------------------------------------------------------------------------------------
# 3. Hertz contact m d'' = -k_h d^(3/2)
# ---------------------------------------------------------------------------------------------

@lru_cache(maxsize=None)
def hertz() -> dict:
    """Maximum overlap, contact duration and tangent frequency of the undamped Hertz impact.

    Energy: m v0^2/2 = int_0^dmax k_h x^(3/2) dx.  Duration: 2 int_0^dmax dx / v(x) with
    v(x)^2 = v0^2 (1 - (x/dmax)^(5/2)); with y = (x/dmax)^(5/2) this is
    2 (dmax/v0) (2/5) B(2/5, 1/2).  Tangent stiffness at dmax: k_t = (3/2) k_h dmax^(1/2).
    In units of dmax and 1/omega_t (omega_t = sqrt(k_t/m)): u'' = -(2/3) u^(3/2), entry speed
    sqrt(8/15).
    """
    X = sp.Symbol("X", positive=True)
    dmax = sp.solve(sp.Eq(m * v0**2 / 2, sp.integrate(k_h * x ** sp.Rational(3, 2), (x, 0, X))), X)[0]
    # v(x)^2 = v0^2 - (2/m) int_0^x k_h q^(3/2) dq = v0^2 (1 - (x/dmax)^(5/2)) (checked):
    q = sp.Symbol("q", positive=True)
    speed2 = v0**2 - 2 / m * sp.integrate(k_h * q ** sp.Rational(3, 2), (q, 0, x))
    if sp.simplify(speed2.subs(x, u * dmax) - v0**2 * (1 - u ** sp.Rational(5, 2))) != 0:
        raise AssertionError("Hertz speed profile")
    # int_0^1 (1 - u^(5/2))^(-1/2) du, with u = y^(2/5): (2/5) int_0^1 y^(-3/5) (1 - y)^(-1/2) dy,
    # the Euler Beta integral B(2/5, 1/2) = Gamma(2/5) Gamma(1/2) / Gamma(9/10).
    y = sp.Symbol("y", positive=True)
    jac = sp.diff(y ** sp.Rational(2, 5), y)
    integrand = ((1 - u ** sp.Rational(5, 2)) ** sp.Rational(-1, 2)).subs(u, y ** sp.Rational(2, 5)) * jac
    if sp.simplify(integrand - sp.Rational(2, 5) * y ** sp.Rational(-3, 5) * (1 - y) ** sp.Rational(-1, 2)) != 0:
        raise AssertionError("Beta substitution")
    beta_integral = sp.Rational(2, 5) * sp.gamma(sp.Rational(2, 5)) * sp.gamma(sp.S.Half) / sp.gamma(sp.Rational(9, 10))
    factor = 2 * beta_integral  # duration in units of dmax/v0
    k_t = sp.diff(k_h * x ** sp.Rational(3, 2), x).subs(x, dmax)
    omega_t = sp.sqrt(k_t / m)
    scaled_coefficient = sp.simplify((k_h * dmax ** sp.Rational(1, 2) / (m * omega_t**2)))
    scaled_speed = sp.simplify(v0 / (dmax * omega_t))
    return {
        "dmax": sp.simplify(dmax),
        "duration_factor": factor,
        "duration": sp.simplify(factor * dmax / v0),
        "omega_t": sp.simplify(omega_t),
        "scaled_coefficient": scaled_coefficient,
        "scaled_speed": scaled_speed,
        "scaled_duration": sp.simplify(factor * dmax * omega_t / v0),
    }


# ---------------------------------------------------------------------------------------------
# 4. Emitted code
# ---------------------------------------------------------------------------------------------

def kernels() -> list[Kernel]:
    z_arg = ((zeta, "damping ratio c/(2 sqrt(k m)) (>= 0)"),)
    tau_arg = (tau, "omega*dt, the step in units of 1/omega")
    phi_arg = (phi, "entry phase in [0, 1): first in-contact position is phi*tau*v0/omega")
    s_f = force_release_time_expr()
    hz = hertz()
    hertz_args = ((k_h, "Hertz coefficient in F = k_h d^(3/2) [N/m^(3/2)]"), (m, "effective mass [kg]"), (v0, "entry speed [m/s]"))
    return [
        Kernel(
            "geometric_duration", z_arg, geometric_duration_expr(),
            "Contact duration with separation when the overlap returns to 0, in units of 1/omega.\n\n"
            "    CFL note: t_d = pi/sqrt(1 - zeta^2); infinite for zeta >= 1 (the overlap never returns to 0).",
            cse=False,
        ),
        Kernel(
            "geometric_exit_ratio", z_arg, geometric_exit_ratio_expr(),
            "Exit/entry speed with separation when the overlap returns to 0.\n\n"
            "    CFL note: v_e/v0 = exp(-zeta pi/sqrt(1 - zeta^2)); 0 (the limit) for zeta >= 1.",
            cse=False,
        ),
        Kernel(
            "force_release_time", z_arg, s_f,
            "Time (units 1/omega) at which the spring-dashpot force k d + c d' reaches 0 (force-based release).\n\n"
            "    s_f = 2 arccos(zeta)/sqrt(1-zeta^2) | 2 | 2 arccosh(zeta)/sqrt(zeta^2-1); Taylor series near zeta = 1.",
        ),
        Kernel(
            "force_exit_ratio", z_arg, sp.exp(-zeta * s_f),
            "Exit/entry speed with force-based release: exp(-zeta s_f).",
        ),
        Kernel(
            "force_release_overlap", z_arg, 2 * zeta * sp.exp(-zeta * s_f),
            "Overlap (units v0/omega) left at force release, 2 zeta exp(-zeta s_f); the bodies then coast\n"
            "    apart at the exit speed and the overlap closes after a further 2 zeta/omega.",
        ),
        Kernel(
            "central_difference_angle", (tau_arg,), central_difference_angle_expr(),
            "Rotation angle theta per step of the undamped central-difference family: cos theta = 1 - tau^2/2 (tau <= 2).",
        ),
        Kernel(
            "central_difference_position", ((n, "step index from the first in-contact step"), phi_arg, tau_arg),
            central_difference_position_expr(),
            "Overlap x_n (units v0/omega) of the undamped central-difference family while in contact.\n\n"
            "    x_n = A cos(n theta) + B sin(n theta), x_0 = phi tau, x_(-1) = (phi - 1) tau (free flight).",
        ),
        Kernel(
            "central_difference_exit_ratio", ((phi, "entry phase in [0, 1)"), (psi, "exit phase in (0, 1]"), tau_arg),
            central_difference_ratio_expr(),
            "v_exit/v0 of the undamped central-difference family from the invariant Q = v^2 + x^2 - tau x v.",
        ),
        Kernel(
            "central_difference_ratio_bounds", (tau_arg,),
            (sp.sqrt(2 - tau) * sp.sqrt(2 + tau) / 2, 2 / (sp.sqrt(2 - tau) * sp.sqrt(2 + tau))),
            "(lower, upper) bound of v_exit/v0 over all phases: sqrt(1 - tau^2/4) and its reciprocal.",
            cse=False,
        ),
        Kernel(
            "central_difference_unit_step", ((N, "number of contact steps (>= 1)"),), central_difference_unit_steps_expr(),
            "tau_N = 2 sin(pi/(2N)): the steps at which v_exit = v0 for every entry phase (theta = pi/N).",
        ),
        Kernel(
            "forward_euler_motion", ((n, "step index from the first in-contact step"), phi_arg, tau_arg),
            forward_euler_motion_expr(),
            "(x_n, v_n) of undamped forward Euler in contact from (phi tau, 1): (1 + tau^2)^(n/2) times a rotation by n arctan(tau).",
        ),
        Kernel(
            "forward_euler_angle", (tau_arg,), forward_euler_map()[1],
            "Rotation angle per undamped forward-Euler step: arctan(tau).",
        ),
        Kernel("hertz_max_overlap", hertz_args, hz["dmax"], "Maximum overlap of the undamped Hertz impact [m]: (5 m v0^2/(4 k_h))^(2/5)."),
        Kernel(
            "hertz_duration", hertz_args, hz["duration"].evalf(20),
            "Contact duration of the undamped Hertz impact [s]: (4/5) B(2/5, 1/2) dmax/v0.",
        ),
        Kernel(
            "hertz_tangent_omega", hertz_args, hz["omega_t"],
            "Linearised contact frequency at maximum overlap [rad/s]: sqrt(1.5 k_h dmax^(1/2)/m).",
        ),
    ]


def postamble() -> str:
    hz = hertz()
    return "\n".join(
        [
            "# Undamped Hertz impact in units of dmax and 1/omega_t: u'' = -HERTZ_SCALED_COEFFICIENT u^(3/2)",
            f"HERTZ_SCALED_COEFFICIENT = {float(hz['scaled_coefficient'])!r}  # {hz['scaled_coefficient']}",
            f"HERTZ_SCALED_SPEED = {float(hz['scaled_speed'])!r}  # entry speed, {hz['scaled_speed']}",
            f"HERTZ_SCALED_DURATION = {float(hz['scaled_duration'])!r}  # contact duration in 1/omega_t",
            f"HERTZ_DURATION_FACTOR = {float(hz['duration_factor'])!r}  # duration in dmax/v0, (4/5) B(2/5, 1/2)",
            f"SERIES_RADIUS = {float(SERIES_RADIUS)!r}  # |1 - zeta| below which the series of g is used",
            f"CENTRAL_DIFFERENCE_FAMILY = {CENTRAL_DIFFERENCE_FAMILY!r}",
        ]
    )


def generated_files() -> dict[str, str]:
    text = python_module(
        PRODUCER,
        "One-dimensional impact of the spring-dashpot and Hertz contacts: exact and time-stepped closed forms.\n\n"
        "Dimensionless: time in 1/omega, overlap in v0/omega, speed in v0 (CFL note; Feng 2005).",
        kernels(),
        postamble=postamble(),
    )
    return {TARGET: text}
