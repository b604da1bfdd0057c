"""The data of ``dtcrit audit --plot``: the packing coloured by the governing mode, and the top of the spectrum.

``dtcrit.figures.audit_plot`` draws it; this module only computes it (NumPy/SciPy, no Matplotlib):

* each particle's share of the governing mode's kinetic energy (``ModeCharacter.particle_share``,
  ``dtcrit.packing.audit.mode_character``); on the spectral-radius route, which returns no mode,
  the top undamped mode's instead (``mode`` says which);
* the ``count`` largest eigenvalues ``omega_k^2`` of ``K phi = omega^2 M phi`` (the springs with the
  pre-load, as the audit solves them) as steps ``2/omega_k`` (the undamped critical step of each mode
  alone); with dashpots and a lagged scheme (LAMMPS's velocity Verlet, YADE's leapfrog) also each
  mode's step with its own modal damping ``c_k = v_k^T C~ v_k``, the root of
  ``2h c_k + h^2 omega_k^2 = 4`` (``dtcrit.packing.solvers.damped_step``, one mode of the scalar
  condition; an approximation, the exact ``dt_crit`` couples the modes);
* the audit's steps as marks: ``dt_crit``, ``dt_safe``, the undamped ``2/omega_max`` (with
  dashpots), the user's step and every estimator.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse.linalg as spla

from dtcrit.errors import InputError
from dtcrit.packing.audit.mode_character import particle_energies
from dtcrit.packing.model import Contacts, Packing
from dtcrit.packing.solvers.damped_step import LAGGED, scaled_matrices

__all__ = ["DENSE_DOFS", "AuditFigureData", "Spectrum", "audit_figure_data", "top_spectrum"]

DENSE_DOFS = 600
"""Up to this many DOFs the spectrum is a dense ``scipy.linalg.eigh``; above, ARPACK's ``eigsh``."""


@dataclass(frozen=True)
class Spectrum:
    """The largest eigenvalues of ``M^(-1/2) K M^(-1/2)`` and their steps, largest first.

    Parameters
    ----------
    omega2 : numpy.ndarray
        ``omega_k^2`` [1/s^2], descending.
    steps : numpy.ndarray
        ``2/omega_k`` [s] (``inf`` for ``omega_k^2 <= 0``).
    damped_steps : numpy.ndarray or None
        Each mode's lagged-scheme step with its modal damping [s] (module docstring), ``None``
        without dashpots or for another scheme.
    top_vector : numpy.ndarray
        The eigenvector of ``omega_1^2`` (mass-scaled, length 6N).
    """

    omega2: np.ndarray
    steps: np.ndarray
    damped_steps: np.ndarray | None
    top_vector: np.ndarray


@dataclass(frozen=True)
class AuditFigureData:
    """What ``dtcrit audit --plot`` draws (module docstring).

    Parameters
    ----------
    ids : numpy.ndarray
        The engine's particle ids, (N,).
    positions : numpy.ndarray
        Particle centres [m], (N, 3).
    radii : numpy.ndarray
        Radii (bounding radii of non-spheres) [m], (N,).
    share : numpy.ndarray
        Each particle's share of the mode's kinetic energy, (N,), summing to 1.
    mode : str
        Which mode ``share`` is of (the governing mode, or the top undamped mode).
    spectrum : Spectrum
        The top of the spectrum.
    marks : tuple of (str, float)
        ``(label, step [s])`` of ``dt_crit``, ``dt_safe``, ``2/omega_max`` (with dashpots), the user's
        step and each estimator.
    title : str
        The snapshot and its law.
    """

    ids: np.ndarray
    positions: np.ndarray
    radii: np.ndarray
    share: np.ndarray
    mode: str
    spectrum: Spectrum
    marks: tuple[tuple[str, float], ...]
    title: str


def _steps(omega2: np.ndarray) -> np.ndarray:
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(omega2 > 0, 2.0 / np.sqrt(np.maximum(omega2, 0.0)), np.inf)


def top_spectrum(packing: Packing, contacts: Contacts, count: int = 10, integrator: str = "velocity-verlet") -> Spectrum:
    """The ``count`` largest ``omega_k^2`` of the packing, their steps and modal-damped steps.

    Parameters
    ----------
    packing : Packing
        The bodies.
    contacts : Contacts
        The contacts with their springs, dashpots and pre-load.
    count : int
        How many eigenvalues (at most the DOF count).
    integrator : str
        The audit's integrator (the modal-damped steps are given for the lagged schemes only).

    Returns
    -------
    Spectrum
        Descending ``omega_k^2`` [1/s^2] with their steps [s].
    """
    k_t, c_t = scaled_matrices(packing, contacts, "assembled")
    n = k_t.shape[0]
    count = max(1, min(int(count), n))
    if n <= DENSE_DOFS or count >= n - 1:
        values, vectors = scipy.linalg.eigh(k_t.toarray(), subset_by_index=[n - count, n - 1])
    else:
        values, vectors = spla.eigsh(k_t.tocsr(), k=count, which="LA", tol=1e-10)
    order = np.argsort(-values, kind="stable")
    values, vectors = values[order], vectors[:, order]
    damped = None
    if contacts.damped and integrator in LAGGED:
        c_k = np.einsum("ik,ik->k", vectors, c_t.tocsr() @ vectors)
        with np.errstate(divide="ignore", invalid="ignore"):
            damped = np.where(values > 0, 4.0 / (c_k + np.sqrt(c_k**2 + 4.0 * np.maximum(values, 0.0))), np.inf)
    return Spectrum(values, _steps(values), damped, vectors[:, 0])


def _marks(audit) -> tuple[tuple[str, float], ...]:
    marks = [("dt_crit", audit.dt_crit), ("dt_safe", audit.dt_safe)]
    if audit.damped:
        marks.append(("2/omega_max (undamped)", audit.dt_undamped))
    if audit.dt_user is not None:
        marks.append(("your dt", audit.dt_user))
    marks += [(e.estimate.name, e.estimate.dt) for e in audit.estimators if e.estimate.dt is not None]
    return tuple((label, float(dt)) for label, dt in marks if math.isfinite(dt) and dt > 0)


def audit_figure_data(audit, count: int = 10) -> AuditFigureData:
    """The data of the audit's figure (module docstring).

    Parameters
    ----------
    audit : SnapshotAudit
        An audit from :func:`dtcrit.packing.audit.run.audit_snapshot` (it keeps its snapshot).
    count : int
        How many of the largest eigenvalues to give.

    Returns
    -------
    AuditFigureData
        The particles, their shares, the spectrum and the marks.

    Raises
    ------
    InputError
        For an audit that does not carry its snapshot.
    """
    snapshot = audit.snapshot
    if snapshot is None:
        raise InputError("plot", "this audit does not carry its snapshot (make it with audit_snapshot)")
    packing = snapshot.packing
    spectrum = top_spectrum(packing, snapshot.contacts, count, audit.integrator)
    if audit.governing_mode is not None:
        share, mode = audit.governing_mode.particle_share, "governing mode"
    else:
        e = particle_energies(spectrum.top_vector)
        share, mode = e / e.sum(), "top undamped mode"
    n = packing.n - int(snapshot.meta.get("fixed_bodies", 0))  # walls come last and are not drawn
    ids = np.array([packing.particle_id(p) for p in range(n)])
    return AuditFigureData(ids, packing.positions[:n].copy(), packing.radii[:n].copy(),
                           np.asarray(share, dtype=float)[:n], mode, spectrum, _marks(audit),
                           f"{snapshot.source}: {snapshot.law}")
