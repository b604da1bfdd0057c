"""Volumes and principal moments of inertia of the particle shapes, derived with SymPy.

Peng, Burns & Hanley (2020), Section 3, restricts the critical-time-step analysis to convex,
centrally symmetric particles (ellipsoids, convex superquadrics, convex centrally symmetric
polyhedra) whose local frame is principal.  The analysis needs each particle's mass and principal
moments ``I_xx, I_yy, I_zz`` (their Eqs (9)-(10), (22)-(26)); the paper itself prints only the
ellipsoid volume ``V = 4/3 pi a b c`` (Section 6.4).  This module rebuilds all of them from the
definition ``I = integral of rho (|r|^2 1 - r r^T) dV``:

* sphere and ellipsoid: direct integration in (stretched) spherical coordinates, Jacobian
  computed by SymPy;
* box (half-lengths a, b, c): direct triple integration;
* superquadric: slicing plus the Euler Beta integral (derived once by SymPy and reused), giving
  Gamma-function forms;
* tetrahedron with one vertex at the origin: integration over the unit simplex after the affine
  map; used at run time for the exact tetrahedral decomposition of convex polyhedra.

Superquadric convention (Barr 1981; Jaklic, Leonardis & Solina 2000)::

    F(x, y, z) = (|x/a|^(2/eps2) + |y/b|^(2/eps2))^(eps2/eps1) + |z/c|^(2/eps1) <= 1

``eps2`` shapes the cross-sections normal to z, ``eps1`` the profile along z; eps = 1 gives the
ellipsoid, eps -> 0 the box and eps1 = eps2 = 2 the octahedron |x/a| + |y/b| + |z/c| <= 1.  The body
is convex exactly when 0 < eps1, eps2 <= 2 (both nested exponents 2/eps are then >= 1, so F^(eps1/2)
is a nested l_p norm).

``generated_files()`` emits ``dtcrit/_generated/mass_properties.py``.
"""
from __future__ import annotations

from functools import lru_cache

import sympy as sp

from dtcrit.symbolic.emit import Kernel, python_module

PRODUCER = "dtcrit.symbolic.mass_properties"
TARGET = "mass_properties.py"

a, b, c = sp.symbols("a b c", positive=True)
radius = sp.Symbol("radius", positive=True)
eps1, eps2 = sp.symbols("eps1 eps2", positive=True)

# Dummy integration variables (all positive: every integral below runs over a first octant).
_u, _v, _w, _t, _s, _r = sp.symbols("u v w t s r", positive=True)
_theta, _phi = sp.symbols("theta phi", real=True)
_alpha, _beta = sp.symbols("alpha beta", positive=True)


class elementwise_gamma(sp.Function):
    """Gamma function printed as ``gamma(...)``: the generated module's own element-wise wrapper of
    ``math.gamma`` (the NumPy printer would emit ``math.gamma``, which accepts scalars only).

    Parameters
    ----------
    *args : sympy.Expr
        The one argument of Gamma.
    """

    def _numpycode(self, printer):  # noqa: D401 - SymPy printer hook
        return f"gamma({printer._print(self.args[0])})"


# --------------------------------------------------------------------------------------------
# Lemma: the Euler Beta integral
# --------------------------------------------------------------------------------------------
@lru_cache(maxsize=None)
def euler_beta_integral() -> sp.Expr:
    """``int_0^1 t^(alpha-1) (1-t)^(beta-1) dt`` for alpha, beta > 0, integrated by SymPy.

    SymPy returns a Gauss hypergeometric value at 1; ``hyperexpand`` applies Gauss's summation
    theorem and ``gammasimp`` gives ``Gamma(alpha) Gamma(beta) / Gamma(alpha + beta)``.
    """
    raw = sp.integrate(_t ** (_alpha - 1) * (1 - _t) ** (_beta - 1), (_t, 0, 1))
    return sp.gammasimp(sp.hyperexpand(raw))


def beta_integral(integrand: sp.Expr) -> sp.Expr:
    """``int_0^1 integrand dt`` for an integrand ``C t^p s^q`` with ``s = 1 - t`` (C free of t, s).

    The exponents are read off the integrand and substituted into :func:`euler_beta_integral`.
    ``s`` is the positive symbol that :func:`_power_substitution` puts in place of ``1 - t``.

    Parameters
    ----------
    integrand : sympy.Expr
        ``C t^p s^q``.

    Returns
    -------
    sympy.Expr
        ``C Gamma(p + 1) Gamma(q + 1) / Gamma(p + q + 2)``.
    """
    coeff, dependent = integrand.as_independent(_t, _s, as_Add=False)
    p = q = sp.Integer(0)
    for factor in sp.Mul.make_args(dependent):
        base, expo = factor.as_base_exp()
        if base == _t:
            p += expo
        elif base == _s:
            q += expo
        else:
            raise ValueError(f"not a Beta integrand: factor {factor}")
    return coeff * euler_beta_integral().subs({_alpha: p + 1, _beta: q + 1})


def _power_substitution(integrand: sp.Expr, u: sp.Symbol, scale: sp.Expr, power: sp.Expr) -> sp.Expr:
    """Rewrite ``integrand du`` on ``u in [0, scale]`` with ``u = scale t^(1/power)``, t in [0, 1].

    ``1 - t`` (also in the scaled form ``scale^power - scale^power t``) is replaced by the positive
    symbol ``s`` so that powers combine without absolute values.
    """
    u_of_t = scale * _t ** (1 / power)
    out = integrand.subs(u, u_of_t) * sp.diff(u_of_t, _t)
    out = sp.powsimp(sp.expand_power_base(out, force=True), force=True)
    out = out.replace(
        lambda e: e.is_Pow and e.base.has(_t) and e.base != _t,
        lambda e: sp.Pow(sp.factor(sp.expand(e.base.subs(_t, 1 - _s))), e.exp),
    )
    return sp.powsimp(sp.expand_power_base(out, force=True), force=True)


# --------------------------------------------------------------------------------------------
# Moments: volume and the diagonal second moments  int x^2 dV, int y^2 dV, int z^2 dV
# --------------------------------------------------------------------------------------------
def _stretched_ball_moments(sx, sy, sz) -> dict[str, sp.Expr]:
    """Volume and second moments of the unit ball stretched by (sx, sy, sz), by direct integration."""
    position = sp.Matrix(
        [sx * _r * sp.sin(_theta) * sp.cos(_phi), sy * _r * sp.sin(_theta) * sp.sin(_phi), sz * _r * sp.cos(_theta)]
    )
    jac = sp.simplify(position.jacobian([_r, _theta, _phi]).det())

    def integrate(f):
        return sp.simplify(sp.integrate(f * jac, (_r, 0, 1), (_theta, 0, sp.pi), (_phi, 0, 2 * sp.pi)))

    return {
        "volume": integrate(sp.Integer(1)),
        "xx": integrate(position[0] ** 2),
        "yy": integrate(position[1] ** 2),
        "zz": integrate(position[2] ** 2),
    }


@lru_cache(maxsize=None)
def ellipsoid_moments() -> dict[str, sp.Expr]:
    """Volume and second moments of ``(x/a)^2 + (y/b)^2 + (z/c)^2 <= 1`` by direct integration.

    Stretched spherical coordinates ``(a r sin(th) cos(ph), b r sin(th) sin(ph), c r cos(th))``;
    SymPy computes the Jacobian determinant ``a b c r^2 sin(th)``.
    """
    return _stretched_ball_moments(a, b, c)


@lru_cache(maxsize=None)
def sphere_moments() -> dict[str, sp.Expr]:
    """Volume and second moments of the ball of radius ``radius`` (spherical coordinates)."""
    return _stretched_ball_moments(radius, radius, radius)


@lru_cache(maxsize=None)
def box_moments() -> dict[str, sp.Expr]:
    """Volume and second moments of ``[-a, a] x [-b, b] x [-c, c]`` by direct triple integration."""
    x, y, z = sp.symbols("x y z", real=True)

    def integrate(f):
        return sp.integrate(f, (x, -a, a), (y, -b, b), (z, -c, c))

    return {"volume": integrate(sp.Integer(1)), "xx": integrate(x**2), "yy": integrate(y**2), "zz": integrate(z**2)}


def superquadric_octant_moment(m: int, n: int, k: int) -> sp.Expr:
    """``int u^m v^n w^k`` over the first octant of the unit superquadric (a = b = c = 1).

    Slicing at height w: the cross-section is the superellipse
    ``u^(2/eps2) + v^(2/eps2) <= rho(w)^(2/eps2)`` with ``rho(w) = (1 - w^(2/eps1))^(eps1/2)``.

    1. inner v-integral up to ``(rho^p2 - u^p2)^(1/p2)``, p2 = 2/eps2 (SymPy ``integrate``);
    2. ``u = rho t^(1/p2)`` turns the u-integral into ``rho^(m+n+2)`` times a Beta integral;
    3. ``w = t^(1/p1)``, p1 = 2/eps1, turns the w-integral into a second Beta integral.

    Parameters
    ----------
    m : int
        Power of ``u``.
    n : int
        Power of ``v``.
    k : int
        Power of ``w``.

    Returns
    -------
    sympy.Expr
        The moment in ``eps1``, ``eps2`` (Gamma functions).
    """
    p1, p2 = 2 / eps1, 2 / eps2
    rho = sp.Symbol("rho", positive=True)
    inner = sp.integrate(_v**n, (_v, 0, (rho**p2 - _u**p2) ** (1 / p2)))
    slice_integrand = _power_substitution(_u**m * inner, _u, rho, p2)
    section = sp.simplify(beta_integral(slice_integrand))
    if section.has(_t, _s) or not section.has(rho):
        raise RuntimeError("slice integral did not reduce to a Beta function")
    profile = (1 - _w**p1) ** (1 / p1)
    height_integrand = _power_substitution(_w**k * section.subs(rho, profile), _w, sp.Integer(1), p1)
    return sp.gammasimp(beta_integral(height_integrand))


@lru_cache(maxsize=None)
def superquadric_moments() -> dict[str, sp.Expr]:
    """Volume and second moments of the superquadric (convention in the module docstring).

    The body is symmetric under each sign flip, so every integral is 8 times its first-octant
    value; ``x = a u, y = b v, z = c w`` scales the unit body.
    """
    scale = 8 * a * b * c
    return {
        "volume": sp.gammasimp(scale * superquadric_octant_moment(0, 0, 0)),
        "xx": sp.gammasimp(scale * a**2 * superquadric_octant_moment(2, 0, 0)),
        "yy": sp.gammasimp(scale * b**2 * superquadric_octant_moment(0, 2, 0)),
        "zz": sp.gammasimp(scale * c**2 * superquadric_octant_moment(0, 0, 2)),
    }


def inertia_per_mass(moments: dict[str, sp.Expr]) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """Principal moments divided by the mass, ``I_xx/m = (<y^2> + <z^2>)`` etc., for a uniform body.

    ``<x^2> = int x^2 dV / V``; each ratio is simplified on its own (Gamma ratios for superquadrics)
    so the emitted sums have no cancellation.

    Parameters
    ----------
    moments : dict of str to sympy.Expr
        Volume ``V`` and second moments ``xx``, ``yy``, ``zz`` (as from :func:`ellipsoid_moments`).

    Returns
    -------
    tuple of sympy.Expr
        ``(I_xx/m, I_yy/m, I_zz/m)`` [m^2].
    """
    vol = moments["volume"]
    mean = {key: sp.gammasimp(sp.simplify(moments[key] / vol)) for key in ("xx", "yy", "zz")}
    return (mean["yy"] + mean["zz"], mean["xx"] + mean["zz"], mean["xx"] + mean["yy"])


# --------------------------------------------------------------------------------------------
# Tetrahedron with one vertex at the origin (exact decomposition of convex polyhedra)
# --------------------------------------------------------------------------------------------
TETRA_VERTICES = sp.symbols("x1 y1 z1 x2 y2 z2 x3 y3 z3", real=True)


@lru_cache(maxsize=None)
def tetrahedron_moments() -> dict[str, sp.Expr]:
    """Signed volume, first and second moments of the tetrahedron (0, p1, p2, p3).

    The affine map ``r = l1 p1 + l2 p2 + l3 p3`` takes the unit simplex (l_i >= 0, sum <= 1) onto
    the tetrahedron with constant Jacobian ``D = det[p1 p2 p3]``; each moment is ``D`` times a
    polynomial integral over the simplex.  Signs follow the orientation of (p1, p2, p3).
    """
    x1, y1, z1, x2, y2, z2, x3, y3, z3 = TETRA_VERTICES
    p = sp.Matrix([[x1, x2, x3], [y1, y2, y3], [z1, z2, z3]])
    l1, l2, l3 = sp.symbols("l1 l2 l3", nonnegative=True)
    r = p * sp.Matrix([l1, l2, l3])
    det = p.det()

    def over_simplex(f):
        return sp.integrate(f, (l3, 0, 1 - l1 - l2), (l2, 0, 1 - l1), (l1, 0, 1))

    out = {"volume": det * over_simplex(sp.Integer(1))}
    for i, name in enumerate("xyz"):
        out[name] = det * sp.factor(over_simplex(sp.expand(r[i])))
    for i, j, name in ((0, 0, "xx"), (1, 1, "yy"), (2, 2, "zz"), (0, 1, "xy"), (0, 2, "xz"), (1, 2, "yz")):
        out[name] = det * sp.expand(over_simplex(sp.expand(r[i] * r[j])))
    return out


# --------------------------------------------------------------------------------------------
# Emission
# --------------------------------------------------------------------------------------------
def _elementwise_gamma(expr: sp.Expr) -> sp.Expr:
    return expr.replace(sp.gamma, elementwise_gamma)


def kernels() -> list[Kernel]:
    """The emitted kernels of the shapes' volumes and moments (sphere, ellipsoid, box, superquadric, tetrahedron).

    Returns
    -------
    list of Kernel
        One per emitted function of ``dtcrit/_generated/mass_properties.py``.
    """
    sph, ell, box, sq, tet = sphere_moments(), ellipsoid_moments(), box_moments(), superquadric_moments(), tetrahedron_moments()
    axes = [(a, "semi-axis / half-length along local x [m]"), (b, "along local y [m]"), (c, "along local z [m]")]
    sq_args = axes + [
        (eps1, "profile exponent along z (0 < eps1 <= 2 for convexity) [-]"),
        (eps2, "cross-section exponent in the x-y plane (0 < eps2 <= 2) [-]"),
    ]
    tet_args = [(s, "vertex coordinate [m]") for s in TETRA_VERTICES]
    inertia_doc = "tuple (I_xx/m, I_yy/m, I_zz/m) about the centre, principal local axes [m^2]"
    return [
        Kernel("sphere_volume", [(radius, "radius [m]")], sph["volume"],
               "Volume of a ball, 4/3 pi R^3 (spherical-coordinate integration).", returns="volume [m^3]"),
        Kernel("sphere_inertia_per_mass", [(radius, "radius [m]")], inertia_per_mass(sph)[0],
               "Moment of inertia of a uniform ball about any centroidal axis divided by its mass, 2/5 R^2.",
               returns="I/m [m^2]"),
        Kernel("ellipsoid_volume", axes, ell["volume"],
               "Volume of the ellipsoid (x/a)^2 + (y/b)^2 + (z/c)^2 <= 1 (Peng et al. 2020, Section 6.4).",
               returns="volume [m^3]"),
        Kernel("ellipsoid_inertia_per_mass", axes, inertia_per_mass(ell),
               "Principal moments of a uniform ellipsoid divided by its mass, e.g. I_xx/m = (b^2 + c^2)/5.",
               returns=inertia_doc),
        Kernel("box_volume", axes, box["volume"],
               "Volume of the box with half-lengths a, b, c.", returns="volume [m^3]"),
        Kernel("box_inertia_per_mass", axes, inertia_per_mass(box),
               "Principal moments of a uniform box (half-lengths) divided by its mass, I_xx/m = (b^2 + c^2)/3.",
               returns=inertia_doc),
        Kernel("superquadric_volume", sq_args, _elementwise_gamma(sq["volume"]),
               "Volume of the superquadric (|x/a|^(2/eps2) + |y/b|^(2/eps2))^(eps2/eps1) + |z/c|^(2/eps1) <= 1\n"
               "    (Barr/Jaklic convention), a product of two Beta functions written with Gamma functions.",
               returns="volume [m^3]"),
        Kernel("superquadric_inertia_per_mass", sq_args, tuple(_elementwise_gamma(e) for e in inertia_per_mass(sq)),
               "Principal moments of a uniform superquadric divided by its mass (Gamma-function ratios whose\n"
               "    arguments lie in [1/2, 6] for 0 < eps <= 2: no poles, no overflow).",
               returns=inertia_doc),
        Kernel("tetrahedron_moments", tet_args,
               tuple(tet[k] for k in ("volume", "x", "y", "z", "xx", "yy", "zz", "xy", "xz", "yz")),
               "Signed volume, first moments (int x dV, ...) and second moments (int x^2 dV, ..., int x y dV, ...)\n"
               "    of the tetrahedron with vertices 0, p1, p2, p3 (affine map of the unit simplex).",
               returns="tuple (V, Mx, My, Mz, Sxx, Syy, Szz, Sxy, Sxz, Syz), signed by det[p1 p2 p3]"),
    ]


def generated_files() -> dict[str, str]:
    """The emitted mass-properties module, by its path under ``dtcrit/_generated``.

    Returns
    -------
    dict of str to str
        File name -> Python source.
    """
    summary = (
        "Volumes and principal moments of inertia of particle shapes (sphere, ellipsoid, box,\n"
        "superquadric) and the moments of a tetrahedron for the exact decomposition of convex polyhedra.\n"
        "Derived in dtcrit.symbolic.mass_properties; used by dtcrit.bodies."
    )
    preamble = (
        "import math\n"
        "\n"
        "\n"
        "def gamma(x):\n"
        "    \"\"\"Gamma function element-wise through ``math.gamma`` (scalars or arrays; no SciPy import,\n"
        "    which keeps ``dtcrit step`` start-up short).\"\"\"\n"
        "    if np.ndim(x) == 0:\n"
        "        return math.gamma(float(x))\n"
        "    return np.vectorize(math.gamma, otypes=[float])(x)"
    )
    return {TARGET: python_module(PRODUCER, summary, kernels(), preamble=preamble)}
