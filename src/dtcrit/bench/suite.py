"""The extreme-case suite of ``dtcrit bench``: named scenes that stress every route.

Each :class:`Case` is one contact, ``xddot = -k A x - c A xdot`` (Peng et al. 2020, Eq. (30)),
given by its float inputs ``k`` [N/m], ``c`` [N s/m] and ``A`` [1/kg]; sphere cases also carry
the particle mass ``m`` (two identical spheres: ``A = 7/m``, Section 4.3), which the paper's
sphere forms (Eqs. (36), (58)-(60)) need.  The groups:

``stiffness``  k A from 1e-12 s^-2 (a 1e6 kg boulder on a very soft contact) to 1e24 s^-2
               (a 1e-18 kg nano-powder grain on a stiff contact), and ordinary DEM scenes;
``mass``       particle masses 1e-18 kg and 1e6 kg at ordinary damping;
``damping``    a 1 mm steel sphere from zeta = 0 through 1e-12 ... 0.5, just below, exactly at
               (Eq. (37) in float64) and just above critical damping, to 10^6 x critical;
``critical``   exactly critical inputs (zeta = 1 with no rounding: powers of two) and one ulp of
               c either side: the switch point of forward Euler's closed form;
``asymptote``  the vertical asymptotes of Eqs. (58) (beta = 2/sqrt 7, i.e. critical damping)
               and (59) (beta = 2 sqrt 2), on them and 1e-9 below;
``aspect``     two identical prolate ellipsoids of aspect ratio 1 ... 1e4 (A from Eq. (26));
``float-range`` inputs near float64's overflow and underflow: k A, c A, c^2 A^2 or zeta beyond
               the range when formed naively, subnormal inputs, and steps that themselves lie
               beyond float64 (which a route must refuse, not return as inf or as 0 = "no
               stable step").

``BATCH``: the random scenes of the timing batch (:func:`random_batch`), log-uniform over the
same decades, with shares of undamped and near-critical scenes.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

WELL_CONDITIONED = "well-conditioned"
NEAR_CRITICAL_OR_EXTREME = "near-critical/extreme"


@dataclass(frozen=True)
class Case:
    """One scene of the extreme suite.

    Parameters
    ----------
    name : str
        Name of the case.
    group : str
        What it stresses (stiffness, damping, ...).
    description : str
        The scene in words.
    k : float
        Stiffness [N/m].
    c : float
        Viscous coefficient [N s/m].
    A : float
        Inverse inertia of the mode [1/kg].
    m : float, optional
        Particle mass for two-identical-sphere cases (A = 7/m) [kg].
    """

    name: str
    group: str
    description: str
    k: float
    c: float
    A: float
    m: float | None = None  # particle mass for two-identical-sphere cases (A = 7/m)

    @property
    def zeta_float(self) -> float:
        """Damping ratio in float64 via exact power-of-two scaling (inf when beyond the range)."""
        from dtcrit.integrators.stability import scaled_rates

        with np.errstate(all="ignore"):
            w, g, _ = scaled_rates(self.k, self.c, self.A)
            return float(g / w)


def _sphere_mass(radius: float, density: float) -> float:
    return 4.0 / 3.0 * math.pi * radius**3 * density


def _sphere(name, group, description, m, k, zeta=None, beta=None, c=None) -> Case:
    """Two identical spheres of mass m: A = 7/m (Peng et al. 2020, Eq. (49) set-up)."""
    A = 7.0 / m
    if c is None:
        c = beta * math.sqrt(m * k) if beta is not None else 2.0 * zeta * math.sqrt(k / A)
    return Case(name, group, description, float(k), float(c), float(A), float(m))


def _prolate_pair(aspect: float, b: float = 1e-3, density: float = 2500.0, k: float = 1e6, zeta: float = 0.2) -> Case:
    """Two identical prolate ellipsoids (a = aspect b, b = c): A_max of Eq. (26)."""
    from dtcrit.bodies import Ellipsoid

    shape = Ellipsoid(aspect * b, b, b, density=density)
    A = _a_max_identical(shape)
    c = 2.0 * zeta * math.sqrt(k / A)
    return Case(f"aspect-{aspect:g}", "aspect",
                f"two prolate ellipsoids {aspect:g}:1:1 (b = 1 mm, 2500 kg/m^3), k = 1e6 N/m, zeta = 0.2; A from Eq. (26)",
                k, c, A)


def _a_max_identical(shape) -> float:
    """Peng et al. 2020, Eq. (26) for two identical particles (``dtcrit.bodies.contact.a_max`` when present)."""
    try:
        from dtcrit.bodies.contact import a_max
    except ImportError:
        a = shape.half_lengths[0]
        I_xx = min(shape.inertia)
        return 2.0 * (a * a / I_xx + 1.0 / shape.mass)
    return float(a_max(shape))


M_NANO = _sphere_mass(45e-9, 2650.0)  # silica grain, ~1.0e-18 kg
M_BOULDER = _sphere_mass(4.47, 2650.0)  # rock, ~1.0e6 kg
M_STEEL = _sphere_mass(1e-3, 7850.0)  # 1 mm radius steel ball, 3.29e-5 kg
M_GLASS = _sphere_mass(50e-6, 2500.0)  # 100 um glass bead
K_STEEL = 1e7


def _steel(name, group, description, **kw) -> Case:
    return _sphere(name, group, description, M_STEEL, K_STEEL, **kw)


def build_suite() -> tuple[Case, ...]:
    """The extreme suite: scenes spread over stiffness, mass and damping ratio to float64's limits.

    Returns
    -------
    tuple of Case
        The cases.
    """
    cases: list[Case] = []
    add = cases.append
    # stiffness: k A over 36 decades
    add(_sphere("kA-1e-12", "stiffness", "k A = 1e-12 s^-2: a 1e6 kg boulder on a 1.4e-7 N/m contact, zeta = 0.1",
                M_BOULDER, 1e-12 * M_BOULDER / 7.0, zeta=0.1))
    add(_sphere("kA-1e24", "stiffness", "k A = 1e24 s^-2: a 1e-18 kg nano-powder grain on a 1.4e5 N/m contact, zeta = 0.1",
                M_NANO, 1e24 * M_NANO / 7.0, zeta=0.1))
    add(_sphere("glass-100um", "stiffness", "100 um glass beads, k = 1e5 N/m, zeta = 0.1", M_GLASS, 1e5, zeta=0.1))
    add(_steel("steel-1mm", "stiffness", "1 mm steel balls, k = 1e7 N/m, zeta = 0.1", zeta=0.1))
    # masses
    add(_sphere("mass-1e-18", "mass", "1e-18 kg grains, k = 1e3 N/m, zeta = 0.3", 1e-18, 1e3, zeta=0.3))
    add(_sphere("mass-1e6", "mass", "1e6 kg bodies, k = 1e10 N/m, zeta = 0.3", 1e6, 1e10, zeta=0.3))
    # damping sweep on the steel balls
    for label, z in (("0", 0.0), ("1e-12", 1e-12), ("1e-6", 1e-6), ("0.05", 0.05), ("0.5", 0.5),
                     ("1-1e-6", 1 - 1e-6), ("1+1e-8", 1 + 1e-8), ("1+1e-4", 1 + 1e-4), ("10", 10.0),
                     ("1e3", 1e3), ("1e6", 1e6)):
        add(_steel(f"zeta-{label}", "damping", f"1 mm steel balls, zeta = {label}", zeta=z))
    c37 = 2.0 * math.sqrt(K_STEEL / (7.0 / M_STEEL))  # Eq. (37) in float64
    add(_steel("zeta-eq37", "damping", "1 mm steel balls, c = Eq. (37) critical damping evaluated in float64", c=c37))
    # exactly critical and one ulp either side (powers of two: no rounding anywhere)
    add(Case("critical-exact", "critical", "k = 4, c = 4, A = 1: zeta = 1 exactly", 4.0, 4.0, 1.0))
    add(Case("critical-plus-1ulp", "critical", "k = 4, c = 4 (1 + 2^-52), A = 1: one ulp overdamped", 4.0, 4.0 * (1 + 2.0**-52), 1.0))
    add(Case("critical-minus-1ulp", "critical", "k = 4, c = 4 (1 - 2^-53), A = 1: one ulp underdamped", 4.0, 4.0 * (1 - 2.0**-53), 1.0))
    add(Case("critical-exact-scaled", "critical", "k = 2^60, c = 2^51, A = 2^-40: zeta = 1 exactly at omega = 1024",
             2.0**60, 2.0**51, 2.0**-40))
    add(Case("critical-plus-1ulp-scaled", "critical", "k = 2^60, c = 2^51 (1 + 2^-52), A = 2^-40",
             2.0**60, 2.0**51 * (1 + 2.0**-52), 2.0**-40))
    # the asymptotes of Eqs. (58) and (59)
    b58, b59 = 2.0 / math.sqrt(7.0), 2.0 * math.sqrt(2.0)
    add(_steel("eq58-asymptote", "asymptote", "beta = 2/sqrt(7) in float64 (Eq. (58)'s pole; zeta = 1 up to rounding)", beta=b58))
    add(_steel("eq58-asymptote-1e-9", "asymptote", "beta = 2/sqrt(7) (1 - 1e-9)", beta=b58 * (1 - 1e-9)))
    add(_steel("eq59-asymptote", "asymptote", "beta = 2 sqrt(2) in float64 (Eq. (59)'s pole; zeta = sqrt(14))", beta=b59))
    add(_steel("eq59-asymptote-1e-9", "asymptote", "beta = 2 sqrt(2) (1 - 1e-9)", beta=b59 * (1 - 1e-9)))
    # aspect ratios
    for ar in (1.0, 10.0, 100.0, 1e3, 1e4):
        add(_prolate_pair(ar))
    # float64 range
    add(Case("kA-overflow", "float-range", "k = A = 1e300: k A = 1e600 overflows if formed; zeta = 0.3", 1e300, 0.6, 1e300))
    add(Case("kA-underflow", "float-range", "k = A = 1e-300: k A = 1e-600 underflows if formed; zeta = 0.3", 1e-300, 0.6, 1e-300))
    add(Case("k-subnormal", "float-range", "k = 5e-324 (smallest subnormal), A = 1, undamped: dt = 9e161 s", 5e-324, 0.0, 1.0))
    add(Case("k-A-max", "float-range", "k = A = largest float, undamped: dt = 1.1e-308 s (subnormal)",
             1.7976931348623157e308, 0.0, 1.7976931348623157e308))
    add(Case("cA-overflow", "float-range", "c = A = 1e160, k = 1e-100: c A = 1e320 overflows if formed; dt ~ 2e-320 s (subnormal)",
             1e-100, 1e160, 1e160))
    add(Case("c2A2-overflow", "float-range", "c = 1e160, A = 1, k = 1e300: c^2 A^2 = 1e320 overflows (Eq. (46) as printed); zeta = 5e9",
             1e300, 1e160, 1.0))
    add(Case("zeta-overflow", "float-range", "k = 1e-300, c = 1e300, A = 1e-10: zeta = 5e444 is beyond float64; dt ~ 2e-290 s",
             1e-300, 1e300, 1e-10))
    add(Case("zeta-underflow", "float-range", "k = 1e300, c = 5e-324, A = 1: zeta ~ 2.5e-474 (c A subnormal)", 1e300, 5e-324, 1.0))
    add(Case("dt-overflow", "float-range", "k = A = 1e-310 (subnormal), undamped: dt = 2e310 s is beyond float64 (must refuse)",
             1e-310, 0.0, 1e-310))
    add(Case("dt-underflow", "float-range", "k = A = c = 1e300: dt ~ 2e-600 s is below float64's range (must refuse, not 0)",
             1e300, 1e300, 1e300))
    return tuple(cases)


def category_of(zeta) -> np.ndarray:
    """True where a scene is near-critical or extreme (for the work-precision plot's split).

    Well-conditioned: 1e-3 <= zeta <= 1e2 with |zeta - 1| > 1e-3.

    Parameters
    ----------
    zeta : array_like
        Damping ratios.

    Returns
    -------
    numpy.ndarray
        Booleans.
    """
    z = np.asarray(zeta, dtype=float)
    with np.errstate(invalid="ignore"):
        return ~((z >= 1e-3) & (z <= 1e2) & (np.abs(z - 1.0) > 1e-3))


@dataclass(frozen=True)
class Batch:
    """Random scenes as arrays.

    Parameters
    ----------
    k : numpy.ndarray
        Stiffness [N/m].
    c : numpy.ndarray
        Viscous coefficient [N s/m].
    A : numpy.ndarray
        Inverse inertia [1/kg].
    zeta : numpy.ndarray
        Damping ratio as intended when drawing.
    extreme : numpy.ndarray
        Near-critical or extreme scenes (``category_of``).
    """

    k: np.ndarray
    c: np.ndarray
    A: np.ndarray
    zeta: np.ndarray  # as intended when drawing (float64)
    extreme: np.ndarray  # bool: near-critical/extreme (see category_of)

    def __len__(self) -> int:
        return self.k.size

    def take(self, idx) -> "Batch":
        """The scenes at ``idx``.

        Parameters
        ----------
        idx : int, slice or array_like
            NumPy index.

        Returns
        -------
        Batch
            The selected scenes.
        """
        return Batch(self.k[idx], self.c[idx], self.A[idx], self.zeta[idx], self.extreme[idx])


def random_batch(n: int, seed: int = 20200501) -> Batch:
    """``n`` scenes: m log-uniform 1e-18 ... 1e6 kg (A = 7/m), k A log-uniform 1e-12 ... 1e24 s^-2;
    zeta log-uniform 1e-6 ... 1e6 (80 %), 0 (5 %), 1 + 10^U(-15, -2) or 1 - 10^U(-15, -2) (15 %).
    Deterministic for a given seed.

    Parameters
    ----------
    n : int
        Number of scenes.
    seed : int
        Seed of the generator.

    Returns
    -------
    Batch
        The scenes.
    """
    rng = np.random.default_rng(seed)
    m = 10.0 ** rng.uniform(-18, 6, n)
    A = 7.0 / m
    kA = 10.0 ** rng.uniform(-12, 24, n)
    k = kA / A
    zeta = 10.0 ** rng.uniform(-6, 6, n)
    u = rng.uniform(0, 1, n)
    near = u < 0.15
    zeta[near] = 1.0 + rng.choice([-1.0, 1.0], near.sum()) * 10.0 ** rng.uniform(-15, -2, near.sum())
    zeta[(u >= 0.15) & (u < 0.20)] = 0.0
    c = 2.0 * zeta * np.sqrt(k / A)
    return Batch(k, c, A, zeta, category_of(zeta))


SUITE: tuple[Case, ...] = build_suite()
