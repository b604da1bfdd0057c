/* x = mantissa 2^exponent, 1/2 <= |mantissa| < 1 (frexp); the exponent of 0, inf or NaN is 0 */
static double PREFIX_mantissa(double x)
{
    int e;
    return frexp(x, &e);
}

static double PREFIX_exponent(double x)
{
    int e = 0;
    if (!isfinite(x)) return 0.0;
    (void)frexp(x, &e);
    return (double)e;
}

/* x 2^e for a whole number e held in a double */
static double PREFIX_ldexp(double x, double e)
{
    return ldexp(x, (int)e);
}

/* a b - fl(a b), exactly (Dekker's product, Veltkamp's splitting; |a|, |b| < 2^995) */
static double PREFIX_two_product_error(double a, double b)
{
    const double prod = a * b;
    const double ta = 134217729.0 * a;
    const double ah = ta - (ta - a);
    const double al = a - ah;
    const double tb = 134217729.0 * b;
    const double bh = tb - (tb - b);
    const double bl = b - bh;
    return ((ah * bh - prod) + ah * bl + al * bh) + al * bl;
}

/* a + b - fl(a + b), exactly (Knuth's two-sum) */
static double PREFIX_two_sum_error(double a, double b)
{
    const double s = a + b;
    const double bb = s - a;
    return (a - (s - bb)) + (b - bb);
}
