"""The contact list of a packing: pairs, normals, arms, overlaps and per-contact stiffness and damping.

Each contact couples the six degrees of freedom of two particles (Otsubo, O'Sullivan & Shire 2017);
the stiffness and damping are filled in per contact by a contact law
(``dtcrit.packing.model.apply_law``).  Plain NumPy; nothing imports SymPy.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from dtcrit.errors import InputError
from dtcrit.packing.normal_arms import NormalArms
from dtcrit.packing.uniform_values import held, one_value, taken, uniform


INDEX_LIMIT = 2**31
"""Particle indices are int32 when every DOF index ``6 p + k`` of the packing stays below this (``index_dtype``)."""


def index_dtype(n_particles: int) -> np.dtype:
    """The dtype of a contact list's particle indices ``i``, ``j``: int32 when ``6 N < 2^31`` (every DOF
    index ``6 p + k`` fits in it too; 4 bytes a contact fewer per index), else int64.

    Arithmetic on the indices beyond ``6 p + k`` (``36 p``, ``p N + q``, ...) casts to int64 first:
    NumPy keeps int32 times a Python int in int32.

    Parameters
    ----------
    n_particles : int
        Particles ``N`` of the packing.

    Returns
    -------
    numpy.dtype
        ``int32`` or ``int64``.

    Examples
    --------
    >>> index_dtype(357_913_941), index_dtype(357_913_942)
    (dtype('int32'), dtype('int64'))
    """
    return np.dtype(np.int32) if 6 * int(n_particles) < INDEX_LIMIT else np.dtype(np.int64)


@dataclass(frozen=True)
class Contacts:
    """Contact list: pair ``(i[c], j[c])``, unit normal from ``i`` to ``j``, contact arms.

    ``arm_i = x_c - x_i`` and ``arm_j = x_c - (x_j + shift)`` share one contact point ``x_c`` (Peng
    et al. 2020, Eqs (1)-(2)), so rigid-body motions of the pair strain no spring.  ``image`` is
    the integer periodic-image shift of ``j`` (``x_j + image * L``); ``i == j`` is a particle
    touching its own periodic image.  ``overlap`` >= 0; ``radius_eff`` is the effective radius of
    curvature ``R* = R_i R_j / (R_i + R_j)`` for spheres (Hertz), NaN otherwise.  ``kn``/``ks``
    are the normal and tangential spring stiffnesses [N/m] once a contact law was applied.

    Optional per-contact terms (``None`` when absent): ``cn``/``cs`` the normal and tangential
    dashpot coefficients [N s/m] (force ``-c`` times the relative velocity of the contact points);
    ``kr``/``ktw`` the rolling and twisting spring stiffnesses [N m/rad] (moment against the
    relative rotation ``theta_j - theta_i`` perpendicular to, and about, the normal), ``cr``/``ctw`` their
    dashpots [N m s/rad]; ``force_n``
    the normal force [N] a pre-loaded contact carries (compressive positive), for its geometric stiffness.
    A per-contact term given as one number (``with_stiffness(1.0, 0.5)``, ``model.LinearLaw``), and the
    ``radius_eff`` of equal spheres, is held once: a read-only view of stride 0 (``uniform_values``).

    Parameters
    ----------
    i, j : numpy.ndarray
        (C,) indices of the two particles of each contact (int32 from the sphere detection when
        ``6 N < 2^31``: ``index_dtype``; int64 otherwise and from the readers).
    normal : numpy.ndarray
        (C, 3) unit normals from ``i`` to ``j``.
    arm_i, arm_j : numpy.ndarray or NormalArms
        (C, 3) contact arms [m] from each centre of mass to the contact point (sphere contacts hold
        them as their lengths along ``normal``: ``dtcrit.packing.normal_arms``).
    overlap : numpy.ndarray
        (C,) overlaps [m], >= 0.
    image : numpy.ndarray
        (C, 3) integer periodic-image shift of ``j``.
    radius_eff : numpy.ndarray
        (C,) effective radius ``R*`` [m] of sphere contacts, NaN otherwise.
    kn, ks : numpy.ndarray or None
        (C,) normal and tangential spring stiffnesses [N/m].
    cn, cs : numpy.ndarray or None
        (C,) normal and tangential dashpot coefficients [N s/m].
    kr, ktw : numpy.ndarray or None
        (C,) rolling and twisting spring stiffnesses [N m/rad].
    force_n : numpy.ndarray or None
        (C,) normal force [N] of a pre-loaded contact, compressive positive.
    cr, ctw : numpy.ndarray or None
        (C,) rolling and twisting dashpot coefficients [N m s/rad].
    """

    i: np.ndarray
    j: np.ndarray
    normal: np.ndarray
    arm_i: np.ndarray | NormalArms
    arm_j: np.ndarray | NormalArms
    overlap: np.ndarray
    image: np.ndarray
    radius_eff: np.ndarray
    kn: np.ndarray | None = None
    ks: np.ndarray | None = None
    cn: np.ndarray | None = None
    cs: np.ndarray | None = None
    kr: np.ndarray | None = None
    ktw: np.ndarray | None = None
    force_n: np.ndarray | None = None
    cr: np.ndarray | None = None
    ctw: np.ndarray | None = None

    @property
    def count(self) -> int:
        """Number of contacts."""
        return int(self.i.shape[0])

    def coordination(self, n_particles: int) -> np.ndarray:
        """Contacts per particle; a contact with one's own image counts twice (both sides).

        Parameters
        ----------
        n_particles : int
            Number of particles of the packing.

        Returns
        -------
        numpy.ndarray
            (n_particles,) number of contacts of each particle.
        """
        return (np.bincount(self.i, minlength=n_particles) + np.bincount(self.j, minlength=n_particles))

    def _values(self, value) -> np.ndarray:
        """``value`` for every contact: a read-only view of stride 0 of its one value when it is one number
        (a scalar, or an array of one value: ``uniform_values``), else a copy of one value per contact.
        """
        one = one_value(value, self.count)
        if one is not None:
            return uniform(one[0], self.count)
        return np.broadcast_to(np.asarray(value, dtype=float), self.i.shape).copy()

    def _per_contact(self, **values) -> dict:
        out: dict[str, np.ndarray | None] = {}
        for key, value in values.items():
            if value is None:
                out[key] = None
                continue
            arr = self._values(value)
            if np.any(~np.isfinite(held(arr))) or np.any(held(arr) < 0):
                raise InputError(key, "every value must be a finite number >= 0")
            out[key] = arr
        return out

    def with_stiffness(self, kn, ks, kr=None, ktw=None) -> "Contacts":
        """Per-contact springs: ``kn``, ``ks`` [N/m]; rolling ``kr`` and twisting ``ktw`` [N m/rad].

        Parameters
        ----------
        kn, ks : float or array_like
            Normal and tangential stiffness [N/m], one value or one per contact (finite, >= 0).
        kr, ktw : float or array_like or None
            Rolling and twisting stiffness [N m/rad], or None for none.

        Returns
        -------
        Contacts
            A copy carrying the springs.
        """
        return replace(self, **self._per_contact(kn=kn, ks=ks, kr=kr, ktw=ktw))

    def with_damping(self, cn, cs, cr=None, ctw=None) -> "Contacts":
        """Per-contact dashpots ``cn`` (normal), ``cs`` (tangential) [N s/m]; rolling ``cr`` and twisting
        ``ctw`` [N m s/rad] on the relative angular velocity.

        Parameters
        ----------
        cn, cs : float or array_like or None
            Normal and tangential dashpot coefficients [N s/m], one value or one per contact (finite, >= 0).
        cr, ctw : float or array_like or None
            Rolling and twisting dashpot coefficients [N m s/rad], or None for none.

        Returns
        -------
        Contacts
            A copy carrying the dashpots.
        """
        return replace(self, **self._per_contact(cn=cn, cs=cs, cr=cr, ctw=ctw))

    def with_normal_force(self, force_n) -> "Contacts":
        """The normal force [N] of each pre-loaded contact, compressive positive (a bond in tension is
        negative), for its geometric stiffness.

        Parameters
        ----------
        force_n : float or array_like
            Normal force [N], one value or one per contact (finite).

        Returns
        -------
        Contacts
            A copy carrying the forces.
        """
        arr = self._values(force_n)
        if not np.all(np.isfinite(held(arr))):
            raise InputError("force_n", "every normal force must be a finite number")
        return replace(self, force_n=arr)

    @property
    def damped(self) -> bool:
        """Whether any contact carries a positive dashpot."""
        return any(c is not None and np.any(held(c) > 0) for c in (self.cn, self.cs, self.cr, self.ctw))

    @property
    def rotational_springs(self) -> bool:
        """Whether any contact carries a positive rolling or twisting spring."""
        return any(k is not None and np.any(held(k) > 0) for k in (self.kr, self.ktw))

    def subset(self, mask) -> "Contacts":
        """The contacts selected by ``mask``.

        Parameters
        ----------
        mask : numpy.ndarray
            Boolean mask or index array over the contacts.

        Returns
        -------
        Contacts
            Those contacts with every per-contact term.
        """
        i = self.i[mask]
        pick = lambda a: None if a is None else taken(a, i.shape[0], mask)  # noqa: E731
        normal = self.normal[mask]

        def arm(a):  # lengths stay lengths on the selected normals when they lie along this list's normals
            return a.select(mask, normal) if isinstance(a, NormalArms) and a.normal is self.normal else a[mask]

        return Contacts(i, self.j[mask], normal, arm(self.arm_i), arm(self.arm_j),
                        self.overlap[mask], self.image[mask], taken(self.radius_eff, i.shape[0], mask), pick(self.kn),
                        pick(self.ks), pick(self.cn), pick(self.cs), pick(self.kr), pick(self.ktw), pick(self.force_n),
                        pick(self.cr), pick(self.ctw))

    @classmethod
    def empty(cls) -> "Contacts":
        """No contacts.

        Returns
        -------
        Contacts
            An empty contact list with zero springs.
        """
        z3 = np.zeros((0, 3))
        zi = np.zeros(0, dtype=np.int64)
        return cls(zi, zi.copy(), z3, z3.copy(), z3.copy(), np.zeros(0), np.zeros((0, 3), dtype=np.int64),
                   np.zeros(0), np.zeros(0), np.zeros(0))
