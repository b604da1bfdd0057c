"""Fused, in-place forms of the closed-form critical steps (issue 5, section 4).

The generated kernels (``dtcrit._generated.critical_steps`` through ``critical_dt_array``) take
every input through ``frexp``/``ldexp`` scaling and ``np.hypot``; both cost many passes over
memory, and NumPy's ``hypot`` alone is about ten times a square root.  The forms here evaluate
the *same* closed forms chunk by chunk (temporaries stay in cache, nothing is allocated per
chunk) in the rates ``K = k A`` and ``u = c A`` (``omega^2 = K``, ``gamma = u/2``):

* symplectic Euler, leapfrog, velocity Verlet (tau* = 2/(zeta + sqrt(zeta^2 + 1)), the CFL note's
  bound): ``dt = 2 / (g + sqrt(g^2 + K))`` with ``g = u/2``;
* velocity Verlet with predicted velocity (tau* = 2/(2 zeta + sqrt(4 zeta^2 + 1))):
  ``dt = 2 / (u + sqrt(u^2 + K))``;
* leapfrog with centred damping (tau* = 2): ``dt = 2 / sqrt(K)``;
* forward Euler (tau* = 2 zeta for zeta <= 1, 2/(zeta + sqrt(zeta^2 - 1)) beyond):
  ``dt = c/k`` when ``c^2 A <= 4 k``, else ``dt = 4 / (u + sqrt(u^2 - 4K))``; where
  1 - 2^-48 < zeta^2 < 16/15 the scene is redone as ``dt = 4 / (u + sqrt(A R))`` with the residual
  ``R = c^2 A - 4 k`` evaluated *exactly* (error-free products, see ``_residual``).  Near
  critical damping ``zeta^2 - 1`` is ill-conditioned in the rounded rates (a relative error of
  1e-16 in ``u`` or ``K`` moves ``sqrt(zeta^2 - 1)`` by ~1e-8 at ``zeta = 1 + 1e-16``), so the
  residual has to come from the float inputs themselves, not from ``u`` and ``K``.

Fast path: a chunk whose ``K`` lies in [2^-1000, 2^1000] and whose ``u`` is at most 2^500 needs
no scaling (``g^2 + K`` can neither overflow nor lose ``K`` to underflow, and the step is a
normal number); other chunks go through ``scaled_closed_form`` (the generated kernel, scaled by a
power of two taken from the larger rate), which has no limits.  A step that lies beyond or below
float64's range is refused (InputError), never returned as inf or as 0 (= "no stable step").
Forward Euler's out-of-range chunks go through ``forward_euler_exact`` (all arithmetic on
mantissas, exponents put back with ``ldexp``).  The paper's printed scheme (``paper-eq40``, a cubic) is not fused: ``paper_eq40_identity`` uses the
generated cubic solver for the root and an identity of the cubic for the last roundings.
"""
from __future__ import annotations

import numpy as np

from dtcrit._generated import critical_steps as _gen
from dtcrit.errors import InputError
from dtcrit.integrators.precise import _two_prod, _two_sum, forward_euler_exact, paper_eq40_identity, scaled_closed_form
from dtcrit.integrators.stability import check_integrator, refuse_unrepresentable

CHUNK = 1 << 14
_K_LO, _K_HI, _U_HI = 2.0**-1000, 2.0**1000, 2.0**500

FUSED = ("symplectic-euler", "leapfrog", "velocity-verlet", "velocity-verlet-predicted", "leapfrog-centred", "forward-euler")


def _hypot_family(half: bool):
    """dt = 2 / (g + sqrt(g^2 + K)), g = u/2 if ``half`` else u (Peng et al. 2020 Eq. (30) rates)."""

    def chunk(k, c, A, out, K, g, t):
        np.multiply(k, A, out=K)
        np.multiply(c, A, out=g)
        if not (K.min() >= _K_LO and K.max() <= _K_HI and g.max() <= _U_HI):
            return False
        if half:
            g *= 0.5
        np.multiply(g, g, out=t)
        t += K
        np.sqrt(t, out=t)
        t += g
        np.divide(2.0, t, out=out)
        return True

    return chunk


def _centred(k, c, A, out, K, g, t):
    np.multiply(k, A, out=K)
    if not (K.min() >= _K_LO and K.max() <= _K_HI):
        return False
    np.sqrt(K, out=K)
    np.divide(2.0, K, out=out)
    return True


def _forward_euler_chunk(k, c, A, out, K, u, t):
    """Forward Euler on a chunk: c/k (zeta <= 1) or 4/(u + sqrt(u^2 - 4K)) (zeta >= 1); the scenes
    with 1 - 2^-48 < zeta^2 < 16/15 are redone with the exact residual (``_forward_euler_near``,
    or ``forward_euler_exact`` when c or A is too large or small to split unscaled)."""
    np.multiply(k, A, out=K)
    np.multiply(c, A, out=u)
    if not (K.min() >= _K_LO and K.max() <= _K_HI and u.max() <= _U_HI):
        return False
    K *= 4.0
    np.multiply(u, u, out=t)  # t / K = zeta^2
    # rounding can misplace the branch only within a few ulps of zeta = 1, and the 'over' form
    # loses digits as zeta^2 -> 1 (error ~ eps u / (2 sqrt(u^2 - 4K))): redo 1 - 2^-48 < zeta^2 < 16/15
    near = (t > (1.0 - 2.0**-48) * K) & (t < (16.0 / 15.0) * K)
    under = t <= K
    t -= K
    np.maximum(t, 0.0, out=t)
    np.sqrt(t, out=t)
    t += u
    np.divide(4.0, t, out=t)
    np.divide(c, k, out=out)
    np.copyto(out, t, where=~under)
    if near.any():
        kn, cn, An = k[near], c[near], A[near]
        if cn.max() <= _C_HI and An.min() >= _A_LO and An.max() <= _A_HI:
            out[near] = _forward_euler_near(kn, cn, An)  # unscaled error-free products
        else:
            out[near] = forward_euler_exact(kn, cn, An)
    return True


_C_HI, _A_LO, _A_HI = 2.0**400, 2.0**-400, 2.0**400


def _forward_euler_near(k, c, A):
    """c/k or 4/(u + sqrt(A R)) with R = c^2 A - 4k from error-free products, for unscaled inputs
    with c <= 2^400 and 2^-400 <= A <= 2^400 (and k A, c A in the fast path's range), so that no
    product of the splitting overflows and the error terms stay normal."""
    p, e = _two_prod(c, c)
    q, f = _two_prod(p, A)
    r, r2 = _two_prod(e, A)
    s, err = _two_sum(q, -4.0 * k)
    for term in (f, r, r2):
        s, e2 = _two_sum(s, term)
        err = err + e2
    R = s + err
    with np.errstate(all="ignore"):
        over = 4.0 / (c * A + np.sqrt(np.maximum(A * R, 0.0)))
    return np.where(R > 0, over, c / k)


def critical_dt_fused(integrator: str, k, c, A, chunk: int = CHUNK) -> np.ndarray:
    """Critical step [s] for float arrays k [N/m], c [N s/m], A [1/kg] (same values as the
    generated closed forms, within 4 ulp of the exact step; see the module docstring)."""
    name = check_integrator(integrator)
    k, c, A = np.broadcast_arrays(*(np.ascontiguousarray(np.atleast_1d(v), dtype=float) for v in (k, c, A)))
    k, c, A = (np.ascontiguousarray(v.ravel()) for v in (k, c, A))
    n = k.size
    if name == "paper-eq40":
        return refuse_unrepresentable(name, paper_eq40_identity(k, c, A), k, c, A)
    if name not in FUSED:
        return refuse_unrepresentable(name, scaled_closed_form(name, k, c, A), k, c, A)
    if name == "forward-euler":
        kern = _forward_euler_chunk
    elif name == "leapfrog-centred":
        kern = _centred
    else:
        kern = _hypot_family(half=name != "velocity-verlet-predicted")
    out = np.empty(n)
    m = max(1, min(chunk, n))
    K, g, t = np.empty(m), np.empty(m), np.empty(m)
    slow = False
    with np.errstate(all="ignore"):
        for i in range(0, n, m):
            j = min(n, i + m)
            w = j - i
            if not kern(k[i:j], c[i:j], A[i:j], out[i:j], K[:w], g[:w], t[:w]):
                if name == "forward-euler":
                    out[i:j] = forward_euler_exact(k[i:j], c[i:j], A[i:j])
                else:
                    out[i:j] = scaled_closed_form(name, k[i:j], c[i:j], A[i:j])
                slow = True
    # the fast path of the hypot family and the centred leapfrog cannot leave the normal range;
    # forward Euler's c/k can (zeta ~ 1e-300)
    return refuse_unrepresentable(name, out, k, c, A) if slow or name == "forward-euler" else out
