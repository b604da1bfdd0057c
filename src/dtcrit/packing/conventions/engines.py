"""How each DEM engine builds the contacts whose stiffness sets its step (``dtcrit audit --engine``).

A snapshot's critical step depends on conventions that differ between engines, each checked here
against the engine's own runs (``tests/engines/test_audit_lammps.py``, ``tests/engines/test_engine_yade.py``):

* **which pairs touch** -- LAMMPS and LIGGGHTS count a pair when ``r < R_i + R_j`` strictly
  (``pair_gran_hooke_history.cpp``: ``if (rsq >= radsum*radsum)`` no force); a pair at a gap of
  1e-11 m is not a contact.  YADE's interactions come from its own export, as YADE keeps them.
* **contact arms** -- LAMMPS ``gran/*`` uses the full radius for the slip velocity and
  the torque (``vtr = vt - n x (R_i w_i + R_j w_j)``, ``torque_i -= R_i n x f_t``): arms ``R_i n`` and
  ``-R_j n``.  dtcrit's own scene convention is the middle of the overlap, ``R - delta/2`` (Peng et
  al. 2020, Eqs (1)-(2)).  On a LAMMPS packing at a mean overlap of 3.6 % of R the mid-overlap arm
  gives a step 0.27 % above LAMMPS's threshold (unsafe); the full arm with the pre-load term below
  lands within 4e-5 of it.  LIGGGHTS 3.x (``surface_model_default.h``: ``cri = radi - 0.5 deltan``
  for the slip velocity, and the torque at the contact point) uses ``R - delta/2`` for both, the
  mid-overlap arms.
* **YADE's kinematics** (``Ig2_Sphere_Sphere_ScGeom.cpp``, ``ScGeom.cpp`` ``getIncidentVel`` with
  ``avoidGranularRatcheting`` on, its default; ``ElasticContactLaw.cpp``): the force acts at the
  contact point ``x_1 + (R_1 - delta/2) n``, so the torque arm is ``R - delta/2``, while the slip
  velocity is ``alpha (v_2 - v_1) + R_2 n x w_2 + R_1 n x w_1`` with ``alpha = (R_1 + R_2)/(R_1 + R_2 - delta)``
  (full radius, translation scaled).  The stiffness ``B_torque^T k_s B_velocity`` is then not
  symmetric; its symmetric equivalent, arms ``sqrt((R - delta/2) R / alpha)`` and shear stiffness
  ``alpha k_s``, is exact for two equal spheres and differs for unequal ones by
  ``delta (R_i - R_j)/(2 (R_i + R_j))`` relative in the arms (below 1e-4 at packing overlaps).  On a
  pair at 10 % overlap dtcrit's mid-overlap arm gives a step 2.6 % above YADE's threshold and the full
  radius 1 % below; this equivalent lands within 5e-7 (``tests/engines/test_engine_yade.py``).
* **LAMMPS ``pair_style granular``** -- slip velocity with the full radius, torque with ``R - delta/2``
  (``dtcrit.packing.conventions.granular_style``): the symmetric equivalent has arms ``sqrt(R (R - delta/2))``
  (exact for two equal spheres, like YADE's below, with ``alpha = 1``).
* **pre-load** -- the normal force turns with the centre line, which adds the geometric stiffness
  ``-(F/r)(1 - n n^T)`` of every pre-loaded contact (``dtcrit.packing.operators.assembly``).  It softens the
  packing and is part of what the engines integrate, so it is included for every engine.
* **integrator and dashpots** -- LAMMPS ``fix nve/sphere`` is velocity Verlet with the dashpots on
  the half-step velocity; YADE's ``NewtonIntegrator`` is the leapfrog with the lagged velocity: the
  same amplification polynomial (``dtcrit.packing.solvers.damped_step``).
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from dtcrit.errors import InputError
from dtcrit.physics.contact_laws import reduced

from dtcrit.packing.detection.overlaps import find_sphere_contacts
from dtcrit.packing.model import Contacts, Packing
from dtcrit.packing.normal_arms import NormalArms
from dtcrit.packing.periodic_cell import nearest_image


@dataclass(frozen=True)
class EngineConvention:
    """How one engine builds the contacts whose stiffness sets its step (module docstring).

    Parameters
    ----------
    name : str
        The engine (``lammps``, ``liggghts``, ``yade``).
    integrator : str
        Its integrator (``dtcrit.integrators.schemes`` name, e.g. ``velocity-verlet`` for LAMMPS
        ``fix nve/sphere``, ``leapfrog`` for YADE's ``NewtonIntegrator``).
    arm : str
        Its contact-arm convention (``radius``, ``mid-overlap``, ``yade``, ``granular``; see
        ``with_arms``).
    preload : bool
        Whether the normal force's geometric stiffness ``-(F/r)(1 - n n^T)`` is included.
    contacts : str
        Which pairs it counts as contacts (e.g. ``r < R_i + R_j`` strictly for LAMMPS).
    source : str
        Where the conventions were read (engine source files).
    """

    name: str
    integrator: str
    arm: str  # "radius" | "mid-overlap" | "yade"
    preload: bool
    contacts: str
    source: str


ENGINES: dict[str, EngineConvention] = {
    "lammps": EngineConvention(
        "lammps", "velocity-verlet", "radius", True, "r < R_i + R_j (strict overlap)",
        "LAMMPS GRANULAR: fix nve/sphere, pair_gran_hooke_history.cpp / pair_gran_hertz_history.cpp"),
    "liggghts": EngineConvention(
        "liggghts", "velocity-verlet", "mid-overlap", True, "r < R_i + R_j (strict overlap)",
        "LIGGGHTS: fix nve/sphere, pair gran, surface_model_default.h (arms R - delta/2)"),
    "yade": EngineConvention(
        "yade", "leapfrog", "yade", True, "the interactions YADE exported",
        "YADE: NewtonIntegrator (leapfrog), ScGeom with avoidGranularRatcheting, force at the contact point"),
}


def engine_convention(name: str) -> EngineConvention:
    """The conventions of engine ``name``.

    Parameters
    ----------
    name : str
        The engine, as given to ``--engine``.

    Returns
    -------
    EngineConvention
        Its conventions (InputError naming ``--engine`` when unknown).
    """
    try:
        return ENGINES[name]
    except KeyError:
        raise InputError("--engine", f"unknown engine {name!r}; choose one of {', '.join(ENGINES)}") from None


def with_arms(packing: Packing, contacts: Contacts, arm: str) -> Contacts:
    """Contacts whose arms follow an engine's convention (module docstring).

    Parameters
    ----------
    packing : Packing
        Spheres (radii).
    contacts : Contacts
        The sphere contacts (normals, overlaps ``delta`` [m]).
    arm : str
        ``"radius"`` (``R_i n``, ``-R_j n``: LAMMPS ``gran/*``), ``"mid-overlap"``
        (``R - delta/2``: Peng et al. 2020, Eqs (1)-(2); LIGGGHTS), ``"granular"`` (LAMMPS ``pair_style
        granular``: ``sqrt(R (R - delta/2))``) or ``"yade"`` (the symmetric equivalent of YADE's
        kinematics, ``sqrt((R - delta/2) R / alpha)``; it also scales ``ks`` by ``alpha``, so apply it
        to contacts that already carry their stiffness).

    Returns
    -------
    Contacts
        Copy with ``arm_i``, ``arm_j`` [m] (and for ``"yade"`` ``ks`` [N/m]) replaced.

    Raises
    ------
    InputError
        For an unknown ``arm``, or ``"yade"`` on contacts without shear stiffness.
    """
    r = packing.radii
    if arm == "yade":
        if contacts.ks is None:
            raise InputError("contacts", "YADE's kinematics scale the shear stiffness: set the stiffness first")
        r_i, r_j, delta = r[contacts.i], r[contacts.j], contacts.overlap
        alpha = (r_i + r_j) / (r_i + r_j - delta)
        arm_i = np.sqrt((r_i - 0.5 * delta) * r_i / alpha)
        arm_j = np.sqrt((r_j - 0.5 * delta) * r_j / alpha)
        return replace(_along(contacts, arm_i, arm_j), ks=alpha * contacts.ks)
    if arm == "granular":  # LAMMPS pair granular: slip velocity with R, torque with R - delta/2
        half = 0.5 * contacts.overlap
        arm_i = np.sqrt(r[contacts.i] * (r[contacts.i] - half))
        arm_j = np.sqrt(r[contacts.j] * (r[contacts.j] - half))
        return _along(contacts, arm_i, arm_j)
    if arm == "radius":
        return _along(contacts, r[contacts.i], r[contacts.j])
    if arm == "mid-overlap":
        half = 0.5 * contacts.overlap
        return _along(contacts, r[contacts.i] - half, r[contacts.j] - half)
    raise InputError("arm", f"unknown arm convention {arm!r}")


def _along(contacts: Contacts, length_i: np.ndarray, length_j: np.ndarray) -> Contacts:
    """``contacts`` with arms ``l_i n`` and ``-l_j n``, held as their lengths (``normal_arms``)."""
    return replace(contacts, arm_i=NormalArms(length_i, contacts.normal, 1.0),
                   arm_j=NormalArms(length_j, contacts.normal, -1.0))


def engine_sphere_contacts(packing: Packing, convention: EngineConvention) -> Contacts:
    """The contacts the engine itself computes forces for, with its arms.

    Pairs with a strictly positive overlap (LAMMPS ``if (rsq >= radsum*radsum)`` no force).

    Parameters
    ----------
    packing : Packing
        Spheres.
    convention : EngineConvention
        The engine's conventions (its ``arm`` is applied).

    Returns
    -------
    Contacts
        The overlapping pairs with the engine's arms.
    """
    found = find_sphere_contacts(packing, tolerance=0.0)
    return with_arms(packing, found.subset(found.overlap > 0), convention.arm)


def overlaps_of_pairs(packing: Packing, i: np.ndarray, j: np.ndarray) -> Contacts:
    """Contacts for given pairs (a contact table or the engine's own list), nearest periodic image.

    Normals point from ``i`` to ``j``; overlaps ``max(R_i + R_j - d, 0)`` come from the positions (may
    be zero); arms are the full radii.

    Parameters
    ----------
    packing : Packing
        Spheres (positions, radii, box).
    i : numpy.ndarray
        First particle of each pair (0-based index).
    j : numpy.ndarray
        Second particle of each pair (0-based index).

    Returns
    -------
    Contacts
        One contact per pair.

    Raises
    ------
    InputError
        When two paired particles have coincident centres.
    """
    x = packing.positions
    sep = x[j] - x[i]
    image = np.zeros((len(i), 3), dtype=np.int64)
    box = packing.box
    if box is not None:  # the nearest image, sheared cells included
        image = nearest_image(box, sep)
        sep = sep + box.shift(image)
    d = np.linalg.norm(sep, axis=1)
    if np.any(d <= 0):
        k = int(np.argmax(d <= 0))
        raise InputError("contacts", f"particles {packing.particle_id(i[k])} and {packing.particle_id(j[k])} "
                                     "have coincident centres")
    n = sep / d[:, None]
    r = packing.radii
    overlap = np.maximum(r[i] + r[j] - d, 0.0)
    return Contacts(i=np.asarray(i, np.int64), j=np.asarray(j, np.int64), normal=n,
                    arm_i=NormalArms(r[i], n, 1.0), arm_j=NormalArms(r[j], n, -1.0), overlap=overlap, image=image,
                    radius_eff=reduced(r[i], r[j]))
