"""All roots of the quadratic and cubic characteristic polynomials of the integrators (NumPy only).

The numerically sound closed forms the generated eigenvalue kernels (``dtcrit._generated.eigenvalues``,
produced by ``dtcrit.symbolic.roots_codegen``) call: cancellation-free quadratic roots, and for the cubic
the isolated real root (Viete / hyperbolic form, Newton-polished) with the other two from the
deflated sum and product, split by ``sqrt(|Disc|) / (2 P'(r))``.  The discriminants arrive from the
kernels evaluated factor by factor in double-double (:func:`dtcrit.numerics.eft.dd_polynomial`).
"""
from __future__ import annotations

import numpy as np

_EPS = np.finfo(float).eps


def stack_roots(*roots):
    """Stack roots into one complex array.

    Parameters
    ----------
    *roots : array_like
        The roots, broadcast against each other.

    Returns
    -------
    numpy.ndarray
        Complex array of shape (number of roots,) + broadcast shape.
    """
    return np.stack(np.broadcast_arrays(*(np.asarray(r, dtype=complex) for r in roots)))


def principal_sqrt(x):
    """Principal complex square root (a negative real gives +i sqrt(-x)).

    Parameters
    ----------
    x : array_like
        Real or complex values.

    Returns
    -------
    numpy.ndarray
        The principal square root, complex.
    """
    return np.sqrt(np.asarray(x, dtype=complex))


def principal_cbrt(x):
    """Principal complex cube root, as a general-purpose complex power would take it.

    Parameters
    ----------
    x : array_like
        Real or complex values.

    Returns
    -------
    numpy.ndarray
        ``x^(1/3)`` on the principal branch, complex.
    """
    return np.power(np.asarray(x, dtype=complex), 1.0 / 3.0)


def sign_plus(x):
    """Sign with sgn(0) = +1.

    Parameters
    ----------
    x : array_like
        Real values.

    Returns
    -------
    numpy.ndarray
        -1.0 where ``x < 0``, else +1.0.
    """
    return np.where(x < 0, -1.0, 1.0)


def quadratic_roots(a, b, c, disc, sqrt_abs_disc):
    """Both roots of a l^2 + b l + c (a > 0) without cancellation.

    ``disc`` is the discriminant b^2 - 4ac evaluated from its factored form (only its sign is
    used) and ``sqrt_abs_disc`` = sqrt(|disc|), also from the factors.  Real roots:
    q = -(b + sgn(b) sqrt(D))/2, roots q/a and c/q; complex pair: -b/(2a) +- i sqrt(-D)/(2a).

    Parameters
    ----------
    a, b, c : array_like
        Coefficients (``a > 0``).
    disc : array_like
        The discriminant ``b^2 - 4ac`` (its sign decides real or complex roots).
    sqrt_abs_disc : array_like
        ``sqrt(|disc|)``, evaluated from the discriminant's factors.

    Returns
    -------
    numpy.ndarray
        Complex array of shape (2,) + broadcast shape: the larger-magnitude real root first, or the
        complex pair with the positive imaginary part first.
    """
    a, b, c, disc, s = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (a, b, c, disc, sqrt_abs_disc)))
    with np.errstate(all="ignore"):
        q = -(b + sign_plus(b) * s) / 2.0
        big = q / a
        small = np.where(q != 0, c / np.where(q != 0, q, 1.0), 0.0)
        re = -b / (2.0 * a)
        im = s / (2.0 * a)
    real = disc >= 0
    return stack_roots(np.where(real, big, re + 1j * im), np.where(real, small, re - 1j * im))


def cubic_roots(a2, a1, a0, p, q, disc, sqrt_abs_disc, disc_scale):
    """The three roots of l^3 + a2 l^2 + a1 l + a0, the isolated real root first.

    ``p``, ``q``: the depressed cubic t^3 + p t + q (l = t - a2/3), expanded symbolically and
    evaluated in double-double; ``disc`` = -4p^3 - 27q^2 from its factored form (double-double
    factors), ``sqrt_abs_disc`` = sqrt(|disc|), and ``disc_scale`` the same product with absolute
    coefficients.  Near a triple root the factored value is below its rounding error
    (~ eps^2 disc_scale); there -4p^3 - 27q^2 from the accurate p and q is used instead, whichever
    has the smaller error bound.

    1. The isolated real root t_r (the one farthest from the other two):
       disc >= 0: Viete, t = 2 sqrt(-p/3) cos(theta/3 - 2 pi k/3), theta = atan2(sqrt(disc),
       -3 sqrt(3) q), k = 0 if theta <= pi/2 else k = 2;
       disc < 0: hyperbolic form, t = -sgn(q) (E - p/E)/sqrt(3), E = ((3 sqrt(3)|q| + sqrt(-disc))/2)^(1/3)
       (= -2 sgn(q) sqrt(|p|/3) sinh or cosh of asinh/acosh(...)/3, written without 1/|p|).
    2. Two Newton steps on the cubic for r = t_r - a2/3, each taken only where its rounding
       error bound is below that of the closed form and it reduces |P|.
    3. Deflation: sum and product of the other two from whichever of (-(a2 + r), a1 - r sigma) and
       ((a1 - pi)/r, -a0/r) has the smaller error estimate (rounding plus the last Newton step).
    4. The other two roots sigma/2 +- d, d = sqrt(|disc|) / (2 P'(r)), P'(r) = 3 t_r^2 + p > 0;
       real: the larger from sigma/2 + sgn(sigma) d, the smaller as pi / larger.

    Parameters
    ----------
    a2, a1, a0 : array_like
        Coefficients of the monic cubic.
    p, q : array_like
        Coefficients of the depressed cubic ``t^3 + p t + q``.
    disc : array_like
        ``-4 p^3 - 27 q^2`` from its factored form.
    sqrt_abs_disc : array_like
        ``sqrt(|disc|)`` from the factors.
    disc_scale : array_like
        The discriminant's product with absolute coefficients (size of its cancelling terms).

    Returns
    -------
    numpy.ndarray
        Complex array of shape (3,) + broadcast shape, the isolated real root first.
    """
    a2, a1, a0, p, q, disc, sad, scale = np.broadcast_arrays(
        *(np.asarray(v, dtype=float) for v in (a2, a1, a0, p, q, disc, sqrt_abs_disc, disc_scale))
    )
    with np.errstate(all="ignore"):
        disc_pq = -4.0 * p**3 - 27.0 * q * q
        use_pq = 8.0 * _EPS * (4.0 * np.abs(p) ** 3 + 27.0 * q * q) < 8.0 * _EPS * _EPS * scale
        disc = np.where(use_pq, disc_pq, disc)
        sad = np.where(use_pq, np.sqrt(np.abs(disc_pq)), sad)
    three_real = disc >= 0
    with np.errstate(all="ignore"):
        # 1. isolated root of the depressed cubic
        radius = 2.0 * np.sqrt(np.maximum(-p, 0.0) / 3.0)
        theta = np.arctan2(sad, -3.0 * np.sqrt(3.0) * q)
        t_trig = radius * np.cos(np.where(theta <= np.pi / 2, theta / 3.0, theta / 3.0 + 2.0 * np.pi / 3.0))
        E = np.cbrt((3.0 * np.sqrt(3.0) * np.abs(q) + sad) / 2.0)
        t_hyp = np.where(E > 0, -sign_plus(q) * (E - p / np.where(E > 0, E, 1.0)) / np.sqrt(3.0), 0.0)
        t = np.where(three_real, t_trig, t_hyp)
        r = t - a2 / 3.0
        # 2. Newton on the original cubic.  Its result is accurate to eps * S / |P'(r)| (S the sum
        # of the absolute terms of P(r)), the closed form to eps * (t_size + |a2|/3) with t_size the
        # size of the terms that make up t: polish only where the first is smaller (not near a
        # multiple root) and the step reduces |P|.
        t_size = np.where(three_real, radius, (E + np.abs(p) / np.where(E > 0, E, 1.0)) / np.sqrt(3.0))
        dPt = 3.0 * t * t + p
        last = np.zeros_like(r)
        for _ in range(2):
            P = ((r + a2) * r + a1) * r + a0
            dP = (3.0 * r + 2.0 * a2) * r + a1
            ar = np.abs(r)
            noise = ((ar + np.abs(a2)) * ar + np.abs(a1)) * ar + np.abs(a0)
            useful = noise < np.abs(dP) * (t_size + np.abs(a2) / 3.0)
            step = np.where(dP != 0, P / np.where(dP != 0, dP, 1.0), 0.0)
            r_new = r - step
            P_new = ((r_new + a2) * r_new + a1) * r_new + a0
            ok = useful & np.isfinite(r_new) & (np.abs(P_new) <= np.abs(P))
            r = np.where(ok, r_new, r)
            last = np.where(ok, np.abs(step), last)
        # 3. deflation: sum sigma and product pi of the other two roots
        nz = r != 0
        rr = np.where(nz, r, 1.0)
        rel_r = _EPS + last / np.abs(rr)
        sigma_a = -(a2 + r)
        err_sigma_a = _EPS * (np.abs(a2) + np.abs(r)) + last
        pi_b = -a0 / rr
        sigma_b = (a1 - pi_b) / rr
        err_sigma_b = (np.abs(a1) + np.abs(pi_b)) / np.abs(rr) * (_EPS + 2.0 * rel_r)
        use_b = nz & (err_sigma_b < err_sigma_a)
        sigma = np.where(use_b, sigma_b, sigma_a)
        pi_a = a1 - r * sigma
        err_pi_a = _EPS * (np.abs(a1) + 2.0 * np.abs(r * sigma)) + last * np.abs(sigma)
        err_pi_b = np.abs(pi_b) * rel_r
        pi = np.where(nz & (err_pi_b < err_pi_a), pi_b, pi_a)
        # 4. the pair, split by the discriminant
        d = np.where(dPt > 0, sad / (2.0 * np.where(dPt > 0, dPt, 1.0)), 0.0)
        # Fujiwara: every root of t^3 + p t + q has |t| <= 2 max(|p|^(1/2), |q/2|^(1/3))
        d = np.minimum(d, 2.0 * np.maximum(np.sqrt(np.abs(p)), np.cbrt(np.abs(q) / 2.0)))
        big = sigma / 2.0 + sign_plus(sigma) * d
        small = np.where(big != 0, pi / np.where(big != 0, big, 1.0), 0.0)
        l2 = np.where(three_real, big, sigma / 2.0 + 1j * d)
        l3 = np.where(three_real, small, sigma / 2.0 - 1j * d)
    return stack_roots(r, l2, l3)
