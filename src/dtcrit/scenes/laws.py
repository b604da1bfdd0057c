"""Contact laws resolved per contact: a pair of particle types at given radii, or a particle and a wall,
to linear(ised) stiffness ``(k_n, k_s)`` and dashpots ``(c_n, c_s)`` (Peng et al. 2020, Eq. (29)).

* ``linear``: ``kn``, ``ks`` as given.
* ``yade``: YADE's default linear law (Ip2_FrictMat_FrictMat_FrictPhys):
  ``kn = 2 E1 R1 E2 R2 / (E1 R1 + E2 R2)`` (``2 E R1 R2/(R1 + R2)`` for one material) and
  ``ks = ks_ratio * kn`` (YADE's ``FrictMat.poisson`` is this ratio, not Poisson's ratio).
* ``hertz`` (Hertz normal, Mindlin no-slip tangential): the tangent stiffnesses at the largest
  overlap of an impact at ``velocity``: ``k_n = 2 E* sqrt(R* delta_max)``,
  ``k_s = 8 G* sqrt(R* delta_max)``, ``delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5)``.

Damping given as ``restitution`` or ``damping_ratio`` is mapped by the scene's damping convention
(:mod:`dtcrit.physics.damping_conventions`), with the reduced mass ``m* = m1 m2/(m1 + m2)`` between particles and
the convention's wall mass against a wall.
"""
from __future__ import annotations

import math

from dtcrit.errors import InputError
from dtcrit.physics import contact_laws as cl
from dtcrit.physics.contact_laws import hertz_max_overlap
from dtcrit.physics.damping_conventions import CONVENTIONS, DEFAULT_CONVENTION
from dtcrit.scenes.damping_input import convention_for
from dtcrit.scenes.law_damping import LAW_CONVENTIONS, is_law_convention, law_dashpots
from dtcrit.scenes.model import PairContact, _harmonic

__all__ = ["hertz_max_overlap", "resolve_pair", "resolve_wall", "wall_convention", "convention_of"]


def _hertz(scene, p, q, m_star: float, r1: float | None, r2: float | None, label: str):
    law = scene.contact
    e_star = cl.effective_youngs_modulus(p.youngs_modulus, p.poisson_ratio, q.youngs_modulus, q.poisson_ratio)
    g_star = cl.effective_shear_modulus(p.youngs_modulus, p.poisson_ratio, q.youngs_modulus, q.poisson_ratio)
    if law.curvature_radius is not None:
        r_star = law.curvature_radius
    else:
        assert r1 is not None and r2 is not None  # resolve_pair gives both radii to a sphere pair
        r_star = _harmonic(r1, r2)
    delta = hertz_max_overlap(m_star, e_star, r_star, law.velocity)
    root = math.sqrt(r_star * delta)
    kn, ks = cl.hertz_normal_stiffness(e_star, root), cl.mindlin_tangent_stiffness(g_star, root)
    for value in (kn, ks):
        if not (math.isfinite(value) and value > 0.0):
            raise InputError("contact.youngs_modulus", f"pair {label}: the Hertz tangent stiffness {value!r} is outside double precision")
    return kn, ks, dict(e_star=e_star, g_star=g_star, r_star=r_star, delta_max=delta, velocity=law.velocity)


def _dashpots(conv, damping: str, cn, cs, zeta, kn: float, ks: float, m_eff: float) -> tuple[float, float, float | None, float | None]:
    """(c_n, c_s, zeta_n, zeta_s) with the zetas as the convention defines them."""
    if damping in ("coefficients", "none"):
        cn, cs = cn or 0.0, cs or 0.0
    else:
        cn, cs = conv.dashpots(zeta or 0.0, kn, ks, m_eff)
    zn, zs = conv.ratios(cn, cs, kn, ks, m_eff)
    return cn, cs, zn, zs


def _law_terms(conv, e, coefficient, factor, kn: float, ks: float, m_eff: float,
               a: float | None) -> tuple[float, float, float | None, float | None]:
    """(c_n, c_s, zeta_n, zeta_s) of a Hertz law convention at the tangent stiffnesses (``scenes.law_damping``)."""
    cn, cs = law_dashpots(conv.name, restitution=e, coefficient=coefficient, tangential_factor=factor, kn=kn, ks=ks,
                          m_eff=m_eff, contact_radius=a)
    zn, zs = conv.ratios(cn, cs, kn, ks, m_eff)
    return cn, cs, zn, zs


def resolve_pair(scene, i: int, j: int, r1: float | None = None, r2: float | None = None) -> PairContact:
    """The linearised contact of particle types ``i`` and ``j`` at given radii (module docstring).

    Stiffness by the scene's law (``linear``/``bond`` as given, ``yade``, ``hertz`` at the largest
    overlap of the impact), dashpots by its damping convention with the reduced mass
    ``m* = m1 m2/(m1 + m2)``, and the rolling/twisting terms of the law (Peng et al. 2020, Eq. (29)).

    Parameters
    ----------
    scene : Scene
        The parsed scene (particle types, contact law).
    i : int
        First particle type, counted from 1.
    j : int
        Second particle type, counted from 1.
    r1 : float or None
        Radius of type ``i`` [m] (spheres; default: its smallest radius).
    r2 : float or None
        Radius of type ``j`` [m] (spheres; default: its smallest radius).

    Returns
    -------
    PairContact
        Reduced mass [kg], springs ``kn``, ``ks`` [N/m], dashpots ``cn``, ``cs`` [N s/m], damping ratios,
        rotational terms and (Hertz) the overlap quantities.

    Raises
    ------
    InputError
        When the Hertz tangent stiffness leaves double precision.
    """
    p, q = scene.particle(i), scene.particle(j)
    r1 = p.radii[0] if r1 is None and p.radii else r1
    r2 = q.radii[0] if r2 is None and q.radii else r2
    m1 = p.mass_at(r1)
    m2 = q.mass_at(r2)
    m_star = _harmonic(m1, m2)
    law = scene.contact
    label = f"{i}-{j}"
    extra: dict = {}
    if law.model in ("linear", "bond"):
        kn, ks = law.kn, law.ks
    elif law.model == "yade":
        kn = cl.yade_normal_stiffness(p.youngs_modulus * r1, q.youngs_modulus * r2)
        ks = law.ks_ratio * kn
    else:
        kn, ks, extra = _hertz(scene, p, q, m_star, r1, r2, label)
    conv = _convention(law)
    if is_law_convention(conv.name, law.model):  # one code's collision law at the linearisation overlap
        cn, cs, zn, zs = _law_terms(conv, law.restitution, law.damping_coefficient, law.tangential_damping_factor, kn, ks,
                                    m_star, math.sqrt(extra["r_star"] * extra["delta_max"]))
    else:
        cn, cs, zn, zs = _dashpots(conv, law.damping, law.cn, law.cs, law.damping_ratio, kn, ks, m_star)
    kr, ktw, cr, ctw = _rotational(law, kn, ks, cs, p.shape_at(r1), q.shape_at(r2), r1, r2, m1, m2, extra.get("delta_max"), label)
    return PairContact(i, j, m_star, kn, ks, cn, cs, law.damping_ratio if law.damping not in ("coefficients", "none") else None,
                       radius_i=r1, radius_j=r2, zeta_n=zn, zeta_s=zs, convention=conv.name, kr=kr, ktw=ktw, cr=cr, ctw=ctw,
                       **extra)


def _convention(law):
    """A bond's dashpots map like a linear contact's, PFC's convention by default."""
    if law.model == "bond":
        return convention_for(law.damping_convention or "pfc", "linear")
    return convention_for(law.damping_convention, law.model)


def _rotational(law, kn, ks, cs, p_shape, q_shape, r1, r2, m1, m2, delta, label):
    """``(k_r, k_tw, c_r, c_tw)`` of a particle pair (:mod:`dtcrit.scenes.rotational`, :mod:`dtcrit.scenes.bonds`)."""
    if law.bond is not None:
        from dtcrit.scenes.bonds import rotational_dashpots

        cr, ctw = rotational_dashpots(law.bond, law.damping_ratio, law.bond.kr, law.bond.ktw, min(p_shape.inertia),
                                      min(q_shape.inertia))
        return law.bond.kr, law.bond.ktw, cr, ctw
    if law.rotational is None:
        return 0.0, 0.0, 0.0, 0.0
    from dtcrit.scenes.rotational import resolve_rotational

    return resolve_rotational(law.rotational, kn, ks, cs, r1, r2, m1, m2, delta, label)


def wall_convention(name: str | None, model: str):
    """The damping convention of a (linear) wall contact.

    The scene's, or its model's default; EDEM, whose law is Hertz-Mindlin only, maps to LIGGGHTS's
    linear (hooke) law.

    Parameters
    ----------
    name : str or None
        Convention named by the scene (``None``: the model's default).
    model : str
        The scene's contact model (``linear``, ``bond``, ``yade``, ``hertz``).

    Returns
    -------
    Convention
        Entry of ``dtcrit.physics.damping_conventions.CONVENTIONS``.
    """
    chosen = name or DEFAULT_CONVENTION["linear" if model == "bond" else model]
    return CONVENTIONS["liggghts" if chosen == "edem" else chosen]


def resolve_wall(scene, wall, i: int, r: float | None = None) -> PairContact:
    """The linear(ised) contact of particle type ``i`` with a fixed wall.

    The wall's springs as given (a Hertz wall's: the tangent stiffness at its overlap,
    :mod:`dtcrit.scenes.hertz_walls`); its dashpots by the wall convention with mass ``wall_mass * m``.

    Parameters
    ----------
    scene : Scene
        The parsed scene.
    wall : Wall
        The wall (springs [N/m], damping input, rotational terms).
    i : int
        Particle type, counted from 1.
    r : float or None
        Radius of the particle [m] (spheres; default: the type's smallest radius).

    Returns
    -------
    PairContact
        The contact against the wall (type ``0`` on the wall's side).
    """
    p = scene.particle(i)
    r = p.radii[0] if r is None and p.radii else r
    m = p.mass_at(r)
    if wall.model == "hertz":
        from dtcrit.scenes.hertz_walls import hertz_wall_springs

        conv = convention_for(scene.contact.damping_convention, "hertz", f"wall[{wall.number}].damping_ratio")
        kn, ks = hertz_wall_springs(scene, wall, p, r, m)
    else:
        conv = wall_convention(scene.contact.damping_convention, scene.contact.model)
        kn, ks = wall.kn, wall.ks
    m_eff = conv.wall_mass * m
    _check_law_wall(scene, wall)
    if is_law_convention(conv.name, "hertz") and wall.model == "hertz":
        cn, cs, zn, zs = _law_terms(conv, wall.restitution, None, scene.contact.tangential_damping_factor, kn, ks, m_eff, None)
    else:
        cn, cs, zn, zs = _dashpots(conv, wall.damping, wall.cn, wall.cs, wall.damping_ratio, kn, ks, m_eff)
    return PairContact(i, 0, m_eff, kn, ks, cn, cs, wall.damping_ratio if wall.damping not in ("coefficients", "none") else None,
                       radius_i=r, zeta_n=zn, zeta_s=zs, convention=conv.name, wall=wall.name, wall_number=wall.number,
                       kr=wall.kr, ktw=wall.ktw, cr=wall.cr_value, ctw=wall.ctw_value)


def _check_law_wall(scene, wall) -> None:
    """Refuse a wall that a Hertz law convention does not describe (``dtcrit.scenes.law_damping``)."""
    name, key = scene.contact.damping_convention, f"wall[{wall.number}]."
    if not is_law_convention(name, scene.contact.model) or (wall.model != "hertz" and name == "mercurydpm"):
        return
    if wall.model != "hertz":
        raise InputError(key + "model", f"a linear wall under the Hertz damping convention {name!r} is not modelled")
    if wall.damping not in ("restitution", "none") or (LAW_CONVENTIONS[name].takes == "coefficient" and wall.damping != "none"):
        raise InputError(key + ("cn" if wall.damping == "coefficients" else wall.damping),
                         f"{name} takes {LAW_CONVENTIONS[name].takes}; a wall's "
                         + ("restitution only" if LAW_CONVENTIONS[name].takes == "restitution" else "coefficient is not read"))


def convention_of(scene, pc: PairContact):
    """The damping convention that resolved a contact (a particle pair's, or a wall's).

    Parameters
    ----------
    scene : Scene
        The parsed scene.
    pc : PairContact
        A contact resolved from ``scene``.

    Returns
    -------
    Convention
        Its convention (``dtcrit.physics.damping_conventions.Convention``).
    """
    if pc.wall is not None:
        if any(w.model == "hertz" and w.number == pc.wall_number for w in scene.walls):
            return convention_for(scene.contact.damping_convention, "hertz")
        return wall_convention(scene.contact.damping_convention, scene.contact.model)
    return _convention(scene.contact)
