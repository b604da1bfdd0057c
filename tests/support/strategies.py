"""Hypothesis strategies shared by the property tests (numbers across decades, ellipsoid axes)."""
from __future__ import annotations

from hypothesis import strategies as st


def log_uniform(lo: float, hi: float) -> st.SearchStrategy[float]:
    """Positive floats ``10**e`` with the exponent ``e`` drawn from ``[lo, hi]``.

    Parameters
    ----------
    lo, hi : float
        Range of the decimal exponent.

    Returns
    -------
    SearchStrategy of float
        Values spread evenly over the decades from ``10**lo`` to ``10**hi``.
    """
    return st.floats(lo, hi).map(lambda e: 10.0**e)


@st.composite
def axes(draw) -> tuple[float, float, float]:
    """Semi-axes ``a >= b >= c``: c in [1e-6, 1e3], ratios a/b and b/c log-uniform with a/c <= 100.

    Parameters
    ----------
    draw : callable
        Hypothesis's draw function (supplied by ``st.composite``).

    Returns
    -------
    tuple of float
        ``(a, b, c)``.
    """
    log_c = draw(st.floats(-6.0, 3.0))
    up2 = draw(st.floats(0.0, 2.0))
    up1 = draw(st.floats(0.0, 2.0 - up2))
    c = 10.0**log_c
    b = c * 10.0**up2
    a = b * 10.0**up1
    return a, max(b, c), c
