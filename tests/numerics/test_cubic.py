"""The cubic root solver (dtcrit.numerics.cubic) against mpmath at 50 digits, and its NumPy text that
``dtcrit codegen`` emits (helper_sources/cubic_positive_root.py.txt) bit for bit against it.
"""
import mpmath as mp
import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from dtcrit.codegen.helpers import helper_source
from dtcrit.numerics.cubic import cubic_positive_root
from dtcrit.numerics.reference import mp_cubic_positive_root


def ulps(got: float, ref) -> float:
    """Distance of ``got`` from the exact ``ref`` in units of the last place of ``ref``."""
    ref_f = float(ref)
    spacing = np.spacing(abs(ref_f)) if ref_f != 0 else 5e-324
    return float(abs(mp.mpf(got) - ref) / spacing)


def _ref(a2, a1, a0, largest):
    with mp.workdps(50):
        return mp_cubic_positive_root(a2, a1, a0, largest)


def _from_roots(r1, r2, r3):
    """Monic coefficients of (t - r1)(t - r2)(t - r3), rounded."""
    return -(r1 + r2 + r3), r1 * r2 + r1 * r3 + r2 * r3, -(r1 * r2 * r3)


def test_known_roots():
    # (t - 1)(t - 2)(t - 3): smallest 1, largest 3; t^3 + t + 1 has no positive root
    assert ulps(float(cubic_positive_root(-6.0, 11.0, -6.0, False)), mp.mpf(1)) <= 2
    assert ulps(float(cubic_positive_root(-6.0, 11.0, -6.0, True)), mp.mpf(3)) <= 2
    assert cubic_positive_root(0.0, 1.0, 1.0, False) == 0.0


@settings(max_examples=80, derandomize=True, deadline=None)
@given(st.floats(min_value=1e-2, max_value=1e2), st.floats(min_value=1e-2, max_value=1e2),
       st.floats(min_value=-1e2, max_value=1e2), st.integers(min_value=-40, max_value=40), st.booleans())
def test_root_against_mpmath(r1, r2, r3, decade, largest):
    # roots within four decades of each other (the boundary cubics' coefficients stay bounded; with
    # roots spread wider Viete's angle loses the small root), the whole cubic over 80 decades (p^3 and
    # q^2 must not overflow)
    assume(abs(r1 - r2) > 1e-3 * max(r1, r2) and abs(r3) > 1e-2)
    assume(abs(r3 - r1) > 1e-3 * abs(r3) and abs(r3 - r2) > 1e-3 * abs(r3))
    r1, r2, r3 = (r * 10.0**decade for r in (r1, r2, r3))
    a2, a1, a0 = _from_roots(r1, r2, r3)
    ref = _ref(a2, a1, a0, largest)
    assume(ref > 0)
    got = float(cubic_positive_root(a2, a1, a0, largest))
    with mp.workdps(50):
        # the root's condition number: Horner's rounding (the absolute terms) against r P'(r)
        terms = abs(ref) ** 3 + abs(a2) * ref**2 + abs(a1) * ref + abs(a0)
        cond = terms / abs(ref * ((3 * ref + 2 * a2) * ref + a1))
    assert ulps(got, ref) <= 4 + 2 * float(cond), (a2, a1, a0, largest, got, ref)


@settings(max_examples=150, derandomize=True, deadline=None)
@given(st.integers(min_value=-300, max_value=-1), st.floats(min_value=1.0, max_value=10.0))
def test_small_damping_cubic_of_eq40(e, m):
    # Peng et al. 2020, Eq. (40) boundary: tau^3 - 4 z tau^2 + (4 z^2 + 2) tau - 2 z, z over many decades
    z = m * 10.0**e
    a2, a1, a0 = -4.0 * z, 4.0 * z * z + 2.0, -2.0 * z
    with mp.workdps(60):
        # the cubic in u = tau/z, divided by z, has its wanted root near u = 1 (findroot's tolerance is
        # absolute, so it runs on this O(1) root); the coefficients are the rounded floats, taken as exact
        zz, b2, b1, b0 = (mp.mpf(v) for v in (z, a2, a1, a0))
        u = mp.findroot(lambda u: ((zz * u + b2) * zz * u + b1) * u + b0 / zz, mp.mpf(1))
        ref = zz * u
    assert ulps(float(cubic_positive_root(a2, a1, a0, False)), ref) <= 4
    assert ulps(float(cubic_positive_root(a2, a1, a0, False, compensated_steps=2)), ref) <= 1


def test_vectorised_and_scalar_agree():
    rng = np.random.default_rng(3)
    a = rng.normal(size=(3, 64)) * 10.0 ** rng.integers(-8, 8, size=(3, 64))
    for largest in (False, True):
        v = cubic_positive_root(a[0], a[1], a[2], largest)
        s = [float(cubic_positive_root(a[0, i], a[1, i], a[2, i], largest)) for i in range(64)]
        assert np.array_equal(v, np.array(s))


def test_emitted_numpy_text_is_the_same_algorithm():
    ns: dict = {"np": np}
    exec(compile(helper_source("cubic_positive_root.py.txt"), "cubic_positive_root.py.txt", "exec"), ns)
    rng = np.random.default_rng(11)
    a = rng.normal(size=(3, 2000)) * 10.0 ** rng.integers(-30, 30, size=(3, 2000))
    z = 10.0 ** rng.uniform(-300, 0, size=500)
    for a2, a1, a0 in (a, (-4.0 * z, 4.0 * z * z + 2.0, -2.0 * z)):
        for largest in (False, True):
            emitted = ns["_cubic_positive_root"](a2, a1, a0, largest)
            library = cubic_positive_root(a2, a1, a0, largest, compensated_steps=2)
            assert np.array_equal(emitted, library)
