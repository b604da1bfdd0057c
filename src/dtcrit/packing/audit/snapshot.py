"""``dtcrit audit``: the critical step of a simulation snapshot as its engine integrates it.

Input: a packing (``Packing``, with the engine's own particle ids) and its contacts carrying every
per-contact term the engine applies (springs ``kn``, ``ks``, ``kr``, ``ktw``; dashpots ``cn``, ``cs``;
the normal force of the pre-load), built with the engine's conventions (``dtcrit.packing.conventions.engines``).

* ``dt_crit`` -- the exact critical step of the whole packing for the engine's integrator: with
  dashpots the root of ``lambda_max(2h C~ + h^2 K~) = 4`` (``dtcrit.packing.solvers.damped_step``, the damping
  matrix assembled contact by contact, not a modal ratio); without, ``2/omega_max``.
* ``dt_safe`` -- a rigorous lower bound on it: the block-diagonal or Gershgorin bound (whichever is
  larger) of the springs, which bounds the packing with its pre-load too (the pre-load term is
  negative semi-definite), combined with the Gershgorin bound of the dashpots.
* ``limiting`` -- the particles the governing mode sits on (largest share of the mode's kinetic
  energy), by the engine's ids, when the ``LIMITING_COUNT`` largest hold at least ``LOCALISED_SHARE`` of
  it; a mode spread wider is described by its participation ratio ``(sum e_p)^2/(N sum e_p^2)`` (1: every
  particle alike; 1/N: one particle) instead of ids.
* each estimator row says what it bounds: the block-diagonal and Gershgorin rows bound the *undamped*
  step ``2/omega_max`` from below (with dashpots ``dt_crit`` is lower, so they may exceed it).
* the codes' own estimators beside it, with their real constants: YADE's GlobalStiffnessTimeStepper
  as it runs (the ``O.dt`` it sets at its default safety 0.8 and at 1, clumps included:
  ``dtcrit.packing.bounds.yade_stepper``),
  the undamped per-body bounds, and the LAMMPS-docs rule of a fraction of the collision time
  ``pi sqrt(m_eff / k_n)`` (1/50 in the LAMMPS granular examples), and with a material (Young's
  modulus, Poisson's ratio) the Rayleigh time and its 20 % and 40 % (EDEM's guidance; LIGGGHTS warns
  when a step exceeds the fraction of it its input sets).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

import dtcrit.packing.bounds.estimates as est
from dtcrit.errors import InputError
from dtcrit.physics import rules_of_thumb as rot
from dtcrit.physics.contact_laws import reduced
from dtcrit.physics.estimate import Estimate, RatedEstimate

from dtcrit.packing.audit.mode_character import ModeCharacter, mode_character, participation_ratio, particle_energies
from dtcrit.packing.bounds.yade_stepper import StepperInput, estimator_rows, from_contacts
from dtcrit.packing.operators.assembly import mass_diagonal, scale_symmetric, stiffness_matrix
from dtcrit.packing.solvers.damped_step import damped_critical_dt
from dtcrit.packing.conventions.engines import EngineConvention
from dtcrit.packing.model import Contacts, Packing

COLLISION_FRACTION = 1.0 / rot.COLLISION_TIME_DIVISOR
"""The fraction of the collision time the LAMMPS granular examples step with (1/50)."""
LIMITING_COUNT = 6
LOCALISED_SHARE = 0.5
"""The ids are named when the ``LIMITING_COUNT`` particles with the most energy hold at least this share of
the governing mode's energy; below it the mode is spread out and its participation ratio is given."""


@dataclass
class AuditReport:
    """Everything ``dtcrit audit`` prints (module docstring); steps in seconds.

    Parameters
    ----------
    source : str
        Where the snapshot came from (file or engine run).
    engine : str
        The engine whose conventions were applied (``EngineConvention.name``).
    engine_source : str
        Where those conventions were read (engine source files).
    integrator : str
        The integrator whose critical step ``dt_crit`` is.
    law : str
        The contact law in words.
    n_particles : int
        Number of particles.
    n_contacts : int
        Number of contacts.
    coordination_mean : float
        Mean contacts per particle.
    damped : bool
        Whether the contacts carry dashpots.
    preload : bool
        Whether pre-loaded contacts' geometric stiffness is included.
    dt_crit : float
        Exact critical step of the packing for ``integrator`` [s] (``damped_critical_dt``).
    dt_safe : float
        Rigorous lower bound on ``dt_crit`` [s].
    dt_undamped : float
        ``2/omega_max`` of the springs alone [s].
    method : str
        How ``dt_crit`` was found.
    limiting : list of int
        Engine ids of the particles the governing mode sits on; empty when the mode is spread out.
    limiting_share : float
        Share of the governing mode's kinetic energy held by the ``LIMITING_COUNT`` most energetic
        particles.
    dt_user : float or None
        The step the user runs with [s], if given.
    estimators : list of RatedEstimate
        The codes' own estimators and the per-body bounds, rated against ``dt_crit``.
    notes : list of str
        Remarks printed with the report.
    participation : float
        Participation ratio ``(sum e_p)^2 / (N sum e_p^2)`` of the governing mode's particle energies
        (1: every particle alike; 1/N: one particle).
    governing_mode : ModeCharacter or None
        Which springs hold the governing mode's energy (``dtcrit.packing.audit.mode_character``);
        ``None`` on the spectral-radius route (no mode vector).
    local_damping : dict or None
        Local (Cundall) damping applied to ``dt_crit`` (``alpha``, ``law``, ``status``, ...;
        :mod:`dtcrit.packing.audit.local_damping`), None without it.
    """

    source: str
    engine: str
    engine_source: str
    integrator: str
    law: str
    n_particles: int
    n_contacts: int
    coordination_mean: float
    damped: bool
    preload: bool
    dt_crit: float
    dt_safe: float
    dt_undamped: float
    method: str
    limiting: list[int]  # empty when the mode is spread out (see participation)
    limiting_share: float  # the share of the LIMITING_COUNT particles with the most energy
    dt_user: float | None
    estimators: list[RatedEstimate] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    participation: float = math.nan  # (sum e_p)^2 / (N sum e_p^2) of the governing mode's particle energies
    governing_mode: ModeCharacter | None = None
    local_damping: dict | None = None  # packing.audit.local_damping: alpha, law, status

    @property
    def participating(self) -> float:
        """About how many particles share the governing mode's energy, ``N x participation``."""
        return self.participation * self.n_particles

    @property
    def ratio(self) -> float | None:
        """``dt_user / dt_crit``, None without a user step."""
        return None if self.dt_user is None else self.dt_user / self.dt_crit


def _check_terms(contacts: Contacts) -> None:
    if contacts.kn is None or contacts.ks is None:
        raise InputError("contacts", "the contacts carry no stiffness (give --pair-style or a --contacts table)")
    if contacts.count == 0:
        raise InputError("contacts", "no two particles touch: no contact limits the step")
    if not np.any(contacts.kn > 0) and not np.any(contacts.ks > 0):
        raise InputError("contacts", "every contact has zero stiffness: no vibrating mode, no critical step")


def _limiting(packing: Packing, vector: np.ndarray | None) -> tuple[list[int], float, float]:
    """``(ids, share of the top LIMITING_COUNT, participation ratio)``; no ids when the mode is spread out."""
    if vector is None:
        return [], 0.0, math.nan
    share = particle_energies(vector)
    total = share.sum()
    if total <= 0:
        return [], 0.0, math.nan
    top = np.argsort(-share, kind="stable")[:LIMITING_COUNT]
    held = float(share[top].sum() / total)
    participation = participation_ratio(share)
    ids = [packing.particle_id(p) for p in top] if held >= LOCALISED_SHARE else []
    return ids, held, participation


def _rayleigh_rows(packing: Packing, material) -> list[tuple]:
    """Rayleigh time of the smallest particle (:func:`dtcrit.physics.rules_of_thumb.rayleigh_time`) and the
    fractions the codes step with: EDEM's 20-40 % guidance, LIGGGHTS' check/timestep/gran warning (the
    fraction its input sets, 0.1-0.2 in its examples).
    """
    if material is None:
        return []
    youngs, nu = material
    rho = packing.masses / ((4.0 / 3.0) * np.pi * packing.radii**3)
    t_r = rot.rayleigh_time(packing.radii, rho, youngs, nu)
    p = int(np.argmin(t_r))
    where = f"particle {packing.particle_id(p)}, E = {youngs:.6g} Pa, nu = {nu:.6g}"
    return [("rayleigh_time", float(t_r[p]), "duration, not a step", f"Rayleigh time T_R of {where}"),
            ("rayleigh_20", 0.2 * float(t_r[p]), "rule of thumb", "20 % of T_R (EDEM's lower guidance; LIGGGHTS warns above its input fraction)"),
            ("rayleigh_40", 0.4 * float(t_r[p]), "rule of thumb", "40 % of T_R (EDEM's upper guidance)")]


def _estimators(packing: Packing, springs: Contacts, dt_crit: float, material=None,
                damped: bool = False, stepper: StepperInput | None = None) -> list[RatedEstimate]:
    md = mass_diagonal(packing)
    a = scale_symmetric(stiffness_matrix(packing, springs), md, inplace=True)
    rows = estimator_rows(stepper if stepper is not None else from_contacts(packing, springs))
    bounds = ("lower bound on the undamped step 2/omega_max (the dashpots lower dt_crit)" if damped
              else "lower bound on dt_crit (= 2/omega_max, no dashpots)")
    for e in (est.block_diagonal(a, packing.particle_id), est.gershgorin(a, md)):
        rows.append((e.name, e.dt, bounds, e.detail))
    assert springs.kn is not None and springs.ks is not None  # checked by _check_terms
    stiff = np.maximum(springs.kn, springs.ks)
    m = packing.masses
    t_c = rot.collision_time(reduced(m[springs.i], m[springs.j]), stiff)
    c = int(np.argmin(t_c))
    rows.append(("collision_time_fraction", float(t_c[c]) * COLLISION_FRACTION, "rule of thumb",
                 f"1/50 of the collision time pi sqrt(m_eff/k) of the contact of particles "
                 f"{packing.particle_id(springs.i[c])} and {packing.particle_id(springs.j[c])}"))
    rows += _rayleigh_rows(packing, material)
    return [RatedEstimate(Estimate(name, dt, kind, detail), dt_crit) for name, dt, kind, detail in rows]


def audit(packing: Packing, contacts: Contacts, convention: EngineConvention, *, law: str, source: str,
          integrator: str | None = None, dt_user: float | None = None, method: str = "auto",
          material: tuple[float, float] | None = None, yade_stepper: StepperInput | None = None) -> AuditReport:
    """The audit of a snapshot: its exact critical step as its engine integrates it (module docstring).

    Parameters
    ----------
    packing : Packing
        The particles, with the engine's own ids.
    contacts : Contacts
        Contacts carrying every term the engine applies (springs [N/m, N m/rad], dashpots
        [N s/m], normal force [N]).
    convention : EngineConvention
        The engine's conventions (integrator, name, source).
    law : str
        The contact law in words.
    source : str
        Where the snapshot came from.
    integrator : str or None
        Integrator to audit (default: the engine's).
    dt_user : float or None
        The step the user runs with [s], rated against ``dt_crit``.
    method : str
        Eigen-solver of ``largest_mode``.
    material : tuple of float or None
        ``(E [Pa], nu)`` when the contact law has a material: adds the Rayleigh-time estimators.
    yade_stepper : StepperInput or None
        What YADE's GlobalStiffnessTimeStepper reads of the scene (a YADE export's spheres, clump
        members and contacts, ``dtcrit.packing.bounds.yade_stepper_export``) for the ``yade_gsts`` rows;
        None: the packing's own sphere contacts (``yade_stepper.from_contacts``).

    Returns
    -------
    AuditReport
        The report.

    Raises
    ------
    InputError
        For contacts without stiffness, no contacts, or a non-positive ``dt_user``.
    """
    _check_terms(contacts)
    integrator = integrator or convention.integrator
    step = damped_critical_dt(packing, contacts, integrator, method=method)
    springs = replace(contacts, force_n=None)
    dt_safe = min(step.dt_lower, step.dt)
    stepper = yade_stepper if yade_stepper is not None else from_contacts(packing, contacts)
    limiting, share, participation = _limiting(packing, step.vector)
    cn = contacts.coordination(packing.n)
    notes = []
    if contacts.force_n is not None and np.any(contacts.force_n > 0):
        notes.append("pre-loaded contacts: the geometric stiffness of their normal forces is included")
    if dt_user is not None and not (math.isfinite(dt_user) and dt_user > 0):
        raise InputError("--dt", f"must be a positive finite number, got {dt_user}")
    return AuditReport(
        source=source, engine=convention.name, engine_source=convention.source, integrator=integrator, law=law,
        n_particles=packing.n, n_contacts=contacts.count, coordination_mean=float(cn.mean()),
        damped=contacts.damped, preload=bool(notes), dt_crit=step.dt, dt_safe=dt_safe,
        dt_undamped=step.dt_undamped, method=step.method, limiting=limiting, limiting_share=share,
        dt_user=dt_user, estimators=_estimators(packing, springs, step.dt, material, contacts.damped, stepper), notes=notes,
        participation=participation, governing_mode=mode_character(packing, contacts, step.vector),
    )
