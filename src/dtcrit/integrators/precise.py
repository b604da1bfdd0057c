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

``tests/test_precise.py`` checks symbolically that these forms are the derived closed forms.
(First written for the bench's fused kernels, issue 5; moved here so every route shares them.)
"""
from __future__ import annotations

import numpy as np

from dtcrit._generated import critical_steps as _gen

_SPLIT = 134217729.0  # 2^27 + 1 (Dekker)


def _two_prod(a, b):
    """(p, e) with p + e = a*b exactly (Dekker's splitting; |a|, |b| < 2^995)."""
    p = a * b
    t = _SPLIT * a
    ah = t - (t - a)
    al = a - ah
    t = _SPLIT * b
    bh = t - (t - b)
    bl = b - bh
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


def _two_sum(a, b):
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


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
    """
    k, c, A = (np.asarray(v, dtype=float) for v in (k, c, A))
    mk, ek = np.frexp(k)
    mc, ec = np.frexp(c)
    mA, eA = np.frexp(A)
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
    The centred leapfrog (dt = 2/omega whatever gamma) is scaled by omega alone."""
    k, c, A = (np.asarray(v, dtype=float) for v in (k, c, A))
    mk, ek = np.frexp(k)
    mc, ec = np.frexp(c)
    mA, eA = np.frexp(A)
    e = ek + eA
    odd = e & 1
    w = np.sqrt(mk * mA * np.where(odd, 2.0, 1.0))  # omega = w 2^sw, w in [1/2, 1.42)
    sw = (e - odd) // 2
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
    """The paper's Eq. (40) scheme: its boundary cubic tau^3 - 4 zeta tau^2 + (4 zeta^2 + 2) tau - 2 zeta
    = tau (tau - 2 zeta)^2 + 2 (tau - zeta) = 0 gives the identity

        tau* = zeta / (1 + (tau* - 2 zeta)^2 / 2),  so  dt = (c / (2k)) / (1 + (tau* - 2 zeta)^2 / 2),

    where c/(2k) = gamma/omega^2 comes straight from the inputs (one rounding) and the root tau*
    (the generated cubic solver) enters only through a correction term.  Used for zeta <= 1; for
    zeta > 1 (tau* ~ 1/(2 zeta)) the generated reciprocal-cubic branch is kept."""
    k, c, A = (np.asarray(v, dtype=float) for v in (k, c, A))
    mk, ek = np.frexp(k)
    mA, eA = np.frexp(A)
    mc, ec = np.frexp(c)
    e = ek + eA
    odd = e & 1
    w = np.sqrt(mk * mA * np.where(odd, 2.0, 1.0))
    s = (e - odd) // 2
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
            t = _gen._cubic_positive_root(-4.0 * zs, 4.0 * zs * zs + 2.0, -2.0 * zs, False)
            d = t - 2.0 * zs
            half_c_over_k = np.ldexp(mc[small] / mk[small], ec[small] - ek[small] - 1)
            out[small] = half_c_over_k / (1.0 + 0.5 * d * d)
    return out


_CHUNK = 1 << 14
_K_LO, _K_HI, _U_HI = 2.0**-1000, 2.0**1000, 2.0**500
_HYPOT_FAMILY = {"symplectic-euler": 0.5, "leapfrog": 0.5, "velocity-verlet": 0.5, "velocity-verlet-predicted": 1.0}


def fast_closed_form(integrator: str, k, c, A) -> np.ndarray:
    """``scaled_closed_form`` with a fast path, chunk by chunk (temporaries stay in cache): where
    K = k A lies in [2^-1000, 2^1000] and u = c A <= 2^500, no scaling is needed and the closed form
    is evaluated directly in the rates, ``2 / (g + sqrt(g^2 + K))`` with ``g = u/2`` (``u`` for the
    predicted velocity Verlet; tau* = 2/(zeta + sqrt(zeta^2 + 1)) resp. 2/(2 zeta + sqrt(4 zeta^2 + 1)))
    and ``2 / sqrt(K)`` for the centred leapfrog (tau* = 2): g^2 + K neither overflows nor loses K,
    so each form is within a few roundings of the exact step.  Other chunks take ``scaled_closed_form``."""
    half = _HYPOT_FAMILY.get(integrator)
    if half is None and integrator != "leapfrog-centred":
        return scaled_closed_form(integrator, k, c, A)
    k, c, A = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (k, c, A)))
    k, c, A = (np.ascontiguousarray(v.ravel()) for v in (k, c, A))
    n = k.size
    out = np.empty(n)
    m = max(1, min(_CHUNK, n))
    K, g = np.empty(m), np.empty(m)
    with np.errstate(all="ignore"):
        for i in range(0, n, m):
            j = min(n, i + m)
            Kw, gw, o = K[: j - i], g[: j - i], out[i:j]
            np.multiply(k[i:j], A[i:j], out=Kw)
            if half is None:
                if Kw.min() >= _K_LO and Kw.max() <= _K_HI:
                    np.sqrt(Kw, out=Kw)
                    np.divide(2.0, Kw, out=o)
                    continue
            else:
                np.multiply(c[i:j], A[i:j], out=gw)
                if Kw.min() >= _K_LO and Kw.max() <= _K_HI and gw.max() <= _U_HI:
                    gw *= half
                    np.multiply(gw, gw, out=o)
                    o += Kw
                    np.sqrt(o, out=o)
                    o += gw
                    np.divide(2.0, o, out=o)
                    continue
            o[:] = scaled_closed_form(integrator, k[i:j], c[i:j], A[i:j])
    return out
