"""The exact critical step of a packing with per-body mass factors, as ``dtcrit audit`` computes it.

``ScaledStep`` holds a snapshot's packing and contacts, its engine's integrator and the local damping
the audit applies (:mod:`dtcrit.packing.audit.local_damping`), and gives the critical step of the
packing whose body ``p`` has mass ``f_p m_p`` and principal moments ``f_p I_p`` -- with the contacts the
engine's law gives at those masses (``rebuild``, :func:`dtcrit.plan.rederive.rebuilder`: a LAMMPS dashpot
``m_eff gamma_n`` grows with the mass, a YADE export's or a table's terms stay) -- the audit's eigen-solve
(:func:`dtcrit.packing.solvers.damped_step.damped_critical_dt`: ``2/omega_max`` without dashpots, the
root of ``lambda_max(2h C~ + h^2 K~) = 4`` with them) times the local-damping factor ``1/sqrt(1 + alpha)``.
Plain NumPy/SciPy.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any, Callable

import numpy as np

from dtcrit.errors import InputError
from dtcrit.packing.model import Contacts, Packing
from dtcrit.packing.solvers.damped_step import CENTRED, LAGGED, damped_critical_dt, scaled_matrices

__all__ = ["FIXED_MASS_RATIO", "MODELLED", "ScaledStep", "confirmed_uniform", "free_bodies", "scaled_packing"]

MODELLED = LAGGED + CENTRED
"""The integrators a plan is made for: the central-difference family, whose condition on the scaled
masses is ``4 F M - 2h C - h^2 K > 0`` (``dtcrit.plan.bounds``)."""
FIXED_MASS_RATIO = 1e100
"""A body heavier than this times the lightest is a fixed body (a wall or a fixed YADE body enters
with 1e150 times the largest free mass, ``dtcrit.packing.wall_bodies``): its factor stays 1 and its
mass counts in no total."""


def free_bodies(packing: Packing) -> np.ndarray:
    """Which bodies are free particles (not walls or fixed bodies; ``FIXED_MASS_RATIO``).

    Parameters
    ----------
    packing : Packing
        The bodies.

    Returns
    -------
    numpy.ndarray
        ``(N,)`` booleans.
    """
    return packing.masses <= FIXED_MASS_RATIO * float(packing.masses.min())


def scaled_packing(packing: Packing, factors) -> Packing:
    """The packing with body ``p``'s mass and principal moments times ``factors[p]``.

    Parameters
    ----------
    packing : Packing
        The bodies.
    factors : array_like
        ``(N,)`` positive factors.

    Returns
    -------
    Packing
        A new packing (positions, radii, ids, box unchanged).
    """
    f = np.asarray(factors, float).reshape(-1)
    return replace(packing, masses=packing.masses * f, inertia=packing.inertia * f[:, None])


@dataclass
class ScaledStep:
    """The exact critical step of a packing under per-body mass factors (module docstring).

    Parameters
    ----------
    packing : Packing
        The unscaled bodies.
    contacts : Contacts
        Their contacts with every term the engine applies.
    integrator : str
        The engine's integrator (one of ``MODELLED``).
    local_factor : float
        ``1/sqrt(1 + alpha)`` of the local damping the audit applies (1 without).
    method : str
        Eigen-solver (``dtcrit.packing.solvers.largest_mode``).
    solves : int
        Exact solves done so far (counted by :meth:`dt`).
    certificates : int
        Inertia counts done so far (:meth:`certified_stable`).
    rebuild : callable or None
        ``factors -> (packing, contacts)`` re-derived by the engine's law
        (:func:`dtcrit.plan.rederive.rebuilder`); None: the contacts' terms do not depend on the masses.
    """

    packing: Packing
    contacts: Contacts
    integrator: str
    local_factor: float = 1.0
    method: str = "auto"
    solves: int = field(default=0)
    certificates: int = field(default=0)
    rebuild: Callable[[np.ndarray], tuple[Packing, Contacts]] | None = field(default=None, repr=False)

    def __post_init__(self):
        self._shifted: dict[float, Any] = {}  # B~ at the last step asked (_b_matrix)
        self._mass_dependent: bool | None = None
        if self.integrator not in MODELLED:
            raise InputError("integrator", f"a plan is made for the central-difference family ({', '.join(MODELLED)}); "
                                           f"{self.integrator!r} is not modelled")

    @property
    def dashpots(self) -> bool:
        """Whether the dashpots enter the stability condition (a lagged scheme with dashpots)."""
        return self.integrator in LAGGED and self.contacts.damped

    def system(self, factors=None) -> tuple[Packing, Contacts]:
        """The packing with ``factors`` and its contacts at those masses.

        Parameters
        ----------
        factors : array_like or None
            ``(N,)`` per-body factors (None: unscaled).

        Returns
        -------
        tuple
            ``(packing, contacts)``: ``rebuild(factors)``, or ``scaled_packing`` with the fixed contacts.
        """
        if factors is None:
            return self.packing, self.contacts
        if self.rebuild is not None:
            return self.rebuild(np.asarray(factors, float))
        return scaled_packing(self.packing, factors), self.contacts

    @property
    def mass_dependent(self) -> bool:
        """Whether any contact term changes with the masses (probed: every factor 2 against none)."""
        if self._mass_dependent is None:
            if self.rebuild is None:
                self._mass_dependent = False
            else:
                _, doubled = self.rebuild(np.full(self.packing.n, 2.0))
                self._mass_dependent = any(
                    (a is None) != (b is None) or (a is not None and not np.array_equal(a, b))
                    for a, b in ((getattr(self.contacts, k), getattr(doubled, k))
                                 for k in ("kn", "ks", "kr", "ktw", "cn", "cs", "cr", "ctw", "force_n")))
        return self._mass_dependent

    def dt(self, factors=None) -> float:
        """The critical step [s] of the packing with ``factors`` (None: unscaled), as the audit reports it.

        Parameters
        ----------
        factors : array_like or None
            ``(N,)`` per-body factors.

        Returns
        -------
        float
            ``damped_critical_dt(...).dt x local_factor``.
        """
        packing, contacts = self.system(factors)
        self.solves += 1
        step = damped_critical_dt(packing, contacts, self.integrator, method=self.method)
        return float(step.dt) * self.local_factor

    def _b_matrix(self, h: float):
        """``B~ = 2h C~ + h^2 K~`` (``h^2 K~`` without dashpots) of the unscaled packing, assembled, cached."""
        if h not in self._shifted:
            k, c = scaled_matrices(self.packing, self.contacts, "assembled")
            b = (h * h) * k.tocsr()
            self._shifted.clear()
            self._shifted[h] = b + (2.0 * h) * c.tocsr() if self.dashpots else b
        return self._shifted[h]

    def certified_stable(self, factors, target: float) -> bool | None:
        """Whether ``4 F M - B(F)`` is proved positive definite at ``h = target / local_factor``: step above ``target``.

        The inertia count of ``dtcrit.packing.solvers.certificate.certify`` on ``4 I - F^-1/2 B~ F^-1/2``
        (``LDL^T``, Sylvester's law of inertia; ``B~`` re-assembled at the scaled masses when the law's
        terms depend on them): by ``dtcrit.packing.solvers.damped_step``'s condition the scaled packing's
        critical step then exceeds ``target``.

        Parameters
        ----------
        factors : array_like
            ``(N,)`` per-body factors.
        target : float
            The step [s].

        Returns
        -------
        bool or None
            True: proved stable; False: not proved (a negative or zero pivot); None: too large to factorise
            (``SPARSE_DOFS``), ask :meth:`dt`.
        """
        import scipy.sparse as sps

        from dtcrit.packing.solvers.certificate import SPARSE_DOFS, certify

        if self.packing.dofs > SPARSE_DOFS:
            return None
        h = self.undamped_target(target)
        self.certificates += 1
        if self.mass_dependent:
            k, c = scaled_matrices(*self.system(factors), "assembled")
            b = (h * h) * k.tocsr()
            b = b + (2.0 * h) * c.tocsr() if self.dashpots else b
            return bool(certify(b, 4.0, 0.0, dense_dofs=0).certified)
        b = self._b_matrix(h)
        d = sps.diags(np.repeat(1.0 / np.sqrt(np.asarray(factors, float)), 6))
        return bool(certify(d @ b @ d, 4.0, 0.0, dense_dofs=0).certified)

    def undamped_target(self, target: float) -> float:
        """The step the packing without local damping must reach for the audit's step to be ``target``.

        Parameters
        ----------
        target : float
            The target step [s].

        Returns
        -------
        float
            ``target / local_factor`` [s].
        """
        return target / self.local_factor

    def uniform_factor(self, target: float) -> float:
        """The least common factor of every free body that reaches ``target``: exact, one eigen-solve.

        With terms that do not depend on the masses ``lambda_max(B, f M) = lambda_max(B, M) / f`` for
        ``B = 2h C + h^2 K`` (``h^2 K`` without dashpots), so ``f = max(1, lambda_max(B~) / 4)`` at
        ``h = target / local_factor``.  When the law's terms grow with the masses (``mass_dependent``:
        a dashpot ``m_eff gamma`` is not divided out) it is not closed-form and ``dtcrit.plan.density`` bisects it.

        Parameters
        ----------
        target : float
            The target step [s].

        Returns
        -------
        float
            The factor (>= 1).

        Raises
        ------
        MisuseError
            The law's terms depend on the masses (no closed form).
        """
        from dtcrit.errors import MisuseError
        from dtcrit.packing.operators.matrix_free import CombinedOperator
        from dtcrit.packing.solvers.largest_mode import largest_mode
        import scipy.sparse.linalg as spla

        if self.mass_dependent:
            raise MisuseError("uniform_factor: the contact terms depend on the masses; bisect on the exact step")
        h = self.undamped_target(target)
        k, c = scaled_matrices(self.packing, self.contacts, "auto")
        self.solves += 1
        if not self.dashpots:
            return max(1.0, largest_mode(k, self.method).value * h * h / 4.0)
        a = CombinedOperator(c, 2.0 * h, k, h * h) if isinstance(k, spla.LinearOperator) else (2.0 * h) * c.tocsr() + (h * h) * k.tocsr()
        return max(1.0, largest_mode(a, self.method).value / 4.0)


def _uniform_bisected(target: float, dt_now: float, free: np.ndarray, ok, max_factor: float) -> tuple[float, float]:
    """The least confirmed common factor when the terms depend on the masses: doubled, then bisected in log."""
    lo, hi = 1.0, max(1.0 + 1e-9, (target / dt_now) ** 2)
    found = None
    while found is None:
        good, dt = ok(np.where(free, min(hi, max_factor), 1.0))
        if good:
            found = (min(hi, max_factor), dt)
        elif hi >= max_factor:
            return math.inf, math.nan
        else:
            lo, hi = hi, 2.0 * hi
    hi = found[0]
    while hi / lo - 1.0 > 1e-5:
        mid = math.sqrt(lo * hi)
        good, dt = ok(np.where(free, mid, 1.0))
        if good:
            hi, found = mid, (mid, dt)
        else:
            lo = mid
    return found


def confirmed_uniform(step: ScaledStep, target: float, free: np.ndarray, ok, dt_now: float, max_factor: float,
                      margin: float) -> tuple[float, float]:
    """The exact uniform factor, nudged up until ``ok`` confirms it; bisected when the terms depend on the masses.

    Parameters
    ----------
    step : ScaledStep
        The evaluator.
    target : float
        The target step [s].
    free : numpy.ndarray
        ``(N,)`` the bodies that take the factor.
    ok : callable
        ``factors -> (confirmed, dt)``.
    dt_now : float
        Today's critical step [s].
    max_factor : float
        The largest factor tried when bisecting.
    margin : float
        The relative margin the closed-form factor starts above (``4 x margin``).

    Returns
    -------
    tuple
        ``(factor, its step [s] or nan when confirmed by an inertia count)``; ``(inf, nan)`` when
        ``max_factor`` on every body is not confirmed (bisected case).
    """
    if step.mass_dependent:
        return _uniform_bisected(target, dt_now, free, ok, max_factor)
    f_u = step.uniform_factor(target) * (1.0 + 4.0 * margin)
    for _ in range(40):
        good, dt = ok(np.where(free, f_u, 1.0))
        if good:
            return f_u, dt
        f_u *= 1.0 + 1e-5
    raise InputError("target_dt", "the exact solve did not confirm a uniform factor (eigen-solver trouble)")


def check_target(target: float) -> float:
    """The target step as a positive finite float, else ``InputError('target_dt', ...)``.

    Parameters
    ----------
    target : float
        The target step [s].

    Returns
    -------
    float
        ``target``.
    """
    if not (isinstance(target, (int, float)) and math.isfinite(target) and target > 0):
        raise InputError("target_dt", f"must be a positive finite number of seconds, got {target!r}")
    return float(target)
