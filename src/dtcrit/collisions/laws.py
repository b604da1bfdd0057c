"""The scaled law of a code's damping model at a restitution (``scaled_law``): the damping group ``g`` from
``e`` by each code's map, or, for the models whose restitution depends on the speed, from the continuum
reference (see ``dtcrit.collisions.scaled`` for the scaled form).
"""
from __future__ import annotations

import math

from dtcrit.collisions.reference import group_for_restitution
from dtcrit.collisions.scaled import ScaledLaw, _base
from dtcrit.errors import InputError
from dtcrit.physics.collision_laws import check_damping, check_normal, check_restitution
from dtcrit.physics.damping_conventions import (
    TSUJI_FACTORS,
    damping_ratio_from_restitution,
    hertz_mindlin_dissipation,
    lammps_coeff_restitution_damp,
    tsuji_alpha,
    yade_mindlin_dissipation,
)


def _group_from_restitution(normal: str, damping: str, e: float, kappa: float, tsuji_version: str) -> float | None:
    """``g`` of a model that takes ``e`` (None when ``g`` must be solved from the continuum restitution)."""
    root = math.pi if normal == "hooke" else math.sqrt(kappa)  # sqrt(k/m) t_c, resp. sqrt(K/m) delta^(1/4) t_c
    if damping == "none" or e == 1.0 and not damping.startswith("lammps-tsuji"):
        return 0.0
    if damping.startswith("lammps-tsuji"):
        version = "2021" if damping == "lammps-tsuji-2021" else tsuji_version
        return TSUJI_FACTORS[version] * tsuji_alpha(e) * root
    if damping == "lammps-coeff-restitution":
        return lammps_coeff_restitution_damp(e, normal) * root
    if damping == "yade-mindlin":
        return yade_mindlin_dissipation(e) * root
    if damping in ("liggghts", "mercurydpm"):
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
    if damping == "none" and e != 1.0:
        raise InputError("restitution", f"damping 'none' has no dashpot: restitution must be 1 (got {e:g})")
    q = model.exponents[normal]
    c = model.clips if clip is None else bool(clip)
    base = _base(normal, 0.0, q, c)
    g = _group_from_restitution(normal, damping, e, base.kappa, tsuji_version)
    if g is None:
        g = group_for_restitution(base, e)
    return _base(normal, g, q, c)


__all__ = ["scaled_law"]
