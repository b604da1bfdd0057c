"""The particles touching a LAMMPS ``fix wall/gran`` wall, found as LAMMPS finds them.

``src/GRANULAR/fix_wall_gran.cpp`` (``post_force``, LAMMPS 29 Sep 2021):

* ``xplane``/``yplane``/``zplane lo hi``: a particle meets only the *nearer* of the two planes,
  ``d = x_a - lo`` when ``x_a - lo < hi - x_a``, else ``d = -(hi - x_a)`` (a ``NULL`` plane sits at
  ``-/+1e20``); it touches when ``|d| < R``;
* ``zcylinder r_c``: ``d = (r_c - rho)/rho (x, y, 0)`` towards the axis, ``rho = sqrt(x^2 + y^2)``;
  it touches when ``|r_c - rho| < R`` (LAMMPS skips ``r_c - rho > R`` and ``|d| > R``).

The overlap is ``R - |d|`` (a contact with zero overlap carries no force and is left out, as for
sphere pairs).  Each contact's wall body sits on the plane below the particle's centre, or on the
cylinder's axis at the particle's height, so that the centre distance is the lever of the normal's
turning (``dtcrit.packing.wall_bodies``).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dtcrit.errors import InputError
from dtcrit.packing.model import Packing
from dtcrit.packing.wall_bodies import WallContacts
from dtcrit.physics.walls import lammps_wall_effective_radius, lammps_zcylinder_rwall

BIG = 1.0e20
"""Where LAMMPS puts a ``NULL`` plane."""
AXES = {"xplane": 0, "yplane": 1, "zplane": 2}

__all__ = ["WallGeometry", "wall_contacts"]


@dataclass(frozen=True)
class WallGeometry:
    """A ``fix wall/gran`` wall: ``style`` ``xplane``/``yplane``/``zplane`` with ``lo``, ``hi`` or
    ``zcylinder`` with ``radius``.

    Parameters
    ----------
    style : str
        ``xplane``, ``yplane``, ``zplane`` or ``zcylinder``.
    lo, hi : float
        The planes [m] (``-/+BIG`` for ``NULL``); unused for a cylinder.
    radius : float
        The cylinder's radius ``r_c`` [m]; unused for planes.
    """

    style: str
    lo: float = -BIG
    hi: float = BIG
    radius: float = 0.0

    def describe(self) -> str:
        """The wall in words.

        Returns
        -------
        str
            E.g. ``zplane lo 0 hi NULL``.
        """
        if self.style == "zcylinder":
            return f"zcylinder r_c = {self.radius:g}"
        show = lambda v: "NULL" if abs(v) >= BIG else f"{v:g}"  # noqa: E731
        return f"{self.style} {show(self.lo)} {show(self.hi)}"


def _check_box(packing: Packing, geometry: WallGeometry, key: str) -> None:
    box = packing.box
    if box is None:
        return
    axes = (0, 1) if geometry.style == "zcylinder" else (AXES[geometry.style],)
    if any(box.periodic[a] for a in axes):
        raise InputError(key, f"{geometry.style}: a wall in a periodic dimension (LAMMPS refuses it too)")


def wall_contacts(packing: Packing, geometry: WallGeometry, number: int, key: str = "--wall") -> WallContacts:
    """The contacts of the particles with one wall, with LAMMPS's geometry (module docstring).

    Parameters
    ----------
    packing : Packing
        Spheres.
    geometry : WallGeometry
        The wall.
    number : int
        The wall's number (counted from 1), stored on its contacts.
    key : str
        The flag named in errors.

    Returns
    -------
    WallContacts
        One contact per touching particle: normal towards the wall, the full radius as arm (LAMMPS),
        LAMMPS's ``R_eff``.

    Raises
    ------
    InputError
        A wall in a periodic dimension, or a particle outside a ``zcylinder`` touching it (not modelled).
    """
    _check_box(packing, geometry, key)
    x, r = packing.positions, packing.radii
    if geometry.style == "zcylinder":
        rho = np.hypot(x[:, 0], x[:, 1])
        gap = geometry.radius - rho
        touch = (np.abs(gap) < r) & (rho > 0)
        if np.any(touch & (gap < 0)):
            k = int(np.argmax(touch & (gap < 0)))
            raise InputError(key, f"particle {packing.particle_id(k)} touches the zcylinder from outside: "
                                  "not modelled")
        idx = np.flatnonzero(touch)
        radial = np.zeros((idx.size, 3))
        radial[:, :2] = x[idx, :2] / rho[idx, None]
        dist = np.abs(gap[idx])
        rwall = lammps_zcylinder_rwall(gap[idx] >= 0, geometry.radius)
        anchor = np.zeros((idx.size, 3))
        anchor[:, 2] = x[idx, 2]
        return WallContacts(idx, radial, r[idx], r[idx] - dist, lammps_wall_effective_radius(r[idx], rwall),
                            anchor, np.full(idx.size, number))
    a = AXES[geometry.style]
    below, above = x[:, a] - geometry.lo, geometry.hi - x[:, a]
    signed = np.where(below < above, below, -above)  # from the wall to the centre, along axis a
    idx = np.flatnonzero(np.abs(signed) < r)
    normal = np.zeros((idx.size, 3))
    normal[:, a] = -np.sign(signed[idx])
    normal[signed[idx] == 0, a] = -1.0
    dist = np.abs(signed[idx])
    anchor = x[idx].copy()
    anchor[:, a] -= signed[idx]
    return WallContacts(idx, normal, r[idx], r[idx] - dist, lammps_wall_effective_radius(r[idx]), anchor,
                        np.full(idx.size, number))
