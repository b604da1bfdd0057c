"""Constants, conventions and argument checks of the 1-D impact study (CFL note, seed 004; Feng 2005).

Units: time ``1/omega`` (``omega = sqrt(k/m)``), overlap ``v0/omega``, speed ``v0``; ``K = 1``, ``C = 2 zeta``,
step ``tau = omega dt``.
"""
from __future__ import annotations

import math

import numpy as np

from dtcrit._generated import impact as _gen
from dtcrit.errors import InputError
from dtcrit.physics.json_numbers import json_safe

STANDARD_ZETAS: tuple[float, ...] = (0.0, 0.05, 0.2)
SWEEP_TOP = 2.2
SWEEP_STEP = 0.005
DEFAULT_PHASES = 128
DEFAULT_ENERGY_THRESHOLD = 0.01
RATIO_RTOL = 1e-9  # relative margin for "ratio > reference" (above rounding of the simulation)
MIN_OMEGA_DT = 1e-4  # below this the step count per impact (> 3e4) makes sweeps impractical
MAX_OMEGA_DT = 1e3
MAX_PHASES = 4096
UNIT_STEPS_FROM = 0.25  # the report checks the isolated steps tau_N >= this (N <= 12)
MAX_CUTOFF = 400.0  # longest simulated contact, units 1/omega
DIVERGED = 1e150  # |state| beyond this: the run has blown up (reported as an infinite ratio)

CENTRAL_DIFFERENCE_FAMILY: tuple[str, ...] = tuple(_gen.CENTRAL_DIFFERENCE_FAMILY)

CONVENTION = (
    "geometric: contact while the overlap d >= 0 (the CFL note's equation); the spring-dashpot "
    "force may be tensile near the end; the time-stepped simulation uses this convention"
)
FORCE_CONVENTION = (
    "force-based: contact force k d + c d' acts only while compressive; released at its first zero"
)
UNITS = "time in 1/omega (omega = sqrt(k/m)), overlap in v0/omega, speeds as ratios to v0"


# ---------------------------------------------------------------------------------------------
# input checks
# ---------------------------------------------------------------------------------------------

def _number(key: str, value) -> float:
    try:
        out = float(value)
    except (TypeError, ValueError):
        raise InputError(key, f"must be a number (got {value!r})") from None
    if not math.isfinite(out):
        raise InputError(key, f"must be finite (got {out})")
    return out


MAX_ZETA = 1e50
"""Above this damping ratio the exact impact's closed forms (powers of mu = sqrt(zeta^2 - 1)) leave the
float64 range; physically the contact is then a pure dashpot that never releases within the sweep."""


def check_zeta(zeta) -> float:
    """The damping ratio of the linear contact, checked.

    Parameters
    ----------
    zeta : float
        Damping ratio ``c / (2 sqrt(k m))``, dimensionless.

    Returns
    -------
    float
        ``zeta`` as a float, in [0, ``MAX_ZETA``].

    Raises
    ------
    InputError
        When it is no finite number, is negative or exceeds ``MAX_ZETA``.
    """
    z = _number("zeta", zeta)
    if z < 0:
        raise InputError("zeta", f"damping ratio must be >= 0 (got {z})")
    if z > MAX_ZETA:
        raise InputError("zeta", f"damping ratio {z:g} is above {MAX_ZETA:g}: the exact impact leaves the float64 range")
    return z


def check_omega_dt(value, key: str = "omega_dt") -> float:
    """A step in units of the contact's period, ``omega dt``, checked.

    Parameters
    ----------
    value : float
        The step ``omega dt`` (dimensionless).
    key : str
        Name of the input reported in the error.

    Returns
    -------
    float
        ``value`` as a float, in [``MIN_OMEGA_DT``, ``MAX_OMEGA_DT``].

    Raises
    ------
    InputError
        When it is no finite number or lies outside that range.
    """
    t = _number(key, value)
    if not MIN_OMEGA_DT <= t <= MAX_OMEGA_DT:
        raise InputError(key, f"must lie in [{MIN_OMEGA_DT:g}, {MAX_OMEGA_DT:g}] (got {t:g})")
    return t


def check_energy_threshold(value) -> float:
    """The tolerated energy error of the Hertz study, checked.

    Parameters
    ----------
    value : float
        Largest accepted ``|v_exit^2/v0^2 - 1|``.

    Returns
    -------
    float
        ``value`` as a float, in (0, 1).

    Raises
    ------
    InputError
        When it is no finite number or lies outside (0, 1).
    """
    thr = _number("energy_threshold", value)
    if not 0 < thr < 1:
        raise InputError("energy_threshold", f"must lie in (0, 1) (got {thr:g})")
    return thr


def check_phases(n) -> int:
    """The number of entry phases of a sweep, checked.

    Parameters
    ----------
    n : int
        Number of equally spaced entry phases in [0, 1).

    Returns
    -------
    int
        ``n`` as an int, in [1, ``MAX_PHASES``].

    Raises
    ------
    InputError
        When it is no integer or lies outside that range.
    """
    try:
        k = int(n)
    except (TypeError, ValueError):
        raise InputError("phases", f"must be an integer (got {n!r})") from None
    if k != n or not 1 <= k <= MAX_PHASES:
        raise InputError("phases", f"must be an integer in [1, {MAX_PHASES}] (got {n!r})")
    return k


# ---------------------------------------------------------------------------------------------
# exact impact
# ---------------------------------------------------------------------------------------------

def _regime(zeta: float) -> str:
    if zeta == 0:
        return "undamped"
    return "underdamped" if zeta < 1 else ("critically damped" if zeta == 1 else "overdamped")


def _scalar(kernel, *args) -> float:
    with np.errstate(all="ignore"):
        return float(kernel(*args))


# ---------------------------------------------------------------------------------------------
# report
# ---------------------------------------------------------------------------------------------

_json_number = json_safe  # a report number: NumPy scalars as Python ones, non-finite as null
