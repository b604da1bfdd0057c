"""Two-sphere collisions for the engine harness: the cases, the engines' damping laws, the measures.

An ``Impact`` is a head-on (or oblique) collision of two equal spheres with no gravity, designed
from dimensionless targets: the steps per collision ``N = t_c/dt`` (``t_c`` the *elastic* contact
duration), the elastic peak overlap as a fraction of the radius, and the **entry phase**: the
continuous free-flight contact starts ``phase*dt`` before a step, so the first step that sees the
spheres overlap sees the overlap ``phase*v*dt``.

Both engines decide contact the same way and integrate alike (sources read for this harness):

* LAMMPS 29Sep2021/20220106 (``fix nve/sphere`` + ``pair_style granular``): velocity Verlet;
  the forces of step n+1 come from x_{n+1} and the half-step velocity v_{n+1/2}
  (``FixNVESphere::initial_integrate`` then ``PairGranular::compute``), and a pair is in contact
  when ``rsq < radsum*radsum`` (``touchflag``), i.e. overlap > 0 at the step's positions.
* YADE 2023.02a (``NewtonIntegrator``): leapfrog; step n's forces come from x_n and the stored
  velocity v_{n-1/2}; ``Ig2_Sphere_Sphere_ScGeom`` makes the contact when the distance is below
  R1 + R2 and ``Law2_ScGeom_MindlinPhys_Mindlin`` drops it when ``penetrationDepth < 0``.

Both are the same position-Verlet map, so with the same initial positions and (half-step)
velocities the two engines step the same trajectory; the phase is set by the initial gap
``g0 = v*(1 - phase)*dt`` (contact starts at t = (1 - phase) dt, step 1 sees overlap phase*v*dt).

Damping laws (force on the approaching pair ``-eta * v_n``, ``v_n`` the normal relative velocity):

* ``lammps-tsuji``: ``eta = alpha(e) sqrt(meff * knfac)``, ``knfac = F_el/delta`` (Hertz:
  ``4/3 E* sqrt(R* delta)``; Hooke: ``kn``), alpha Tsuji's polynomial of the coefficient e
  (``PairGranular::coeff``/``compute`` of the 2021-2022 sources).  Not clipped unless
  ``limit_damping`` is given.
* ``lammps-coeff-restitution``: the newer LAMMPS law (``GranSubModDampingCoeffRestitution``):
  ``eta = d sqrt(meff F_el/delta)`` with ``d = 2 beta`` (Hooke) or ``sqrt(3/2) 2 sqrt(5/6) beta``
  (Hertz), ``beta = -ln e/sqrt(ln^2 e + pi^2)``.  Debian's 2021 build has no ``coeff_restitution``,
  but its ``tsuji`` has the same form ``damp*sqrt(meff*knfac)``, so the harness writes
  ``damping tsuji`` with the coefficient ``e'`` whose Tsuji polynomial equals ``d``
  (``tsuji_coefficient_for``; e' < 0 for e below ~0.12, which the 2021 parser accepts).
* ``lammps-mass-velocity``: ``eta = gamma * meff`` (coefficient as LAMMPS takes it).
* ``yade-mindlin``: YADE 2023.02a (``Ip2_FrictMat_FrictMat_MindlinPhys::go`` with ``en``;
  ``Law2_ScGeom_MindlinPhys_Mindlin::go``): ``eta = 2 beta_n sqrt(mbar * kn)``, ``kn = 3/2 kno
  sqrt(delta) = 2 E* sqrt(R* delta)`` (tangent stiffness), with ``beta_n = sqrt(1/(1 - (1+en)^2
  exp(alpha_n)) - 1)`` and ``alpha_n = en (h1 + en (h2 + ... + en h10))`` (Thornton et al. 2013,
  eqs. B6-B7, fitted so that the *clipped* law restitutes en); the total normal force is clipped
  at zero; the damping velocity is the plain normal relative velocity (``getIncidentVel(...,
  false)``; ``preventGranularRatcheting`` is deprecated and unused in this version).  Older YADE
  versions used ``2 sqrt(5/6) beta(en)`` instead, which the clipping turns into a higher
  restitution (0.55 for en = 0.5).
* ``none``: elastic.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import brentq
from scipy.special import beta as beta_fn

__all__ = [
    "Impact", "Outcome", "DAMPINGS", "tsuji_alpha", "beta_of", "coeff_restitution_prefactor",
    "tsuji_coefficient_for", "thornton_beta", "THORNTON_H", "hertz_time_factor", "design", "measure",
]

DAMPINGS = ("lammps-tsuji", "lammps-coeff-restitution", "lammps-mass-velocity", "yade-mindlin", "none")
NORMALS = ("hertz", "hooke")


def tsuji_alpha(e: float) -> float:
    """Tsuji's polynomial as LAMMPS evaluates it (``PairGranular::coeff``, 2021 sources)."""
    return (1.2728 - 4.2783 * e + 11.087 * e**2 - 22.348 * e**3 + 27.467 * e**4
            - 18.022 * e**5 + 4.8218 * e**6)


def beta_of(e: float) -> float:
    """``-ln e / sqrt(ln^2 e + pi^2)`` (0 for e = 1)."""
    if e >= 1.0:
        return 0.0
    lg = math.log(e)
    return -lg / math.sqrt(lg * lg + math.pi**2)


def coeff_restitution_prefactor(e: float, normal: str) -> float:
    """LAMMPS ``coeff_restitution`` prefactor d of ``d*sqrt(meff*F/delta)`` (newer sources)."""
    b = beta_of(e)
    return 2.0 * b if normal == "hooke" else math.sqrt(1.5) * 2.0 * math.sqrt(5.0 / 6.0) * b


def tsuji_coefficient_for(prefactor: float) -> float:
    """The ``tsuji`` coefficient e' whose polynomial equals ``prefactor`` (root near [-0.2, 1])."""
    return brentq(lambda x: tsuji_alpha(x) - prefactor, -0.2, 1.05, xtol=1e-18, rtol=8.9e-16, maxiter=500)


#: Thornton et al. (2013) Table 2 fit coefficients h1..h10, as YADE 2023.02a codes them
THORNTON_H = (-6.918798, -16.41105, 146.8049, -796.4559, 2928.711, -7206.864, 11494.29, -11342.18, 6276.757,
              -1489.915)


def thornton_beta(en: float) -> float:
    """YADE's normal damping ratio from ``en`` (Thornton et al. 2013 eqs. B6-B7; 0 for en = 1)."""
    if en == 1.0:
        return 0.0
    acc = THORNTON_H[-1]
    for h in THORNTON_H[-2::-1]:  # Horner, as YADE nests it: en*(h1 + en*(h2 + ... + en*h10))
        acc = h + en * acc
    alphan = en * acc
    return math.sqrt(1.0 / (1.0 - (1.0 + en) ** 2 * math.exp(alphan)) - 1.0)


def hertz_time_factor() -> float:
    """``t_c v / delta_max`` of an elastic Hertz impact: ``2 * (2/5) B(2/5, 1/2)`` (= 2.9432...)."""
    return 2.0 * 0.4 * float(beta_fn(0.4, 0.5))


@dataclass(frozen=True)
class Impact:
    """One collision of two equal spheres (SI units).

    ``coefficient`` is the damping parameter as the law takes it: the restitution ``e`` for
    ``lammps-tsuji`` (Tsuji's polynomial of it), ``lammps-coeff-restitution`` and ``yade-mindlin``,
    gamma for ``lammps-mass-velocity``; ignored for ``none``.  ``clip`` adds LAMMPS's
    ``limit_damping`` (YADE always clips).  ``tangential_speed`` > 0 makes an oblique impact
    (relative tangential velocity along y at contact; LAMMPS ``tangential mindlin NULL
    gammat_ratio friction``).
    """

    normal: str
    damping: str
    coefficient: float
    radius: float
    mass: float  # of each sphere
    speed: float  # normal approach speed at contact
    phase: float
    young: float = 1.0e7
    poisson: float = 0.3
    kn: float = 0.0  # Hooke stiffness
    clip: bool = False
    tangential_speed: float = 0.0
    friction: float = 0.0
    gammat_ratio: float = 0.0

    @property
    def meff(self) -> float:
        """Effective mass ``m/2`` of two equal spheres."""
        return 0.5 * self.mass

    @property
    def reff(self) -> float:
        """Effective radius ``R/2``."""
        return 0.5 * self.radius

    @property
    def estar(self) -> float:
        """E* of two spheres of the same material, ``E / (2 (1 - nu^2))``."""
        return self.young / (2.0 * (1.0 - self.poisson**2))

    @property
    def gstar(self) -> float:
        """LAMMPS ``mix_stiffnessG``: ``E / (4 (2 - nu)(1 + nu))``."""
        return self.young / (4.0 * (2.0 - self.poisson) * (1.0 + self.poisson))

    @property
    def khertz(self) -> float:
        """``F = khertz * delta^(3/2)``: ``4/3 E* sqrt(R*)``."""
        return 4.0 / 3.0 * self.estar * math.sqrt(self.reff)

    def elastic_force(self, delta):
        """Elastic normal force at overlap ``delta`` (``kn delta`` or ``khertz delta^(3/2)``)."""
        d = np.maximum(delta, 0.0)
        return self.kn * d if self.normal == "hooke" else self.khertz * d**1.5

    def eta(self, delta):
        """Normal dashpot coefficient at overlap ``delta`` (force ``-eta*v_n``)."""
        d = np.maximum(delta, 0.0)
        knfac = self.kn if self.normal == "hooke" else self.khertz * np.sqrt(d)
        if self.damping == "none":
            return 0.0 * d
        if self.damping == "lammps-tsuji":
            return tsuji_alpha(self.coefficient) * np.sqrt(self.meff * knfac)
        if self.damping == "lammps-coeff-restitution":
            return coeff_restitution_prefactor(self.coefficient, self.normal) * np.sqrt(self.meff * knfac)
        if self.damping == "lammps-mass-velocity":
            return self.coefficient * self.meff + 0.0 * d
        if self.damping == "yade-mindlin":
            return 2.0 * thornton_beta(self.coefficient) * np.sqrt(
                self.meff * 2.0 * self.estar * np.sqrt(self.reff * d))
        raise ValueError(f"unknown damping {self.damping!r}")

    @property
    def elastic_peak(self) -> float:
        """Elastic peak overlap: ``v sqrt(m*/k)`` (Hooke), ``(15 m* v^2/(16 E* sqrt R*))^(2/5)``."""
        if self.normal == "hooke":
            return self.speed * math.sqrt(self.meff / self.kn)
        return (15.0 * self.meff * self.speed**2 / (16.0 * self.estar * math.sqrt(self.reff))) ** 0.4

    @property
    def contact_time(self) -> float:
        """Elastic contact duration t_c: ``pi sqrt(m*/k)`` (Hooke), 2.9432 delta_max/v (Hertz)."""
        if self.normal == "hooke":
            return math.pi * math.sqrt(self.meff / self.kn)
        return hertz_time_factor() * self.elastic_peak / self.speed

    @property
    def clipped(self) -> bool:
        """Whether the engine clips the total normal force at zero (LAMMPS limit_damping, YADE)."""
        return self.clip or self.damping == "yade-mindlin"


def design(normal: str, damping: str, coefficient: float, *, dt: float, steps_per_collision: float,
           phase: float, peak_over_radius: float = 1.0e-3, radius: float = 1.0e-3, young: float = 1.0e7,
           poisson: float = 0.3, kn: float = 1.0e3, **kw) -> Impact:
    """An ``Impact`` with ``t_c = steps_per_collision * dt`` and the elastic peak overlap.

    The elastic peak overlap is ``peak_over_radius * radius``; the speed and the sphere mass
    follow (t_c and delta_max fix them).
    """
    tc = steps_per_collision * dt
    dmax = peak_over_radius * radius
    probe = Impact(normal, damping, coefficient, radius, 1.0, 1.0, phase, young=young, poisson=poisson, kn=kn, **kw)
    if normal == "hooke":
        meff = kn * (tc / math.pi) ** 2
        v = dmax * math.sqrt(kn / meff)
    else:
        v = hertz_time_factor() * dmax / tc
        meff = dmax**2.5 * 16.0 * probe.estar * math.sqrt(0.5 * radius) / (15.0 * v * v)
    return replace(probe, mass=2.0 * meff, speed=v)


@dataclass(frozen=True)
class Outcome:
    """Measured outcome of one collision (ratios as dtcrit's ``CollisionOutcome``)."""

    restitution: float  # exit/entry normal relative speed
    peak_overlap: float  # max overlap at the steps / elastic peak overlap
    duration: float  # interpolated contact duration / t_c
    duration_steps: float  # (steps with overlap > 0) * dt / t_c
    energy_ratio: float  # exit/entry kinetic energy (translation + rotation)
    steps_in_contact: int
    tangential_restitution: float = math.nan  # exit/entry contact-point slip velocity along t
    spin: float = math.nan  # rebound spin of sphere 1 times R over the entry tangential speed
    separated: bool = True


def measure(imp: Impact, dt: float, x1, x2, v1, v2, w1, w2) -> Outcome:
    """Outcome of a collision from per-step arrays (rows = steps 0..n, columns x, y, z).

    Positions at the steps; ``v`` the velocities the engine reports with them (LAMMPS: full
    step; YADE: the following half step), which equal the free-flight velocities before and
    after the contact.  The entry contact time is (1 - phase) dt; the exit one is where the
    overlap, linear between the last overlapping step and the next (the drift of both
    integrators is a straight line), crosses zero.
    """
    x1, x2, v1, v2, w1, w2 = (np.asarray(a, dtype=float) for a in (x1, x2, v1, v2, w1, w2))
    d = x2 - x1
    r = np.sqrt(np.sum(d * d, axis=1))
    overlap = 2.0 * imp.radius - r
    inside = np.flatnonzero(overlap > 0.0)
    separated = bool(inside.size and inside[-1] < len(r) - 1 and overlap[-1] < 0.0)
    if not inside.size:
        raise ValueError("the spheres never touched")
    last = inside[-1]
    t_out = (last + overlap[last] / (overlap[last] - overlap[last + 1])) * dt if separated else math.nan
    t_in = (1.0 - imp.phase) * dt
    # the normals at first and last touch: the drift between two steps is a straight line
    d_in = d[0] + (d[1] - d[0]) * (t_in / dt)
    n0 = d_in / np.linalg.norm(d_in)
    if separated:
        d_out = d[last] + (d[last + 1] - d[last]) * (t_out / dt - last)
        n1 = d_out / np.linalg.norm(d_out)
    else:
        n1 = d[-1] / r[-1]
    vin = float(np.dot(v2[0] - v1[0], n0))
    vout = float(np.dot(v2[-1] - v1[-1], n1))
    inertia = 0.4 * imp.mass * imp.radius**2

    def ke(k):
        return 0.5 * imp.mass * (v1[k] @ v1[k] + v2[k] @ v2[k]) + 0.5 * inertia * (w1[k] @ w1[k] + w2[k] @ w2[k])

    et = spin = math.nan
    if imp.tangential_speed > 0.0:
        def slip(k, n):
            # contact-point velocity of 2 relative to 1, tangential part
            vc = (v2[k] - v1[k]) - np.cross(imp.radius * w2[k] + imp.radius * w1[k], n)
            return vc - np.dot(vc, n) * n
        s0 = slip(0, n0)
        t0 = s0 / np.linalg.norm(s0)
        et = float(np.dot(slip(-1, n1), t0) / np.dot(s0, t0))
        spin = float(w1[-1][2] * imp.radius / imp.tangential_speed)
    return Outcome(restitution=-vout / vin, peak_overlap=float(overlap.max()) / imp.elastic_peak,
                   duration=(t_out - t_in) / imp.contact_time, duration_steps=inside.size * dt / imp.contact_time,
                   energy_ratio=ke(-1) / ke(0), steps_in_contact=int(inside.size), tangential_restitution=et,
                   spin=spin, separated=separated)
