"""An oblique impact of two equal spheres: Hertz normal law + Mindlin tangential spring with Coulomb's limit.

Units as ``collisions.scaled``: time ``t_c``, length ``delta_el``, the effective mass ``m* = 1`` (each
sphere ``m = 2``).  The plane motion is stepped as LAMMPS applies it (``pair_style granular ... tangential
mindlin NULL gammat mu``, ``PairGranular::compute`` of the 2021-2022 sources, ``fix nve/sphere``):

* relative position ``r = x1 - x2``, ``n = r/|r|``, overlap ``delta = 2R - |r|``, contact when ``delta > 0``;
* normal force ``F_n = kappa delta^p + g delta^q delta'`` (``delta' = -v_r.n``, clipped at 0 when the law
  clips); tangential stiffness ``k_t a = 8 G* sqrt(R* delta) = (4 G*/E*) (3/2) kappa delta^(1/2)`` with
  LAMMPS's ``mix_stiffnessG``: ``4 G*/E* = 2 (1 - nu)/(2 - nu)`` (equal materials); tangential damping
  ``gammat g delta^q``;
* slip ``v_tr = v_t + n x (R w1 + R w2)`` (full radii); history ``xi`` (kept in the tangent plane: LAMMPS
  projects and rescales it every step), ``xi += v_tr dt`` at every contact step -- the first included, so
  the first contact step adds the whole step's slip, the part before touch too (LAMMPS's convention);
  ``F_t = -k_t a xi - damp v_tr``, scaled to ``mu |F_n|`` and ``xi`` reset when it exceeds it
  (``physics.collision_laws.mindlin_tangential``); the history is dropped when the spheres separate;
* torque on each sphere ``-(R - delta/2) n x F_t`` (the arm LAMMPS and YADE use); inertia ``k_g^2 m R^2``.

The map is velocity Verlet with ``v_{n+1/2}`` to the forces (LAMMPS, LIGGGHTS); leapfrog with
``v_{n-1/2}`` (YADE) and symplectic Euler with ``v_n`` (MFiX, Kratos) step the same positions and are
accepted as the same map.  YADE's shear law is incremental (``Law2_ScGeom_MindlinPhys_Mindlin``), which
coincides with this one while the contact slides (the force is ``mu |F_n|`` along the slip), not when it
sticks.  Entry phase as ``collisions.stepping``: the continuum contact starts ``phase`` of a step before
the first step, laid out as the engine harness lays out its pairs.

Surviving dimensionless parameters (beyond the normal law's restitution and clipping): the friction
``mu``, the ratio ``v_t/v_n`` of tangential to normal entry speed, Poisson's ratio through
``k_t/k_n = 2 (1 - nu)/(2 - nu)``, the radius of gyration ``k_g^2 = I/(m R^2)`` (2/5 for solid
spheres, LAMMPS's ``INERTIA``), the tangential damping ratio, and -- only through the turning contact
plane -- ``delta_el/R`` (``overlap_ratio``; 0 is the small-overlap limit).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from dtcrit.collisions.laws import scaled_law
from dtcrit.collisions.scaled import ScaledLaw
from dtcrit.collisions.stepping import MAX_STEPS_PER_COLLISION, scheme_of
from dtcrit.errors import InputError

SAME_MAP = ("velocity-verlet", "leapfrog", "symplectic-euler")
CUTOFF = 12.0


@dataclass(frozen=True)
class ObliqueCase:
    """An oblique impact in scaled units.

    Parameters
    ----------
    law : ScaledLaw
        The normal law (hertz).
    friction : float
        Coulomb coefficient ``mu``.
    tangential_ratio : float
        ``v_t/v_n`` at entry.
    poisson : float
        Poisson's ratio (sets ``k_t/k_n``).
    gyration : float
        ``k_g^2 = I/(m R^2)``.
    gammat_ratio : float
        Tangential over normal damping prefactor (LAMMPS ``mindlin NULL gammat mu``).
    overlap_ratio : float
        ``delta_el/R``.
    """

    law: ScaledLaw
    friction: float
    tangential_ratio: float
    poisson: float = 0.3
    gyration: float = 0.4
    gammat_ratio: float = 0.0
    overlap_ratio: float = 1.0e-3


@dataclass(frozen=True)
class ObliqueOutcome:
    """Outcome of an oblique impact (ratios as the engine harness measures them).

    Parameters
    ----------
    restitution : float
        Exit/entry normal relative speed.
    tangential_restitution : float
        Exit/entry tangential contact-point (slip) speed along the entry tangent.
    spin : float
        Rebound spin of sphere 1 times ``R`` over the entry tangential speed.
    """

    restitution: float
    tangential_restitution: float
    spin: float


def _geometry(c: ObliqueCase, a: float, b: float):
    """Overlap and normal of ``r = (-2R + a, b)`` (``R = 1/eps``), without cancellation."""
    eps = c.overlap_ratio
    er = math.hypot(-2.0 + eps * a, eps * b)  # eps |r|
    delta = (4.0 * a - eps * (a * a + b * b)) / (2.0 + er)
    return delta, np.array([(-2.0 + eps * a) / er, eps * b / er])


def _forces(c: ObliqueCase, delta, n, vr, W, xi, dt):
    """(normal force, tangential force vector, new history vector, dW/dt, slip along t) at one evaluation.

    LAMMPS 2021 ``PairGranular::compute``: the history is projected onto the tangent plane and rescaled to
    its length only when ``|xi.n| k_t a > 1e-10 mu |F_n|`` (``frameupdate``, EPSILON = 1e-10); then
    ``xi += v_tr dt``; ``F_t = -k_t a xi - damp v_tr`` (vectors); Coulomb rescaling on ``|F_t|``.
    """
    L = c.law
    rate = -float(vr @ n)
    gq = L.g * delta**L.q if L.q else L.g
    fn = L.kappa * delta**L.p + gq * rate
    if L.clip:
        fn = max(fn, 0.0)
    t = np.array([-n[1], n[0]])
    vtr = float((vr - (vr @ n) * n) @ t) - W  # slip along t: (n x W z).t = -W
    kt = 2.0 * (1.0 - c.poisson) / (2.0 - c.poisson) * 1.5 * L.kappa * math.sqrt(delta)
    damp = c.gammat_ratio * gq
    lim = c.friction * abs(fn)
    x = np.asarray(xi, dtype=float)
    rsht = float(x @ n)
    if abs(rsht) * kt > 1e-10 * lim:
        mag = math.hypot(*x)
        x = x - rsht * n
        pm = math.hypot(*x)
        x = x * (mag / pm) if pm > 0.0 else 0.0 * x
    x = x + vtr * dt * t
    fs = -kt * x - damp * vtr * t
    mag = math.hypot(*fs)
    if mag > lim:
        if math.hypot(*x) != 0.0:
            x = -(lim * fs / mag + damp * vtr * t) / kt
            fs = fs * (lim / mag)
        else:
            fs = 0.0 * fs
    tor = float(n[0] * fs[1] - n[1] * fs[0])  # (n x F_t)_z
    dW = -(1.0 - 0.5 * c.overlap_ratio * delta) * tor / c.gyration  # W = R (w1 + w2)
    return fn, fs, x, dW, vtr


def _measure(c, r_in, vr0, r_a, r_b, vr1, W1) -> ObliqueOutcome:
    vt0 = c.law.w0 * c.tangential_ratio
    _, n0 = _geometry(c, *r_in)
    da, db = _geometry(c, *r_a)[0], _geometry(c, *r_b)[0]
    r_out = r_a + (r_b - r_a) * (da / (da - db))
    _, n1 = _geometry(c, *r_out)
    t0 = np.array([-n0[1], n0[0]])

    def slip(vr, n, W):
        return vr - (vr @ n) * n - W * np.array([-n[1], n[0]])

    s0 = slip(vr0, n0, 0.0)
    et = float(slip(vr1, n1, W1) @ t0 / (s0 @ t0))
    return ObliqueOutcome(-float(vr1 @ n1) / float(vr0 @ n0), et, 0.5 * W1 / vt0)


def step_oblique(c: ObliqueCase, steps_per_collision: float, phase: float) -> ObliqueOutcome:
    """One oblique impact stepped with the LAMMPS/YADE map (see the module docstring).

    Parameters
    ----------
    c : ObliqueCase
        The case.
    steps_per_collision : float
        N = t_c/dt.
    phase : float
        Entry phase in [0, 1).

    Returns
    -------
    ObliqueOutcome
        Normal and tangential restitution and rebound spin.
    """
    if not (1.0 <= steps_per_collision <= MAX_STEPS_PER_COLLISION):
        raise InputError("steps_per_collision", f"must lie in [1, {MAX_STEPS_PER_COLLISION:g}]")
    if not 0.0 <= phase < 1.0:
        raise InputError("phase", "must lie in [0, 1)")
    h = 1.0 / steps_per_collision
    w0 = c.law.w0
    vr = np.array([w0, w0 * c.tangential_ratio])
    t_in = (1.0 - phase) * h
    r = np.array([-w0 * t_in, -vr[1] * t_in])  # (a, b): r = (-2R + a, b)
    vr0, r_in = vr.copy(), r + vr * t_in
    acc, dW, W, xi = np.zeros(2), 0.0, 0.0, np.zeros(2)
    touched, prev = False, r.copy()
    for _ in range(int(CUTOFF * steps_per_collision) + 8):
        vh, Wh = vr + 0.5 * h * acc, W + 0.5 * h * dW
        prev, r = r, r + h * vh
        delta, n = _geometry(c, *r)
        if delta > 0.0:
            fn, ft, xi, dW, _ = _forces(c, delta, n, vh, Wh, xi, h)
            acc = fn * n + ft
            touched = True
        else:
            acc, dW, xi = np.zeros(2), 0.0, np.zeros(2)
        vr, W = vh + 0.5 * h * acc, Wh + 0.5 * h * dW
        if touched and delta <= 0.0:
            return _measure(c, r_in, vr0, prev, r, vr, W)
    raise InputError("steps_per_collision", "the spheres did not separate by the cut-off")


def reference_oblique(c: ObliqueCase, mode: str) -> ObliqueOutcome:
    """The continuum outcome (DOP853, rtol 1e-12, events at separation), sliding or sticking throughout.

    ``mode="slide"``: ``F_t = -mu |F_n| sign(v_tr)``, refused when the slip reverses; ``mode="stick"``:
    ``xi' = v_tr``, refused when Coulomb's limit binds before the last 1 % of the contact.  Mixed stick-slip
    is not modelled: sliding is refused with a normal or tangential dashpot (the dashpot's force at touch
    exceeds the spring's, so the onset sticks) and when ``(3/2) (k_t/k_n) v_t/v_n <= mu`` (the elastic
    onset sticks; the harness's ``oblique_sliding`` applies the same rule).

    Parameters
    ----------
    c : ObliqueCase
        The case.
    mode : str
        ``"slide"`` or ``"stick"``.

    Returns
    -------
    ObliqueOutcome
        The continuum outcome.
    """
    if mode not in ("slide", "stick"):
        raise InputError("mode", f"must be 'slide' or 'stick' (got {mode!r})")
    w0 = c.law.w0
    ratio_t = 2.0 * (1.0 - c.poisson) / (2.0 - c.poisson)
    if mode == "slide" and (c.law.g != 0.0 or c.gammat_ratio != 0.0):
        raise InputError("damping", "a normal or tangential dashpot makes the onset stick; stick-slip is not modelled")
    if mode == "slide" and 1.5 * ratio_t * c.tangential_ratio <= c.friction:
        raise InputError("friction", "the contact sticks at first touch; stick-slip is not modelled")
    fail = []

    def rhs(s, y):
        delta, n = _geometry(c, y[0], y[1])
        d = max(delta, 0.0)
        L = c.law
        gq = L.g * d**L.q if L.q else L.g
        fn = L.kappa * d**L.p - gq * float(y[2:4] @ n)
        fn = max(fn, 0.0) if L.clip else fn
        t = np.array([-n[1], n[0]])
        vtr = float(y[2:4] @ t) - y[4]
        if mode == "stick":
            ft = -2.0 * (1.0 - c.poisson) / (2.0 - c.poisson) * 1.5 * L.kappa * math.sqrt(d) * y[5]
            ft -= c.gammat_ratio * gq * vtr
            if abs(ft) > c.friction * abs(fn):
                fail.append(s)
        else:
            ft = -c.friction * abs(fn) * math.copysign(1.0, vtr)
            if vtr * c.tangential_ratio >= 0.0:  # the entry slip along t is -v_t
                fail.append(s)
        acc = fn * n + ft * t
        dW = -(1.0 - 0.5 * c.overlap_ratio * d) * ft / c.gyration
        return [y[2], y[3], acc[0], acc[1], dW, vtr]

    def out(s, y):
        return _geometry(c, y[0], y[1])[0]

    out.terminal, out.direction = True, -1.0  # type: ignore[attr-defined]
    y0 = [0.0, 0.0, w0, w0 * c.tangential_ratio, 0.0, 0.0]
    sol = solve_ivp(rhs, (1e-14, CUTOFF), [w0 * 1e-14, w0 * c.tangential_ratio * 1e-14] + y0[2:], method="DOP853",
                    rtol=1e-12, atol=1e-14, events=[out])
    if sol.status != 1:
        raise InputError("oblique", f"the continuum impact did not separate ({sol.message})")
    if any(s < 0.99 * sol.t_events[0][0] for s in fail):  # the limit binds at the very end, fn -> 0
        raise InputError("friction", "the contact changes between sticking and sliding; not modelled")
    ye = sol.y_events[0][0]
    r_end = ye[0:2]
    return _measure(c, np.zeros(2), np.array(y0[2:4]), r_end, r_end + 1e-9 * ye[2:4], ye[2:4], ye[4])


def oblique_case(*, normal: str, damping: str, restitution: float, friction: float, tangential_ratio: float,
                 poisson: float = 0.3, gyration: float = 0.4, gammat_ratio: float = 0.0,
                 overlap_ratio: float = 1.0e-3, clip: bool | None = None) -> ObliqueCase:
    """Build and check an ``ObliqueCase`` from a code's normal law (``collisions.laws.scaled_law``).

    Parameters
    ----------
    normal, damping, restitution, clip
        As ``scaled_law`` (``normal`` must be ``"hertz"``: the Mindlin spring needs ``a = sqrt(R* delta)``).
    friction, tangential_ratio, poisson, gyration, gammat_ratio, overlap_ratio
        As ``ObliqueCase``.

    Returns
    -------
    ObliqueCase
        The case.
    """
    if normal != "hertz":
        raise InputError("normal", "the Mindlin tangential spring is modelled with a hertz normal law only")
    for key, val, lo, hi in (("friction", friction, 0.0, math.inf), ("tangential_ratio", tangential_ratio, 0.0, math.inf),
                             ("poisson", poisson, -1.0, 0.5), ("gyration", gyration, 0.0, 1.0),
                             ("gammat_ratio", gammat_ratio, -1e-300, math.inf), ("overlap_ratio", overlap_ratio, -1e-300, 0.1)):
        if not (isinstance(val, (int, float)) and lo < val < hi or (key == "poisson" and val == 0.5)):
            raise InputError(key, f"must lie in ({lo:g}, {hi:g}) (got {val!r})")
    return ObliqueCase(scaled_law(normal, damping, restitution, clip), float(friction), float(tangential_ratio),
                       float(poisson), float(gyration), float(gammat_ratio), float(overlap_ratio))


def oblique_errors(*, engine: str, normal: str, damping: str, restitution: float, friction: float,
                   tangential_ratio: float, steps_per_collision: float, mode: str, poisson: float = 0.3,
                   gyration: float = 0.4, gammat_ratio: float = 0.0, overlap_ratio: float = 1.0e-3,
                   clip: bool | None = None, phases: int = 64) -> dict:
    """Worst relative error over the entry phase of the normal and tangential restitution and the spin.

    The phase is sampled at ``phases`` points and the worst refined by bounded scalar optimisation.

    Parameters
    ----------
    engine : str
        An engine or scheme of the velocity-Verlet/leapfrog/symplectic-Euler map.
    normal, damping, restitution, clip
        The normal law (``scaled_law``).
    friction, tangential_ratio, poisson, gyration, gammat_ratio, overlap_ratio
        As ``ObliqueCase``.
    steps_per_collision : float
        N = t_c/dt.
    mode : str
        ``"slide"`` or ``"stick"``: the continuum regime of the reference.
    phases : int
        Phase samples.

    Returns
    -------
    dict
        ``reference`` (ObliqueOutcome) and, per quantity, ``{"error", "phase"}``: the worst error and its
        phase; relative for the two restitutions, absolute for the spin (already in units of ``v_t/R``; it
        nearly vanishes when the contact sticks).
    """
    from scipy.optimize import minimize_scalar

    scheme = scheme_of(engine)
    if scheme not in SAME_MAP:
        raise InputError("engine", f"the oblique impact is modelled for {', '.join(SAME_MAP)}, not {scheme!r}")
    c = oblique_case(normal=normal, damping=damping, restitution=restitution, friction=friction,
                     tangential_ratio=tangential_ratio, poisson=poisson, gyration=gyration,
                     gammat_ratio=gammat_ratio, overlap_ratio=overlap_ratio, clip=clip)
    ref = reference_oblique(c, mode)
    out: dict = {"reference": ref}
    for name in ("restitution", "tangential_restitution", "spin"):
        want = getattr(ref, name)

        def err(p, name=name, want=want):
            got = getattr(step_oblique(c, steps_per_collision, p), name)
            return abs(got - want) if name == "spin" else abs(got - want) / abs(want)

        grid = (np.arange(phases) + 0.5) / phases
        vals = [err(p) for p in grid]
        k = int(np.argmax(vals))
        lo, hi = max(grid[k] - 1.0 / phases, 0.0), min(grid[k] + 1.0 / phases, 1.0 - 1e-12)
        best = minimize_scalar(lambda p: -err(p), bounds=(lo, hi), method="bounded", options={"xatol": 1e-6})
        worst, at = (-best.fun, best.x) if -best.fun > vals[k] else (vals[k], grid[k])
        out[name] = {"error": float(worst), "phase": float(at)}
    return out


__all__ = ["ObliqueCase", "ObliqueOutcome", "oblique_case", "step_oblique", "reference_oblique", "oblique_errors"]
