"""Size distributions of a sphere type: one radius, a list of radii with fractions, or a lognormal
distribution with cut-offs.

The critical step of a polydisperse simulation is the minimum over every pair of sizes that can
touch, so what matters is which radii occur, not how often:

* ``radii = [...]`` with ``fractions = [...]`` (number fractions, summing to 1): every radius listed;
* ``lognormal = {median = , sigma = , min = , max = }`` (``sigma`` of ln R): the radii in
  ``[min, max]``, evaluated at ``LOGNORMAL_POINTS`` log-spaced radii including both cut-offs.  For a
  linear law with given stiffness every mode's ``omega^2`` decreases in both radii, and for YADE's
  law ``kn = 2 E R1 R2/(R1 + R2)`` ``omega_n^2 ~ 1/R1^2 - 1/(R1 R2) + 1/R2^2`` is largest at
  ``R1 = R2 = min`` (on ``[min, max]^2`` its maximum lies on the boundary and equals ``1/min^2``
  only there): the step is the cut-off pair's, which the grid contains.  For Hertz contacts the grid
  is an evaluation, said so in the scene's warnings.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from dtcrit.errors import InputError
from dtcrit.scenes.fields import _check_keys, _number, _required, _type_name, _vector

LOGNORMAL_POINTS = 33
DESCRIBE_RADII = 12  # longer lists of radii are printed as their count and range
FRACTION_RTOL = 1e-9
LOGNORMAL_KEYS = ("median", "sigma", "min", "max")


@dataclass(frozen=True)
class SizeDistribution:
    """The sphere radii of one particle type (``radius``, ``radii`` with ``fractions``, or ``lognormal``).

    Parameters
    ----------
    kind : str
        ``"single"``, ``"discrete"`` or ``"lognormal"``.
    radii : tuple of float
        The radii evaluated, ascending [m].
    fractions : tuple of float
        Number fractions of the discrete radii (empty otherwise).
    parameters : dict, optional
        The lognormal's ``median``, ``sigma``, ``min`` and ``max`` (None otherwise).
    """

    kind: str  # single | discrete | lognormal
    radii: tuple[float, ...]  # the radii evaluated, ascending
    fractions: tuple[float, ...] = ()
    parameters: dict | None = None

    def describe(self) -> str:
        """One line for the text report, e.g. ``radius = 0.001`` or the lognormal's parameters.

        Returns
        -------
        str
            The description.
        """
        if self.kind == "single":
            return f"radius = {self.radii[0]:g}"
        if self.kind == "discrete" and len(self.radii) > DESCRIBE_RADII:
            return f"{len(self.radii)} radii from {self.radii[0]:g} to {self.radii[-1]:g}"
        if self.kind == "discrete":
            return "radii = [" + ", ".join(f"{r:g}" for r in self.radii) + "]"
        p = self.parameters
        assert p is not None  # a lognormal distribution always carries its parameters
        return f"lognormal radius (median {p['median']:g}, sigma {p['sigma']:g}, cut-offs {p['min']:g}..{p['max']:g})"


def size_distribution(prefix: str, table: dict) -> SizeDistribution:
    """The distribution a sphere table gives: exactly one of ``radius``, ``radii`` (+ ``fractions``), ``lognormal``.

    Parameters
    ----------
    prefix : str
        Location of the table in the scene file, prefixed to the keys of error messages.
    table : dict
        The ``[[particle]]`` table's entries.

    Returns
    -------
    SizeDistribution
        The validated distribution.

    Raises
    ------
    InputError
        When none or several of the keys are given, or a value is invalid.
    """
    given = [k for k in ("radius", "radii", "lognormal") if k in table]
    if not given:
        raise InputError(prefix + "radius", "missing: a sphere needs radius, or radii with fractions, or lognormal")
    if len(given) > 1:
        raise InputError(prefix + given[1], f"give one of radius, radii or lognormal (got {' and '.join(given)})")
    if "fractions" in table and given[0] != "radii":
        raise InputError(prefix + "fractions", "fractions go with radii")
    if given[0] == "radius":
        return SizeDistribution("single", (_number(prefix + "radius", table["radius"]),))
    if given[0] == "radii":
        return _discrete(prefix, table)
    return _lognormal(prefix + "lognormal", table["lognormal"])


def _discrete(prefix: str, table: dict) -> SizeDistribution:
    raw = table["radii"]
    if not isinstance(raw, list) or not raw:
        raise InputError(prefix + "radii", f"must be a non-empty array of radii [m] (got {_type_name(raw)})")
    radii = _vector(prefix + "radii", raw, len(raw))
    raw_fractions = _required(prefix, table, "fractions", "number fractions of the radii, summing to 1")
    if not isinstance(raw_fractions, list):
        raise InputError(prefix + "fractions", f"must be an array of {len(radii)} fractions (got {_type_name(raw_fractions)})")
    fractions = _vector(prefix + "fractions", raw_fractions, len(radii))
    total = math.fsum(fractions)
    if abs(total - 1.0) > FRACTION_RTOL:
        raise InputError(prefix + "fractions", f"must sum to 1 (they sum to {total:.12g})")
    order = sorted(range(len(radii)), key=lambda k: radii[k])
    return SizeDistribution("discrete", tuple(radii[k] for k in order), tuple(fractions[k] for k in order))


def _lognormal(key: str, table: Any) -> SizeDistribution:
    if not isinstance(table, dict):
        raise InputError(key, f"must be a table {{median, sigma, min, max}} (got {_type_name(table)})")
    _check_keys(key + ".", table, LOGNORMAL_KEYS, LOGNORMAL_KEYS, "in a lognormal distribution")
    values = {k: _number(f"{key}.{k}", _required(key + ".", table, k, "median, sigma, min and max (the cut-offs) [m]"),
                         allow_zero=(k == "sigma")) for k in LOGNORMAL_KEYS}
    lo, hi = values["min"], values["max"]
    if not lo < hi:
        raise InputError(f"{key}.max", f"must exceed min ({hi:g} <= {lo:g})")
    if not lo <= values["median"] <= hi:
        raise InputError(f"{key}.median", f"must lie between the cut-offs {lo:g} and {hi:g}")
    n = LOGNORMAL_POINTS
    grid = tuple(lo if k == 0 else hi if k == n - 1 else math.exp(math.log(lo) + (math.log(hi) - math.log(lo)) * k / (n - 1))
                 for k in range(n))
    return SizeDistribution("lognormal", grid, parameters=values)


class SizeShapes:
    """The bodies of a size distribution, one per radius, built by ``build(radius)`` when first asked for
    (a scene may list 10^5 radii of which the step needs two).  The smallest and largest are built at
    once: the mass is monotone in the radius, so they carry every range check the others could fail.

    Parameters
    ----------
    build : callable
        ``build(radius)`` returns the body of that radius.
    radii : tuple of float
        The radii, ascending [m].
    """

    def __init__(self, build, radii: tuple):
        self._build = build
        self._radii = radii
        self._built: dict[int, Any] = {}
        self[0], self[len(radii) - 1]  # noqa: B018 (validates the extremes now)

    def __len__(self) -> int:
        return len(self._radii)

    def __getitem__(self, k: int):
        k = range(len(self._radii))[k]
        if k not in self._built:
            self._built[k] = self._build(self._radii[k])
        return self._built[k]

    def __iter__(self):
        return (self[k] for k in range(len(self._radii)))
