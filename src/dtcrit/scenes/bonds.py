"""Bonded particles: ``[contact] model = "bond"``, the springs of a bond between two particles.

A bond has four springs: normal ``k_n`` and shear ``k_s`` [N/m] on the relative displacement of the
contact point, bending ``k_r`` and twisting ``k_tw`` [N m/rad] on the relative rotation (perpendicular
to and about the bond axis), the same contact element as a contact with rotational springs
(:mod:`dtcrit.symbolic.rotational_modes`: arms ``R_i n``, relative rotation ``theta_2 - theta_1``).
They are given

* directly: ``kn``, ``ks``, ``kr``, ``ktw``.  LAMMPS ``bond_style bpm/rotational`` takes them so
  (``bond_coeff`` ``K_r`` = ``kn``, ``K_s`` = ``ks``, ``K_b`` = ``kr``, ``K_t`` = ``ktw``; docs
  ``bond_bpm_rotational``; with ``normalize yes`` ``K_r``, ``K_s`` are forces and ``kn = K_r/r_0``);
* or from the bond's material and cylinder as PFC's linear parallel bond defines them (PFC manual,
  "Linear Parallel Bond Model": force ``kn_bar A du_n``, ``ks_bar A du_s``, twisting moment
  ``ks_bar J dtheta_t``, bending moment ``kn_bar I dtheta_b``, with ``A = pi r^2``, ``I = pi r^4/4``,
  ``J = pi r^4/2`` of the bond radius ``r``; its deformability method sets ``kn_bar = E/L``, ``L`` the
  bond length, and ``ks_bar = kn_bar/kappa``): ``bond_youngs_modulus`` ``E``, ``bond_radius`` ``r``,
  ``bond_length`` ``L`` and the shear as ``bond_stiffness_ratio`` ``kappa`` (PFC's ``kn_bar/ks_bar``),
  or ``bond_shear_modulus`` ``G`` / ``bond_poisson_ratio`` ``nu`` (``ks_bar = G/L``, ``G = E/(2 (1 + nu))``:
  the cylinder's elastic beam springs ``E A/L``, ``G A/L``, ``E I/L``, ``G J/L``).

YADE's cohesive bond (``CohFrictPhys`` with its moment law) is ``model = "yade"`` with
``rolling_model = "yade"`` (:mod:`dtcrit.scenes.rotational`): the same element.  ``contact_kn``,
``contact_ks`` add the particles' own linear contact in parallel (PFC's linear parallel bond model,
LAMMPS ``overlay/pair yes``): the springs add.  Damping: coefficients ``cn``, ``cs`` [N s/m], ``cr``,
``ctw`` [N m s/rad] (LAMMPS ``gamma_n``, ``gamma_s``, ``gamma_r``, ``gamma_t``), or ``damping_ratio``
``zeta``: ``cn``, ``cs`` as the scene's ``damping_convention`` maps it (default ``pfc``) and
``c_r = 2 zeta sqrt(k_r I*)``, ``c_tw = 2 zeta sqrt(k_tw I*)``, ``I* = I_1 I_2/(I_1 + I_2)``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from dtcrit.errors import InputError
from dtcrit.scenes.fields import _number

MATERIAL_KEYS = ("bond_youngs_modulus", "bond_shear_modulus", "bond_poisson_ratio", "bond_stiffness_ratio", "bond_radius",
                 "bond_length")
SPRINGS = ("kn", "ks", "kr", "ktw")


@dataclass(frozen=True)
class BondLaw:
    """A bonded contact: the bond's springs, the contact's in parallel, and rotational dashpots.

    Parameters
    ----------
    kn : float
        Normal spring of the bond [N/m].
    ks : float
        Tangential spring of the bond [N/m].
    kr : float
        Rolling (bending) spring [N m/rad].
    ktw : float
        Twisting spring [N m/rad].
    source : str
        How the springs were obtained, in words.
    contact_kn : float
        Normal spring of the contact in parallel [N/m].
    contact_ks : float
        Tangential spring of the contact in parallel [N/m].
    cr : float or None
        Rolling dashpot [N m s/rad] when given.
    ctw : float or None
        Twisting dashpot [N m s/rad] when given.
    """

    kn: float
    ks: float
    kr: float
    ktw: float
    source: str  # how the springs were obtained, in words
    contact_kn: float = 0.0
    contact_ks: float = 0.0
    cr: float | None = None
    ctw: float | None = None


def parallel_bond_springs(E: float, radius: float, length: float, *, kappa: float | None = None,
                          G: float | None = None) -> tuple[float, float, float, float]:
    """``(k_n, k_s, k_r, k_tw)`` of PFC's linear parallel bond with ``kn_bar = E/L`` and ``ks_bar = kn_bar/kappa``
    (or ``G/L``): ``kn_bar A``, ``ks_bar A``, ``kn_bar I``, ``ks_bar J`` (module docstring).

    Parameters
    ----------
    E : float
        Young's modulus of the bond [Pa].
    radius : float
        Radius of the bond's cylinder [m].
    length : float
        Length of the bond [m].
    kappa : float, optional
        Normal-to-shear stiffness ratio ``kn_bar/ks_bar``.
    G : float, optional
        Shear modulus of the bond [Pa], used when ``kappa`` is not given.

    Returns
    -------
    tuple of float
        ``(k_n, k_s, k_r, k_tw)`` [N/m, N/m, N m/rad, N m/rad].
    """
    area = math.pi * radius * radius
    second = area * radius * radius / 4.0  # I = pi r^4/4
    polar = 2.0 * second  # J = pi r^4/2
    kn_bar = E / length
    if kappa is not None:
        ks_bar = kn_bar / kappa
    elif G is not None:
        ks_bar = G / length
    else:
        raise ValueError("give kappa or G")
    return kn_bar * area, ks_bar * area, kn_bar * second, ks_bar * polar


def parse_bond(prefix: str, table: dict) -> BondLaw:
    """Validate a ``model = "bond"`` table: springs directly, or the parallel bond's material and cylinder.

    Parameters
    ----------
    prefix : str
        Location of the table in the scene file, prefixed to the keys of error messages.
    table : dict
        The ``[contact]`` table's entries.

    Returns
    -------
    BondLaw
        The bond's springs, the contact springs in parallel and the rotational dashpots.

    Raises
    ------
    InputError
        When springs and material are mixed, a key is missing, or a value is invalid.
    """
    direct = [k for k in SPRINGS if k in table]
    material = [k for k in MATERIAL_KEYS if k in table]
    if direct and material:
        raise InputError(prefix + material[0], f"the bond's springs are given directly ({', '.join(direct)}); give them "
                         "directly or from the bond's material and cylinder, not both")
    if material or not direct:
        for key, what in (("bond_youngs_modulus", "the bond's Young's modulus E [Pa]"),
                          ("bond_radius", "the bond's radius r [m]"), ("bond_length", "the bond's length L [m] (kn = E A/L)")):
            if key not in table:
                raise InputError(prefix + key, f"missing: {what}; or give the springs kn, ks, kr, ktw directly")
        shear = [k for k in ("bond_stiffness_ratio", "bond_shear_modulus", "bond_poisson_ratio") if k in table]
        if len(shear) != 1:
            raise InputError(prefix + (shear[1] if shear else "bond_stiffness_ratio"),
                             "give the bond's shear one way: bond_stiffness_ratio (PFC's kn_bar/ks_bar), "
                             "bond_shear_modulus or bond_poisson_ratio")
        E = _number(prefix + "bond_youngs_modulus", table["bond_youngs_modulus"])
        radius = _number(prefix + "bond_radius", table["bond_radius"])
        length = _number(prefix + "bond_length", table["bond_length"])
        kappa = G = None
        if shear[0] == "bond_stiffness_ratio":
            kappa = _number(prefix + "bond_stiffness_ratio", table["bond_stiffness_ratio"])
            how = f"PFC linear parallel bond, kn_bar = E/L, ks_bar = kn_bar/{kappa:g}"
        elif shear[0] == "bond_shear_modulus":
            G = _number(prefix + "bond_shear_modulus", table["bond_shear_modulus"])
            how = "PFC linear parallel bond, kn_bar = E/L, ks_bar = G/L"
        else:
            nu = _number(prefix + "bond_poisson_ratio", table["bond_poisson_ratio"], allow_zero=True, lo=-1.0, hi=0.5,
                         hi_open=True)
            if nu <= -1.0:
                raise InputError(prefix + "bond_poisson_ratio", "must exceed -1")
            G = E / (2.0 * (1.0 + nu))
            how = f"PFC linear parallel bond, kn_bar = E/L, ks_bar = G/L with G = E/(2 (1 + {nu:g}))"
        springs: tuple[float, ...] = parallel_bond_springs(E, radius, length, kappa=kappa, G=G)
        for name, value in zip(SPRINGS, springs):
            if not (math.isfinite(value) and value > 0):
                raise InputError(prefix + "bond_youngs_modulus", f"the bond's {name} = {value!r} is outside double precision")
        source = f"{how}, r = {radius:g} m, L = {length:g} m"
    else:
        missing = [k for k in SPRINGS if k not in table]
        if missing:
            raise InputError(prefix + missing[0], "missing: a bond given by its springs needs kn, ks, kr, ktw "
                             "(LAMMPS bpm/rotational K_r, K_s, K_b, K_t); 0 is allowed for ks, kr, ktw")
        springs = (_number(prefix + "kn", table["kn"]),) + tuple(
            _number(prefix + k, table[k], allow_zero=True) for k in SPRINGS[1:])
        source = "given directly"
    contact = tuple(_number(prefix + k, table[k], allow_zero=True) if k in table else 0.0 for k in ("contact_kn", "contact_ks"))
    cr = _number(prefix + "cr", table["cr"], allow_zero=True) if "cr" in table else None
    ctw = _number(prefix + "ctw", table["ctw"], allow_zero=True) if "ctw" in table else None
    if (cr is not None or ctw is not None) and "damping_ratio" in table:
        raise InputError(prefix + ("cr" if cr is not None else "ctw"),
                         "conflicting damping specifications: coefficients and damping_ratio; give exactly one way")
    kn, ks, kr, ktw = springs
    contact_kn, contact_ks = contact
    return BondLaw(kn, ks, kr, ktw, source, contact_kn, contact_ks, cr=cr, ctw=ctw)


def bond_springs(bond: BondLaw) -> tuple[float, float, float, float]:
    """``(k_n, k_s, k_r, k_tw)`` of the element: the bond's springs plus the contact's in parallel.

    Parameters
    ----------
    bond : BondLaw
        The validated bond.

    Returns
    -------
    tuple of float
        ``(k_n, k_s, k_r, k_tw)`` [N/m, N/m, N m/rad, N m/rad].
    """
    return bond.kn + bond.contact_kn, bond.ks + bond.contact_ks, bond.kr, bond.ktw


def rotational_dashpots(bond: BondLaw, zeta: float | None, kr: float, ktw: float, i1: float, i2: float | None):
    """``(c_r, c_tw)``: the coefficients given, or ``2 zeta sqrt(k I*)`` from a damping ratio.

    ``I* = I_1 I_2/(I_1 + I_2)`` (``I_1`` against a wall).

    Parameters
    ----------
    bond : BondLaw
        The validated bond (its ``cr``, ``ctw`` when given).
    zeta : float or None
        Damping ratio of the rotational modes; None to use the given coefficients.
    kr : float
        Rolling spring [N m/rad].
    ktw : float
        Twisting spring [N m/rad].
    i1 : float
        Moment of inertia of the first particle [kg m^2].
    i2 : float or None
        Moment of inertia of the second particle, None against a wall.

    Returns
    -------
    tuple of float
        ``(c_r, c_tw)`` [N m s/rad].
    """
    if zeta is None:
        return bond.cr or 0.0, bond.ctw or 0.0
    i_star = i1 if i2 is None else (i1 / (1.0 + i1 / i2) if i1 <= i2 else i2 / (1.0 + i2 / i1))
    return 2.0 * zeta * math.sqrt(kr * i_star), 2.0 * zeta * math.sqrt(ktw * i_star)
