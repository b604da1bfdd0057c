"""Admissible contacts of two convex particles and the suprema behind ``dtcrit.a_bound``.

Peng et al. (2020), Section 3, keep only the diagonal of the coefficient matrix ``A`` of the
contact force in three tip-to-tip configurations and state (Eq 26) that
``A_max = a1^2/Ixx1 + a2^2/Ixx2 + 1/m1 + 1/m2`` bounds it.  For an arbitrary contact

    A = (1/m1 + 1/m2) 1 + T1 + T2,   T_i = Q_i [p_i]x^T I_i^-1 [p_i]x Q_i^T,

where ``p_i`` is the contact point in particle ``i``'s local frame and ``Q_i`` its orientation
(body -> global).  This module provides

* :func:`arm_term_supremum` (from :mod:`dtcrit.bodies.arm_supremum`, re-exported): bounds on
  ``S = sup over the body of lambda_max([p]x^T I^-1 [p]x)``.
* :func:`contact_frames` / :func:`random_contacts`: admissible contacts (the two outward normals
  opposite, particle 2 free to spin about the normal), for sampling.
* :func:`search_supremum`: random sampling plus local maximisation of ``lambda_max(A)`` over
  admissible contacts (the searched supremum the derivation record compares with).
* :func:`mirror_contact`: for two identical particles, the admissible contact (particle 2 is
  particle 1 turned by a half-turn about an axis normal to the contact normal and to the top
  eigenvector) at which ``lambda_max(A) = 2/m + 2 S`` is attained.

No SymPy: NumPy, SciPy and the generated kernels only.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from dtcrit.bodies.arm_terms import arm_terms_local, largest_eigenvalue
from dtcrit.bodies.rotations import axis_angle, random_rotations, rotation_between, unit_vectors


# ============================================================================================
# Admissible contacts
# ============================================================================================
@dataclass
class Contacts:
    """A batch of contacts (arrays with a leading axis of length N).

    ``p1, p2``: contact points in the local frames; ``n1``: outward normal of particle 1 (local);
    ``Q1, Q2``: orientations (body -> global, so the paper's ``R_i = Q_i^T``, Eq 5);
    ``r1, r2``: contact arms ``x_c - x_i`` in global components (Eqs 1-2); ``normal``: global
    outward normal of particle 1 (particle 2's is its negative).

    Parameters
    ----------
    p1, p2 : numpy.ndarray
        Contact points in the local frames, (N, 3) [m].
    Q1, Q2 : numpy.ndarray
        Orientations, body to global, (N, 3, 3).
    r1, r2 : numpy.ndarray
        Contact arms in global components, (N, 3) [m].
    normal : numpy.ndarray
        Global outward normal of particle 1, (N, 3).
    """

    p1: np.ndarray
    p2: np.ndarray
    Q1: np.ndarray
    Q2: np.ndarray
    r1: np.ndarray
    r2: np.ndarray
    normal: np.ndarray

    def coefficient_matrices(self, shape1, shape2) -> np.ndarray:
        """``A`` (global frame) for each contact (Peng et al. 2020, Eqs 3-19).

        Parameters
        ----------
        shape1, shape2 : object
            The two shapes (mass and principal moments).

        Returns
        -------
        numpy.ndarray
            Coefficient matrices, (N, 3, 3) [1/kg].
        """
        T1 = self.Q1 @ arm_terms_local(self.p1, shape1.inertia) @ self.Q1.transpose(0, 2, 1)
        T2 = self.Q2 @ arm_terms_local(self.p2, shape2.inertia) @ self.Q2.transpose(0, 2, 1)
        return (1.0 / shape1.mass + 1.0 / shape2.mass) * np.eye(3) + T1 + T2

    def largest_eigenvalues(self, shape1, shape2) -> np.ndarray:
        """``lambda_max(A)`` for each contact.

        Parameters
        ----------
        shape1, shape2 : object
            The two shapes (mass and principal moments).

        Returns
        -------
        numpy.ndarray
            Largest eigenvalues, (N,) [1/kg].
        """
        return largest_eigenvalue(self.coefficient_matrices(shape1, shape2))


def contact_frames(p1, n1, p2, n2, spin, Q1=None) -> Contacts:
    """Place particle 2 against particle 1: its outward normal ``n2`` (local) is turned onto minus
    the global normal ``Q1 n1`` and then spun by ``spin`` [rad] about that normal.

    Parameters
    ----------
    p1, n1 : array_like
        Contact point and outward normal of particle 1, local frame.
    p2, n2 : array_like
        Contact point and outward normal of particle 2, local frame.
    spin : array_like
        Spin of particle 2 about the common normal [rad].
    Q1 : array_like, optional
        Orientation of particle 1, body to global (identity when omitted).

    Returns
    -------
    Contacts
        The batch of contacts.
    """
    p1, n1, p2, n2 = (np.atleast_2d(np.asarray(x, float)) for x in (p1, n1, p2, n2))
    N = max(x.shape[0] for x in (p1, n1, p2, n2))
    p1, n1, p2, n2 = (np.broadcast_to(x, (N, 3)) for x in (p1, n1, p2, n2))
    Q1 = np.broadcast_to(np.eye(3), (N, 3, 3)) if Q1 is None else np.broadcast_to(np.asarray(Q1, float), (N, 3, 3))
    normal = np.einsum("nij,nj->ni", Q1, n1 / np.linalg.norm(n1, axis=1, keepdims=True))
    align = rotation_between(n2, -normal)
    Q2 = axis_angle(normal, np.broadcast_to(np.asarray(spin, float), (N,))) @ align
    r1 = np.einsum("nij,nj->ni", Q1, p1)
    r2 = np.einsum("nij,nj->ni", Q2, p2)
    return Contacts(np.array(p1), np.array(p2), np.array(Q1), Q2, r1, r2, normal)


def _support_samples(shape, rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Support points of random directions with those directions as normals (for a polyhedron: its
    vertices, with normals spread over their normal cones).
    """
    d = unit_vectors(rng, n)
    return np.asarray(shape.support(d), float), d


def surface_samples(shape, rng: np.random.Generator, n: int, n_surface: int = 400) -> tuple[np.ndarray, np.ndarray]:
    """``n`` surface points and outward normals (local frame): half support points of random
    directions (every vertex with normals spread over its cone for polyhedra), half drawn from
    ``shape.surface_points`` (faces, edges and smooth regions with their normals).

    Parameters
    ----------
    shape : object
        The shape.
    rng : numpy.random.Generator
        Source of randomness.
    n : int
        Number of samples.
    n_surface : int
        Size of the ``surface_points`` pool drawn from.

    Returns
    -------
    tuple of numpy.ndarray
        Points and outward normals, each (n, 3).
    """
    k = n // 2
    p_a, n_a = _support_samples(shape, rng, k)
    pts, nrm = shape.surface_points(n_surface)
    idx = rng.integers(0, pts.shape[0], size=n - k)
    return np.vstack([p_a, pts[idx]]), np.vstack([n_a, nrm[idx]])


def random_contacts(shape1, shape2, n: int, seed: int = 0) -> Contacts:
    """``n`` random admissible contacts: random surface points and normals on both particles, a
    random orientation of particle 1 and a random spin of particle 2 about the common normal.

    Parameters
    ----------
    shape1, shape2 : object
        The two shapes.
    n : int
        Number of contacts.
    seed : int
        Seed of the random generator.

    Returns
    -------
    Contacts
        The batch of contacts.
    """
    rng = np.random.default_rng(seed)
    p1, n1 = surface_samples(shape1, rng, n)
    p2, n2 = surface_samples(shape2, rng, n)
    spin = rng.uniform(0.0, 2.0 * math.pi, size=n)
    return contact_frames(p1, n1, p2, n2, spin, random_rotations(rng, n))


# ============================================================================================
# Searched supremum of lambda_max(A) over admissible contacts
# ============================================================================================
def _direction(angles: np.ndarray) -> np.ndarray:
    t, f = angles[..., 0], angles[..., 1]
    return np.stack([np.cos(f) * np.sin(t), np.sin(f) * np.sin(t), np.cos(t)], -1)


@dataclass(frozen=True)
class SearchResult:
    """Largest ``lambda_max(A)`` found [1/kg] and the contact that gives it (one-element batch).

    Parameters
    ----------
    value : float
        The largest value found [1/kg].
    contact : Contacts
        The contact that gives it.
    evaluations : int
        Number of contacts evaluated.
    """

    value: float
    contact: Contacts
    evaluations: int


def search_supremum(shape1, shape2, n_random: int = 4000, n_starts: int = 8, iterations: int = 200,
                    seed: int = 0) -> SearchResult:
    """Maximise ``lambda_max(A)`` over admissible contacts.

    Random admissible contacts (:func:`random_contacts`) first; then, from the ``n_starts`` best of
    them, a vectorised (1+16) evolution strategy with step-size adaptation over the parameters
    (polar angles of particle 1's normal, of particle 2's normal, spin about the common normal),
    the contact points being the support points of the normals: by convexity of ``lambda_max`` in
    the contact points, at fixed normals the maximum over the touching faces is at their vertices.

    Parameters
    ----------
    shape1, shape2 : object
        The two shapes.
    n_random : int
        Number of random contacts to start from.
    n_starts : int
        Number of best contacts refined.
    iterations : int
        Generations of the evolution strategy.
    seed : int
        Seed of the random generator.

    Returns
    -------
    SearchResult
        The best contact found (a lower bound on the supremum).
    """
    rng = np.random.default_rng(seed)
    batch = random_contacts(shape1, shape2, n_random, seed)
    lam = batch.largest_eigenvalues(shape1, shape2)
    evaluations = n_random

    def build(x):
        n1, n2 = _direction(x[:, 0:2]), _direction(x[:, 2:4])
        return contact_frames(shape1.support(n1), n1, shape2.support(n2), n2, x[:, 4])

    def value(x):
        return build(x).largest_eigenvalues(shape1, shape2)

    order = np.argsort(-lam)[:n_starts]
    n1 = np.einsum("nji,nj->ni", batch.Q1[order], batch.normal[order])  # local normal of particle 1
    n2 = -np.einsum("nji,nj->ni", batch.Q2[order], batch.normal[order])
    rel = batch.Q1[order].transpose(0, 2, 1) @ batch.Q2[order] @ rotation_between(n2, -n1).transpose(0, 2, 1)
    u = np.cross(n1, np.eye(3)[np.argmin(np.abs(n1), axis=1)])
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    ru = np.einsum("nij,nj->ni", rel, u)
    spin = np.arctan2(np.einsum("ni,ni->n", np.cross(u, ru), n1), np.einsum("ni,ni->n", u, ru))
    x = np.column_stack([np.arccos(np.clip(n1[:, 2], -1, 1)), np.arctan2(n1[:, 1], n1[:, 0]),
                         np.arccos(np.clip(n2[:, 2], -1, 1)), np.arctan2(n2[:, 1], n2[:, 0]), spin])
    fx = value(x)
    evaluations += x.shape[0]
    sigma = np.full(x.shape[0], 0.05)
    children = 16
    for _ in range(iterations):
        trial = x[:, None, :] + sigma[:, None, None] * rng.normal(size=(x.shape[0], children, 5))
        ft = value(trial.reshape(-1, 5)).reshape(x.shape[0], children)
        evaluations += ft.size
        j = np.argmax(ft, axis=1)
        better = ft[np.arange(x.shape[0]), j] > fx
        x[better] = trial[better, j[better]]
        fx[better] = ft[better, j[better]]
        sigma = np.clip(np.where(better, sigma * 1.5, sigma * 0.6), 1e-9, 1.0)
    k = int(np.argmax(fx))
    i = int(np.argmax(lam))
    if lam[i] >= fx[k]:
        one = Contacts(*(np.asarray(getattr(batch, f))[i : i + 1] for f in ("p1", "p2", "Q1", "Q2", "r1", "r2", "normal")))
        return SearchResult(float(lam[i]), one, evaluations)
    return SearchResult(float(fx[k]), build(x[k : k + 1]), evaluations)


def mirror_contact(shape, point, normal) -> Contacts:
    """Two copies of ``shape`` touching at the same local ``point`` with outward ``normal`` (local,
    in the normal cone at ``point``), particle 2 turned by a half-turn about the axis normal to
    both the contact normal and the top eigenvector ``v`` of ``[p]x^T I^-1 [p]x``: then particle
    2's top eigenvector is ``-v`` and ``lambda_max(A) = 2/m + 2 lambda_max(T(p))``.

    Parameters
    ----------
    shape : object
        The shape of both particles.
    point : array_like
        Contact point, local frame [m].
    normal : array_like
        Outward normal at ``point``, local frame.

    Returns
    -------
    Contacts
        A one-element batch.
    """
    p = np.asarray(point, float)
    nrm = np.asarray(normal, float) / np.linalg.norm(normal)
    _, vecs = np.linalg.eigh(arm_terms_local(p[None, :], shape.inertia)[0])
    v = vecs[:, -1]
    axis = np.cross(nrm, v)
    if np.linalg.norm(axis) < 1e-12:  # v along the normal: any axis normal to it
        axis = np.cross(nrm, np.eye(3)[int(np.argmin(np.abs(nrm)))])
    Q2 = axis_angle(axis[None, :], math.pi)
    r1 = p[None, :]
    r2 = np.einsum("nij,j->ni", Q2, p)
    return Contacts(r1.copy(), p[None, :].copy(), np.eye(3)[None], Q2, r1, r2, nrm[None, :])
