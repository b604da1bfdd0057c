"""The exact impact of the CFL note's contact ``m d'' = -c d' - k d`` (d >= 0): contact duration and
exit/entry speed for both separation conventions, and the exact Hertz impact, from the closed forms
that ``dtcrit.symbolic.impact`` derives and emits into ``dtcrit._generated.impact``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from dtcrit._generated import impact as _gen
from dtcrit.errors import InputError
from dtcrit.impact.conventions import CONVENTION, FORCE_CONVENTION, _json_number, _number, _regime, _scalar, check_zeta


@dataclass(frozen=True)
class ExactImpact:
    """The exact impact in units of 1/omega and v0 (CFL note; ``dtcrit.symbolic.impact``).

    Geometric separation (d returns to 0): ``duration = pi/sqrt(1 - zeta^2)`` and
    ``exit_ratio = exp(-zeta pi/sqrt(1 - zeta^2))`` for ``zeta < 1``; for ``zeta >= 1`` the overlap
    never returns to 0 (``duration = inf``, ``exit_ratio = 0``, the limit).
    Force-based release (force k d + c d' reaches 0): ``force_release_time = 2 g(zeta)`` with
    ``g = arccos(zeta)/sqrt(1 - zeta^2)`` (continued analytically past 1), ``force_exit_ratio =
    exp(-zeta s_f)``; ``force_release_overlap = 2 zeta exp(-zeta s_f)`` is left at release.

    Parameters
    ----------
    zeta : float
        Damping ratio.
    regime : str
        ``"underdamped"``, ``"critical"`` or ``"overdamped"``.
    duration : float
        Contact duration until the overlap returns to 0, in 1/omega (``inf`` for ``zeta >= 1``).
    exit_ratio : float
        Exit speed over entry speed, geometric separation (0 when it never separates).
    separates : bool
        Whether the overlap returns to 0 (``zeta < 1``).
    force_release_time : float
        Time at which the contact force reaches 0, in 1/omega.
    force_exit_ratio : float
        Speed at force release over entry speed.
    force_release_overlap : float
        Overlap left at force release, in v0/omega.
    """

    zeta: float
    regime: str
    duration: float
    exit_ratio: float
    separates: bool
    force_release_time: float
    force_exit_ratio: float
    force_release_overlap: float

    def as_dict(self) -> dict:
        """The JSON form (``dtcrit impact --json``, key ``exact``).

        Returns
        -------
        dict
            The geometric quantities with the convention, and the force-based ones under ``force_based``;
            an infinite duration becomes null.
        """
        return {
            "duration": _json_number(self.duration),
            "exit_ratio": self.exit_ratio,
            "separates": self.separates,
            "regime": self.regime,
            "convention": CONVENTION,
            "force_based": {
                "duration": self.force_release_time,
                "exit_ratio": self.force_exit_ratio,
                "overlap_at_release": self.force_release_overlap,
                "convention": FORCE_CONVENTION,
            },
        }


def exact_impact(zeta) -> ExactImpact:
    """Exact contact duration and exit/entry speed of the linear spring-dashpot impact.

    Parameters
    ----------
    zeta : float
        Damping ratio of ``m d'' = -c d' - k d``.

    Returns
    -------
    ExactImpact
        Both separation conventions, from the generated closed forms of ``dtcrit.symbolic.impact``.

    Examples
    --------
    >>> from dtcrit import exact_impact
    >>> imp = exact_impact(0.0)   # undamped: half a period, the speed kept
    >>> round(imp.exit_ratio, 12)
    1.0
    """
    z = check_zeta(zeta)
    duration = _scalar(_gen.geometric_duration, z)
    return ExactImpact(
        zeta=z,
        regime=_regime(z),
        duration=duration,
        exit_ratio=_scalar(_gen.geometric_exit_ratio, z),
        separates=math.isfinite(duration),
        force_release_time=_scalar(_gen.force_release_time, z),
        force_exit_ratio=_scalar(_gen.force_exit_ratio, z),
        force_release_overlap=_scalar(_gen.force_release_overlap, z),
    )


@dataclass(frozen=True)
class HertzExact:
    """Undamped Hertz impact ``m d'' = -k_h d^(3/2)``: exit ratio 1; durations in two unit systems.

    Parameters
    ----------
    duration : float
        Contact duration in units of 1/omega_t, omega_t the tangent frequency at maximum overlap.
    duration_dmax_over_v0 : float
        Contact duration in units of dmax/v0: (4/5) B(2/5, 1/2).
    exit_ratio : float
        Exit speed over entry speed (1: the undamped impact is elastic).
    scaled_speed : float
        Entry speed in units of dmax omega_t, sqrt(8/15).
    scaled_coefficient : float
        Coefficient of the scaled law ``u'' = -coef u^(3/2)`` (2/3).
    """

    duration: float  # units 1/omega_t, omega_t the linearised frequency at maximum overlap
    duration_dmax_over_v0: float  # units dmax/v0: (4/5) B(2/5, 1/2)
    exit_ratio: float = 1.0
    scaled_speed: float = _gen.HERTZ_SCALED_SPEED  # entry speed in dmax*omega_t
    scaled_coefficient: float = _gen.HERTZ_SCALED_COEFFICIENT  # u'' = -coef u^(3/2)


def hertz_exact() -> HertzExact:
    """The exact undamped Hertz impact in scaled units (generated constants).

    Returns
    -------
    HertzExact
        Durations in 1/omega_t and dmax/v0, exit ratio 1.
    """
    return HertzExact(duration=_gen.HERTZ_SCALED_DURATION, duration_dmax_over_v0=_gen.HERTZ_DURATION_FACTOR)


def hertz_dimensional(k_h, m, v0) -> dict:
    """Maximum overlap [m], contact duration [s] and tangent frequency at dmax [rad/s] (Hertz).

    Energy balance ``m v0^2/2 = (2/5) k_h dmax^(5/2)`` gives dmax; omega_t = sqrt(1.5 k_h dmax^(1/2)/m).

    Parameters
    ----------
    k_h : float
        Hertz coefficient of ``F = k_h d^(3/2)`` [N/m^(3/2)].
    m : float
        Effective mass [kg].
    v0 : float
        Entry speed [m/s].

    Returns
    -------
    dict
        The maximum overlap, contact duration and tangent frequency, each in SI units.

    Raises
    ------
    InputError
        When an input is no finite positive number.
    """
    k_h, m, v0 = (_number(k, x) for k, x in (("k_h", k_h), ("m", m), ("v0", v0)))
    for key, val in (("k_h", k_h), ("m", m), ("v0", v0)):
        if val <= 0:
            raise InputError(key, f"must be positive (got {val})")
    return {
        "max_overlap": float(_gen.hertz_max_overlap(k_h, m, v0)),
        "duration": float(_gen.hertz_duration(k_h, m, v0)),
        "tangent_omega": float(_gen.hertz_tangent_omega(k_h, m, v0)),
    }
