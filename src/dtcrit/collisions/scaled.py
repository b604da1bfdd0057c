"""A collision law in units of the elastic contact time ``t_c`` and the elastic peak overlap ``delta_el``.

Every law of ``dtcrit.physics.collision_laws`` (``F = k_p delta^p + c0 delta^q delta'``, clipped or not)
becomes, with ``u = delta/delta_el`` and ``s = t/t_c``,

    u'' = -(kappa u^p + g u^q u'),   u(0) = 0,  u'(0) = w0,

with ``w0 = v t_c/delta_el`` and ``kappa = (p + 1) w0^2/2`` fixed by the normal law alone (hooke:
``w0 = pi``; hertz: ``w0 = (4/5) B(2/5, 1/2)``) and one damping group ``g = (c0/m) delta_el^q t_c``.
So the impact depends only on ``g`` (equivalently the continuum restitution) and on clipping
(derived symbolically in ``dtcrit.symbolic.collision_scaling``).  ``g`` is independent of the speed
for the dashpots proportional to ``sqrt(m S_n)`` (tsuji, coeff_restitution, LIGGGHTS, YADE, MercuryDPM)
and for every linear-dashpot hooke law; for ``lammps-viscoelastic`` and hertz ``lammps-mass-velocity``
it depends on the speed, and these laws are keyed by the continuum restitution they produce.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from scipy.special import beta as _beta

from dtcrit.errors import InputError
from dtcrit.physics.collision_laws import (
    DAMPING_MODELS,
    CollisionLaw,
    check_damping,
    check_normal,
    check_restitution,
)
from dtcrit.physics.damping_conventions import (
    TSUJI_FACTORS,
    damping_ratio_from_restitution,
    hertz_mindlin_dissipation,
    lammps_coeff_restitution_damp,
    tsuji_alpha,
)

HERTZ_W0 = 0.8 * float(_beta(0.4, 0.5))
"""``t_c v/delta_el`` of the undamped Hertz impact: ``2 int_0^1 du/sqrt(1 - u^(5/2)) = (4/5) B(2/5, 1/2)``."""
HOOKE_W0 = math.pi


@dataclass(frozen=True)
class ScaledLaw:
    """``u'' = -(kappa u^p + g u^q u')`` for ``u >= 0`` (clipped at 0 when ``clip``), entry speed ``w0``.

    Parameters
    ----------
    p : float
        Exponent of the elastic force (1 or 3/2).
    q : float
        Exponent of the dashpot.
    kappa : float
        Elastic coefficient ``(p + 1) w0^2/2``.
    g : float
        Damping group.
    clip : bool
        Whether the total force is clipped at zero.
    w0 : float
        Entry speed in ``delta_el/t_c``.
    """

    p: float
    q: float
    kappa: float
    g: float
    clip: bool
    w0: float


def entry_speed(normal: str) -> float:
    """``w0 = v t_c/delta_el`` of the normal law (hooke ``pi``, hertz ``(4/5) B(2/5, 1/2)``).

    Parameters
    ----------
    normal : str
        ``"hooke"`` or ``"hertz"``.

    Returns
    -------
    float
        ``w0``.
    """
    return HOOKE_W0 if check_normal(normal) == "hooke" else HERTZ_W0


def _base(normal: str, g: float, q: float, clip: bool) -> ScaledLaw:
    p = 1.0 if normal == "hooke" else 1.5
    w0 = entry_speed(normal)
    return ScaledLaw(p, q, (p + 1.0) * w0 * w0 / 2.0, float(g), bool(clip), w0)


def elastic_scales(law: CollisionLaw, v_impact: float) -> tuple[float, float]:
    """``(t_c, delta_el)`` [s, m]: the undamped contact duration and peak overlap at impact speed ``v_impact``.

    Parameters
    ----------
    law : CollisionLaw
        The physical law.
    v_impact : float
        Relative normal speed at impact [m/s].

    Returns
    -------
    tuple of float
        ``t_c``, ``delta_el``.
    """
    k_m = law.stiffness / law.m_eff
    if law.exponent == 1.0:
        return math.pi / math.sqrt(k_m), v_impact / math.sqrt(k_m)
    d_el = (1.25 * v_impact * v_impact / k_m) ** 0.4
    return HERTZ_W0 * d_el / v_impact, d_el


def scaled_from_physical(law: CollisionLaw, v_impact: float) -> ScaledLaw:
    """The scaled form of a physical law at impact speed ``v_impact``: ``g = (c0/m) delta_el^q t_c``.

    Parameters
    ----------
    law : CollisionLaw
        The physical law.
    v_impact : float
        Relative normal speed at impact [m/s] (> 0).

    Returns
    -------
    ScaledLaw
        The scaled law.
    """
    if not (v_impact is not None and v_impact > 0 and math.isfinite(v_impact)):
        raise InputError("v_impact", f"must be a positive finite speed (got {v_impact!r})")
    t_c, d_el = elastic_scales(law, v_impact)
    g = law.c0 / law.m_eff * d_el**law.q * t_c
    return _base(law.normal, g, law.q, law.clip)


def _group_from_restitution(normal: str, damping: str, e: float, kappa: float, tsuji_version: str) -> float | None:
    """``g`` of a model that takes ``e`` (None when ``g`` must be solved from the continuum restitution)."""
    root = math.pi if normal == "hooke" else math.sqrt(kappa)  # sqrt(k/m) t_c, resp. sqrt(K/m) delta^(1/4) t_c
    if damping == "none" or e == 1.0 and damping != "lammps-tsuji":
        return 0.0
    if damping == "lammps-tsuji":
        return TSUJI_FACTORS[tsuji_version] * tsuji_alpha(e) * root
    if damping == "lammps-coeff-restitution":
        return lammps_coeff_restitution_damp(e, normal) * root
    if damping in ("liggghts", "yade-mindlin", "mercurydpm"):
        return 2.0 * damping_ratio_from_restitution(e) * root if normal == "hooke" else hertz_mindlin_dissipation(e) * root
    if damping == "lammps-mass-velocity" and normal == "hooke":
        return 2.0 * damping_ratio_from_restitution(e) * math.pi  # a linear dashpot: exact
    return None


def scaled_law(normal: str, damping: str, restitution: float, clip: bool | None = None,
               tsuji_version: str = "current") -> ScaledLaw:
    """The scaled law of a code's model at restitution ``e`` (``e`` as the code takes it).

    For ``lammps-viscoelastic`` and hertz ``lammps-mass-velocity`` (which take a coefficient and whose
    restitution depends on the speed) ``restitution`` is the continuum restitution the impact has; the
    group is then solved from the continuum reference.

    Parameters
    ----------
    normal : str
        ``"hooke"`` or ``"hertz"``.
    damping : str
        A key of ``DAMPING_MODELS``.
    restitution : float
        ``e`` in (0, 1].
    clip : bool, optional
        Clip the force at zero; default: what the code does.
    tsuji_version : str
        ``"current"`` or ``"2021"`` (``lammps-tsuji`` only).

    Returns
    -------
    ScaledLaw
        The scaled law.
    """
    normal = check_normal(normal)
    model = check_damping(damping, normal)
    e = check_restitution(restitution)
    if tsuji_version not in TSUJI_FACTORS:
        raise InputError("tsuji_version", f"must be one of {', '.join(TSUJI_FACTORS)} (got {tsuji_version!r})")
    q = model.exponents[normal]
    c = model.clips if clip is None else bool(clip)
    base = _base(normal, 0.0, q, c)
    g = _group_from_restitution(normal, damping, e, base.kappa, tsuji_version)
    if g is None:
        from dtcrit.collisions.reference import group_for_restitution
        g = group_for_restitution(base, e)
    return _base(normal, g, q, c)


__all__ = ["ScaledLaw", "HERTZ_W0", "HOOKE_W0", "entry_speed", "elastic_scales", "scaled_from_physical",
           "scaled_law", "DAMPING_MODELS"]
