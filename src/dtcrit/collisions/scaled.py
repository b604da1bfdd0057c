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
from dtcrit.physics.collision_laws import CollisionLaw, check_normal

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


__all__ = ["ScaledLaw", "HERTZ_W0", "HOOKE_W0", "entry_speed", "elastic_scales", "scaled_from_physical"]
