"""Numerically careful evaluation of the exact critical steps (runtime; no SymPy).

The generated kernels ``dtcrit._generated.critical_steps.dt_<name>(omega, gamma)`` are exact
closed forms; evaluating them well for *every* float64 input needs three more things, collected
here and used by ``dtcrit.integrators.stability``:

* a power-of-two scale taken from the **larger** of omega = sqrt(k A) and gamma = c A / 2 (the
  kernels are homogeneous of degree -1, so ``dt = 2^-s dt(omega 2^-s, gamma 2^-s)`` exactly), so that
  neither rate overflows even when zeta = gamma/omega is beyond float64 (``scaled_closed_form``);
* forward Euler near critical damping: ``zeta^2 - 1`` is ill-conditioned in the rounded rates, so
  the residual ``R = c^2 A - 4 k`` is computed exactly from the float inputs with error-free
  products (Dekker) and ``dt = c/k`` (zeta <= 1) or ``4/(c A + sqrt(A R))`` (``forward_euler_exact``);
* the Eq. (40) scheme's cubic ``tau (tau - 2 zeta)^2 + 2 (tau - zeta) = 0`` gives
  ``tau* = zeta / (1 + (tau* - 2 zeta)^2 / 2)``, so for zeta <= 1 the step is
  ``(c / 2k) / (1 + (tau* - 2 zeta)^2 / 2)`` with the root entering only a correction
  (``paper_eq40_identity``).

``tests/integrators/test_precise.py`` checks symbolically that these forms are the derived closed forms.
(First written for the bench's fused kernels; moved here so every route shares them.)

``fast_steps`` (used by ``critical_dt_array``) evaluates every scheme chunk by chunk in the unscaled
rates where they cannot overflow, and falls back to the scaled forms above elsewhere:

* the central-difference family ``2/(g + sqrt(g^2 + K))``, the centred leapfrog ``2/sqrt(K)``;
* forward Euler ``min(c/k, 4/(u + sqrt(u^2 - 4K)))``; only the scenes with 7/8 < zeta^2 < 9/8 (about
  15 % of the bench's batch, which draws that many near-critical scenes) are redone with the exact
  residual, gathered from all chunks;
* the Eq. (40) cubic in bounded variables (``dtcrit.integrators.precise_eq40``: w = c^2 A/(2k + c^2 A) in [0, 1],
  root r in (1, 3/2), dt = (c/2) r/(k + c^2 A/2)), two Halley steps and one Newton step for every
  element at once, no branch on zeta.
"""
from __future__ import annotations

import numpy as np

from dtcrit._generated import critical_steps as _gen
from dtcrit.integrators import precise_onstep
from dtcrit.integrators.precise_eq40 import _K_HI, _K_LO, _eq40_chunk
from dtcrit.numerics.cubic import cubic_positive_root
from dtcrit.numerics.eft import split as _split
from dtcrit.numerics.eft import two_product as _two_prod
from dtcrit.numerics.eft import two_sum as _two_sum
from dtcrit.numerics.scaling import frexp_parts, scaled_root


def _residual(mc, mA, mk, shift):
    """mc^2 mA 2^shift - 4 mk to about one rounding, for mantissas in [1/2, 1) and |shift| <= 64.

    c^2 = p + e and p A = q + f, e A = r + r2 are error-free, so c^2 A = q + f + r + r2 exactly;
    the five terms (scaled by 2^shift where needed) are summed with compensated two-sums.
    """
    p, e = _two_prod(mc, mc)
    q, f = _two_prod(p, mA)
    r, r2 = _two_prod(e, mA)
    q, f, r, r2 = (np.ldexp(x, shift) for x in (q, f, r, r2))
    s, err = _two_sum(q, -4.0 * mk)  # exact when the two are close (Sterbenz)
    for term in (f, r, r2):
        s, e2 = _two_sum(s, term)
        err = err + e2
    return s + err


def forward_euler_exact(k, c, A):
    """Forward Euler's critical step with the near-critical residual evaluated exactly.

    dt = c/k (c^2 A <= 4k, i.e. zeta <= 1; tau* = 2 zeta) else 4/(u + sqrt(A R)),
    R = c^2 A - 4k (tau* = 2/(zeta + sqrt(zeta^2 - 1))).  Every input is split into mantissa and
    exponent; all arithmetic is on O(1) numbers and the exponents are put back with ldexp.

    Parameters
    ----------
    k, c, A : float or array_like
        Stiffness [N/m], viscous damping coefficient [N s/m] and inverse inertia coefficient [1/kg].

    Returns
    -------
    numpy.ndarray
        The critical step [s], elementwise.
    """
    k, c, A = (np.asarray(v, dtype=float) for v in (k, c, A))
    mk, ek, mc, ec, mA, eA = frexp_parts(k, c, A)
    E = 2 * ec + eA - ek  # c^2 A / (4k) ~ mc^2 mA / (4 mk) * 2^E
    with np.errstate(all="ignore"):
        under = np.ldexp(mc / mk, ec - ek)  # c / k
        near = np.abs(E) <= 64
        Rn = _residual(mc, mA, mk, np.clip(E, -64, 64))  # R / 2^ek, valid where near
        over = np.where(near, Rn > 0, E > 0) & (c > 0)
        # A R = mA Rn 2^(eA + ek); u = mc mA 2^(ec + eA); common scale 2^S, S = ec + eA
        #   A R / 2^(2S) = mA Rn 2^(ek - 2 ec - eA) = mA Rn 2^(-E)
        far = np.ldexp(mc * mc * mA, 0) - np.ldexp(4.0 * mk, -np.clip(E, -1100, 1100))  # E > 64: R/2^(2ec+eA)
        ar = np.where(near, np.ldexp(mA * Rn, -np.clip(E, -64, 64)), mA * far)
        u = mc * mA
        dt_over = np.ldexp(4.0 / (u + np.sqrt(np.maximum(ar, 0.0))), -(ec + eA))
    return np.where(over, dt_over, under)


def scaled_closed_form(integrator: str, k, c, A) -> np.ndarray:
    """The generated kernel ``dt_<integrator>(omega, gamma)`` with a power-of-two scale taken from
    the *larger* of omega = sqrt(k A) and gamma = c A / 2 (``critical_dt_array`` scales by omega
    alone, so gamma/omega beyond float64 -- k = 1e-300, c = 1e300, A = 1e-10 -- overflows there and
    the step comes out as 0).  The kernels are homogeneous of degree -1, so
    dt = 2^-s dt(omega 2^-s, gamma 2^-s) exactly; the smaller rate may underflow harmlessly.
    The centred leapfrog (dt = 2/omega whatever gamma) is scaled by omega alone.

    Parameters
    ----------
    integrator : str
        Name of a built-in integrator (a key of ``dtcrit._generated.critical_steps.DT_KERNELS``).
    k, c, A : float or array_like
        Stiffness [N/m], viscous damping coefficient [N s/m] and inverse inertia coefficient [1/kg].

    Returns
    -------
    numpy.ndarray
        The critical step [s] (0 where no positive step is stable or it underflows, inf beyond float64).
    """
    k, c, A = (np.asarray(v, dtype=float) for v in (k, c, A))
    mk, ek, mc, ec, mA, eA = frexp_parts(k, c, A)
    w, sw = scaled_root(mk, ek, mA, eA)  # omega = w 2^sw, w in [1/2, 1.42)
    gm = mc * mA * 0.5  # gamma = gm 2^sg
    sg = ec + eA
    if integrator == "leapfrog-centred":
        s = sw
    else:
        s = np.where(gm > 0, np.maximum(sw, sg), sw)
    with np.errstate(all="ignore"):
        w1 = np.ldexp(w, sw - s)
        g1 = np.ldexp(gm, np.where(gm > 0, sg - s, 0))
        return np.ldexp(_gen.DT_KERNELS[integrator](w1, g1), -s)


def paper_eq40_identity(k, c, A) -> np.ndarray:
    """Critical step of the paper's Eq. (40) scheme from an identity of its boundary cubic.

    The cubic tau^3 - 4 zeta tau^2 + (4 zeta^2 + 2) tau - 2 zeta = tau (tau - 2 zeta)^2 + 2 (tau - zeta) = 0
    gives the identity

        tau* = zeta / (1 + (tau* - 2 zeta)^2 / 2),  so  dt = (c / (2k)) / (1 + (tau* - 2 zeta)^2 / 2),

    where c/(2k) = gamma/omega^2 comes straight from the inputs (one rounding) and the root tau*
    (the generated cubic solver) enters only through a correction term.  Used for zeta <= 1; for
    zeta > 1 (tau* ~ 1/(2 zeta)) the generated reciprocal-cubic branch is kept.

    Parameters
    ----------
    k, c, A : float or array_like
        Stiffness [N/m], viscous damping coefficient [N s/m] and inverse inertia coefficient [1/kg].

    Returns
    -------
    numpy.ndarray
        The critical step [s] of the Eq. (40) scheme, elementwise (flattened like ``k``).
    """
    k, c, A = (np.asarray(v, dtype=float) for v in (k, c, A))
    mk, ek, mA, eA, mc, ec = frexp_parts(k, A, c)
    w, s = scaled_root(mk, ek, mA, eA)
    with np.errstate(all="ignore"):
        g = np.ldexp(mc * mA * 0.5, ec + eA - s)
        z = g / w
        small = (z <= 1.0) & (c > 0)
        out = np.empty(np.shape(z))
        rest = ~small
        if np.any(rest):  # zeta > 1 or undamped: the generated kernel (its reciprocal-cubic branch)
            out[rest] = scaled_closed_form("paper-eq40", k[rest], c[rest], A[rest])
        if np.any(small):
            zs = z[small]
            t = cubic_positive_root(-4.0 * zs, 4.0 * zs * zs + 2.0, -2.0 * zs, False)
            d = t - 2.0 * zs
            half_c_over_k = np.ldexp(mc[small] / mk[small], ec[small] - ek[small] - 1)
            out[small] = half_c_over_k / (1.0 + 0.5 * d * d)
    return out


_CHUNK = 1 << 15
_REDO_CHUNK = 1 << 12  # small temporaries: no fresh pages per operation
_U_HI = 2.0**500
_HYPOT_FAMILY = {"symplectic-euler": 0.5, "leapfrog": 0.5, "velocity-verlet": 0.5, "velocity-verlet-predicted": 1.0}


def _forward_euler_chunk(k, c, A, o, B):
    """Forward Euler on one chunk: dt = min(c/k, 4/(u + sqrt(max(u^2 - 4K, 0)))) with K = k A, u = c A
    (c/k <= 4/u exactly when zeta <= 1, and 4/(u + sqrt(u^2 - 4K)) < c/k when zeta > 1).  Returns the
    (local) indices of the scenes with |u^2 - 4K| < 4K/8 (7/8 < zeta^2 < 9/8, where the rounded rates
    lose digits), which the caller redoes with the exact residual (``_forward_euler_redo``), all chunks
    at once; False when K or u is outside the unscaled range.
    """
    K, u, t, a = B
    np.multiply(k, A, out=K)
    np.multiply(c, A, out=u)
    if not (K.min() >= _K_LO and K.max() <= _K_HI and u.max() <= _U_HI):
        return False
    K *= 4.0
    np.multiply(u, u, out=t)
    t -= K  # u^2 - 4K = A R
    np.abs(t, out=a)
    a *= 8.0
    near = np.flatnonzero(a < K)
    np.maximum(t, 0.0, out=t)
    np.sqrt(t, out=t)
    t += u
    np.divide(4.0, t, out=t)
    np.divide(c, k, out=o)
    np.minimum(o, t, out=o)
    return near


def _forward_euler_redo(k, c, A):
    """The near-critical scenes of ``_forward_euler_chunk`` with the exact residual: unscaled
    error-free products (``_forward_euler_near``) where 2^-450 <= c <= 2^450 and k, A lie in
    [2^-900, 2^900] (no split overflows, no error term underflows), ``forward_euler_exact`` elsewhere.
    """
    ok = (c >= _C_LO) & (c <= _C_HI) & (k >= _KA_LO) & (k <= _KA_HI) & (A >= _KA_LO) & (A <= _KA_HI)
    if ok.all():
        return _forward_euler_near(k, c, A)
    return np.where(ok, _forward_euler_near(k, c, A), forward_euler_exact(k, c, A))


_C_LO, _C_HI, _KA_LO, _KA_HI = 2.0**-450, 2.0**450, 2.0**-900, 2.0**900


def _forward_euler_near(k, c, A):
    """c/k or 4/(c A + sqrt(A R)), R = c^2 A - 4k summed from error-free products, for scenes with
    7/8 < zeta^2 < 9/8 and the ranges of ``_forward_euler_redo``: c^2 = p + e, p A = q + f and
    e A = r + r2 exactly (Dekker), q - 4k is exact (Sterbenz: q/4k lies in [1/2, 2]), and the small
    terms f + r + r2 are summed last (their rounding, ~2^-106 c^2 A, moves dt by less than an ulp).
    """
    ch, cl = _split(c)
    p = c * c
    e = ((ch * ch - p) + 2.0 * ch * cl) + cl * cl
    ph, pl = _split(p)
    Ah, Al = _split(A)
    q = p * A
    f = ((ph * Ah - q) + ph * Al + pl * Ah) + pl * Al
    eh, el = _split(e)
    r = e * A
    r2 = ((eh * Ah - r) + eh * Al + el * Ah) + el * Al
    R = (q - 4.0 * k) + ((f + r) + r2)
    with np.errstate(all="ignore"):
        over = 4.0 / (c * A + np.sqrt(np.maximum(A * R, 0.0)))
    return np.where(R > 0, over, c / k)


def _hypot_chunk(half):
    def chunk(k, c, A, o, B) -> bool:
        K, g = B[0], B[1]
        np.multiply(k, A, out=K)
        np.multiply(c, A, out=g)
        if not (K.min() >= _K_LO and K.max() <= _K_HI and g.max() <= _U_HI):
            return False
        g *= half
        np.multiply(g, g, out=o)
        o += K
        np.sqrt(o, out=o)
        o += g
        np.divide(2.0, o, out=o)
        return True

    return chunk


def _centred_chunk(k, c, A, o, B) -> bool:
    K = B[0]
    np.multiply(k, A, out=K)
    if not (K.min() >= _K_LO and K.max() <= _K_HI):
        return False
    np.sqrt(K, out=K)
    np.divide(2.0, K, out=o)
    return True


_CHUNKS = {name: _hypot_chunk(h) for name, h in _HYPOT_FAMILY.items()}
_CHUNKS["leapfrog-centred"] = _centred_chunk
_CHUNKS["forward-euler"] = _forward_euler_chunk
_CHUNKS["paper-eq40"] = _eq40_chunk
_BUFFERS = {"forward-euler": 4, "paper-eq40": 9}
# the schemes whose fast path can give 0 (no stable step when undamped, or an underflowed c/k)
_ZERO_WHEN_UNDAMPED = ("forward-euler", "paper-eq40")


def _slow(integrator: str, k, c, A):
    if integrator in precise_onstep.CAREFUL:
        return precise_onstep.steps(integrator, k, c, A)
    if integrator == "forward-euler":
        return forward_euler_exact(k, c, A)
    if integrator == "paper-eq40":
        return paper_eq40_identity(k, c, A)
    return scaled_closed_form(integrator, k, c, A)


def fast_steps(integrator: str, k, c, A, chunk: int = _CHUNK) -> tuple[np.ndarray, bool]:
    """(dt, checked): the exact step chunk by chunk (temporaries stay in cache).  A chunk whose rates
    lie in the unscaled range takes the fast form of its scheme (``_CHUNKS``: the closed form in the
    rates K = k A, u = c A for the central-difference family, ``_forward_euler_chunk``,
    ``_eq40_chunk``); other chunks take the scaled forms (``scaled_closed_form``,
    ``forward_euler_exact``, ``paper_eq40_identity``), which have no limits.  ``checked`` is True when
    every chunk was fast and none holds a step outside float64 (inf, NaN, or 0 for a damped contact),
    so that ``stability.refuse_unrepresentable`` has nothing to find.

    Parameters
    ----------
    integrator : str
        Name of a built-in integrator.
    k, c, A : float or array_like
        Stiffness [N/m], viscous damping coefficient [N s/m] and inverse inertia coefficient [1/kg].
    chunk : int, optional
        Number of elements per chunk.

    Returns
    -------
    tuple of (numpy.ndarray, bool)
        ``(dt, checked)``: the flattened steps [s] and whether every chunk was fast and in range.
    """
    k, c, A = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (k, c, A)))
    k, c, A = (np.ascontiguousarray(v.ravel()) for v in (k, c, A))
    if integrator in precise_onstep.CAREFUL:  # whole-array forms; the caller checks the range
        return precise_onstep.steps(integrator, k, c, A), False
    n = k.size
    out = np.empty(n)
    m = max(1, min(chunk, n))
    B = [np.empty(m) for _ in range(_BUFFERS.get(integrator, 2))]
    kern = _CHUNKS[integrator]
    zero_ok = integrator in _ZERO_WHEN_UNDAMPED
    checked = True
    redo = []
    with np.errstate(all="ignore"):
        for i in range(0, n, m):
            j = min(n, i + m)
            w = j - i
            o = out[i:j]
            done = kern(k[i:j], c[i:j], A[i:j], o, [b[:w] for b in B])
            if done is False:
                o[:] = _slow(integrator, k[i:j], c[i:j], A[i:j])
                checked = False
                continue
            if zero_ok and checked and np.count_nonzero(o) != np.count_nonzero(c[i:j]):
                checked = False  # a damped contact whose step underflowed (refused by the caller)
            if done is not True and done.size:
                redo.append(done + i)
        if redo:  # forward Euler's near-critical scenes of all chunks, gathered, in small chunks
            idx = np.concatenate(redo)
            kn, cn, An = k[idx], c[idx], A[idx]
            dn = np.empty(idx.size)
            for i in range(0, idx.size, _REDO_CHUNK):
                j = min(idx.size, i + _REDO_CHUNK)
                dn[i:j] = _forward_euler_redo(kn[i:j], cn[i:j], An[i:j])
            out[idx] = dn
    return out, checked


def fast_closed_form(integrator: str, k, c, A) -> np.ndarray:
    """The exact step of ``integrator`` for every float64 input (``fast_steps`` without the flag).

    Parameters
    ----------
    integrator : str
        Name of a built-in integrator.
    k, c, A : float or array_like
        Stiffness [N/m], viscous damping coefficient [N s/m] and inverse inertia coefficient [1/kg].

    Returns
    -------
    numpy.ndarray
        The flattened critical steps [s].
    """
    return fast_steps(integrator, k, c, A)[0]
