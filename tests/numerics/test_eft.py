"""Error-free transformations and double-double polynomials (dtcrit.numerics.eft), checked exactly
with fractions.Fraction over many decades, and the power-of-two scaling (dtcrit.numerics.scaling).
"""
from fractions import Fraction

import mpmath as mp
import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from dtcrit.numerics.eft import dd_polynomial, split, two_product, two_sum
from dtcrit.numerics.scaling import frexp_parts, scaled_rates, scaled_root

# |a|, |b| below 2^995 (the splitting constant times a must not overflow) and products whose error
# term stays normal (above 2^-1022 * 2^53)
FACTOR = st.floats(min_value=-2.0**480, max_value=2.0**480, allow_nan=False, allow_infinity=False).filter(
    lambda x: x == 0 or abs(x) > 2.0**-480)
ADDEND = st.floats(min_value=-2.0**1020, max_value=2.0**1020, allow_nan=False, allow_infinity=False)


@settings(max_examples=400, derandomize=True, deadline=None)
@given(FACTOR, FACTOR)
def test_two_product_is_exact(a, b):
    p, e = two_product(a, b)
    assert p == a * b
    assert Fraction(p) + Fraction(e) == Fraction(a) * Fraction(b)


@settings(max_examples=400, derandomize=True, deadline=None)
@given(ADDEND, ADDEND)
def test_two_sum_is_exact(a, b):
    s, e = two_sum(a, b)
    assume(np.isfinite(s))
    assert s == a + b
    assert Fraction(s) + Fraction(e) == Fraction(a) + Fraction(b)


@settings(max_examples=300, derandomize=True, deadline=None)
@given(FACTOR)
def test_split_halves_fit_in_26_bits(a):
    hi, lo = split(a)
    assert Fraction(hi) + Fraction(lo) == Fraction(a)
    for half in (hi, lo):
        if half != 0:
            m, _ = np.frexp(half)
            assert float(m * 2.0**26) == int(m * 2.0**26)  # at most 26 significant bits


def test_two_product_vectorised_matches_scalars():
    rng = np.random.default_rng(7)
    a = rng.normal(size=50) * 10.0 ** rng.integers(-100, 100, size=50)
    b = rng.normal(size=50) * 10.0 ** rng.integers(-100, 100, size=50)
    p, e = two_product(a, b)
    for i in range(50):
        assert Fraction(float(p[i])) + Fraction(float(e[i])) == Fraction(float(a[i])) * Fraction(float(b[i]))


@settings(max_examples=150, derandomize=True, deadline=None)
@given(st.floats(min_value=0.5, max_value=2.0), st.floats(min_value=0.0, max_value=2.0),
       st.integers(min_value=-40, max_value=0))
def test_dd_polynomial_near_cancellation(x, y, shift):
    # (x - y)^2 expanded: x^2 - 2 x y + y^2, with y close to x the terms cancel to many digits
    y = x + np.ldexp(y, shift) if shift > -40 else x
    terms = [(1, 2, 0), (-2, 1, 1), (1, 0, 2)]
    got = float(dd_polynomial(terms, x, y))
    fx, fy = Fraction(x), Fraction(y)
    exact = (fx - fy) ** 2
    size = fx * fx + 2 * fx * fy + fy * fy  # the terms that cancel
    # double-double: an absolute error of ~2^-104 of the terms, then one rounding of the result
    assert abs(Fraction(got) - exact) <= exact * Fraction(1, 2**52) + size * Fraction(1, 2**100)
    if shift >= -20:  # cancellation to 40 bits at most: still full float64 precision
        assert abs(Fraction(got) - exact) <= exact * Fraction(1, 2**51)


@settings(max_examples=300, derandomize=True, deadline=None)
@given(st.floats(min_value=1e-300, max_value=1e300), st.floats(min_value=0.0, max_value=1e300),
       st.floats(min_value=1e-300, max_value=1e300))
def test_scaled_rates_against_mpmath(k, c, A):
    w, g, s = (np.asarray(v)[()] for v in scaled_rates(k, c, A))
    with mp.workdps(50):
        omega = mp.sqrt(mp.mpf(k) * mp.mpf(A))
        gamma = mp.mpf(c) * mp.mpf(A) / 2
        assert 0.5 <= w < 1.42
        rel = abs(mp.ldexp(mp.mpf(float(w)), int(s)) - omega) / omega
        assert rel <= 1.5 * 2.0**-53  # half the product's rounding (under the root) and the root's own
        if c > 0 and np.isfinite(g) and g > 2.0**-1000:
            assert abs(mp.ldexp(mp.mpf(float(g)), int(s)) - gamma) / gamma <= 2.0**-53


def test_frexp_parts_and_scaled_root_are_exact_powers_of_two():
    mk, ek, mA, eA = frexp_parts([3.0, 1e-310], [12.0, 1e300])
    assert np.all((0.5 <= mk) & (mk < 1)) and np.all((0.5 <= mA) & (mA < 1))
    w, s = scaled_root(mk, ek, mA, eA)
    assert float(np.ldexp(w[0], s[0])) == 6.0  # sqrt(3 * 12) exactly
    with mp.workdps(40):
        ref = mp.sqrt(mp.mpf(1e-310) * mp.mpf(1e300))
        assert abs(mp.ldexp(mp.mpf(float(w[1])), int(s[1])) - ref) / ref < 2.0**-52
