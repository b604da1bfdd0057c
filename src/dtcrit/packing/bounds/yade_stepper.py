"""YADE's GlobalStiffnessTimeStepper as it runs: the per-body steps and the ``O.dt`` it sets.

Read in YADE's ``pkg/dem/GlobalStiffnessTimeStepper.cpp`` (``computeStiffnesses``,
``findTimeStepFromBody``, ``computeTimeStep``; defaults in ``GlobalStiffnessTimeStepper.hpp``) and
checked against YADE 2023.02a's own ``O.dt`` in ``tests/engines/test_engine_yade_gsts.py``:

* **per contact** (an interaction whose normal force is not zero: ``if (fn==0) continue``), with
  ``n`` the contact normal (global axes), ``kn``, ``ks`` its springs, ``R_1``, ``R_2`` the two
  spheres' own radii (``geom->refR1``, ``refR2``) and ``(k_0, k_1, k_2) = getRotStiffness()``
  (``(ktw, kr, kr)`` for the physics derived from ``RotStiffFrictPhys`` -- CohFrictPhys, MindlinPhys,
  ... -- whether or not their moment law acts; zero for the others), each sphere ``s`` gets the
  diagonals, along the *global* axes ``a``,

  ``K_a += (kn - ks) n_a^2 + ks``,
  ``K_rot,a += ks (1 - n_a^2) R_s^2 + (k_0 - k_1) n_a^2 + k_1``;

* **clumps**: the members' sums are added to their clump (``stiffness += stiffnesses[member]``), so
  a member's contact turns its clump about an arm of the *member's radius*, not of its distance to
  the clump's centre, and the global-axis sums meet the clump's *body-frame* principal moments;
* **per body** (dynamic, not a clump member, ``K`` not zero):
  ``dt_b = 1.41044 x safety x sqrt(min(m / max_a K_a, min_a I_a / K_rot,a))``, a zero ``K_rot,a``
  leaving its axis out;
* ``O.dt = min(min_b dt_b, maxDt, 1.05 previousDt)``: on its first call (``previousDt`` and ``maxDt``
  at their default ``MAX_REAL``) the minimum over the bodies.  With no body to compute
  (``computedSomething`` false) YADE keeps its ``defaultDt`` (``safety x PWaveTimeStep``), which
  needs the material's Young's modulus: :func:`yade_stepper` then has no step.

The defaults are modelled: ``timestepSafetyCoefficient`` 0.8
(:data:`dtcrit.physics.rules_of_thumb.YADE_GSTS_SAFETY`), ``densityScaling`` off (with it, ``O.dt``
is ``targetDt`` and the masses are scaled instead), ``viscEl`` off (see :func:`viscous_steps` for its
viscous term).  Plain NumPy.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from dtcrit.physics import rules_of_thumb as rot

if TYPE_CHECKING:
    from dtcrit.packing.model import Contacts, Packing

__all__ = ["StepperInput", "StepperStep", "contact_diagonals", "body_diagonals", "squared_periods",
           "yade_stepper", "single_contact_step", "viscous_steps", "from_contacts", "estimator_rows", "ROTATIONAL_PHYSICS"]

ROTATIONAL_PHYSICS = frozenset({"RotStiffFrictPhys", "CohFrictPhys", "InelastCohFrictPhys", "MindlinPhys",
                                "MindlinPhysCDM", "MindlinCapillaryPhys", "CapillaryMindlinPhysDelaunay"})
"""YADE 2023.02a's physics whose ``getRotStiffness()`` is ``(ktw, kr, kr)`` (``RotStiffFrictPhys`` and the
classes derived from it); every other ``NormShearPhys`` returns zero (``NormPhys::getRotStiffness``)."""


@dataclass(frozen=True)
class StepperInput:
    """What GlobalStiffnessTimeStepper reads of a scene: bodies, spheres and contacts.

    Parameters
    ----------
    masses : numpy.ndarray
        ``(N,)`` body masses [kg] (``state->mass``).
    inertia : numpy.ndarray
        ``(N, 3)`` principal moments in each body's frame [kg m^2] (``state->inertia``).
    dynamic : numpy.ndarray
        ``(N,)`` whether each body is dynamic (``isDynamic()``; the others are skipped).
    sphere_body : numpy.ndarray
        ``(S,)`` the body of each sphere: itself for a free sphere, its clump for a member.
    sphere1, sphere2 : numpy.ndarray
        ``(C,)`` the two spheres of each contact (indices into ``sphere_body``).
    normal : numpy.ndarray
        ``(C, 3)`` contact normals in global axes (``geom->normal``).
    kn, ks : numpy.ndarray
        ``(C,)`` normal and shear springs [N/m] (``phys->kn``, ``phys->ks``).
    rot_stiffness : numpy.ndarray
        ``(C, 3)`` ``getRotStiffness()`` = ``(ktw, kr, kr)`` [N m/rad], zero without moment springs.
    radius1, radius2 : numpy.ndarray
        ``(C,)`` the spheres' radii [m] (``geom->refR1``, ``refR2``).
    loaded : numpy.ndarray
        ``(C,)`` whether the normal force is not zero (the others are skipped).
    body_id : tuple of int
        The engine id of each body, for messages.
    missing : str or None
        Why the stepper's step cannot be computed from this input (None: it can).
    """

    masses: np.ndarray
    inertia: np.ndarray
    dynamic: np.ndarray
    sphere_body: np.ndarray
    sphere1: np.ndarray
    sphere2: np.ndarray
    normal: np.ndarray
    kn: np.ndarray
    ks: np.ndarray
    rot_stiffness: np.ndarray
    radius1: np.ndarray
    radius2: np.ndarray
    loaded: np.ndarray
    body_id: tuple[int, ...]
    missing: str | None = None


@dataclass(frozen=True)
class StepperStep:
    """The step GlobalStiffnessTimeStepper sets and where it comes from.

    Parameters
    ----------
    dt : float or None
        ``O.dt`` after its first call [s]; None when no body could be computed (``missing`` says why).
    safety : float
        ``timestepSafetyCoefficient``.
    body : int or None
        Index of the body that sets it.
    term : str
        ``"translation"`` or ``"rotation about body axis x|y|z"``.
    per_body : numpy.ndarray
        ``(N,)`` each body's step [s] at this safety (``inf``: not computed).
    missing : str or None
        Why there is no step.
    """

    dt: float | None
    safety: float
    body: int | None
    term: str
    per_body: np.ndarray
    missing: str | None = None


def contact_diagonals(normal, kn, ks, rot_stiffness, radius) -> tuple[np.ndarray, np.ndarray]:
    """One side's diagonal stiffnesses of each contact along the global axes (``computeStiffnesses``).

    Parameters
    ----------
    normal : array_like
        ``(C, 3)`` unit normals.
    kn, ks : array_like
        ``(C,)`` normal and shear springs [N/m].
    rot_stiffness : array_like
        ``(C, 3)`` ``(ktw, kr, kr)`` [N m/rad].
    radius : array_like
        ``(C,)`` this side's sphere radius [m] (``refR``), the arm of the shear spring.

    Returns
    -------
    tuple of numpy.ndarray
        ``(K, K_rot)``, each ``(C, 3)``: ``(kn - ks) n_a^2 + ks`` and
        ``ks (n_b^2 + n_c^2) R^2 + (k_0 - k_1) n_a^2 + k_1``.
    """
    n2 = np.asarray(normal, float) ** 2
    kn, ks = np.asarray(kn, float)[:, None], np.asarray(ks, float)[:, None]
    krot = np.asarray(rot_stiffness, float)
    k = n2 * (kn - ks) + ks
    across = np.stack([n2[:, 1] + n2[:, 2], n2[:, 0] + n2[:, 2], n2[:, 0] + n2[:, 1]], axis=1) * ks
    moment = (krot[:, :1] - krot[:, 1:2]) * n2 + krot[:, 1:2]
    return k, across * np.asarray(radius, float)[:, None] ** 2 + moment


def body_diagonals(inp: StepperInput) -> tuple[np.ndarray, np.ndarray]:
    """The summed diagonals of every body: each loaded contact on its two spheres, members into clumps.

    Parameters
    ----------
    inp : StepperInput
        The scene.

    Returns
    -------
    tuple of numpy.ndarray
        ``(K, K_rot)``, each ``(N, 3)`` [N/m, N m/rad].
    """
    spheres = inp.sphere_body.shape[0]
    k_s, r_s = np.zeros((spheres, 3)), np.zeros((spheres, 3))
    on = np.flatnonzero(inp.loaded)
    args = (inp.normal[on], inp.kn[on], inp.ks[on], inp.rot_stiffness[on])
    for side, radius in ((inp.sphere1[on], inp.radius1[on]), (inp.sphere2[on], inp.radius2[on])):
        k, kr = contact_diagonals(*args, radius)
        np.add.at(k_s, side, k)
        np.add.at(r_s, side, kr)
    n = inp.masses.shape[0]
    k_b, r_b = np.zeros((n, 3)), np.zeros((n, 3))
    np.add.at(k_b, inp.sphere_body, k_s)
    np.add.at(r_b, inp.sphere_body, r_s)
    return k_b, r_b


def squared_periods(masses, inertia, k, k_rot) -> tuple[np.ndarray, np.ndarray]:
    """``m / max_a K_a`` and ``I_a / K_rot,a`` per body (``findTimeStepFromBody``; ``inf`` for a zero stiffness).

    Parameters
    ----------
    masses : array_like
        ``(N,)`` masses [kg].
    inertia : array_like
        ``(N, 3)`` body-frame principal moments [kg m^2].
    k, k_rot : array_like
        ``(N, 3)`` global-axis diagonal stiffnesses [N/m, N m/rad].

    Returns
    -------
    tuple of numpy.ndarray
        ``(N,)`` translational and ``(N, 3)`` rotational squared periods [s^2].
    """
    k, k_rot = np.asarray(k, float), np.asarray(k_rot, float)
    top = k.max(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(top != 0, np.asarray(masses, float) / np.where(top != 0, top, 1.0), np.inf)
        r = np.where(k_rot != 0, np.asarray(inertia, float) / np.where(k_rot != 0, k_rot, 1.0), np.inf)
    return t, r


def yade_stepper(inp: StepperInput, safety: float = rot.YADE_GSTS_SAFETY) -> StepperStep:
    """The ``O.dt`` GlobalStiffnessTimeStepper sets on its first call, and the body that sets it.

    Parameters
    ----------
    inp : StepperInput
        The scene (:func:`from_contacts`, or ``dtcrit.packing.bounds.yade_stepper_export``).
    safety : float
        ``timestepSafetyCoefficient`` (YADE's default 0.8).

    Returns
    -------
    StepperStep
        ``1.41044 x safety x sqrt(min over bodies)`` (module docstring), or no step with the reason.

    Examples
    --------
    >>> import numpy as np
    >>> inp = StepperInput(np.ones(2), np.full((2, 3), 0.4), np.ones(2, bool), np.arange(2), np.array([0]),
    ...                    np.array([1]), np.array([[1.0, 0, 0]]), np.array([1.0]), np.array([0.5]),
    ...                    np.zeros((1, 3)), np.ones(1), np.ones(1), np.ones(1, bool), (1, 2))
    >>> round(yade_stepper(inp).dt / (1.41044 * 0.8 * math.sqrt(0.4 / 0.5)), 12)
    1.0
    """
    n = inp.masses.shape[0]
    if inp.missing is not None:
        return StepperStep(None, safety, None, "", np.full(n, np.inf), inp.missing)
    k, k_rot = body_diagonals(inp)
    t, r = squared_periods(inp.masses, inp.inertia, k, k_rot)
    both = np.column_stack([t, r])
    computed = inp.dynamic & np.any(k != 0, axis=1)
    per_body = np.full(n, np.inf)
    if not computed.any():
        why = ("no dynamic body has a contact with a normal force: YADE keeps its defaultDt "
               "(timestepSafetyCoefficient x PWaveTimeStep)")
        return StepperStep(None, safety, None, "", per_body, why)
    per_body[computed] = [rot.YADE_GSTS_CONSTANT * safety * math.sqrt(v) for v in both[computed].min(axis=1)]
    body = int(np.argmin(per_body))
    col = int(np.argmin(both[body]))
    term = "translation" if col == 0 else f"rotation about body axis {'xyz'[col - 1]}"
    return StepperStep(float(per_body[body]), safety, body, term, per_body)


def single_contact_step(mass: float, inertia, kn: float, ks: float, kr: float, ktw: float, radius: float,
                        safety: float = rot.YADE_GSTS_SAFETY) -> float:
    """The stepper's step of a body with one contact, its normal along the worst direction.

    ``dtcrit step`` scenes give no contact directions.  The body's squared periods are
    ``m / max_a K_a`` and ``I_a / K_rot,a``, each ``K`` linear in the ``n_a^2`` (which sum to 1), so
    the smallest over all directions is at a normal along an axis: the smaller of ``m / max(kn, ks)``
    and ``I_min / max(ks R^2 + kr, ktw)``, found here with :func:`contact_diagonals` on the three axes.

    Parameters
    ----------
    mass : float
        Body mass [kg].
    inertia : array_like
        Its three principal moments [kg m^2].
    kn, ks : float
        Normal and shear springs [N/m].
    kr, ktw : float
        Rolling and twisting springs [N m/rad] (``getRotStiffness`` ``(ktw, kr, kr)``).
    radius : float
        The touching sphere's radius [m] (for a clump, its member's).
    safety : float
        ``timestepSafetyCoefficient``.

    Returns
    -------
    float
        ``1.41044 x safety x sqrt(min over the three normals)`` [s].
    """
    axes = np.eye(3)
    k, k_rot = contact_diagonals(axes, np.full(3, kn), np.full(3, ks), np.tile([ktw, kr, kr], (3, 1)), np.full(3, radius))
    t, r = squared_periods(np.full(3, mass), np.tile(np.asarray(inertia, float), (3, 1)), k, k_rot)
    return rot.YADE_GSTS_CONSTANT * safety * math.sqrt(float(min(t.min(), r.min())))


def viscous_steps(masses, inertia, c, c_rot, safety: float = rot.YADE_GSTS_SAFETY) -> np.ndarray:
    """The ``viscEl`` term (off by default): ``2 x safety x min(m / max_a C_a, min_a I_a / C_rot,a)``.

    With ``viscEl`` YADE sums the dashpots of ViscElPhys like the springs (``cn``, ``cs`` for
    ``kn``, ``ks``, no moment term) and takes per body the smaller of this and the elastic step
    (``findTimeStepFromBody``: no square root, factor 2).

    Parameters
    ----------
    masses, inertia : array_like
        ``(N,)`` masses [kg], ``(N, 3)`` body-frame principal moments [kg m^2].
    c, c_rot : array_like
        ``(N, 3)`` summed global-axis diagonals of the dashpots [N s/m, N m s/rad].
    safety : float
        ``timestepSafetyCoefficient``.

    Returns
    -------
    numpy.ndarray
        ``(N,)`` the viscous steps [s] (``inf`` where every dashpot sum is zero).
    """
    t, r = squared_periods(masses, inertia, c, c_rot)
    return 2.0 * safety * np.minimum(t, r.min(axis=1))


def from_contacts(packing: Packing, contacts: Contacts) -> StepperInput:
    """The stepper's input from a sphere packing's contacts (a dump, a table, any non-YADE source).

    Every particle is a dynamic sphere of its own radius; a contact's springs are the ones it
    carries (``kr``, ``ktw`` as YADE's rotational physics would hold them); a contact whose normal
    force is given as exactly zero is skipped, as YADE skips it.  A packing of other bodies
    (orientations or shapes) gets ``missing``: the stepper reads sphere contacts, and the arms of a
    clump's members are only in a YADE export.

    Parameters
    ----------
    packing : Packing
        The packing.
    contacts : Contacts
        Its contacts with ``kn``, ``ks``.

    Returns
    -------
    StepperInput
        The input of :func:`yade_stepper`.
    """
    n, c = packing.n, contacts.count
    ids = tuple(packing.particle_id(p) for p in range(n))
    missing = None
    if packing.shapes is not None or packing.orientations is not None:
        missing = ("needs the member spheres of each body (the YADE export of a clump scene): "
                   "YADE's stepper reads sphere contacts")
    zero = np.zeros(c)
    kr = zero if contacts.kr is None else contacts.kr
    ktw = zero if contacts.ktw is None else contacts.ktw
    loaded = np.ones(c, bool) if contacts.force_n is None else contacts.force_n != 0
    return StepperInput(
        masses=packing.masses, inertia=packing.inertia, dynamic=np.ones(n, bool), sphere_body=np.arange(n),
        sphere1=contacts.i, sphere2=contacts.j, normal=contacts.normal,
        kn=zero if contacts.kn is None else contacts.kn, ks=zero if contacts.ks is None else contacts.ks,
        rot_stiffness=np.column_stack([ktw, kr, kr]), radius1=packing.radii[contacts.i],
        radius2=packing.radii[contacts.j], loaded=loaded, body_id=ids, missing=missing)


def estimator_rows(inp: StepperInput) -> list[tuple[str, float | None, str, str]]:
    """The audit's rows ``yade_gsts`` (YADE's default safety) and ``yade_gsts_unscaled`` (safety 1).

    Parameters
    ----------
    inp : StepperInput
        The scene.

    Returns
    -------
    list of tuple
        ``(name, dt or None, kind, detail)`` for each row; ``dt`` None with the reason as detail.
    """
    rows: list[tuple[str, float | None, str, str]] = []
    for name, safety in (("yade_gsts", rot.YADE_GSTS_SAFETY), ("yade_gsts_unscaled", 1.0)):
        step = yade_stepper(inp, safety)
        if step.dt is None or step.body is None:
            rows.append((name, None, "heuristic", f"YADE GlobalStiffnessTimeStepper: {step.missing}"))
            continue
        rows.append((name, step.dt, "heuristic",
                     f"YADE GlobalStiffnessTimeStepper as it runs (O.dt of its first call): {rot.YADE_GSTS_CONSTANT} x "
                     f"safety {safety:g} x sqrt(min(m/max K_a, I_a/K_rot,a)) of body {inp.body_id[step.body]}, "
                     f"{step.term} (sphere radius as arm, global-axis sums against body-frame moments)"))
    return rows
