"""What a plan changes in the physics: added mass per size class, inertial number, collision durations.

* **size classes**: the free bodies in ``bins`` equal-width radius bins, each with its mass, its added
  mass under the plan and under YADE's rule;
* **inertial number** ``I = gamma_dot d sqrt(rho / p)`` (GDR MiDi 2004; quasi-static below about
  ``1e-3``): ``d`` the mean diameter, ``rho`` the solid density ``sum m / sum V``, ``p`` the mean stress
  of the contact forces (Love-Weber, ``p = sum_c F_n (l_c . n_c) / (3 V_box)``, ``l_c`` the branch
  vector between the centres, periodic image included).  The normal forces are the contacts' own (``force_n``) or, without them, the law's at the
  snapshot's overlaps: ``kn delta`` for linear springs, ``(2/3) kn delta`` for Hertz (``F = 4/3 E*
  sqrt(R*) delta^3/2`` and ``k = 2 E* sqrt(R* delta)``).  Scaling the masses by ``f`` scales ``rho``
  by ``f``, so ``I`` grows by ``sqrt(f)``: by ``sqrt(1 + added mass fraction)`` in the mean and
  ``sqrt(max f)`` for the heaviest-scaled body;
* **collision duration** of each contact at the snapshot's stiffness, ``t_c = pi sqrt(m_eff / kn)``
  (``dtcrit.collisions.contact_time``, linear; Hertz at an impact speed from the modulus its ``kn`` and
  overlap give), the shortest today, after density scaling (masses ``f m``) and after stiffness
  reduction (``t_c / sqrt(s)``), the steps per collision at each step, and, at a given speed, the step
  that resolves an impact to 1 % (``dtcrit.collisions.resolution_step``; a damped law as
  ``dtcrit.plan.resolution`` maps it, else not assessed).
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["QUASI_STATIC_LIMIT", "contact_durations", "hertz_durations", "inertial_number", "mean_pressure",
           "resolution_steps", "size_classes", "unbalanced_force_ratio", "EQUILIBRIUM_LIMIT"]

QUASI_STATIC_LIMIT = 1e-3
"""Inertial number below which a granular flow is quasi-static (GDR MiDi 2004, Eur. Phys. J. E 14, 341)."""
EQUILIBRIUM_LIMIT = 1e-2
"""Unbalanced force ratio above which a snapshot is not at rest: it will move and make or break contacts
(YADE scripts wait for ``unbalancedForce() < 0.01`` or less before loading)."""


def size_classes(radii: np.ndarray, masses: np.ndarray, factors: np.ndarray, free: np.ndarray,
                 yade: np.ndarray | None = None, bins: int = 5) -> list[dict]:
    """The free bodies in ``bins`` equal-width radius bins, with their mass and added mass.

    Parameters
    ----------
    radii, masses, factors : numpy.ndarray
        ``(N,)`` radii [m], masses [kg], planned factors.
    free : numpy.ndarray
        ``(N,)`` which bodies count.
    yade : numpy.ndarray or None
        ``(N,)`` YADE's factors, for its added mass per class.
    bins : int
        Number of bins (one when every radius is equal).

    Returns
    -------
    list of dict
        Per bin: ``radius_min``, ``radius_max`` [m], ``count``, ``mass`` [kg], ``added_mass`` [kg],
        ``added_mass_fraction``, ``factor_max``, ``yade_rule_added_mass`` [kg] (None without YADE's factors).
    """
    r, m, f = radii[free], masses[free], factors[free]
    y = None if yade is None else yade[free]
    lo, hi = float(r.min()), float(r.max())
    edges = np.linspace(lo, hi, bins + 1) if hi > lo else np.array([lo, hi])
    which = np.clip(np.searchsorted(edges, r, side="right") - 1, 0, len(edges) - 2)
    out = []
    for b in range(len(edges) - 1):
        sel = which == b
        if not sel.any():
            continue
        added = float(np.sum(m[sel] * (f[sel] - 1.0)))
        out.append({"radius_min": float(edges[b]), "radius_max": float(edges[b + 1]), "count": int(sel.sum()),
                    "mass": float(m[sel].sum()), "added_mass": added, "added_mass_fraction": added / float(m[sel].sum()),
                    "factor_max": float(f[sel].max()),
                    "yade_rule_added_mass": None if y is None else float(np.sum(m[sel] * (y[sel] - 1.0)))})
    return out


def normal_forces(contacts, hertz: bool) -> np.ndarray:
    """Each contact's normal force [N], compressive positive (module docstring).

    Parameters
    ----------
    contacts : dtcrit.packing.contact_set.Contacts
        The contacts (``force_n``, else ``kn`` and ``overlap``).
    hertz : bool
        Whether the law is Hertzian (``F = (2/3) kn delta``).

    Returns
    -------
    numpy.ndarray
        ``(C,)`` forces.
    """
    if contacts.force_n is not None:
        return np.asarray(contacts.force_n, float)
    return (2.0 / 3.0 if hertz else 1.0) * contacts.kn * contacts.overlap


def mean_pressure(packing, contacts, hertz: bool, free: np.ndarray) -> float | None:
    """The Love-Weber mean stress ``sum_c F_n (l_c . n_c) / (3 V)`` [Pa] of the box; None without a box.

    Parameters
    ----------
    packing : dtcrit.packing.model.Packing
        The bodies (its ``box`` gives ``V``).
    contacts : dtcrit.packing.contact_set.Contacts
        The contacts (arms, normals, forces).
    hertz : bool
        Whether the law is Hertzian.
    free : numpy.ndarray
        ``(N,)`` free bodies: contacts with a fixed body (wall) are left out.

    Returns
    -------
    float or None
        The mean stress [Pa], None without a box or a positive one.
    """
    if packing.box is None:
        return None
    volume = abs(float(np.linalg.det(packing.box.matrix)))
    both = free[contacts.i] & free[contacts.j]
    x = packing.positions
    branch = np.einsum("ck,ck->c", x[contacts.j] + packing.box.shift(contacts.image) - x[contacts.i], contacts.normal)
    p = float(np.sum((normal_forces(contacts, hertz) * branch)[both])) / (3.0 * volume)
    return p if p > 0 and math.isfinite(p) else None


def inertial_number(strain_rate: float, packing, free: np.ndarray, pressure: float) -> float:
    """``I = gamma_dot d sqrt(rho / p)`` with the mean diameter and the solid density (module docstring).

    Parameters
    ----------
    strain_rate : float
        Shear strain rate [1/s].
    packing : dtcrit.packing.model.Packing
        The bodies (radii, masses).
    free : numpy.ndarray
        ``(N,)`` which bodies count.
    pressure : float
        Mean stress [Pa].

    Returns
    -------
    float
        The inertial number.
    """
    r, m = packing.radii[free], packing.masses[free]
    rho = float(m.sum() / np.sum(4.0 / 3.0 * math.pi * r**3))
    return strain_rate * 2.0 * float(r.mean()) * math.sqrt(rho / pressure)


def hertz_durations(packing, contacts, velocity: float, factors: np.ndarray | None = None) -> np.ndarray:
    """Each contact's Hertz duration at the impact speed ``velocity`` [s] (``dtcrit.collisions.contact_time``).

    ``E*`` from the snapshot's tangent stiffness ``kn = 2 E* sqrt(R* delta)`` at its overlap, ``R*`` the
    contact's effective radius; ``t_c ~ (m*^2 / (R* E*^2 v))^(1/5)``.

    Parameters
    ----------
    packing : dtcrit.packing.model.Packing
        The bodies.
    contacts : dtcrit.packing.contact_set.Contacts
        The contacts (``kn``, ``overlap``, ``radius_eff``).
    velocity : float
        Relative normal impact speed [m/s].
    factors : numpy.ndarray or None
        ``(N,)`` mass factors.

    Returns
    -------
    numpy.ndarray
        ``(C,)`` durations (``inf`` where ``E*`` is not defined: no overlap or no stiffness).
    """
    from dtcrit.collisions import contact_time

    m = packing.masses if factors is None else packing.masses * factors
    mi, mj = m[contacts.i], m[contacts.j]
    m_eff = mi * mj / (mi + mj)
    out = np.full(contacts.count, np.inf)
    for c in range(contacts.count):
        r, d, k = contacts.radius_eff[c], contacts.overlap[c], contacts.kn[c]
        if r > 0 and d > 0 and k > 0 and velocity > 0:
            out[c] = contact_time("hertz", m_eff=float(m_eff[c]), E_eff=float(k / (2.0 * math.sqrt(r * d))),
                                  R_eff=float(r), v_impact=float(velocity))
    return out


def contact_durations(packing, contacts, factors: np.ndarray | None = None) -> np.ndarray:
    """Each contact's elastic duration ``pi sqrt(m_eff / kn)`` [s] at the snapshot's stiffness.

    Parameters
    ----------
    packing : dtcrit.packing.model.Packing
        The bodies.
    contacts : dtcrit.packing.contact_set.Contacts
        The contacts with ``kn``.
    factors : numpy.ndarray or None
        ``(N,)`` mass factors (None: unscaled).

    Returns
    -------
    numpy.ndarray
        ``(C,)`` durations (``inf`` for a contact without normal stiffness).
    """
    m = packing.masses if factors is None else packing.masses * factors
    mi, mj = m[contacts.i], m[contacts.j]
    m_eff = np.where(contacts.i == contacts.j, mi / 2.0, mi * mj / (mi + mj))
    with np.errstate(divide="ignore"):
        return math.pi * np.sqrt(m_eff / contacts.kn)


def resolution_steps(engine: str, integrator: str, hertz: bool, damping: str = "none", restitution: float = 1.0) -> float:
    """Steps per collision that resolve an impact's restitution and peak overlap to 1 %.

    ``dtcrit.collisions.resolution_step`` of the engine's scheme (``damping='none'``, restitution 1:
    undamped; ``dtcrit.plan.resolution`` maps a damped snapshot's law to its model and restitution).

    Parameters
    ----------
    engine : str
        The engine (``lammps``, ``liggghts``, ``yade``).
    integrator : str
        Its integrator (used when the engine's name is not a scheme ``dtcrit.collisions`` knows).
    hertz : bool
        Hertz (else linear) normal law.
    damping : str
        A key of ``dtcrit.physics.collision_laws.DAMPING_MODELS``.
    restitution : float
        The restitution in (0, 1] (as ``resolution_step`` takes it).

    Returns
    -------
    float
        ``N_res``: the step must be at most ``t_c / N_res``.
    """
    from dtcrit.collisions import resolution_step
    from dtcrit.errors import InputError

    normal = "hertz" if hertz else "hooke"
    try:
        return float(resolution_step(engine=engine, normal=normal, damping=damping,
                                     restitution=restitution).steps_per_collision)
    except InputError:
        return float(resolution_step(engine=integrator, normal=normal, damping=damping,
                                     restitution=restitution).steps_per_collision)


def unbalanced_force_ratio(packing, contacts, hertz: bool, free: np.ndarray) -> float | None:
    """Mean net normal contact force on the free bodies over the mean contact force (YADE's ``unbalancedForce``).

    YADE's ``utils.unbalancedForce``: the mean of the summed force on the bodies over the mean force of
    the interactions; here of the normal forces (``normal_forces``; a dump carries no tangential history,
    and a LAMMPS run from it starts with none).

    Parameters
    ----------
    packing : dtcrit.packing.model.Packing
        The bodies.
    contacts : dtcrit.packing.contact_set.Contacts
        The contacts (normals from ``i`` to ``j``, compressive forces positive).
    hertz : bool
        Whether the law is Hertzian.
    free : numpy.ndarray
        ``(N,)`` free bodies (walls are left out of the mean).

    Returns
    -------
    float or None
        The ratio (0: every free body at rest), None without a contact force.
    """
    f = normal_forces(contacts, hertz)
    mean = float(np.abs(f).mean()) if f.size else 0.0
    if not mean > 0:
        return None
    net = np.zeros((packing.n, 3))
    np.add.at(net, contacts.i, -f[:, None] * contacts.normal)
    np.add.at(net, contacts.j, f[:, None] * contacts.normal)
    return float(np.linalg.norm(net[free], axis=1).mean() / mean)
