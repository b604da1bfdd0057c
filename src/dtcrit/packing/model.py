"""Data model of a packing: particles, an optional (periodic) box and the contact laws.

The contact list is ``dtcrit.packing.contact_set.Contacts``.

The global analysis (Otsubo, O'Sullivan & Shire 2017) gives every particle six degrees of freedom:
three translations in the global frame and three small rotations about the particle's own
principal axes.  With that choice the mass matrix is diagonal, ``(m, m, m, I1, I2, I3)`` per
particle, for any shape and orientation.

Everything here is plain NumPy; nothing imports SymPy.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Sequence

import numpy as np

from dtcrit.errors import InputError
from dtcrit.packing.contact_set import Contacts
from dtcrit.packing.uniform_values import uniform
from dtcrit.physics.contact_laws import hertz_normal_stiffness, mindlin_tangent_stiffness, same_material_moduli


@dataclass(frozen=True)
class Box:
    """A simulation box: the parallelepiped spanned from ``lo`` by the columns of ``cell``; ``periodic[a]``
    says whether the box wraps along cell vector ``a``.

    Without ``cell`` the box is axis-aligned, ``[lo, hi)``.  A sheared (triclinic) box gives ``cell``,
    whose columns are the edge vectors ``a, b, c`` (YADE's ``O.cell.hSize``; LAMMPS's
    ``(lx, 0, 0), (xy, ly, 0), (xz, yz, lz)``, Howto triclinic); then ``hi`` is ``lo + diag(cell)``
    (LAMMPS's ``xhi, yhi, zhi``).  ``dtcrit.packing.periodic_cell`` wraps, shifts and finds images.

    Parameters
    ----------
    lo, hi : array_like
        Lower and upper bounds [m] along x, y, z (finite, ``hi > lo``).
    periodic : tuple of bool
        Whether each cell vector (axis) wraps.
    cell : array_like or None
        (3, 3) edge vectors as columns [m]; None, or a diagonal matrix: the axis-aligned box.
    """

    lo: np.ndarray
    hi: np.ndarray
    periodic: tuple[bool, bool, bool]
    cell: np.ndarray | None = None

    def __post_init__(self):
        lo = np.asarray(self.lo, dtype=float).reshape(3)
        hi = np.asarray(self.hi, dtype=float).reshape(3)
        if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi))):
            raise InputError("box", "bounds must be finite numbers")
        if np.any(hi <= lo):
            raise InputError("box", f"each upper bound must exceed its lower bound (lo={lo}, hi={hi})")
        object.__setattr__(self, "lo", lo)
        object.__setattr__(self, "hi", hi)
        object.__setattr__(self, "periodic", tuple(bool(p) for p in self.periodic))
        if self.cell is not None:  # sheared: finite, diagonal hi - lo, right-handed; a diagonal cell is None
            h = np.array(self.cell, dtype=float)
            if h.shape != (3, 3) or not np.all(np.isfinite(h)) or not np.allclose(np.diag(h), hi - lo, rtol=1e-12, atol=0):
                raise InputError("box", f"the cell must be a finite 3 x 3 matrix with diagonal hi - lo = {hi - lo}")
            if not np.linalg.det(h) > 1e-12 * np.prod(np.linalg.norm(h, axis=0)):
                raise InputError("box", f"the cell vectors (columns) {h.T.tolist()} must be right-handed, not coplanar")
            object.__setattr__(self, "cell", h if np.any(h - np.diag(np.diag(h))) else None)

    @property
    def lengths(self) -> np.ndarray:
        """Edge lengths ``hi - lo`` [m] along x, y, z (of a sheared box: ``diag(cell)``)."""
        return self.hi - self.lo

    @property
    def matrix(self) -> np.ndarray:
        """The (3, 3) edge vectors as columns [m]: ``cell``, or ``diag(lengths)``."""
        return np.diag(self.lengths) if self.cell is None else self.cell

    def shift(self, image) -> np.ndarray:
        """The translation [m] of integer periodic images ``image`` (``(..., 3)``): ``cell @ image``.

        Parameters
        ----------
        image : array_like
            Integer image shifts along the cell vectors, shape ``(..., 3)``.

        Returns
        -------
        numpy.ndarray
            The translations, shape ``(..., 3)`` (``image * lengths`` for an axis-aligned box).
        """
        image = np.asarray(image)
        return image * self.lengths if self.cell is None else image @ self.cell.T

    @classmethod
    def cube(cls, length: float, periodic: bool = True) -> "Box":
        """A cube ``[0, length)^3``.

        Parameters
        ----------
        length : float
            Edge length [m].
        periodic : bool
            Whether every axis wraps.

        Returns
        -------
        Box
            The cube.
        """
        return cls(np.zeros(3), np.full(3, float(length)), (periodic,) * 3)


@dataclass(frozen=True)
class Packing:
    """Particles of a packing.

    ``positions`` (N, 3) centres of mass; ``masses`` (N,); ``inertia`` (N, 3) principal moments of
    inertia; ``radii`` (N,) sphere radii, or for non-spherical particles the radius of the
    bounding sphere (used only to find candidate contacts); ``orientations`` (N, 3, 3) rotation
    matrices from each body frame to the global frame, or ``None`` for spheres (identity);
    ``shapes`` one object per particle with ``.support(direction)`` for non-spheres, else ``None``;
    ``ids`` the engine's own particle ids (a dump's ``id`` column), else ``None`` (then particles are
    numbered from 1 in messages: ``particle_id``).

    Parameters
    ----------
    positions : numpy.ndarray
        (N, 3) centres of mass [m].
    masses : numpy.ndarray
        (N,) masses [kg].
    inertia : numpy.ndarray
        (N, 3) principal moments of inertia [kg m^2] (an (N,) array means equal moments).
    radii : numpy.ndarray
        (N,) sphere radii, or bounding-sphere radii of other shapes [m].
    box : Box or None
        The simulation box, or None for an open packing.
    orientations : numpy.ndarray or None
        (N, 3, 3) body-to-global rotation matrices, or None (identity).
    shapes : sequence or None
        One shape object per particle for non-spheres, else None.
    half_lengths : numpy.ndarray or None
        (N, 3) half-lengths [m] of each particle along its principal axes.
    label : str
        Name printed in reports.
    ids : numpy.ndarray or None
        (N,) the engine's distinct particle ids, or None.
    """

    positions: np.ndarray
    masses: np.ndarray
    inertia: np.ndarray
    radii: np.ndarray
    box: Box | None = None
    orientations: np.ndarray | None = None
    shapes: Sequence[Any] | None = None
    half_lengths: np.ndarray | None = None
    label: str = ""
    ids: np.ndarray | None = None

    def __post_init__(self):
        x = np.ascontiguousarray(self.positions, dtype=float)
        if x.ndim != 2 or x.shape[1] != 3:
            raise InputError("positions", f"expected an (N, 3) array, got shape {x.shape}")
        n = x.shape[0]
        if n < 1:
            raise InputError("positions", "a packing needs at least one particle")
        m = np.ascontiguousarray(self.masses, dtype=float).reshape(-1)
        inertia = np.ascontiguousarray(self.inertia, dtype=float)
        if inertia.ndim == 1:
            inertia = np.repeat(inertia[:, None], 3, axis=1)
        r = np.ascontiguousarray(self.radii, dtype=float).reshape(-1)
        for key, arr, shape in (("masses", m, (n,)), ("inertia", inertia, (n, 3)), ("radii", r, (n,))):
            if arr.shape != shape:
                raise InputError(key, f"expected shape {shape}, got {arr.shape}")
            if not np.all(np.isfinite(arr)) or np.any(arr <= 0):
                raise InputError(key, "every value must be a positive finite number")
        if not np.all(np.isfinite(x)):
            raise InputError("positions", "every coordinate must be a finite number")
        q = self.orientations
        if q is not None:
            q = np.ascontiguousarray(q, dtype=float)
            if q.shape != (n, 3, 3):
                raise InputError("orientations", f"expected shape {(n, 3, 3)}, got {q.shape}")
            err = np.abs(np.einsum("nij,nkj->nik", q, q) - np.eye(3)).max()
            if err > 1e-8:
                raise InputError("orientations", f"not rotation matrices (|R R^T - I| = {err:.2e})")
        h = self.half_lengths
        if h is not None:
            h = np.ascontiguousarray(h, dtype=float)
            if h.shape != (n, 3):
                raise InputError("half_lengths", f"expected shape {(n, 3)}, got {h.shape}")
        ids = self.ids
        if ids is not None:
            ids = np.ascontiguousarray(ids).reshape(-1).astype(np.int64)
            if ids.shape != (n,) or np.unique(ids).size != n:
                raise InputError("ids", f"expected {n} distinct particle ids")
            object.__setattr__(self, "ids", ids)
        if self.shapes is not None and len(self.shapes) != n:
            raise InputError("shapes", f"expected {n} shapes, got {len(self.shapes)}")
        object.__setattr__(self, "positions", x)
        object.__setattr__(self, "masses", m)
        object.__setattr__(self, "inertia", inertia)
        object.__setattr__(self, "radii", r)
        object.__setattr__(self, "orientations", q)
        object.__setattr__(self, "half_lengths", h)

    @property
    def n(self) -> int:
        """Number of particles."""
        return self.positions.shape[0]

    def particle_id(self, index) -> int:
        """The id of particle ``index`` as the user knows it: the engine's id, else ``index + 1``.

        Parameters
        ----------
        index : int
            Zero-based particle index.

        Returns
        -------
        int
            The particle's id.
        """
        return int(self.ids[index]) if self.ids is not None else int(index) + 1

    @property
    def dofs(self) -> int:
        """Degrees of freedom, six per particle."""
        return 6 * self.n

    @property
    def is_spheres(self) -> bool:
        """Whether every particle is a sphere (no ``shapes``)."""
        return self.shapes is None

    def with_label(self, label: str) -> "Packing":
        """The packing under another label.

        Parameters
        ----------
        label : str
            The name printed in reports.

        Returns
        -------
        Packing
            A copy with ``label`` set.
        """
        return replace(self, label=label)

    @classmethod
    def spheres(cls, positions, radii, *, density=None, masses=None, box: Box | None = None,
                label: str = "", ids=None) -> "Packing":
        """Solid spheres: ``m = 4/3 pi R^3 rho`` (or given masses) and ``I = 2/5 m R^2``."""
        positions = np.asarray(positions, dtype=float)
        radii = np.broadcast_to(np.asarray(radii, dtype=float), positions.shape[:1]).copy()
        if np.any(~np.isfinite(radii)) or np.any(radii <= 0):
            raise InputError("radius", "every radius must be a positive finite number")
        if (density is None) == (masses is None):
            raise InputError("density", "give exactly one of density or masses")
        if masses is None:
            density = float(density)
            if not np.isfinite(density) or density <= 0:
                raise InputError("density", f"must be a positive finite number, got {density}")
            with np.errstate(over="ignore", under="ignore"):
                masses = (4.0 / 3.0) * np.pi * radii**3 * density
            if np.any(~np.isfinite(masses)) or np.any(masses <= 0):
                bad = radii[~(np.isfinite(masses) & (masses > 0))]
                raise InputError("radius", f"the mass 4/3 pi R^3 rho of a sphere of radius {float(bad[0]):.3g} m "
                                           f"and density {density:.3g} kg/m^3 leaves the floating-point range")
        masses = np.broadcast_to(np.asarray(masses, dtype=float), radii.shape).copy()
        if np.any(~np.isfinite(masses)) or np.any(masses <= 0):
            raise InputError("mass", "every mass must be a positive finite number")
        with np.errstate(over="ignore", under="ignore"):
            inertia = 0.4 * masses * radii**2
        if np.any(~np.isfinite(inertia)) or np.any(inertia <= 0):
            raise InputError("radius", "the moment of inertia 2/5 m R^2 of a sphere leaves the floating-point range")
        return cls(positions, masses, np.repeat(inertia[:, None], 3, axis=1), radii, box=box,
                   half_lengths=np.repeat(radii[:, None], 3, axis=1), label=label, ids=ids)

    @classmethod
    def from_shapes(cls, shapes, positions, orientations=None, *, box: Box | None = None,
                    label: str = "") -> "Packing":
        """Convex, centrally symmetric bodies (``dtcrit.bodies`` objects: ``mass``, ``inertia``,
        ``half_lengths``, ``max_arm``, ``support``) at ``positions`` with body-to-global rotation
        matrices ``orientations`` (identity when omitted).
        """
        shapes = list(shapes)
        x = np.asarray(positions, dtype=float)
        if len(shapes) != x.shape[0]:
            raise InputError("shapes", f"expected {x.shape[0]} shapes, got {len(shapes)}")
        for k, s in enumerate(shapes):
            for attr in ("mass", "inertia", "half_lengths", "max_arm", "support"):
                if not hasattr(s, attr):
                    raise InputError("shapes", f"shape {k} has no {attr!r}")
        q = None if orientations is None else np.asarray(orientations, dtype=float)
        return cls(x, np.array([s.mass for s in shapes]), np.array([s.inertia for s in shapes], dtype=float),
                   np.array([s.max_arm for s in shapes]), box=box, orientations=q, shapes=shapes,
                   half_lengths=np.array([s.half_lengths for s in shapes], dtype=float), label=label)


@dataclass(frozen=True)
class LinearLaw:
    """Linear spring contact: constant normal ``kn`` and tangential ``ks`` stiffness [N/m].

    Parameters
    ----------
    kn, ks : float
        Normal and tangential stiffness [N/m] (finite, >= 0, not both zero).
    """

    kn: float
    ks: float

    def __post_init__(self):
        for key in ("kn", "ks"):
            value = float(getattr(self, key))
            if not np.isfinite(value) or value < 0:
                raise InputError(key, f"must be a finite number >= 0, got {value}")
        if float(self.kn) == 0 and float(self.ks) == 0:
            raise InputError("kn", "kn and ks cannot both be zero")

    def stiffness(self, contacts: Contacts) -> tuple[np.ndarray, np.ndarray]:
        """The springs of every contact, ``kn`` and ``ks`` as given.

        Parameters
        ----------
        contacts : Contacts
            The contacts.

        Returns
        -------
        tuple of numpy.ndarray
            ``(k_n, k_s)`` [N/m] per contact, each one value held once (``uniform_values.uniform``).
        """
        n = contacts.count
        return uniform(float(self.kn), n), uniform(float(self.ks), n)

    def describe(self) -> str:
        """The law in words, for reports.

        Returns
        -------
        str
            The description.
        """
        return f"linear springs kn = {float(self.kn):.6g} N/m, ks = {float(self.ks):.6g} N/m"


@dataclass(frozen=True)
class HertzMindlinLaw:
    """Hertz-Mindlin (no-slip) spheres: tangent stiffnesses at each contact's overlap ``delta``.

    ``kn = dF/d(delta) = 2 E* sqrt(R* delta)`` (from ``F = 4/3 E* sqrt(R*) delta^(3/2)``) and
    ``ks = 8 G* sqrt(R* delta)`` (Mindlin, no slip), one material for all particles:
    ``E* = E / (2 (1 - nu^2))``, ``G = E / (2 (1 + nu))``, ``G* = G / (2 (2 - nu))``.

    Parameters
    ----------
    youngs : float
        Young's modulus E [Pa] (positive).
    poisson : float
        Poisson's ratio nu, in (-1, 0.5).
    """

    youngs: float
    poisson: float

    def __post_init__(self):
        e, nu = float(self.youngs), float(self.poisson)
        if not np.isfinite(e) or e <= 0:
            raise InputError("youngs", f"must be a positive finite number, got {e}")
        if not np.isfinite(nu) or not (-1.0 < nu < 0.5):
            raise InputError("poisson", f"must lie in (-1, 0.5), got {nu}")

    def stiffness(self, contacts: Contacts) -> tuple[np.ndarray, np.ndarray]:
        """Tangent stiffnesses ``2 E* a`` and ``8 G* a``, ``a = sqrt(R* delta)`` (:mod:`dtcrit.physics.contact_laws`).

        Parameters
        ----------
        contacts : Contacts
            Sphere contacts (effective radius and overlap).

        Returns
        -------
        tuple of numpy.ndarray
            ``(k_n, k_s)`` [N/m] per contact.
        """
        if np.any(~np.isfinite(contacts.radius_eff)):
            raise InputError("law", "the Hertz-Mindlin law needs sphere contacts (effective radius)")
        e_star, g_star = same_material_moduli(float(self.youngs), float(self.poisson))
        a = np.sqrt(contacts.radius_eff * np.maximum(contacts.overlap, 0.0))
        return hertz_normal_stiffness(e_star, a), mindlin_tangent_stiffness(g_star, a)

    def describe(self) -> str:
        """The law in words, for reports.

        Returns
        -------
        str
            The description.
        """
        return f"Hertz-Mindlin tangent stiffness, E = {float(self.youngs):.6g} Pa, nu = {float(self.poisson):.6g}"


def apply_law(contacts: Contacts, law) -> Contacts:
    """Contacts with per-contact ``kn``/``ks`` from ``law`` (``LinearLaw`` or ``HertzMindlinLaw``).

    Parameters
    ----------
    contacts : Contacts
        The contacts.
    law : LinearLaw or HertzMindlinLaw
        The contact law (any object with ``stiffness(contacts) -> (kn, ks)``).

    Returns
    -------
    Contacts
        A copy carrying the law's springs [N/m].
    """
    kn, ks = law.stiffness(contacts)
    return contacts.with_stiffness(kn, ks)
