"""Regular sphere lattices in periodic boxes: simple cubic, BCC, FCC and HCP.

Equal spheres of radius ``R`` touch their nearest neighbours (coordination 6, 8, 12, 12):
cubic cell edge ``2R`` (SC), ``4R/sqrt(3)`` (BCC), ``2 sqrt(2) R`` (FCC); HCP uses the
orthorhombic cell ``a x sqrt(3) a x c`` with ``a = 2R``, ``c = sqrt(8/3) a`` and four spheres.
``cells`` repeats the cell along each axis (an int or three ints); the box is periodic.
"""
from __future__ import annotations

import numpy as np

from dtcrit.errors import InputError

from dtcrit.packing.model import Box, Packing

# fractional basis positions in the repeated cell and the cell edges in units of R
_BASIS = {
    "sc": (np.array([[0.0, 0.0, 0.0]]), np.array([2.0, 2.0, 2.0])),
    "bcc": (np.array([[0.0, 0.0, 0.0], [0.5, 0.5, 0.5]]), np.full(3, 4.0 / np.sqrt(3.0))),
    "fcc": (np.array([[0.0, 0.0, 0.0], [0.5, 0.5, 0.0], [0.5, 0.0, 0.5], [0.0, 0.5, 0.5]]),
            np.full(3, 2.0 * np.sqrt(2.0))),
    "hcp": (np.array([[0.0, 0.0, 0.0], [0.5, 0.5, 0.0], [0.5, 1.0 / 6.0, 0.5], [0.0, 2.0 / 3.0, 0.5]]),
            np.array([2.0, 2.0 * np.sqrt(3.0), 2.0 * np.sqrt(8.0 / 3.0)])),
}
LATTICES: tuple[str, ...] = tuple(_BASIS)
COORDINATION = {"sc": 6, "bcc": 8, "fcc": 12, "hcp": 12}


def _cells(cells) -> np.ndarray:
    c = np.broadcast_to(np.asarray(cells), (3,))
    if not np.all(np.equal(np.mod(c, 1), 0)) or np.any(c < 1):
        raise InputError("cells", f"must be a positive whole number (or three), got {cells!r}")
    return c.astype(np.int64)


def lattice_positions(name: str, cells, radius: float = 1.0) -> tuple[np.ndarray, Box]:
    """Centres of every sphere and the periodic box of ``cells`` repeats of a lattice (module docstring).

    Parameters
    ----------
    name : str
        ``sc``, ``bcc``, ``fcc`` or ``hcp`` (case-insensitive).
    cells : int or sequence of int
        Repeats of the cell along each axis (one number or three).
    radius : float
        Sphere radius ``R`` [m]; nearest neighbours touch.

    Returns
    -------
    positions : numpy.ndarray
        Centres, shape ``(n, 3)`` [m].
    box : Box
        The fully periodic box.

    Raises
    ------
    InputError
        For an unknown lattice, a non-positive radius or bad ``cells``.
    """
    key = str(name).lower()
    if key not in _BASIS:
        raise InputError("lattice", f"unknown lattice {name!r}; choose one of {', '.join(LATTICES)}")
    radius = float(radius)
    if not np.isfinite(radius) or radius <= 0:
        raise InputError("radius", f"must be a positive finite number, got {radius}")
    c = _cells(cells)
    basis, edge = _BASIS[key]
    edge = edge * radius
    grid = np.stack(np.meshgrid(*(np.arange(k) for k in c), indexing="ij"), -1).reshape(-1, 3)
    frac = (grid[:, None, :] + basis[None, :, :]).reshape(-1, 3)
    return frac * edge, Box(np.zeros(3), c * edge, (True, True, True))


def lattice(name: str, cells, *, radius: float = 1.0, density: float | None = None,
            mass: float | None = None) -> Packing:
    """A periodic sphere lattice as a :class:`Packing` (module docstring).

    Parameters
    ----------
    name : str
        ``sc``, ``bcc``, ``fcc`` or ``hcp``.
    cells : int or sequence of int
        Repeats of the cell along each axis.
    radius : float
        Sphere radius [m].
    density : float or None
        Density [kg/m^3] (1 when neither it nor ``mass`` is given).
    mass : float or None
        Mass of each sphere [kg], instead of ``density``.

    Returns
    -------
    Packing
        The spheres, labelled with the lattice and cell counts.
    """
    if density is None and mass is None:
        density = 1.0
    x, box = lattice_positions(name, cells, radius)
    label = f"{str(name).lower()} lattice, {'x'.join(str(k) for k in _cells(cells))} cells"
    return Packing.spheres(x, radius, density=density, masses=mass, box=box, label=label)
