"""Leapfrog with local (non-viscous, Cundall) damping, as YADE and PFC apply it, and its stable step.

Local damping scales each force component by ``1 -+ alpha`` according to the sign of its power.  The
two laws, stated from their sources (their code is not reproduced here):

* **PFC** (Itasca, "Energy and Dissipation Mechanisms in PFC", local damping):
  ``F_d = -alpha |F_i| sign(v_i)`` added to the unbalanced force of each degree of freedom, i.e.
  ``F_i <- F_i (1 - alpha sign(F_i v_i))``, with the velocity the central-difference scheme holds
  when the force is known, ``v_{n-1/2}`` (``law="pfc"``).  YADE's ``cundallDamp1st`` is the same
  formula with the velocity it is handed.
* **YADE** (``pkg/dem/NewtonIntegrator.cpp``, ``cundallDamp2nd``, used for every translational and
  spherical rotational degree of freedom): ``a_i <- a_i (1 - alpha sign(a_i (v_i + dt a_i / 2)))`` with
  ``a = F/m`` undamped and ``v = v_{n-1/2}``, i.e. the sign of the power at the on-step velocity
  estimate ``v_{n-1/2} + dt a_n / 2`` (``law="yade"``).

``sign(0) = 0`` in both (no damping when the power is zero).  The integrator is YADE's and PFC's
leapfrog, state ``(x_n, u = v_{n-1/2})``:  ``a_n = D(s) M^{-1} F(x_n)``, ``u' = u + dt a_n``,
``x' = x_n + dt u'`` with ``F = -K x`` (K symmetric, M diagonal) and ``D(s) = diag(1 - alpha s_i)``.

The law is positively homogeneous of degree one (``(x, u) -> c (x, u)``, ``c > 0``, scales every
later state by ``c`` and leaves every sign unchanged), so whether a step is stable cannot depend on
the amplitude.  What it does to the stable step (proofs in ``derivations/records/local_damping.md``):

* **Instability above** ``omega_max dt = 2/sqrt(1 + alpha)`` (both laws, any network): along the top
  mode's flip ray every ``F_i v_i < 0``, so the map there is the undamped leapfrog with stiffness
  ``(1 + alpha) K``, whose eigenvalue ``< -1`` then grows geometrically.
* **Stability below it** (PFC's law, proved): ``I = u^T M u + (1 + alpha) x_n^T K x_{n-1}`` never
  increases, and is positive definite for ``omega_max dt < 2/sqrt(1 + alpha)``.  YADE's on-step sign
  breaks this proof; its threshold is measured by simulation here.

Plain NumPy on batches: ``x``, ``u`` of shape ``(B, n)``; ``K`` ``(n, n)`` or ``(B, n, n)``;
``inv_mass`` ``(n,)`` or ``(B, n)``; ``h``, ``alpha`` scalars or ``(B,)``.
"""
from __future__ import annotations

import numpy as np

from dtcrit.physics.local_damping import LAWS, flip_threshold

__all__ = ["LAWS", "flip_threshold", "force", "power_sign", "step", "energy_norm", "lyapunov", "grows",
           "bisect_threshold", "chain", "sphere_wall_sphere", "omega_max"]


def _col(v, batch):
    v = np.asarray(v, dtype=float)
    return np.broadcast_to(v, (batch,))[:, None] if v.ndim <= 1 else v


def force(K, x):
    """``F = -K x`` for a batch (K shared or one per system).

    Summed column by column in a fixed order with NumPy's elementwise multiply and add (each rounded
    once, as IEEE 754 prescribes), not by BLAS or ``einsum``, whose kernels and summation order
    depend on the processor: a run near YADE's threshold is chaotic, and whether it grows must not
    follow the last bits of ``K x``.

    Parameters
    ----------
    K : numpy.ndarray, shape (n, n) or (B, n, n)
        Symmetric stiffness matrix [N/m], shared or one per system.
    x : numpy.ndarray, shape (B, n)
        Positions ``x_n`` of a batch of ``B`` systems.

    Returns
    -------
    numpy.ndarray, shape (B, n)
        The spring forces [N].
    """
    x = np.asarray(x, dtype=float)
    cols = K.T[None, :, :] if K.ndim == 2 else np.swapaxes(K, 1, 2)  # cols[b, j] = column j of K
    acc = x[:, :1] * cols[:, 0]
    for j in range(1, x.shape[1]):
        acc = acc + x[:, j:j + 1] * cols[:, j]
    return -acc


def power_sign(F, u, h, inv_mass, law):
    """``s_i``: the sign of the power each law reads (``sign(0) = 0``).

    Parameters
    ----------
    F : numpy.ndarray, shape (B, n)
        Undamped forces [N].
    u : numpy.ndarray, shape (B, n)
        Half-step velocities ``v_{n-1/2}``.
    h : float or numpy.ndarray, shape (B,)
        Time step [s].
    inv_mass : numpy.ndarray, shape (n,) or (B, n)
        Inverse masses [1/kg] (M diagonal).
    law : {"pfc", "yade"}
        Whose sign of the power is read (module docstring).

    Returns
    -------
    numpy.ndarray, shape (B, n)
        -1, 0 or 1 per degree of freedom: ``sign(F u)`` (PFC) or ``sign(a (u + h a / 2))`` (YADE).
    """
    if law == "pfc":
        return np.sign(F * u)
    if law == "yade":
        a = F * inv_mass
        return np.sign(a * (u + 0.5 * h * a))
    raise ValueError(f"law: {law!r} is not one of {LAWS}")


def step(x, u, h, K, inv_mass, alpha, law):
    """One leapfrog step with local damping: ``(x_n, v_{n-1/2}) -> (x_{n+1}, v_{n+1/2})``.

    Parameters
    ----------
    x : numpy.ndarray, shape (B, n)
        Positions ``x_n`` of a batch of ``B`` systems.
    u : numpy.ndarray, shape (B, n)
        Half-step velocities ``v_{n-1/2}``.
    h : float or numpy.ndarray, shape (B,)
        Time step [s].
    K : numpy.ndarray, shape (n, n) or (B, n, n)
        Symmetric stiffness matrix [N/m], shared or one per system.
    inv_mass : numpy.ndarray, shape (n,) or (B, n)
        Inverse masses [1/kg] (M diagonal).
    alpha : float or numpy.ndarray, shape (B,)
        Local damping coefficient, 0 <= alpha < 1.
    law : {"pfc", "yade"}
        Whose sign of the power is read (module docstring).

    Returns
    -------
    tuple of numpy.ndarray
        ``(x_{n+1}, v_{n+1/2})``.
    """
    batch = x.shape[0]
    hc, ac = _col(h, batch), _col(alpha, batch)
    F = force(K, x)
    s = power_sign(F, u, hc, inv_mass, law)
    u_next = u + hc * (F * (1.0 - ac * s)) * inv_mass
    return x + hc * u_next, u_next


def energy_norm(x, u, K, inv_mass):
    """``sqrt(u^T M u + x^T K x)``: the undamped energy norm (K positive definite).

    Parameters
    ----------
    x : numpy.ndarray, shape (B, n)
        Positions ``x_n`` of a batch of ``B`` systems.
    u : numpy.ndarray, shape (B, n)
        Half-step velocities ``v_{n-1/2}``.
    K : numpy.ndarray, shape (n, n) or (B, n, n)
        Symmetric stiffness matrix [N/m], shared or one per system.
    inv_mass : numpy.ndarray, shape (n,) or (B, n)
        Inverse masses [1/kg] (M diagonal).

    Returns
    -------
    numpy.ndarray, shape (B,)
        The norm per system.
    """
    return np.sqrt(np.sum(u * u / inv_mass, axis=1) + np.sum(x * -force(K, x), axis=1))


def lyapunov(x, u, h, K, inv_mass, alpha):
    """``I = u^T M u + (1 + alpha) x_n^T K x_{n-1}`` with ``x_{n-1} = x_n - h u`` (non-increasing for PFC's law).

    Parameters
    ----------
    x : numpy.ndarray, shape (B, n)
        Positions ``x_n`` of a batch of ``B`` systems.
    u : numpy.ndarray, shape (B, n)
        Half-step velocities ``v_{n-1/2}``.
    h : float or numpy.ndarray, shape (B,)
        Time step [s].
    K : numpy.ndarray, shape (n, n) or (B, n, n)
        Symmetric stiffness matrix [N/m], shared or one per system.
    inv_mass : numpy.ndarray, shape (n,) or (B, n)
        Inverse masses [1/kg] (M diagonal).
    alpha : float or numpy.ndarray, shape (B,)
        Local damping coefficient, 0 <= alpha < 1.

    Returns
    -------
    numpy.ndarray, shape (B,)
        ``I`` per system.
    """
    batch = x.shape[0]
    hc, ac = _col(h, batch)[:, 0], _col(alpha, batch)[:, 0]
    Kx = -force(K, x)
    return np.sum(u * u / inv_mass, axis=1) + (1.0 + ac) * np.sum(Kx * (x - hc[:, None] * u), axis=1)


def grows(x0, u0, h, K, inv_mass, alpha, law, n_steps, blowup=1e6, check_every=16):
    """Per system: True if the energy norm exceeds ``blowup`` times its start within ``n_steps`` (growing),
    False if it stays below (bounded over the run).  A grown system is zeroed and stays flagged.

    Parameters
    ----------
    x0 : numpy.ndarray, shape (B, n)
        Initial positions.
    u0 : numpy.ndarray, shape (B, n)
        Initial half-step velocities.
    h : float or numpy.ndarray, shape (B,)
        Time step [s].
    K : numpy.ndarray, shape (n, n) or (B, n, n)
        Symmetric stiffness matrix [N/m], shared or one per system.
    inv_mass : numpy.ndarray, shape (n,) or (B, n)
        Inverse masses [1/kg] (M diagonal).
    alpha : float or numpy.ndarray, shape (B,)
        Local damping coefficient, 0 <= alpha < 1.
    law : {"pfc", "yade"}
        Whose sign of the power is read (module docstring).
    n_steps : int
        Steps to run.
    blowup : float
        Growth of the energy norm that counts as unstable.
    check_every : int
        Steps between checks of the norm.

    Returns
    -------
    numpy.ndarray of bool, shape (B,)
        Whether each run grew.
    """
    x, u = np.array(x0, dtype=float), np.array(u0, dtype=float)
    start = energy_norm(x, u, K, inv_mass)
    grown = np.zeros(x.shape[0], dtype=bool)
    for i in range(1, n_steps + 1):
        x, u = step(x, u, h, K, inv_mass, alpha, law)
        if i % check_every == 0 or i == n_steps:
            with np.errstate(over="ignore", invalid="ignore"):
                big = ~(energy_norm(x, u, K, inv_mass) <= blowup * start)
            grown |= big
            x[big] = 0.0
            u[big] = 0.0
    return grown


def bisect_threshold(x0, u0, K, inv_mass, alpha, law, omega_max, lo, hi, iterations=32, n_steps=6000, blowup=1e6):
    """Bisect, per system, the largest ``omega_max dt`` whose run from ``(x0, u0)`` stays bounded.

    ``lo`` must be bounded and ``hi`` growing for every system (checked; a bracket that fails raises
    ``ValueError``).

    Parameters
    ----------
    x0 : numpy.ndarray, shape (B, n)
        Initial positions.
    u0 : numpy.ndarray, shape (B, n)
        Initial half-step velocities.
    K : numpy.ndarray, shape (n, n) or (B, n, n)
        Symmetric stiffness matrix [N/m], shared or one per system.
    inv_mass : numpy.ndarray, shape (n,) or (B, n)
        Inverse masses [1/kg] (M diagonal).
    alpha : float or numpy.ndarray, shape (B,)
        Local damping coefficient, 0 <= alpha < 1.
    law : {"pfc", "yade"}
        Whose sign of the power is read (module docstring).
    omega_max : float or numpy.ndarray, shape (B,)
        Largest undamped angular frequency [rad/s] (:func:`omega_max`); the step is ``omega_max dt``.
    lo : float or numpy.ndarray, shape (B,)
        Bounded end of the bracket, in ``omega_max dt``.
    hi : float or numpy.ndarray, shape (B,)
        Growing end of the bracket, in ``omega_max dt``.
    iterations : int
        Bisection steps.
    n_steps : int
        Steps of each run (:func:`grows`).
    blowup : float
        Growth that counts as unstable.

    Returns
    -------
    numpy.ndarray, shape (B,)
        The upper end of the final bracket (growing side), in ``omega_max dt``.
    """
    batch = x0.shape[0]
    w = np.broadcast_to(np.asarray(omega_max, dtype=float), (batch,))
    lo = np.broadcast_to(np.asarray(lo, dtype=float), (batch,)).copy()
    hi = np.broadcast_to(np.asarray(hi, dtype=float), (batch,)).copy()
    if grows(x0, u0, lo / w, K, inv_mass, alpha, law, n_steps, blowup).any():
        raise ValueError("bisect_threshold: the lower end of the bracket is not stable")
    if not grows(x0, u0, hi / w, K, inv_mass, alpha, law, n_steps, blowup).all():
        raise ValueError("bisect_threshold: the upper end of the bracket is not unstable")
    for _ in range(iterations):
        mid = 0.5 * (lo + hi)
        g = grows(x0, u0, mid / w, K, inv_mass, alpha, law, n_steps, blowup)
        hi = np.where(g, mid, hi)
        lo = np.where(g, lo, mid)
    return hi


def chain(masses, springs):
    """Stiffness matrix and inverse masses of a 1-D chain: ``springs[0]`` ties mass 0 to a wall,
    ``springs[i]`` masses i-1 and i; one more spring than masses ties the last to a second wall.

    Parameters
    ----------
    masses : array_like
        Masses [kg].
    springs : array_like
        Spring stiffnesses [N/m], ``len(masses)`` or ``len(masses) + 1`` of them.

    Returns
    -------
    tuple of numpy.ndarray
        ``(K, inv_mass)``: the (n, n) stiffness matrix and the inverse masses.
    """
    m = np.asarray(masses, dtype=float)
    k = np.asarray(springs, dtype=float)
    n = m.size
    if k.size not in (n, n + 1):
        raise ValueError("chain: need len(springs) == len(masses) or len(masses) + 1")
    K = np.zeros((n, n))
    for i in range(n):
        K[i, i] += k[i]
        if i > 0:
            K[i - 1, i - 1] += k[i]
            K[i, i - 1] -= k[i]
            K[i - 1, i] -= k[i]
    if k.size == n + 1:
        K[n - 1, n - 1] += k[n]
    return K, 1.0 / m


def sphere_wall_sphere(normal, m1, m2, kn_wall, ks_wall, kn, ks):
    """6-DOF translational stiffness (global x, y, z of each sphere) of sphere 1 on a fixed wall and
    sphere 2 on sphere 1, both contacts along the unit ``normal`` (normal and tangential springs).

    Parameters
    ----------
    normal : array_like, shape (3,)
        Contact normal (normalised here).
    m1 : float
        Mass of sphere 1 [kg].
    m2 : float
        Mass of sphere 2 [kg].
    kn_wall : float
        Normal stiffness of the wall contact [N/m].
    ks_wall : float
        Tangential stiffness of the wall contact [N/m].
    kn : float
        Normal stiffness of the sphere-sphere contact [N/m].
    ks : float
        Tangential stiffness of the sphere-sphere contact [N/m].

    Returns
    -------
    tuple of numpy.ndarray
        ``(K, inv_mass)``: the (6, 6) stiffness matrix and the 6 inverse masses.
    """
    n = np.asarray(normal, dtype=float)
    n = n / np.linalg.norm(n)
    P = np.outer(n, n)
    Q = np.eye(3) - P
    Kw = kn_wall * P + ks_wall * Q
    Kc = kn * P + ks * Q
    K = np.zeros((6, 6))
    K[:3, :3] = Kw + Kc
    K[3:, 3:] = Kc
    K[:3, 3:] = -Kc
    K[3:, :3] = -Kc
    inv_mass = np.concatenate([np.full(3, 1.0 / m1), np.full(3, 1.0 / m2)])
    return K, inv_mass


def omega_max(K, inv_mass):
    """Largest undamped angular frequency: ``sqrt(lambda_max(M^{-1/2} K M^{-1/2}))`` (symmetric eigen-solve).

    Parameters
    ----------
    K : numpy.ndarray, shape (n, n)
        Symmetric stiffness matrix [N/m].
    inv_mass : array_like, shape (n,)
        Inverse masses [1/kg].

    Returns
    -------
    float
        ``omega_max`` [rad/s].
    """
    s = np.sqrt(np.asarray(inv_mass, dtype=float))
    return float(np.sqrt(np.linalg.eigvalsh(s[:, None] * K * s[None, :])[-1]))
