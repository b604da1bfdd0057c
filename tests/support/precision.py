"""Units in the last place, for comparisons of floats with an mpmath (or exact) reference."""
from __future__ import annotations

import math


def ulps(got: float, ref) -> float:
    """Distance of a float from a reference in units in the last place of the reference.

    Parameters
    ----------
    got : float
        The computed value.
    ref : float, mpmath.mpf or fractions.Fraction
        The reference; it is rounded to the nearest float first.

    Returns
    -------
    float
        ``|got - float(ref)| / ulp(float(ref))``; 0 when both are zero, infinity when only the
        reference is zero.
    """
    r = float(ref)
    if r == 0.0:
        return 0.0 if got == 0.0 else math.inf
    return abs(got - r) / math.ulp(r)
