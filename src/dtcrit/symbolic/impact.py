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

from dtcrit.symbolic.emit import Kernel, python_module
from dtcrit.symbolic.impact_contact import (
    CENTRAL_DIFFERENCE_FAMILY,
    SERIES_RADIUS,
    N,
    force_release_time_expr,
    geometric_duration_expr,
    geometric_exit_ratio_expr,
    k_h,
    m,
    n,
    phi,
    psi,
    u,
    v0,
    x,
    zeta,
)
from dtcrit.symbolic.impact_stepping import (
    central_difference_angle_expr,
    central_difference_position_expr,
    central_difference_ratio_expr,
    central_difference_unit_steps_expr,
    forward_euler_map,
    forward_euler_motion_expr,
)
from dtcrit.symbolic.integrators import tau

PRODUCER = "dtcrit.symbolic.impact"
TARGET = "impact.py"


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

    Returns
    -------
    dict
        SymPy expressions by name (``dmax``, ``duration_factor``, ``scaled_coefficient``,
        ``scaled_speed``, ``scaled_duration``, ...).
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
    """The emitted kernels of the one-dimensional impact (exact and time-stepped closed forms).

    Returns
    -------
    list of Kernel
        One per emitted function of ``dtcrit/_generated/impact.py``.
    """
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
    """The constants appended to the emitted impact module (Hertz impact in scaled units, series radius).

    Returns
    -------
    str
        Python source lines.
    """
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
    """The emitted impact module, by its path under ``dtcrit/_generated``.

    Returns
    -------
    dict of str to str
        File name -> Python source.
    """
    text = python_module(
        PRODUCER,
        "One-dimensional impact of the spring-dashpot and Hertz contacts: exact and time-stepped closed forms.\n\n"
        "Dimensionless: time in 1/omega, overlap in v0/omega, speed in v0 (CFL note; Feng 2005).",
        kernels(),
        postamble=postamble(),
    )
    return {TARGET: text}
