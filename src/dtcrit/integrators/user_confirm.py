"""Confirm the step of a user-written scheme by stepping its own rules in physical units (runtime; no SymPy).

The step ``dt`` of a user scheme comes from its scaled amplification matrix
(``dtcrit.integrators.spectral_route``).  Before it is printed it is checked on the scheme itself in
physical units, ``x'' = -K x - C x'`` with ``K = k A`` [1/s^2] and ``C = c A`` [1/s]
(Peng et al. 2020, Eq. (30)), at ``h = 0.99 dt`` and ``h = 1.01 dt``:

1. ``G(h)`` is built by applying the rules to the unit states (float64, physical units);
2. ``N = 2^40`` steps are taken by repeated squaring of ``G`` (balanced by exact powers of two,
   renormalised each squaring): the growth rate ``||G^N||^(1/N)`` tends to the spectral radius
   (Gelfand's formula) with ``log(kappa)/N ~ 1e-11`` of transient;
3. 256 steps of the rules themselves are taken from a generic state and must match ``G^256`` applied to
   it (the matrix is the map the rules make).

``0.99 dt`` must not grow (rate <= 1 + 1e-10) and ``1.01 dt`` must grow (rate > 1 + 1e-10); otherwise
the step is refused (``InputError``) rather than printed.  A step of 0 (no stable step) is not a step
anyone runs and is not checked; an unbounded step (stable up to omega dt = 1e4) is refused.  Cost:
about 40 ms per contact mode, mostly the literal steps (the 50-digit boundary itself takes 0.4-2 s);
``tests/integrators/test_user_rules_consistency.py`` bounds it.
"""
from __future__ import annotations

import math

import numpy as np

from dtcrit.errors import InputError
from dtcrit.integrators.schemes import LinearForce, MatrixForce, lookup

SQUARINGS = 40
LITERAL_STEPS = 256
GROWTH_TOL = 1e-10
FACTORS = (0.99, 1.01)


def _stepper(integrator, h: float, K, C):
    """One step of the rules on the flat state (all variables of all ``n`` degrees of freedom)."""
    integ = lookup(integrator)
    n = 1 if np.ndim(K) == 0 else np.shape(K)[0]
    force = LinearForce(K, C) if np.ndim(K) == 0 else MatrixForce(np.asarray(K), np.asarray(C))
    parts = len(integ.state)

    def step(flat: np.ndarray) -> np.ndarray:
        if n == 1:
            return np.array([float(c) for c in integ.step(tuple(float(c) for c in flat), h, force)])
        out = integ.step(tuple(flat[p * n:(p + 1) * n] for p in range(parts)), h, force)
        return np.concatenate([np.broadcast_to(np.asarray(c, dtype=float), (n,)) for c in out])

    return step, parts * n


def physical_matrix(integrator, h: float, K, C) -> np.ndarray:
    """``G`` of the rules at the physical step ``h`` [s] for ``f(x, v) = -K x - C v`` (K, C scalars or matrices).

    Parameters
    ----------
    integrator : str or Integrator
        A built-in or user-written scheme.
    h : float
        Time step [s].
    K : float or array_like
        Stiffness per unit mass ``k A`` [1/s^2]: a scalar (one mode) or an (n, n) matrix (a coupled block).
    C : float or array_like
        Damping per unit mass ``c A`` [1/s], shaped as ``K``.

    Returns
    -------
    numpy.ndarray
        The amplification matrix, ``(parts n) x (parts n)`` for ``parts`` state variables.
    """
    step, size = _stepper(integrator, h, K, C)
    with np.errstate(all="ignore"):
        return np.column_stack([step(np.eye(size)[j]) for j in range(size)])


def _balance(G: np.ndarray) -> np.ndarray:
    """Osborne balancing by exact powers of two (a similarity: the spectrum is unchanged)."""
    G = G.copy()
    for _ in range(60):
        changed = False
        for i in range(len(G)):
            r = np.sum(np.abs(G[i])) - abs(G[i, i])
            c = np.sum(np.abs(G[:, i])) - abs(G[i, i])
            if r == 0 or c == 0:
                continue
            e = round(math.log2(c / r) / 2)
            if e:
                G[i, :] *= 2.0**e
                G[:, i] *= 2.0**-e
                changed = True
        if not changed:
            break
    return G


def growth_rate(G: np.ndarray) -> float:
    """``||G^N||^(1/N)`` for ``N = 2^SQUARINGS``, by renormalised repeated squaring.

    Parameters
    ----------
    G : numpy.ndarray
        A square amplification matrix.

    Returns
    -------
    float
        The growth rate per step, which tends to the spectral radius of ``G`` (Gelfand's formula).
    """
    M = _balance(G)
    log_scale = 0.0
    for _ in range(SQUARINGS):
        s = float(np.max(np.abs(M)))
        if s == 0.0:
            return 0.0
        M = M / s
        log_scale = 2.0 * (log_scale + math.log(s))
        M = M @ M
    s = float(np.max(np.abs(M)))
    return 0.0 if s == 0.0 else math.exp((log_scale + math.log(s)) / 2.0**SQUARINGS)


def _literal_matches(integrator, G: np.ndarray, h: float, K, C) -> bool:
    step, size = _stepper(integrator, h, K, C)
    z = np.array([1.0 / (i + 1.5) for i in range(size)])
    ref, peak = z.copy(), np.abs(z)
    with np.errstate(all="ignore"):
        for n in range(LITERAL_STEPS):
            z, ref = step(z), G @ ref
            peak = np.maximum(peak, np.abs(ref))
            if not (np.all(np.isfinite(z)) and np.all(np.isfinite(ref))):
                return False
            if n % 16 == 15:  # the same exact power-of-two rescaling of both runs keeps a growing one finite
                scale = 2.0 ** -math.frexp(float(np.max(peak)) or 1.0)[1]
                z, ref, peak = z * scale, ref * scale, peak * scale
    return bool(np.all(np.abs(z - ref) <= 1e-6 * peak + 1e-300))


def confirm_step(integrator, dt: float, K, C) -> None:
    """Refuse (InputError on ``integrator``) a printed step ``dt`` [s] that stepping the rules in physical
    units does not confirm: stable at 0.99 dt, growing at 1.01 dt.

    Parameters
    ----------
    integrator : str or Integrator
        A user-written (or built-in) scheme.
    dt : float
        The step to confirm [s]; 0 is not checked, inf is refused.
    K : float or array_like
        Stiffness per unit mass [1/s^2]: a scalar (one mode) or a matrix (a coupled block,
        ``x'' = -K x - C x'``).
    C : float or array_like
        Damping per unit mass [1/s], shaped as ``K``.
    """
    name = getattr(integrator, "name", integrator)
    if dt == 0.0:
        return
    if not math.isfinite(dt):
        raise InputError("integrator", f"the user-written scheme '{name}' stays stable up to omega dt = 1e4 here; "
                         "dtcrit does not certify an unbounded step for it")
    rates = []
    for factor in FACTORS:
        h = factor * dt
        G = physical_matrix(integrator, h, K, C)
        if not np.all(np.isfinite(G)) or not _literal_matches(integrator, G, h, K, C):
            raise InputError("integrator", f"the step {dt:.6g} s of '{name}' cannot be confirmed by stepping its rules "
                             f"in float64 at K = {np.max(np.abs(K)):.3g} 1/s^2, C = {np.max(np.abs(C)):.3g} 1/s; "
                             "rescale the units and retry")
        rates.append(growth_rate(G))
    if not (rates[0] <= 1 + GROWTH_TOL < rates[1]):
        raise InputError("integrator", f"the step {dt:.6g} s of '{name}' is not confirmed by stepping its rules in "
                         f"physical units (growth per step {rates[0]:.12g} at 0.99 dt, {rates[1]:.12g} at 1.01 dt); "
                         "refused rather than printed")
