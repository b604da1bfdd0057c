"""Per-body mass factors that make a packing's critical step at least a target step: sufficient, by two rigorous bounds.

A lagged central-difference scheme (leapfrog, velocity Verlet, symplectic Euler: LAMMPS ``fix
nve/sphere``, YADE's NewtonIntegrator) with contact dashpots is stable at the step ``h`` iff
``4 M - 2h C - h^2 K`` is positive definite (``dtcrit.packing.solvers.damped_step``), i.e. iff
``lambda_max(B, M) < 4`` with ``B = 2h C + h^2 K``; ``leapfrog-centred`` drops the dashpot term
(``B = h^2 K``).  Scaling body ``p``'s mass and principal moments by ``f_p >= 1`` replaces ``M`` by
``F M``.  Two bounds on ``lambda_max(B, F M)`` give factors that are *sufficient* body by body:

* **Gershgorin rows of** ``(F M)^-1 B`` (similar to the symmetric ``(F M)^-1/2 B (F M)^-1/2``, so with
  the same real eigenvalues): every eigenvalue is at most ``max_i sum_j |B_ij| / (f_p(i) M_ii)``.  With
  ``r_p`` the largest row sum of ``M^-1 B`` among body ``p``'s six rows, ``f_p = max(1, r_p / 4)``
  makes every row at most 4.  The rows of ``|2h C + h^2 K|`` are bounded by ``2h`` times those of
  ``|C|`` plus ``h^2`` times those of ``|K|`` (triangle inequality), which keeps the matrix-free route.
* **Block diagonal**: each contact's element of ``B`` is positive semi-definite, so ``B <= 2
  blockdiag(B)`` (``dtcrit.packing.bounds.estimates``: flip one body's sign, add), and
  ``lambda_max(B, F M) <= 2 max_p mu_p / f_p`` with ``mu_p = lambda_max(M_p^-1/2 B_pp M_p^-1/2)`` the
  top of body ``p``'s 6 x 6 block (translation and rotation together).  ``f_p = max(1, mu_p / 2)``.

When the law's terms grow with the masses (a LAMMPS dashpot ``m_eff gamma_n``, ``dtcrit.plan.rederive``)
``B`` itself depends on ``F``.  Both bounds hold for any ``F`` with ``B(F)`` assembled at the scaled
masses, so :func:`sufficient_factors` iterates ``f <- f q`` with ``q_p`` body ``p``'s demand relative to
its scaled mass until every ``q_p <= 1`` (a fixed point of a monotone map: the terms only grow with
``f``, so the sequence only grows); the factors it returns satisfy the bound at their own ``B(F)``.
Either set gives ``lambda_max <= 4``: a critical step at least the target (``= 4`` is the margin,
which the exact confirmation of ``dtcrit.plan.density`` clears).

Both need the springs' elements positive semi-definite: as in ``damped_step``'s ``dt_lower`` the
compressive pre-loads (negative semi-definite terms, which only lower ``lambda_max``) are left out and
the tensile ones kept.  Plain NumPy/SciPy.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Callable

import numpy as np

from dtcrit.packing.bounds.estimates import _abs_row_sums
from dtcrit.packing.model import Contacts, Packing
from dtcrit.packing.solvers.damped_step import scaled_matrices

__all__ = ["BodyDemands", "body_demands", "diagonal_blocks", "sufficient_factors"]

RELAXATION = 1e-3
"""Each step of :func:`sufficient_factors` after the first overshoots the demand by this fraction, so a
fixed point approached from below is passed in finitely many steps."""
MAX_ITERATIONS = 60
ROUNDING = 1e-12
"""A demand within this of 1 counts as met: the same factors assembled twice differ by rounding."""


@dataclass(frozen=True)
class BodyDemands:
    """Each body's demand ``lambda``-share at the target step, by the two bounds (module docstring).

    Parameters
    ----------
    gershgorin : numpy.ndarray
        ``(N,)`` ``r_p / 4``: the factor of body ``p`` by the Gershgorin rows (before the floor at 1).
    block_diagonal : numpy.ndarray
        ``(N,)`` ``mu_p / 2``: the factor of body ``p`` by its 6 x 6 block (before the floor at 1).
    """

    gershgorin: np.ndarray
    block_diagonal: np.ndarray

    def factors(self, which: str) -> np.ndarray:
        """The sufficient per-body factors of one bound, ``max(1, demand)``.

        Parameters
        ----------
        which : {'gershgorin', 'block_diagonal'}
            The bound.

        Returns
        -------
        numpy.ndarray
            ``(N,)`` factors >= 1.
        """
        return np.maximum(1.0, getattr(self, which))


def diagonal_blocks(a) -> np.ndarray:
    """The ``(N, 6, 6)`` diagonal blocks of a mass-scaled 6N x 6N matrix (BSR, operator or dense).

    Parameters
    ----------
    a : scipy.sparse.bsr_matrix or LinearOperator or array_like
        ``M^-1/2 K M^-1/2`` (or of ``C``); a matrix-free operator gives its own ``diagonal_blocks()``.

    Returns
    -------
    numpy.ndarray
        ``(N, 6, 6)`` blocks.
    """
    n = a.shape[0] // 6
    if hasattr(a, "diagonal_blocks"):
        return np.asarray(a.diagonal_blocks())
    if hasattr(a, "blocksize") and a.blocksize == (6, 6):
        rows = np.repeat(np.arange(n), np.diff(a.indptr))
        on_diag = a.indices == rows
        blocks = np.zeros((n, 6, 6))
        np.add.at(blocks, rows[on_diag], a.data[on_diag])
        return blocks
    dense = a.toarray() if hasattr(a, "toarray") else np.asarray(a)
    return np.stack([dense[6 * p:6 * p + 6, 6 * p:6 * p + 6] for p in range(n)])


def _springs_bounding(contacts: Contacts) -> Contacts:
    """The contacts with only their tensile pre-loads: elements positive semi-definite (module docstring)."""
    if contacts.force_n is None or not np.any(contacts.force_n > 0):
        return contacts
    return replace(contacts, force_n=np.minimum(contacts.force_n, 0.0))


def _row_sums(a, root: np.ndarray) -> np.ndarray:
    """Row sums of ``|M^-1 X|`` from ``a = M^-1/2 X M^-1/2`` (``dtcrit.packing.bounds.estimates.gershgorin``)."""
    return _abs_row_sums(a, root) / root


def body_demands(packing: Packing, contacts: Contacts, h: float, *, dashpots: bool,
                 route: str = "auto") -> BodyDemands:
    """Per-body sufficient mass factors for stability at the step ``h`` (module docstring).

    Parameters
    ----------
    packing : Packing
        The bodies (masses [kg], principal moments [kg m^2]).
    contacts : Contacts
        Springs [N/m, N m/rad], dashpots [N s/m, N m s/rad], pre-loads [N].
    h : float
        The target step [s] (for a local-damping scene: the undamped step it needs).
    dashpots : bool
        Whether the dashpot term ``2h C`` enters (lagged schemes); False for ``leapfrog-centred``.
    route : str
        ``auto``, ``assembled`` or ``matrix-free`` (``dtcrit.packing.solvers.damped_step.scaled_matrices``).

    Returns
    -------
    BodyDemands
        The Gershgorin and block-diagonal demands ``r_p / 4`` and ``mu_p / 2``.
    """
    from dtcrit.packing.operators.assembly import mass_diagonal

    k, c = scaled_matrices(packing, _springs_bounding(contacts), route)
    root = np.sqrt(mass_diagonal(packing))
    rows = h * h * _row_sums(k, root)
    blocks = h * h * diagonal_blocks(k)
    if dashpots and contacts.damped:
        rows = rows + 2.0 * h * _row_sums(c, root)
        blocks = blocks + 2.0 * h * diagonal_blocks(c)
    per_body_rows = rows.reshape(-1, 6).max(axis=1)
    top = np.empty(packing.n)
    for lo in range(0, packing.n, 1 << 16):
        part = blocks[lo:lo + (1 << 16)]
        top[lo:lo + (1 << 16)] = np.linalg.eigvalsh(0.5 * (part + np.swapaxes(part, 1, 2)))[:, -1]
    return BodyDemands(gershgorin=per_body_rows / 4.0, block_diagonal=np.maximum(top, 0.0) / 2.0)


def sufficient_factors(system: Callable[[np.ndarray], tuple[Packing, Contacts]], n: int, h: float, which: str,
                       free: np.ndarray, *, dashpots: bool, max_factor: float) -> np.ndarray | None:
    """Per-body factors that satisfy one bound with the terms at the scaled masses (module docstring).

    Parameters
    ----------
    system : callable
        ``factors -> (packing, contacts)`` at the scaled masses (``dtcrit.plan.exact.ScaledStep.system``).
    n : int
        Number of bodies.
    h : float
        The step [s] (for a local-damping scene: the undamped step it needs).
    which : {'gershgorin', 'block_diagonal'}
        The bound.
    free : numpy.ndarray
        ``(N,)`` which bodies may be scaled (the others keep 1).
    dashpots : bool
        Whether the dashpot term enters.
    max_factor : float
        The largest factor allowed.

    Returns
    -------
    numpy.ndarray or None
        ``(N,)`` factors with ``lambda_max(B(F), F M) <= 4`` by the bound, or None when the iteration
        does not get there within ``max_factor`` (a dashpot ``m_eff gamma`` can keep the bound above 4
        at any mass).
    """
    f = np.ones(n)
    for k in range(MAX_ITERATIONS):
        q = np.where(free, getattr(body_demands(*system(f), h, dashpots=dashpots), which), 0.0)
        if np.all(q <= 1.0 + ROUNDING):
            return f
        grow = q > 1.0 + ROUNDING
        f = np.where(grow, f * q * (1.0 if k == 0 else 1.0 + RELAXATION), f)
        if np.any(f > max_factor):
            return None
    return None
