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

**Rotational springs** (rolling ``k_r``, twisting ``k_tw``, dashpots ``c_r``, ``c_tw``; the element of
:mod:`dtcrit.symbolic.rotational_modes`, coefficients from ``dtcrit._generated.rotational_modes``):

* spheres: twisting always separates, ``(k_tw, c_tw, 1/I_1 + 1/I_2)`` (wall: ``1/I``).  Rolling
  separates when ``a_sr = R_1/I_1 - R_2/I_2 = 0`` (two equal spheres): ``(k_r, c_r, 1/I_1 + 1/I_2)``,
  ``omega^2 = 2 k_r/I``.  Otherwise (unequal spheres, a wall) shear and rolling form one coupled 2x2
  block, solved exactly by :func:`dtcrit.scenes.coupled_modes.block_step` (mode ``shear-rolling``,
  which replaces the shear mode);
* other shapes (a bound): with ``A6`` the 6x6 coefficient matrix of the element, for any positive
  semi-definite ``[[P, Q], [Q^T, R]]`` ``lambda_max <= lambda_max(P) + lambda_max(R)`` (Cauchy-Schwarz), so
  ``omega^2 <= max(k_n, k_s) A_bound + max(k_r, k_tw) A_rot`` with ``A_rot = 1/I_min,1 + 1/I_min,2``, and
  likewise for the dashpots; every eigenvalue of the element is then that of one mode with those
  ``(k/m, c/m)`` at most (:mod:`dtcrit.scenes.dense`, step 2), stable for the schemes whose one-mode
  stable set is closed downwards (``DENSE_SCHEMES``); mode ``translation+rotation``.
"""
from __future__ import annotations

from dataclasses import dataclass

from dtcrit.integrators.stability import mode_dt
from dtcrit.scenes.model import PairContact

EXACT = "exact modes"
BOUND = "bound (A_bound)"


@dataclass(frozen=True)
class DirectionStep:
    """The step of one contact mode: ``direction`` normal | shear.

    Parameters
    ----------
    direction : str
        ``"normal"``, ``"shear"`` or the name of a rotational or coupled mode.
    k : float
        Spring of the mode [N/m, or N m/rad].
    c : float
        Dashpot of the mode [N s/m, or N m s/rad].
    A : float
        Inverse inertia of the mode [1/kg, or 1/(kg m^2)] (Peng et al. 2020, Eq. (29)).
    zeta : float or None
        The damping ratio of this direction as the scene's convention defines it.
    zeta_mode : float
        ``c A / (2 sqrt(k A))``: the mode's own damping ratio, which decides the step.
    regime : str
        Regime of ``zeta`` (underdamped, ...), or ``"dashpot only"`` / ``"free"``.
    dt : float
        Critical step of the mode [s].
    reason : str
        Which bound of the integrator gives ``dt``, in words.
    """

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
    """The isolated-contact step of one pair of particle types (or a particle type and a wall).

    Parameters
    ----------
    contact : PairContact
        The linearised contact.
    A_max : float or None
        Eq. (26) of Peng et al. 2020 as printed (None against a wall) [1/kg].
    A_bound : float
        Bound on the coefficient matrix's largest eigenvalue [1/kg].
    normal : DirectionStep
        The normal mode.
    shear : DirectionStep
        The shear mode.
    method : str
        ``EXACT`` (sphere modes) or ``BOUND`` (the eigenvalue bound).
    B_sum : float or None
        ``B_i + B_j`` of the rotation-dominant bound (None without ``omega_max``).
    dt_rotation : float or None
        Rotation-dominant step (Eqs. (54), (56)) [s].
    rotational : tuple of DirectionStep
        Rolling, twisting, shear-rolling or translation+rotation modes.
    shear_coupled : bool
        The shear spring is part of a coupled mode (then ``shear`` is not a mode).
    """

    contact: PairContact
    A_max: float | None  # Eq. (26) as printed (None against a wall)
    A_bound: float  # the bound on the coefficient matrix's largest eigenvalue (reported for every pair)
    normal: DirectionStep
    shear: DirectionStep
    method: str  # EXACT | BOUND
    B_sum: float | None = None  # B_i + B_j (None without omega_max)
    dt_rotation: float | None = None
    rotational: tuple[DirectionStep, ...] = ()  # rolling, twisting, shear-rolling or translation+rotation modes
    shear_coupled: bool = False  # the shear spring is part of a coupled mode (then ``shear`` is not a mode)

    @property
    def label(self) -> str:
        """The contact's label, ``"i-j"`` or ``"i-wallN"``."""
        return self.contact.label

    @property
    def modes(self) -> tuple[DirectionStep, ...]:
        """The contact's modes (or bounds): normal, shear (unless coupled), and the rotational ones."""
        return (self.normal,) + (() if self.shear_coupled else (self.shear,)) + self.rotational

    @property
    def governing_direction(self) -> DirectionStep:
        """The mode with the smallest step."""
        return min(self.modes, key=lambda d: d.dt)

    @property
    def translational_direction(self) -> DirectionStep:
        """The governing one of the normal and shear springs' own modes."""
        return self.normal if self.normal.dt <= self.shear.dt else self.shear

    @property
    def dt_translation(self) -> float:
        """The contact's step: its smallest mode, rotational springs included."""
        return self.governing_direction.dt


def _regime(zeta: float | None, mode) -> str:
    if mode.regime in ("dashpot only", "free"):
        return mode.regime
    z = mode.zeta if zeta is None else zeta
    if z == 0:
        return "undamped"
    return "underdamped" if z < 1 else ("critically damped" if z == 1 else "overdamped")


def direction_step(integrator: str, name: str, k: float, c: float, A: float, zeta: float | None) -> DirectionStep:
    """The critical step of one mode ``x'' = -k A x - c A x'`` (``dtcrit.integrators.stability.mode_dt``).

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    name : str
        Name of the mode (``"normal"``, ``"shear"``, ...).
    k : float
        Spring [N/m or N m/rad].
    c : float
        Dashpot [N s/m or N m s/rad].
    A : float
        Inverse inertia of the mode [1/kg or 1/(kg m^2)].
    zeta : float or None
        The damping ratio as the scene's convention defines it (reported, not used for the step).

    Returns
    -------
    DirectionStep
        The mode's step with its regime and reason.
    """
    r = mode_dt(integrator, k, c, A)
    return DirectionStep(name, k, c, A, zeta, r.zeta, _regime(zeta, r), r.dt, r.reason)


def sphere_modes(p_shape, q_shape) -> tuple[float, float]:
    """(A_n, A_t) of two spheres, or of a sphere and a fixed wall (``q_shape`` None), arm = radius.

    ``A_n = 1/m_p + 1/m_q`` and ``A_t = A_n + R_p^2/I_p + R_q^2/I_q`` (Peng et al. 2020, Section 4.3).

    Parameters
    ----------
    p_shape : dtcrit.bodies.smooth.Sphere
        The first sphere.
    q_shape : dtcrit.bodies.smooth.Sphere or None
        The second sphere, or None for a fixed wall.

    Returns
    -------
    tuple of float
        ``(A_n, A_t)`` [1/kg].
    """
    inv = 1.0 / p_shape.mass + (0.0 if q_shape is None else 1.0 / q_shape.mass)
    rot = p_shape.max_arm**2 / p_shape.inertia[0] + (0.0 if q_shape is None else q_shape.max_arm**2 / q_shape.inertia[0])
    return inv, inv + rot


def pair_step(integrator: str, pc: PairContact, p_shape, q_shape, p_kind: str, q_kind: str | None) -> PairStep:
    """The isolated contact ``pc`` between ``p_shape`` and ``q_shape`` (``None``: a fixed wall).

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    pc : PairContact
        The linearised contact.
    p_shape : object
        Body of the first particle (a ``dtcrit.bodies`` object).
    q_shape : object or None
        Body of the second particle, or None for a fixed wall.
    p_kind : str
        Kind of the first particle (``"sphere"``, ``"ellipsoid"``, ...).
    q_kind : str or None
        Kind of the second particle (None for a wall).

    Returns
    -------
    PairStep
        The steps of every mode of the contact.
    """
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
    rotational: tuple[DirectionStep, ...] = ()
    coupled = False
    if pc.rotational:
        rotational, coupled = rotational_modes(integrator, pc, p_shape, q_shape, method == EXACT, a_bound)
    return PairStep(pc, a_max, a_bound, normal, shear, method, rotational=rotational, shear_coupled=coupled)


def rotational_modes(integrator: str, pc: PairContact, p_shape, q_shape, spheres: bool,
                     a_bound: float) -> tuple[tuple[DirectionStep, ...], bool]:
    """The rolling and twisting modes (module docstring) and whether the shear spring is coupled.

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    pc : PairContact
        The linearised contact (its ``kr``, ``ktw``, ``cr``, ``ctw``).
    p_shape : object
        Body of the first particle.
    q_shape : object or None
        Body of the second particle, or None for a fixed wall.
    spheres : bool
        Both bodies are spheres (exact modes); otherwise the block bound with ``a_bound``.
    a_bound : float
        Bound on the translational coefficient matrix's largest eigenvalue [1/kg].

    Returns
    -------
    tuple
        The rotational modes' steps, and whether the shear spring is coupled into one of them.
    """
    from dtcrit._generated import rotational_modes as gen
    from dtcrit.scenes.coupled_modes import block_step

    if not spheres:
        from dtcrit.errors import InputError
        from dtcrit.scenes.dense import DENSE_SCHEMES, dense_reason

        why = dense_reason(integrator)
        if why is not None:
            raise InputError("integrator", f"rotational springs on non-spherical bodies are bounded for "
                             f"{', '.join(DENSE_SCHEMES)} only ({why})")
        a_rot = 1.0 / min(p_shape.inertia) + (0.0 if q_shape is None else 1.0 / min(q_shape.inertia))
        a_tr = a_bound if q_shape is not None else a_bound
        lam_k = max(pc.kn, pc.ks) * a_tr + max(pc.kr, pc.ktw) * a_rot
        lam_c = max(pc.cn, pc.cs) * a_tr + max(pc.cr, pc.ctw) * a_rot
        r = mode_dt(integrator, lam_k, lam_c, 1.0)
        why = (f"bound: omega^2 <= max(kn, ks) A_bound + max(kr, ktw) A_rot = {lam_k:.6g} 1/s^2, "
               f"c/m <= {lam_c:.6g} 1/s, A_rot = {a_rot:.6g} 1/(kg m^2); {r.reason}")
        return (DirectionStep("translation+rotation", lam_k, lam_c, 1.0, None, r.zeta, _regime(None, r), r.dt, why),), False
    if q_shape is None:
        a_ss, a_sr, a_rr, a_tw, a_det = (float(x) for x in gen.wall_shear_rolling_block(p_shape.mass, p_shape.inertia[0],
                                                                                 p_shape.max_arm))
    else:
        a_ss, a_sr, a_rr, a_tw, a_det = (float(x) for x in gen.shear_rolling_block(
            p_shape.mass, p_shape.inertia[0], p_shape.max_arm, q_shape.mass, q_shape.inertia[0], q_shape.max_arm))
    modes, coupled = [], False
    if pc.kr > 0 or pc.cr > 0:
        if a_sr == 0.0:
            modes.append(direction_step(integrator, "rolling", pc.kr, pc.cr, a_rr, None))
        else:
            b = block_step(integrator, a_ss, a_sr, a_rr, a_det, (pc.ks, pc.kr), (pc.cs, pc.cr))
            regime = "undamped" if pc.cs == 0 and pc.cr == 0 else ("underdamped" if b.zeta_mode < 1 else "overdamped")
            why = (f"shear and rolling coupled (a_sr = {a_sr:.6g} 1/(kg m)): largest omega^2 = {b.omega2:.6g} 1/s^2; {b.route}")
            modes.append(DirectionStep("shear-rolling", pc.kr, pc.cr, a_rr, None, b.zeta_mode, regime, b.dt, why))
            coupled = True
    if pc.ktw > 0 or pc.ctw > 0:
        modes.append(direction_step(integrator, "twisting", pc.ktw, pc.ctw, a_tw, None))
    return tuple(modes), coupled
