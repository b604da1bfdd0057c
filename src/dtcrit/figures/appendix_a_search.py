"""The search behind Peng et al. (2020), Appendix A: the paper's ellipsoid and comparison shapes,
batched contact coefficient matrices, contact configurations and the pair search over admissible
contacts (surface points, normals and orientations).
"""
from __future__ import annotations

import math

import numpy as np

from dtcrit.figures._rotations import (
    angles_from_unit,
    fibonacci_sphere,
    rotvec_matrices,
    rotvec_matrix,
    super_fibonacci_rotations,
    unit_from_angles,
)
from dtcrit.figures.appendix_a_contacts import ContactConfig, SearchResult, _config

FORCE = (1.0, 1.0, 1.0)
"""Appendix A's contact force on particle 2 [N]."""
PAPER_BASE_QUATERNION = (math.cos(math.pi / 8), 0.0, -math.sin(math.pi / 8), 0.0)
"""(qw, qx, qy, qz) of particle 2 in the 'change centre' scenario, body to world: 45 degrees about -y."""
GRIDS = {
    # name: (normals, orientations, refined seeds per objective, scenario grid per side)
    "coarse": (256, 384, 4, 31),
    "fine": (2048, 4096, 12, 121),
}


# ============================================================================================
# Shapes of the study
# ============================================================================================
def paper_ellipsoid(density: float = 1.0):
    """The a = 3, b = 2, c = 1 m ellipsoid of Section 6 and Appendix A (unit density there).

    Parameters
    ----------
    density : float
        Density [kg/m^3].

    Returns
    -------
    dtcrit.bodies.Ellipsoid
        The ellipsoid.
    """
    from dtcrit.bodies import Ellipsoid

    return Ellipsoid(3.0, 2.0, 1.0, density=density)


def comparison_shapes(density: float = 1.0) -> dict:
    """The shapes of the extended search: the paper's ellipsoid, a superquadric and a box of the
    same half-lengths 3, 2, 1 m (superquadric exponents eps1 = eps2 = 0.5, a rounded box).

    Parameters
    ----------
    density : float
        Density [kg/m^3].

    Returns
    -------
    dict
        Name to body.
    """
    import warnings

    from dtcrit.bodies import Box, Superquadric

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the shapes warn if assumption 3 fails; that is reported
        return {
            "ellipsoid": paper_ellipsoid(density),
            "superquadric": Superquadric(3.0, 2.0, 1.0, 0.5, 0.5, density=density),
            "box": Box(3.0, 2.0, 1.0, density=density),
        }


# ============================================================================================
# Coefficient matrices
# ============================================================================================
def batch_coefficient_matrices(body1, body2, normals, p1, p2, Q2) -> np.ndarray:
    """``A`` for many contacts at once, through ``dtcrit.bodies.contact_search.Contacts`` (particle 1 axis
    aligned: its local contact point ``p1`` is also its global arm).

    Parameters
    ----------
    body1, body2 : object
        The two bodies.
    normals : numpy.ndarray
        Outward normals of particle 1, (N, 3).
    p1, p2 : numpy.ndarray
        Local contact points, (N, 3) [m].
    Q2 : numpy.ndarray
        Orientations of particle 2, body to world, (N, 3, 3).

    Returns
    -------
    numpy.ndarray
        Coefficient matrices, (N, 3, 3) [1/kg].
    """
    from dtcrit.bodies.contact_search import Contacts

    Q2 = np.asarray(Q2, dtype=float)
    Q1 = np.broadcast_to(np.eye(3), Q2.shape)
    r2 = np.einsum("nij,nj->ni", Q2, p2)
    return Contacts(p1, p2, Q1, Q2, p1, r2, normals).coefficient_matrices(body1, body2)


def coefficient_matrix_single(body1, body2, r1, r2, Q2) -> np.ndarray:
    """One contact's ``A`` through ``dtcrit.bodies.contact.coefficient_matrix`` (particle 1 axis aligned,
    ``Q2`` the body-to-world orientation of particle 2, as that function takes it).

    Parameters
    ----------
    body1, body2 : object
        The two bodies.
    r1, r2 : array_like
        Contact arms in global components [m].
    Q2 : array_like
        Orientation of particle 2, body to world.

    Returns
    -------
    numpy.ndarray
        The 3x3 coefficient matrix ``A`` [1/kg].
    """
    from dtcrit.bodies.contact import coefficient_matrix

    return np.asarray(coefficient_matrix(body1, body2, np.asarray(r1, float), np.asarray(r2, float),
                                         body_to_world=(None, np.asarray(Q2, float))), dtype=float)


# ============================================================================================
# Configurations
# ============================================================================================
class PairSearch:
    """Admissible contacts of ``body2`` on ``body1`` and their coefficient matrices.

    Parameters
    ----------
    body1, body2 : object
        The two convex bodies (particle 1 axis aligned at the origin).
    force : array_like
        The applied contact force [N].
    """

    def __init__(self, body1, body2, force=FORCE):
        self.body1 = body1
        self.body2 = body2
        self.force = np.asarray(force, dtype=float)

    # ----- geometry ---------------------------------------------------------------------------
    def place(self, normals: np.ndarray, Q2: np.ndarray):
        """``(r1, r2)`` for rows of ``normals`` (N, 3) and orientations ``Q2`` (N, 3, 3).

        Parameters
        ----------
        normals : numpy.ndarray
            Outward normals of particle 1, (N, 3).
        Q2 : numpy.ndarray
            Orientations of particle 2, (N, 3, 3).

        Returns
        -------
        tuple of numpy.ndarray
            The arms ``r1`` and ``r2``, each (N, 3) [m].
        """
        n = np.asarray(normals, dtype=float)
        r1 = self.body1.support(n)
        local_dir = -np.einsum("nji,nj->ni", Q2, n)  # Q2^T (-n)
        r2 = np.einsum("nij,nj->ni", Q2, self.body2.support(local_dir))
        return r1, r2

    def matrices(self, r1, r2, Q2) -> np.ndarray:
        """``A`` for arms ``r1, r2`` (global) and orientations ``Q2`` (body 1 axis aligned).

        Parameters
        ----------
        r1, r2 : numpy.ndarray
            Contact arms, (N, 3) [m].
        Q2 : numpy.ndarray
            Orientations of particle 2, (N, 3, 3).

        Returns
        -------
        numpy.ndarray
            Coefficient matrices, (N, 3, 3) [1/kg].
        """
        Q2 = np.asarray(Q2, dtype=float)
        p2 = np.einsum("nji,nj->ni", Q2, r2)  # local contact point of particle 2
        normals = np.zeros_like(r1)  # not used by the coefficient matrix
        return batch_coefficient_matrices(self.body1, self.body2, normals, r1, p2, Q2)

    def objectives(self, A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(|A F|, largest eigenvalue)`` per matrix.

        Parameters
        ----------
        A : numpy.ndarray
            Coefficient matrices, (..., 3, 3).

        Returns
        -------
        tuple of numpy.ndarray
            ``|A F|`` and the largest eigenvalue.
        """
        return np.linalg.norm(A @ self.force, axis=-1), np.linalg.eigvalsh(A)[..., -1]

    def config(self, n, Q2, label: str = "", canonical: bool = True) -> ContactConfig:
        """One contact evaluated with ``dtcrit.bodies.contact.coefficient_matrix``.

        ``canonical``: report the contact in a unique form.  Both bodies are symmetric under the
        half-turns about their axes and under inversion, so ``(n, Q2)``, ``(-n, Q2)`` (both arms
        reversed) and ``Q2`` times a half-turn about a body axis all describe the same ``A``; the
        form with ``n`` pointing to ``x >= 0`` (first non-zero component positive) and the
        orientation closest to the identity is returned.

        Parameters
        ----------
        n : array_like
            Outward normal of particle 1.
        Q2 : array_like
            Orientation of particle 2.
        label : str
            Name of the configuration.
        canonical : bool
            Report the unique form.

        Returns
        -------
        ContactConfig
            The evaluated contact.
        """
        n = np.asarray(n, dtype=float)
        n = n / np.linalg.norm(n)
        Q2 = np.asarray(Q2, dtype=float)
        if canonical:
            lead = n[np.flatnonzero(np.abs(n) > 1e-9)[0]]
            if lead < 0:
                n = -n
            flips = [np.diag(d) for d in ((1, 1, 1), (1, -1, -1), (-1, 1, -1), (-1, -1, 1))]
            Q2 = max((Q2 @ f for f in flips), key=lambda q: float(np.trace(q)))
        r1, r2 = self.place(n[None, :], np.asarray(Q2, dtype=float)[None])
        A = coefficient_matrix_single(self.body1, self.body2, r1[0], r2[0], Q2)
        return _config(self.body1, self.body2, n, Q2, r1[0], r2[0], A, self.force, label)

    # ----- grid + polish ----------------------------------------------------------------------
    def _values(self, params: np.ndarray, which: int) -> np.ndarray:
        """Objective ``which`` (0: |A F|, 1: largest eigenvalue) for rows of 5 parameters
        (polar angle and azimuth of ``n``, rotation vector of ``Q2``).
        """
        params = np.atleast_2d(params)
        n = unit_from_angles(params[:, 0], params[:, 1])
        Q2 = rotvec_matrices(params[:, 2:5])
        r1, r2 = self.place(n, Q2)
        return self.objectives(self.matrices(r1, r2, Q2))[which]

    def polish(self, starts: list[tuple[np.ndarray, np.ndarray]], which: int, population: int = 48,
               iterations: int = 400, tol: float = 1e-10) -> list[tuple[np.ndarray, np.ndarray]]:
        """Local maximisation of objective ``which`` from each ``(n, Q2)`` start, all in one batch.

        A (1, lambda) evolution strategy with step-size control: each iteration draws ``population``
        Gaussian perturbations of every current point (fixed seed, so reproducible), keeps the best
        if it improves and widens the step, or else narrows it by 0.6, until every step is below
        ``tol`` radians.  Suits the polyhedral (piecewise smooth) cases as well as the smooth ones.

        Parameters
        ----------
        starts : list of tuple
            ``(n, Q2)`` start points.
        which : int
            Objective: 0 for ``|A F|``, 1 for the largest eigenvalue.
        population : int
            Perturbations per point and iteration.
        iterations : int
            Largest number of iterations.
        tol : float
            Step size [rad] at which a point is converged.

        Returns
        -------
        list of tuple
            The polished ``(n, Q2)``.
        """
        from scipy.spatial.transform import Rotation

        x = np.array([[*angles_from_unit(n), *Rotation.from_matrix(np.asarray(Q)).as_rotvec()] for n, Q in starts])
        f = self._values(x, which)
        sigma = np.full(x.shape[0], 0.05)
        rng = np.random.default_rng(20200)
        S = x.shape[0]
        for _ in range(iterations):
            active = sigma > tol
            if not np.any(active):
                break
            trial = x[:, None, :] + sigma[:, None, None] * rng.standard_normal((S, population, 5))
            ft = self._values(trial.reshape(-1, 5), which).reshape(S, population)
            j = np.argmax(ft, axis=1)
            better = (ft[np.arange(S), j] > f) & active
            x[better] = trial[np.arange(S), j][better]
            f[better] = ft[np.arange(S), j][better]
            sigma = np.where(better, np.minimum(sigma * 1.5, 0.3), np.where(active, sigma * 0.6, sigma))
        return [(unit_from_angles(p[0], p[1]), rotvec_matrix(p[2:5])) for p in x]

    def search(self, n_normals: int = 256, n_orientations: int = 384, seeds: int = 4,
               chunk: int = 64, progress_label: str | None = None) -> SearchResult:
        """Grid over normals x orientations, then polish the ``seeds`` best of each objective.

        Parameters
        ----------
        n_normals : int
            Normals of the grid.
        n_orientations : int
            Orientations of the grid.
        seeds : int
            Best grid points polished per objective.
        chunk : int
            Orientations evaluated per batch.
        progress_label : str, optional
            Label of a progress bar (none when omitted).

        Returns
        -------
        SearchResult
            The maxima found.
        """
        normals = fibonacci_sphere(n_normals)
        rotations = super_fibonacci_rotations(n_orientations)
        starts = range(0, n_orientations, chunk)
        if progress_label:
            from tqdm import tqdm

            starts = tqdm(list(starts), desc=progress_label, disable=None)
        keep = max(seeds * 8, 16)
        cand: dict[int, list[tuple[float, int, int]]] = {0: [], 1: []}
        for s in starts:
            Qc = rotations[s:s + chunk]
            nn = np.repeat(normals[None, :, :], Qc.shape[0], axis=0).reshape(-1, 3)
            QQ = np.repeat(Qc[:, None], normals.shape[0], axis=1).reshape(-1, 3, 3)
            r1, r2 = self.place(nn, QQ)
            vals = self.objectives(self.matrices(r1, r2, QQ))
            for which in (0, 1):
                top = np.argsort(-vals[which], kind="stable")[:keep]
                cand[which] += [(float(vals[which][t]), s + t // normals.shape[0], t % normals.shape[0]) for t in top]
        out: dict[int, ContactConfig] = {}
        polished = []
        grid_best = {}
        for which in (0, 1):
            ranked = sorted(cand[which], key=lambda c: (-c[0], c[1], c[2]))
            grid_best[which] = ranked[0][0]
            chosen: list[tuple[float, int, int]] = []
            for val, qi, ni in ranked:  # distinct seeds: different normal or orientation cells
                if all(qi != q or ni != m for _, q, m in chosen):
                    chosen.append((val, qi, ni))
                if len(chosen) == seeds:
                    break
            best_cfg = None
            ends = self.polish([(normals[ni], rotations[qi]) for _, qi, ni in chosen], which)
            for n, Q2 in ends:
                cfg = self.config(n, Q2, label=("max |A F|" if which == 0 else "max eigenvalue"))
                polished.append(cfg)
                key = cfg.accel if which == 0 else cfg.lam
                if best_cfg is None or key > (best_cfg.accel if which == 0 else best_cfg.lam):
                    best_cfg = cfg
            assert best_cfg is not None  # polish returns at least one end per seed
            out[which] = best_cfg
        return SearchResult(out[0], out[1], grid_best[0], grid_best[1], n_normals * n_orientations, polished)
