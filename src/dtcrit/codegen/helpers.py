"""The cubic-root helper for the integrator whose boundary is a cubic (``paper-eq40``), per language.

The algorithm is the one of the library's generated NumPy helper
(``dtcrit.symbolic.stability_codegen.PREAMBLE``, reused for NumPy output): Viete's trigonometric
form when the three roots are real, the hyperbolic forms of Cardano's formula otherwise, the
smallest (or largest) positive candidate, then three Newton steps on the cubic.  Two further
Newton steps evaluate the residual by compensated Horner (error-free transformations: ``fma`` in
C, Dekker's product in NumPy and Fortran), so the root is as accurate as the coefficients allow
even where ``a1 t`` and ``a0`` nearly cancel (small damping), which plain Horner is not.
The kernel calls it with coefficients that stay bounded (the cubic in tau for zeta <= 1, the cubic
in y = 1/(zeta tau) for zeta > 1).
"""
from __future__ import annotations

from dtcrit.symbolic.stability_codegen import PREAMBLE as _LIBRARY_HELPER

NUMPY_HELPER_NAME = "_cubic_positive_root"

_COMPENSATED = '''

def _two_product(a, b):
    """p = fl(a b) and the exact error a b - p (Dekker, Veltkamp splitting; no fma in NumPy)."""
    p = a * b
    ca = 134217729.0 * a
    ah = ca - (ca - a)
    al = a - ah
    cb = 134217729.0 * b
    bh = cb - (cb - b)
    bl = b - bh
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


def _compensated_newton(t, a2, a1, a0):
    """One Newton step on t^3 + a2 t^2 + a1 t + a0 with the residual from compensated Horner."""
    s = np.ones_like(t)
    c = np.zeros_like(t)
    for a in (a2, a1, a0):
        pr, pe = _two_product(s, t)
        sm = pr + a
        bb = sm - pr
        se = (pr - (sm - bb)) + (a - bb)
        s = sm
        c = c * t + (pe + se)
    dg = (3.0 * t + 2.0 * a2) * t + a1
    ok = np.isfinite(t) & (dg != 0)
    return np.where(ok, t - (s + c) / np.where(ok, dg, 1.0), t)
'''


def _numpy_helper() -> str:
    """The library's NumPy helper with two compensated Newton steps added before it returns."""
    text = _LIBRARY_HELPER.strip("\n")
    anchor = "        t = np.where(np.isfinite(t), t, 0.0)"
    if anchor not in text:  # pragma: no cover - the library helper changed shape
        raise RuntimeError("dtcrit.symbolic.stability_codegen.PREAMBLE changed; update dtcrit.codegen.helpers")
    text = text.replace(anchor, "        for _ in range(2):\n            t = _compensated_newton(t, a2, a1, a0)\n" + anchor)
    text = text.replace("then three Newton steps on the cubic polish the root to working precision.",
                        "then three Newton steps on the cubic and two with a compensated residual\n    "
                        "(accurate where a1 t and a0 nearly cancel).")
    return _COMPENSATED.strip("\n") + "\n\n\n" + text


NUMPY_HELPER = _numpy_helper()

C_HELPER = """\
/* Smallest (largest when `largest` is non-zero) positive real root of
   t^3 + a2 t^2 + a1 t + a0; 0.0 when there is none.  Viete's trigonometric form when the three
   roots are real, the hyperbolic forms of Cardano's formula otherwise, then three Newton steps
   and two Newton steps with a compensated residual. */
static double {name}(double a2, double a1, double a0, int largest)
{{
    const double pi = 3.14159265358979323846;
    const double shift = a2 / 3.0;
    const double p = a1 - a2 * shift;
    const double q = (2.0 * shift * shift - a1) * shift + a0;
    double cand[3];
    int n = 0;
    if (p < 0.0 && q * q / 4.0 + p * p * p / 27.0 <= 0.0) {{
        const double r = 2.0 * sqrt(-p / 3.0);
        double arg = (r > 0.0) ? 4.0 * q / (r * r * r) : 0.0;
        double phi;
        int j;
        if (arg > 1.0) arg = 1.0;
        if (arg < -1.0) arg = -1.0;
        phi = acos(-arg) / 3.0;
        for (j = 0; j < 3; ++j) cand[n++] = r * cos(phi - 2.0 * pi * j / 3.0) - shift;
    }} else {{
        const double s3 = sqrt(fabs(p) / 3.0);
        double one;
        if (p > 0.0) {{
            one = -2.0 * s3 * sinh(asinh(1.5 * q / (p * s3)) / 3.0);
        }} else if (p < 0.0) {{
            double u = 1.5 * fabs(q) / (-p * s3);
            if (u < 1.0) u = 1.0;
            one = -2.0 * ((q > 0.0) - (q < 0.0)) * s3 * cosh(acosh(u) / 3.0);
        }} else {{
            one = -cbrt(q);
        }}
        cand[n++] = one - shift;
    }}
    {{
        double t = largest ? -INFINITY : INFINITY;
        int i, k;
        for (i = 0; i < n; ++i) {{
            if (cand[i] > 0.0 && (largest ? cand[i] > t : cand[i] < t)) t = cand[i];
        }}
        for (k = 0; k < 3; ++k) {{
            const double g = ((t + a2) * t + a1) * t + a0;
            const double dg = (3.0 * t + 2.0 * a2) * t + a1;
            if (isfinite(t) && dg != 0.0) t -= g / dg;
        }}
        /* two more Newton steps with the residual from compensated Horner (error-free products
           through fma, error-free sums): accurate even where a1 t and a0 nearly cancel */
        for (k = 0; k < 2 && isfinite(t); ++k) {{
            const double coef[3] = {{a2, a1, a0}};
            double s = 1.0, c = 0.0;
            int i2;
            for (i2 = 0; i2 < 3; ++i2) {{
                const double pr = s * t;
                const double pe = fma(s, t, -pr);
                const double sm = pr + coef[i2];
                const double bb = sm - pr;
                const double se = (pr - (sm - bb)) + (coef[i2] - bb);
                s = sm;
                c = c * t + (pe + se);
            }}
            {{
                const double dg = (3.0 * t + 2.0 * a2) * t + a1;
                if (dg != 0.0) t -= (s + c) / dg;
            }}
        }}
        return isfinite(t) ? t : 0.0;
    }}
}}
"""

FORTRAN_HELPER = """\
  ! Smallest (largest when `largest`) positive real root of t^3 + a2 t^2 + a1 t + a0; 0 when
  ! there is none.  Viete's trigonometric form when the three roots are real, the hyperbolic
  ! forms of Cardano's formula otherwise, then three Newton steps and two Newton steps with a
  ! compensated residual.
  pure function {name}(a2, a1, a0, largest) result(t)
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_positive_inf
    real(c_double), intent(in) :: a2, a1, a0
    logical, intent(in) :: largest
    real(c_double) :: t
    real(c_double), parameter :: pi = 3.141592653589793_c_double
    real(c_double) :: shift, p, q, r, arg, phi, s3, u, one, g, dg, big
    real(c_double) :: s, c, pr, pe, sm, bb, se, sh, sl, th, tl
    real(c_double) :: cand(3), coef(3)
    integer :: n, j, k
    shift = a2 / 3.0_c_double
    p = a1 - a2 * shift
    q = (2.0_c_double * shift * shift - a1) * shift + a0
    n = 0
    if (p < 0.0_c_double .and. q * q / 4.0_c_double + p * p * p / 27.0_c_double <= 0.0_c_double) then
      r = 2.0_c_double * sqrt(-p / 3.0_c_double)
      arg = 0.0_c_double
      if (r > 0.0_c_double) arg = 4.0_c_double * q / (r * r * r)
      arg = max(-1.0_c_double, min(1.0_c_double, arg))
      phi = acos(-arg) / 3.0_c_double
      do j = 0, 2
        n = n + 1
        cand(n) = r * cos(phi - 2.0_c_double * pi * real(j, c_double) / 3.0_c_double) - shift
      end do
    else
      s3 = sqrt(abs(p) / 3.0_c_double)
      if (p > 0.0_c_double) then
        one = -2.0_c_double * s3 * sinh(asinh(1.5_c_double * q / (p * s3)) / 3.0_c_double)
      else if (p < 0.0_c_double) then
        u = max(1.0_c_double, 1.5_c_double * abs(q) / (-p * s3))
        one = -2.0_c_double * sign(1.0_c_double, q) * s3 * cosh(acosh(u) / 3.0_c_double)
        if (q == 0.0_c_double) one = 0.0_c_double
      else
        one = -sign(abs(q)**(1.0_c_double / 3.0_c_double), q)
      end if
      n = 1
      cand(1) = one - shift
    end if
    big = ieee_value(big, ieee_positive_inf)
    if (largest) then
      t = -big
    else
      t = big
    end if
    do j = 1, n
      if (cand(j) > 0.0_c_double) then
        if (largest .and. cand(j) > t) t = cand(j)
        if (.not. largest .and. cand(j) < t) t = cand(j)
      end if
    end do
    do k = 1, 3
      g = ((t + a2) * t + a1) * t + a0
      dg = (3.0_c_double * t + 2.0_c_double * a2) * t + a1
      if (ieee_is_finite(t) .and. dg /= 0.0_c_double) t = t - g / dg
    end do
    ! two more Newton steps with the residual from compensated Horner (Dekker's error-free
    ! product with Veltkamp splitting, error-free sums)
    do k = 1, 2
      if (.not. ieee_is_finite(t)) exit
      coef = [a2, a1, a0]
      s = 1.0_c_double
      c = 0.0_c_double
      do j = 1, 3
        pr = s * t
        sh = 134217729.0_c_double * s
        sh = sh - (sh - s)
        sl = s - sh
        th = 134217729.0_c_double * t
        th = th - (th - t)
        tl = t - th
        pe = ((sh * th - pr) + sh * tl + sl * th) + sl * tl
        sm = pr + coef(j)
        bb = sm - pr
        se = (pr - (sm - bb)) + (coef(j) - bb)
        s = sm
        c = c * t + (pe + se)
      end do
      dg = (3.0_c_double * t + 2.0_c_double * a2) * t + a1
      if (dg /= 0.0_c_double) t = t - (s + c) / dg
    end do
    if (.not. ieee_is_finite(t)) t = 0.0_c_double
  end function {name}
"""


# ----------------------------------------------------------------------------------------------
# Floating-point primitives of dtcrit.symbolic.careful_forms (frexp parts, scaling by a power of
# two, error-free product and sum), one small helper each.  C and Fortran use the same
# operations (Dekker's product with Veltkamp's splitting, no fma), so they agree bit for bit.
# ----------------------------------------------------------------------------------------------
C_PRIMITIVES = """\
/* x = mantissa 2^exponent, 1/2 <= |mantissa| < 1 (frexp); the exponent of 0, inf or NaN is 0 */
static double {p}_mantissa(double x)
{{
    int e;
    return frexp(x, &e);
}}

static double {p}_exponent(double x)
{{
    int e = 0;
    if (!isfinite(x)) return 0.0;
    (void)frexp(x, &e);
    return (double)e;
}}

/* x 2^e for a whole number e held in a double */
static double {p}_ldexp(double x, double e)
{{
    return ldexp(x, (int)e);
}}

/* a b - fl(a b), exactly (Dekker's product, Veltkamp's splitting; |a|, |b| < 2^995) */
static double {p}_two_product_error(double a, double b)
{{
    const double prod = a * b;
    const double ta = 134217729.0 * a;
    const double ah = ta - (ta - a);
    const double al = a - ah;
    const double tb = 134217729.0 * b;
    const double bh = tb - (tb - b);
    const double bl = b - bh;
    return ((ah * bh - prod) + ah * bl + al * bh) + al * bl;
}}

/* a + b - fl(a + b), exactly (Knuth's two-sum) */
static double {p}_two_sum_error(double a, double b)
{{
    const double s = a + b;
    const double bb = s - a;
    return (a - (s - bb)) + (b - bb);
}}
"""

FORTRAN_PRIMITIVES = """\
  ! x = mantissa 2^exponent, 1/2 <= |mantissa| < 1 (frexp); 0, inf and NaN are their own mantissa
  pure function frexp_mantissa(x) result(m)
    real(c_double), intent(in) :: x
    real(c_double) :: m
    m = x
    if (ieee_is_finite(x) .and. abs(x) > 0.0_c_double) m = fraction(x)
  end function frexp_mantissa

  ! the exponent of x (0 for 0, inf and NaN), as a real
  pure function frexp_exponent(x) result(e)
    real(c_double), intent(in) :: x
    real(c_double) :: e
    e = 0.0_c_double
    if (ieee_is_finite(x) .and. abs(x) > 0.0_c_double) e = real(exponent(x), c_double)
  end function frexp_exponent

  ! x 2^e for a whole number e held in a real
  pure function times_power_of_two(x, e) result(y)
    real(c_double), intent(in) :: x, e
    real(c_double) :: y
    y = x
    if (ieee_is_finite(x) .and. abs(x) > 0.0_c_double) y = scale(x, int(e))
  end function times_power_of_two

  ! a b - fl(a b), exactly (Dekker's product, Veltkamp's splitting; |a|, |b| < 2^995)
  pure function two_product_error(a, b) result(err)
    real(c_double), intent(in) :: a, b
    real(c_double) :: err, prod, ta, ah, al, tb, bh, bl
    prod = a * b
    ta = 134217729.0_c_double * a
    ah = ta - (ta - a)
    al = a - ah
    tb = 134217729.0_c_double * b
    bh = tb - (tb - b)
    bl = b - bh
    err = ((ah * bh - prod) + ah * bl + al * bh) + al * bl
  end function two_product_error

  ! a + b - fl(a + b), exactly (Knuth's two-sum)
  pure function two_sum_error(a, b) result(err)
    real(c_double), intent(in) :: a, b
    real(c_double) :: err, s, bb
    s = a + b
    bb = s - a
    err = (a - (s - bb)) + (b - bb)
  end function two_sum_error
"""

NUMPY_PRIMITIVES = '''\
def _mantissa(x):
    """x = mantissa 2^exponent, 1/2 <= |mantissa| < 1 (np.frexp)."""
    return np.frexp(x)[0]


def _exponent(x):
    """The exponent of x as a float (0 for 0, inf and NaN)."""
    return np.where(np.isfinite(x), np.frexp(x)[1], 0).astype(float)


def _ldexp(x, e):
    """x 2^e for whole numbers e held in floats."""
    return np.ldexp(x, np.asarray(e).astype(np.int64))


def _two_product_error(a, b):
    """a b - fl(a b), exactly (Dekker's product, Veltkamp's splitting)."""
    p = a * b
    ta = 134217729.0 * a
    ah = ta - (ta - a)
    al = a - ah
    tb = 134217729.0 * b
    bh = tb - (tb - b)
    bl = b - bh
    return ((ah * bh - p) + ah * bl + al * bh) + al * bl


def _two_sum_error(a, b):
    """a + b - fl(a + b), exactly (Knuth's two-sum)."""
    s = a + b
    bb = s - a
    return (a - (s - bb)) + (b - bb)
'''


def _blocks(text: str, sep: str) -> dict[str, str]:
    """Split a helper text into its functions, keyed by the primitive each implements."""
    keys = ("mantissa", "exponent", "ldexp", "two_product_error", "two_sum_error")
    blocks = [b.strip("\n") + "\n" for b in text.split(sep) if b.strip()]
    return dict(zip(keys, blocks))


C_PRIMITIVE_BLOCKS = _blocks(C_PRIMITIVES, "\n\n")
FORTRAN_PRIMITIVE_BLOCKS = _blocks(FORTRAN_PRIMITIVES, "\n\n")
NUMPY_PRIMITIVE_BLOCKS = _blocks(NUMPY_PRIMITIVES, "\n\n\n")
