"""The critical step of one isolated contact, mode by mode (Peng et al. 2020, Sections 3-4).

A contact obeys ``xddot = -A (K x + C xdot)`` with ``K = kn n n^T + ks (1 - n n^T)``,
``C = cn n n^T + cs (1 - n n^T)`` and ``A`` the 3x3 coefficient matrix of the actual contact.

* **Two spheres** (arm = the full radius, as LAMMPS's gran styles and YADE apply torques):
  ``A = (1/m1 + 1/m2) n n^T + (1/m1 + 1/m2 + R1^2/I1 + R2^2/I2)(1 - n n^T)``.  ``A``, ``K`` and ``C``
  share the eigenvectors ``n`` and the tangent plane, so the modes separate *exactly*, damped or not,
  proportional or not: the normal mode ``(kn, cn, A_n)`` and two tangential modes ``(ks, cs, A_t)``.
  Each mode's step is the exact boundary of the integrator's amplification matrix
  (:func:`dtcrit.integrators.stability.mode_dt`; a tangential dashpot without spring, LAMMPS
  ``gran/hooke``, included).  The contact's step is the smaller one.
* **A sphere against a fixed wall**: the same with ``A_n = 1/m``, ``A_t = 1/m + R^2/I``.
* **Other shapes** (a bound, labelled so): ``A`` is bounded by ``A_bound`` (the verified bound on the
  largest eigenvalue of the coefficient matrix over all admissible contacts,
  :func:`dtcrit.bodies.contact.a_bound`), against a wall by ``1/m + S`` with the body's arm
  supremum ``S``; each direction is checked with its own stiffness and dashpot at that ``A``.
  Every integrator's step is non-increasing in ``A``, so this is safe for every contact.
"""
from __future__ import annotations

from dataclasses import dataclass

from dtcrit.integrators.stability import mode_dt
from dtcrit.scenes.model import PairContact

EXACT = "exact modes"
BOUND = "bound (A_bound)"


@dataclass(frozen=True)
class DirectionStep:
    """The step of one contact mode: ``direction`` normal | shear."""

    direction: str
    k: float
    c: float
    A: float  # inverse inertia of the mode [1/kg]
    zeta: float | None  # the damping ratio of this direction as the scene's convention defines it
    zeta_mode: float  # c A / (2 sqrt(k A)): the mode's own damping ratio, which decides the step
    regime: str  # of ``zeta`` (the user's), or "dashpot only" / "free"
    dt: float
    reason: str


@dataclass(frozen=True)
class PairStep:
    contact: PairContact
    A_max: float | None  # Eq. (26) as printed (None against a wall)
    A_bound: float  # the bound on the coefficient matrix's largest eigenvalue (reported for every pair)
    normal: DirectionStep
    shear: DirectionStep
    method: str  # EXACT | BOUND
    B_sum: float | None = None  # B_i + B_j (None without omega_max)
    dt_rotation: float | None = None

    @property
    def label(self) -> str:
        return self.contact.label

    @property
    def governing_direction(self) -> DirectionStep:
        return self.normal if self.normal.dt <= self.shear.dt else self.shear

    @property
    def dt_translation(self) -> float:
        return self.governing_direction.dt


def _regime(zeta: float | None, mode) -> str:
    if mode.regime in ("dashpot only", "free"):
        return mode.regime
    z = mode.zeta if zeta is None else zeta
    if z == 0:
        return "undamped"
    return "underdamped" if z < 1 else ("critically damped" if z == 1 else "overdamped")


def direction_step(integrator: str, name: str, k: float, c: float, A: float, zeta: float | None) -> DirectionStep:
    r = mode_dt(integrator, k, c, A)
    return DirectionStep(name, k, c, A, zeta, r.zeta, _regime(zeta, r), r.dt, r.reason)


def sphere_modes(p_shape, q_shape) -> tuple[float, float]:
    """(A_n, A_t) of two spheres, or of a sphere and a fixed wall (``q_shape`` None), arm = radius."""
    inv = 1.0 / p_shape.mass + (0.0 if q_shape is None else 1.0 / q_shape.mass)
    rot = p_shape.max_arm**2 / p_shape.inertia[0] + (0.0 if q_shape is None else q_shape.max_arm**2 / q_shape.inertia[0])
    return inv, inv + rot


def pair_step(integrator: str, pc: PairContact, p_shape, q_shape, p_kind: str, q_kind: str | None) -> PairStep:
    """The isolated contact ``pc`` between ``p_shape`` and ``q_shape`` (``None``: a fixed wall)."""
    from dtcrit.bodies import arm_supremum, contact

    if q_shape is None:
        a_max = None
        a_bound = 1.0 / p_shape.mass + arm_supremum.arm_term_supremum(p_shape).upper
    else:
        a_max = float(contact.a_max(p_shape, q_shape))
        a_bound = float(contact.a_bound(p_shape, q_shape))
    if p_kind == "sphere" and q_kind in ("sphere", None):
        a_n, a_t = sphere_modes(p_shape, q_shape)
        method = EXACT
    else:
        a_n = a_t = a_bound
        method = BOUND
    normal = direction_step(integrator, "normal", pc.kn, pc.cn, a_n, pc.zeta_n)
    shear = direction_step(integrator, "shear", pc.ks, pc.cs, a_t, pc.zeta_s)
    return PairStep(pc, a_max, a_bound, normal, shear, method)
