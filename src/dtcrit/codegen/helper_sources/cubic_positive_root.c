/* Smallest (largest when `largest` is non-zero) positive real root of
   t^3 + a2 t^2 + a1 t + a0; 0.0 when there is none.  Viete's trigonometric form when the three
   roots are real, the hyperbolic forms of Cardano's formula otherwise, then three Newton steps
   and two Newton steps with a compensated residual. */
static double PREFIX_cubic_positive_root(double a2, double a1, double a0, int largest)
{
    const double pi = 3.14159265358979323846;
    const double shift = a2 / 3.0;
    const double p = a1 - a2 * shift;
    const double q = (2.0 * shift * shift - a1) * shift + a0;
    double cand[3];
    int n = 0;
    if (p < 0.0 && q * q / 4.0 + p * p * p / 27.0 <= 0.0) {
        const double r = 2.0 * sqrt(-p / 3.0);
        double arg = (r > 0.0) ? 4.0 * q / (r * r * r) : 0.0;
        double phi;
        int j;
        if (arg > 1.0) arg = 1.0;
        if (arg < -1.0) arg = -1.0;
        phi = acos(-arg) / 3.0;
        for (j = 0; j < 3; ++j) cand[n++] = r * cos(phi - 2.0 * pi * j / 3.0) - shift;
    } else {
        const double s3 = sqrt(fabs(p) / 3.0);
        double one;
        if (p > 0.0) {
            one = -2.0 * s3 * sinh(asinh(1.5 * q / (p * s3)) / 3.0);
        } else if (p < 0.0) {
            double u = 1.5 * fabs(q) / (-p * s3);
            if (u < 1.0) u = 1.0;
            one = -2.0 * ((q > 0.0) - (q < 0.0)) * s3 * cosh(acosh(u) / 3.0);
        } else {
            one = -cbrt(q);
        }
        cand[n++] = one - shift;
    }
    {
        double t = largest ? -INFINITY : INFINITY;
        int i, k;
        for (i = 0; i < n; ++i) {
            if (cand[i] > 0.0 && (largest ? cand[i] > t : cand[i] < t)) t = cand[i];
        }
        for (k = 0; k < 3; ++k) {
            const double g = ((t + a2) * t + a1) * t + a0;
            const double dg = (3.0 * t + 2.0 * a2) * t + a1;
            if (isfinite(t) && dg != 0.0) t -= g / dg;
        }
        /* two more Newton steps with the residual from compensated Horner (error-free products
           through fma, error-free sums): accurate even where a1 t and a0 nearly cancel */
        for (k = 0; k < 2 && isfinite(t); ++k) {
            const double coef[3] = {a2, a1, a0};
            double s = 1.0, c = 0.0;
            int i2;
            for (i2 = 0; i2 < 3; ++i2) {
                const double pr = s * t;
                const double pe = fma(s, t, -pr);
                const double sm = pr + coef[i2];
                const double bb = sm - pr;
                const double se = (pr - (sm - bb)) + (coef[i2] - bb);
                s = sm;
                c = c * t + (pe + se);
            }
            {
                const double dg = (3.0 * t + 2.0 * a2) * t + a1;
                if (dg != 0.0) t -= (s + c) / dg;
            }
        }
        return isfinite(t) ? t : 0.0;
    }
}
