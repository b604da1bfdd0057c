"""Fused, in-place forms of the closed-form critical steps (section 4 of the benchmark).

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
* forward Euler and the paper's printed scheme (``paper-eq40``, a cubic): the runtime's own
  chunked forms, ``dtcrit.integrators.precise.fast_steps`` (forward Euler as
  ``min(c/k, 4/(u + sqrt(u^2 - 4K)))`` with the near-critical scenes, 7/8 < zeta^2 < 9/8, redone
  with the exact residual ``R = c^2 A - 4 k``; the cubic in bounded variables solved by two Halley
  steps and a Newton step), so this route and ``critical_dt_array`` agree there.

Fast path: a chunk whose ``K`` lies in [2^-1000, 2^1000] and whose ``u`` is at most 2^500 needs
no scaling (``g^2 + K`` can neither overflow nor lose ``K`` to underflow, and the step is a
normal number); other chunks go through ``scaled_closed_form`` (the generated kernel, scaled by a
power of two taken from the larger rate), which has no limits.  A step that lies beyond or below
float64's range is refused (InputError), never returned as inf or as 0 (= "no stable step").
"""
from __future__ import annotations

import numpy as np

import dtcrit.integrators.precise_onstep as onstep
from dtcrit.integrators.precise import fast_steps, scaled_closed_form
from dtcrit.integrators.stability import check_integrator, refuse_unrepresentable

CHUNK = 1 << 14
_K_LO, _K_HI, _U_HI = 2.0**-1000, 2.0**1000, 2.0**500

FUSED = ("symplectic-euler", "leapfrog", "velocity-verlet", "velocity-verlet-predicted", "leapfrog-centred", "forward-euler",
         "paper-eq40")


def _hypot_family(half: bool):
    """The step dt = 2 / (g + sqrt(g^2 + K)), g = u/2 if ``half`` else u (Peng et al. 2020 Eq. (30) rates)."""

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


def critical_dt_fused(integrator: str, k, c, A, chunk: int = CHUNK) -> np.ndarray:
    """Critical step [s] for float arrays k [N/m], c [N s/m], A [1/kg] (same values as the
    generated closed forms, within 4 ulp of the exact step; see the module docstring).

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].
    chunk : int
        Scenes per block (keeps the temporaries in cache).

    Returns
    -------
    numpy.ndarray
        The critical steps [s], flattened.
    """
    name = check_integrator(integrator)
    k, c, A = np.broadcast_arrays(*(np.ascontiguousarray(np.atleast_1d(v), dtype=float) for v in (k, c, A)))
    k, c, A = (np.ascontiguousarray(v.ravel()) for v in (k, c, A))
    n = k.size
    if name in ("paper-eq40", "forward-euler"):  # the runtime's chunked forms (dtcrit.integrators.precise)
        dt, checked = fast_steps(name, k, c, A, chunk)
        return dt if checked else refuse_unrepresentable(name, dt, k, c, A)
    if name in onstep.SCHEMES:  # the on-step schemes' own careful forms (dtcrit.integrators.precise_onstep)
        return refuse_unrepresentable(name, onstep.steps(name, k, c, A), k, c, A)
    if name not in FUSED:
        return refuse_unrepresentable(name, scaled_closed_form(name, k, c, A), k, c, A)
    if name == "leapfrog-centred":
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
                out[i:j] = scaled_closed_form(name, k[i:j], c[i:j], A[i:j])
                slow = True
    # the fast path of the hypot family and the centred leapfrog cannot leave the normal range
    return refuse_unrepresentable(name, out, k, c, A) if slow else out
