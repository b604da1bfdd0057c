"""Argument checks, tolerances and the paper's ordering assumption shared by every shape.

Peng, Burns & Hanley (2020), Section 3, assumption 3: semi-axes ``a >= b >= c`` and principal
moments ``I_zz >= I_yy >= I_xx``, checked with the relative slack ``ORDER_RTOL``.  Bad arguments
raise :class:`dtcrit.errors.InputError` naming the argument.
"""
from __future__ import annotations

import math
import numbers
from typing import Any

import numpy as np

from dtcrit.errors import InputError

SUPERQUADRIC_EPS_MIN = 0.01
"""Smallest accepted superquadric exponent: at eps = 0.01 the corner on the body diagonal lies at
3^(-eps/2) = 0.9945 of the box corner, and the inside-outside exponent 2/eps = 200 is as large as
double precision tolerates for points up to ~35 half-lengths away."""
SUPERQUADRIC_EPS_MAX = 2.0
"""Largest exponent for which the superquadric is convex (eps = 2 gives flat faces)."""
SYMMETRY_RTOL = 1e-6
"""Default tolerance of the central-symmetry and convexity checks of :class:`ConvexPolyhedron`,
relative to the largest distance of a vertex from the vertex mean."""
ORDER_RTOL = 1e-9
"""Relative slack of the assumption check ``a >= b >= c``, ``I_zz >= I_yy >= I_xx``: equal values
(a sphere, a prolate spheroid) pass despite rounding."""

_PLANE_RTOL = 1e-8  # facets whose unit normals and offsets differ by less are one planar face
_DEGENERATE_RTOL = 1e-9  # second moments this close (relative) share a principal subspace


class AssumptionWarning(UserWarning):
    """A shape breaks Peng et al. (2020) Section 3 assumption 3 (a >= b >= c, I_zz >= I_yy >= I_xx).

    Examples
    --------
    >>> from dtcrit import AssumptionWarning
    >>> issubclass(AssumptionWarning, UserWarning)
    True
    """


def _real(key: str, value: Any) -> float:
    if isinstance(value, (bool, np.bool_)):
        raise InputError(key, f"must be a real number (got {value!r})")
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    if not isinstance(value, numbers.Real):
        raise InputError(key, f"must be a real number (got {value!r})")
    return float(value)


def _positive(key: str, value: Any) -> float:
    x = _real(key, value)
    if not math.isfinite(x):
        raise InputError(key, f"must be finite (got {x})")
    if x <= 0.0:
        raise InputError(key, f"must be positive (got {x})")
    return x


def _axes(a: Any, b: Any, c: Any) -> tuple[float, float, float]:
    a, b, c = _positive("a", a), _positive("b", b), _positive("c", c)
    if a < b:
        raise InputError("b", f"a >= b >= c required (got a={a:g}, b={b:g})")
    if b < c:
        raise InputError("c", f"a >= b >= c required (got b={b:g}, c={c:g})")
    return a, b, c


def _exponent(key: str, value: Any) -> float:
    e = _real(key, value)
    if not math.isfinite(e):
        raise InputError(key, f"must be finite (got {e})")
    if not SUPERQUADRIC_EPS_MIN <= e <= SUPERQUADRIC_EPS_MAX:
        raise InputError(
            key,
            f"must lie in [{SUPERQUADRIC_EPS_MIN:g}, {SUPERQUADRIC_EPS_MAX:g}] (convex superquadrics; "
            f"eps > 2 is non-convex, eps < {SUPERQUADRIC_EPS_MIN:g} is a box to 0.6 %) (got {e:g})",
        )
    return e


def _mass_and_density(volume: float, density: Any, mass: Any, size_key: str) -> tuple[float, float]:
    if not (math.isfinite(volume) and volume > 0.0):
        raise InputError(size_key, f"dimensions give a volume of {volume!r}, outside double precision")
    if density is not None and mass is not None:
        raise InputError("density", "give exactly one of density= or mass= (got both)")
    if density is None and mass is None:
        raise InputError("density", "give exactly one of density= or mass= (got neither)")
    if density is not None:
        rho = _positive("density", density)
        m = rho * volume
        if not (math.isfinite(m) and m > 0.0):
            raise InputError("density", f"density * volume = {m!r} is not a positive finite mass")
        return m, rho
    m = _positive("mass", mass)
    rho = m / volume
    if not (math.isfinite(rho) and rho > 0.0):
        raise InputError("mass", f"mass / volume = {rho!r} is not a positive finite density")
    return m, rho


def _direction(direction: Any) -> np.ndarray:
    try:
        d = np.asarray(direction, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError("direction", f"must be a 3-vector of real numbers ({exc})") from None
    if d.shape[-1:] != (3,) or d.ndim > 2:
        raise InputError("direction", f"must have shape (3,) or (N, 3) (got {d.shape})")
    if not np.all(np.isfinite(d)):
        raise InputError("direction", "must be finite")
    if np.any(np.max(np.abs(d), axis=-1) == 0.0):
        raise InputError("direction", "must be non-zero")
    return d


def _vec3(v: Any) -> tuple[float, float, float]:
    """The three components of ``v`` as floats."""
    x, y, z = (float(t) for t in v)
    return x, y, z


def _count(n: Any) -> int:
    if isinstance(n, (bool, np.bool_)) or not isinstance(n, numbers.Integral):
        raise InputError("n", f"must be an integer (got {n!r})")
    if int(n) < 1:
        raise InputError("n", f"must be at least 1 (got {n})")
    if int(n) > 1_000_000:
        raise InputError("n", f"must be at most 1000000 (got {n})")
    return int(n)


def _kernel(fn, *args):
    """Call a generated kernel in NumPy float64 so that overflow gives inf (checked by the caller)."""
    with np.errstate(over="ignore", under="ignore"):
        out = fn(*(np.float64(x) for x in args))
    return tuple(float(x) for x in out) if isinstance(out, tuple) else float(out)


def _fmt(x: float) -> str:
    return f"{x:.6g}"


def _unit_rows(v: np.ndarray) -> np.ndarray:
    scale = np.max(np.abs(v), axis=1, keepdims=True)
    v = v / np.where(scale > 0, scale, 1.0)
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def _assumption_issues(label: str, half: tuple[float, float, float], inertia: tuple[float, float, float]) -> tuple[str, ...]:
    """Peng et al. (2020) Section 3 assumption 3, checked with relative slack ``ORDER_RTOL``."""
    a, b, c = half
    ixx, iyy, izz = inertia
    issues = []
    if a < b * (1 - ORDER_RTOL) or b < c * (1 - ORDER_RTOL):
        issues.append(f"{label}: half-lengths violate a >= b >= c (a={_fmt(a)}, b={_fmt(b)}, c={_fmt(c)})")
    if izz < iyy * (1 - ORDER_RTOL) or iyy < ixx * (1 - ORDER_RTOL):
        issues.append(
            f"{label}: principal moments violate I_zz >= I_yy >= I_xx "
            f"(I_xx={_fmt(ixx)}, I_yy={_fmt(iyy)}, I_zz={_fmt(izz)})"
        )
    return tuple(issues)


def _readonly(x: np.ndarray) -> np.ndarray:
    x = np.ascontiguousarray(x, dtype=float)
    x.flags.writeable = False
    return x
