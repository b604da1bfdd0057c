"""Peng et al. 2020, Appendix A, reproduced: which contact maximises the relative acceleration?

Setting (Appendix A): particle 1 at the origin, axis aligned; particle 2 identical; unit density;
contact force ``F = (1, 1, 1)`` on particle 2 (``-F`` on particle 1); zero angular velocities, so
Eq. (25) reduces to ``xdd_c = A F`` with ``A`` the 3x3 coefficient matrix of Eqs. (1)-(19)
(``dtcrit.bodies.contact.coefficient_matrix``).

Admissible contacts.  A contact is fixed by the outward unit normal ``n`` of particle 1 at the
contact point and the orientation ``Q2`` (body-to-global) of particle 2:

* contact point ``x_c = support_1(n)`` (for a smooth body the point whose normal is ``n``; for a
  polyhedron a vertex whose normal cone contains ``n``), ``r_1 = x_c``;
* particle 2 is placed tangent with opposite outward normal: its touching point is
  ``p_2 = support_2(-Q2^T n)`` in its own frame, ``r_2 = Q2 p_2`` and its centre ``x_2 = x_c - r_2``.

Every pair ``(n, Q2)`` gives a touching, non-overlapping pair of convex bodies, and every such
contact arises this way.  The search samples ``n`` on a Fibonacci sphere and ``Q2`` on a
super-Fibonacci set of SO(3), evaluates ``|A F|`` and the largest eigenvalue of ``A`` on the whole
grid (batched through ``dtcrit.bodies.contact_search.Contacts``), and polishes the best few points by a
seeded evolution strategy in the five parameters (two angles of ``n``, the rotation vector of
``Q2``).  It is a numerical search: the grid maximum and the polished maximum are both reported.

The paper's two scenarios (Figs. A1-A4) are the one-parameter-pair families
:func:`scenario_centre_moved` (fixed ``Q2``, contact point over octant I of particle 1) and
:func:`scenario_orientation_changed` (contact fixed at the tip (a, 0, 0), ``Q2`` varied).  The
paper's own second family keeps the *tip* of particle 2 on the contact point whatever its
orientation (``pinned_tip=True``); it is reproduced as printed although, apart from collinear
axes, the bodies then interpenetrate (:func:`penetration_depth` measures by how much).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import minimize  # penetration depth only

from dtcrit.figures._rotations import (
    align_x_to,
    angles_from_unit,
    fibonacci_sphere,
    matrix_quaternion,
    quaternion_matrix,
    rotation_about,
    rotvec_matrices,
    rotvec_matrix,
    super_fibonacci_rotations,
    unit_from_angles,
)

__all__ = [
    "FORCE",
    "PAPER_BASE_QUATERNION",
    "GRIDS",
    "ContactConfig",
    "SearchResult",
    "PairSearch",
    "paper_ellipsoid",
    "comparison_shapes",
    "paper_base_orientation",
    "paper_orthogonal",
    "penetration_depth",
    "scenario_centre_moved",
    "scenario_orientation_changed",
    "appendix_a_study",
]

FORCE = (1.0, 1.0, 1.0)
"""Appendix A's contact force on particle 2 [N]."""
PAPER_BASE_QUATERNION = (math.cos(math.pi / 8), 0.0, -math.sin(math.pi / 8), 0.0)
"""(qw, qx, qy, qz) of particle 2 in the 'change centre' scenario: 45 degrees about -y."""
GRIDS = {
    # name: (normals, orientations, refined seeds per objective, scenario grid per side)
    "coarse": (256, 384, 4, 31),
    "fine": (2048, 4096, 12, 121),
}


# ============================================================================================
# Shapes of the study
# ============================================================================================
def paper_ellipsoid(density: float = 1.0):
    """The a = 3, b = 2, c = 1 m ellipsoid of Section 6 and Appendix A (unit density there)."""
    from dtcrit.bodies import Ellipsoid

    return Ellipsoid(3.0, 2.0, 1.0, density=density)


def comparison_shapes(density: float = 1.0) -> dict:
    """The shapes of the extended search: the paper's ellipsoid, a superquadric and a box of the
    same half-lengths 3, 2, 1 m (superquadric exponents eps1 = eps2 = 0.5, a rounded box)."""
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
    aligned: its local contact point ``p1`` is also its global arm)."""
    from dtcrit.bodies.contact_search import Contacts

    Q2 = np.asarray(Q2, dtype=float)
    Q1 = np.broadcast_to(np.eye(3), Q2.shape)
    r2 = np.einsum("nij,nj->ni", Q2, p2)
    return Contacts(p1, p2, Q1, Q2, p1, r2, normals).coefficient_matrices(body1, body2)


def coefficient_matrix_single(body1, body2, r1, r2, Q2) -> np.ndarray:
    """One contact's ``A`` through ``dtcrit.bodies.contact.coefficient_matrix`` (rotations global to local)."""
    from dtcrit.bodies.contact import coefficient_matrix

    return np.asarray(coefficient_matrix(body1, body2, np.asarray(r1, float), np.asarray(r2, float),
                                         np.eye(3), np.asarray(Q2, float).T), dtype=float)


# ============================================================================================
# Configurations
# ============================================================================================
@dataclass(frozen=True)
class ContactConfig:
    """One contact of particle 2 on particle 1 (global frame = particle 1's frame)."""

    normal: tuple[float, float, float]  # outward normal of particle 1 at the contact (global)
    orientation: tuple[tuple[float, ...], ...]  # Q2, body-to-global, rows
    contact_point: tuple[float, float, float]
    r1: tuple[float, float, float]
    r2: tuple[float, float, float]
    centre2: tuple[float, float, float]
    matrix: tuple[tuple[float, ...], ...]
    accel: float  # |A F|
    lam: float  # largest eigenvalue of A
    label: str = ""

    @property
    def quaternion(self) -> tuple[float, float, float, float]:
        """(qw, qx, qy, qz) of particle 2 (active rotation, Eq. (7) gives ``Q2``)."""
        return matrix_quaternion(np.array(self.orientation))

    def describe(self, digits: int = 6) -> dict:
        """Rounded, JSON-ready description."""
        def rnd(v):
            if isinstance(v, (tuple, list, np.ndarray)):
                return [rnd(x) for x in v]
            return float(f"{float(v):.{digits}g}") + 0.0

        Q = np.array(self.orientation)
        long2 = Q[:, 0]
        return {
            "label": self.label,
            "accel": rnd(self.accel),
            "lambda_max": rnd(self.lam),
            "normal_1": rnd(self.normal),
            "contact_point": rnd(self.contact_point),
            "r1": rnd(self.r1),
            "r2": rnd(self.r2),
            "centre_2": rnd(self.centre2),
            "quaternion_2_wxyz": rnd(self.quaternion),
            "long_axis_2": rnd(long2 * (1 if long2[np.argmax(np.abs(long2))] > 0 else -1)),
            "angle_between_long_axes_deg": rnd(math.degrees(math.acos(min(1.0, abs(float(long2[0])))))),
            "matrix": rnd(self.matrix),
        }


def _config(body1, body2, n, Q2, r1, r2, A, force, label="") -> ContactConfig:
    tup = lambda v: tuple(float(x) for x in np.ravel(v))  # noqa: E731
    A = np.asarray(A, dtype=float)
    return ContactConfig(
        tup(n), tuple(tup(row) for row in Q2), tup(r1), tup(r1), tup(r2), tup(np.asarray(r1) - np.asarray(r2)),
        tuple(tup(row) for row in A), float(np.linalg.norm(A @ force)), float(np.linalg.eigvalsh(A)[-1]), label,
    )


# ============================================================================================
# The search
# ============================================================================================
@dataclass
class SearchResult:
    """Maxima over all admissible contacts found by :meth:`PairSearch.search`."""

    best_accel: ContactConfig
    best_lam: ContactConfig
    grid_accel: float  # best on the grid, before polishing
    grid_lam: float
    evaluated: int  # number of grid contacts
    polished: list[ContactConfig] = field(default_factory=list)


class PairSearch:
    """Admissible contacts of ``body2`` on ``body1`` and their coefficient matrices."""

    def __init__(self, body1, body2, force=FORCE):
        self.body1 = body1
        self.body2 = body2
        self.force = np.asarray(force, dtype=float)

    # ----- geometry ---------------------------------------------------------------------------
    def place(self, normals: np.ndarray, Q2: np.ndarray):
        """``(r1, r2)`` for rows of ``normals`` (N, 3) and orientations ``Q2`` (N, 3, 3)."""
        n = np.asarray(normals, dtype=float)
        r1 = self.body1.support(n)
        local_dir = -np.einsum("nji,nj->ni", Q2, n)  # Q2^T (-n)
        r2 = np.einsum("nij,nj->ni", Q2, self.body2.support(local_dir))
        return r1, r2

    def matrices(self, r1, r2, Q2) -> np.ndarray:
        """``A`` for arms ``r1, r2`` (global) and orientations ``Q2`` (body 1 axis aligned)."""
        Q2 = np.asarray(Q2, dtype=float)
        p2 = np.einsum("nji,nj->ni", Q2, r2)  # local contact point of particle 2
        normals = np.zeros_like(r1)  # not used by the coefficient matrix
        return batch_coefficient_matrices(self.body1, self.body2, normals, r1, p2, Q2)

    def objectives(self, A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(|A F|, largest eigenvalue)`` per matrix."""
        return np.linalg.norm(A @ self.force, axis=-1), np.linalg.eigvalsh(A)[..., -1]

    def config(self, n, Q2, label: str = "", canonical: bool = True) -> ContactConfig:
        """One contact evaluated with ``dtcrit.bodies.contact.coefficient_matrix``.

        ``canonical``: report the contact in a unique form.  Both bodies are symmetric under the
        half-turns about their axes and under inversion, so ``(n, Q2)``, ``(-n, Q2)`` (both arms
        reversed) and ``Q2`` times a half-turn about a body axis all describe the same ``A``; the
        form with ``n`` pointing to ``x >= 0`` (first non-zero component positive) and the
        orientation closest to the identity is returned.
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
        (polar angle and azimuth of ``n``, rotation vector of ``Q2``)."""
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
        """Grid over normals x orientations, then polish the ``seeds`` best of each objective."""
        normals = fibonacci_sphere(n_normals)
        rotations = super_fibonacci_rotations(n_orientations)
        starts = range(0, n_orientations, chunk)
        if progress_label:
            from dtcrit.progress import progress

            starts = progress(list(starts), label=progress_label)
        keep = max(seeds * 8, 16)
        cand = {0: [], 1: []}
        for s in starts:
            Qc = rotations[s:s + chunk]
            nn = np.repeat(normals[None, :, :], Qc.shape[0], axis=0).reshape(-1, 3)
            QQ = np.repeat(Qc[:, None], normals.shape[0], axis=1).reshape(-1, 3, 3)
            r1, r2 = self.place(nn, QQ)
            vals = self.objectives(self.matrices(r1, r2, QQ))
            for which in (0, 1):
                top = np.argsort(-vals[which], kind="stable")[:keep]
                cand[which] += [(float(vals[which][t]), s + t // normals.shape[0], t % normals.shape[0]) for t in top]
        out = {}
        polished = []
        grid_best = {}
        for which in (0, 1):
            ranked = sorted(cand[which], key=lambda c: (-c[0], c[1], c[2]))
            grid_best[which] = ranked[0][0]
            chosen = []
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
            out[which] = best_cfg
        return SearchResult(out[0], out[1], grid_best[0], grid_best[1], n_normals * n_orientations, polished)


# ============================================================================================
# Reference configurations and the overlap measure
# ============================================================================================
def paper_base_orientation(roll: float = 0.0) -> np.ndarray:
    """Particle 2 in Appendix A's 'change centre' scenario: 45 deg about -y, then ``roll`` about its local x.

    Scenario 1 is ``roll = 0``, scenario 2 ``roll = pi/2`` ("a 90 degree rotation of ellipsoid 2
    around its local x axis").
    """
    return quaternion_matrix(PAPER_BASE_QUATERNION) @ rotation_about((1.0, 0.0, 0.0), roll)


def _orientation_with_long_axis(u, roll: float) -> np.ndarray:
    """Long (local x) axis along ``u``, reached from the axis-aligned pose by the smallest rotation,
    after a ``roll`` about the local x axis.  For ``u`` in the x-z plane the local y axis stays on
    global y (roll 0), as in the paper's 'rotation about -y' (scenario 1)."""
    return align_x_to(u) @ rotation_about((1.0, 0.0, 0.0), roll)


def paper_orthogonal(body1, body2, roll: float = 0.0, force=FORCE) -> ContactConfig:
    """The paper's orthogonal tip-to-tip configuration (Fig. 2(A), Eq. (22); Fig. A3(B, D)).

    Contact at the tip ``(a1, 0, 0)`` of particle 1; particle 2's long axis along global z with its
    tip on the contact point, centre at ``(a1, 0, a2)``; ``roll = 0`` is scenario 1 (its local y on
    global y), ``roll = pi/2`` scenario 2.  The outward normals there are +x and -z: not opposite.
    """
    a1 = body1.half_lengths[0]
    a2 = body2.half_lengths[0]
    Q2 = _orientation_with_long_axis((0.0, 0.0, 1.0), roll)
    r1 = np.array([a1, 0.0, 0.0])
    r2 = np.array([0.0, 0.0, -a2])
    A = coefficient_matrix_single(body1, body2, r1, r2, Q2)
    label = "paper orthogonal (Eq. 22), scenario " + ("1" if roll == 0.0 else "2")
    return _config(body1, body2, (1.0, 0.0, 0.0), Q2, r1, r2, A, np.asarray(force, float), label)


def penetration_depth(body1, body2, centre2, Q2, directions: int = 4000) -> float:
    """Depth of overlap of particle 1 (origin, axis aligned) and particle 2 (``centre2``, ``Q2``).

    For convex bodies, ``min over unit d of h1(d) + h2(-d) - d . centre2`` (``h`` the support
    function) is the penetration depth when positive and minus the gap when negative: touching
    bodies give 0.  Minimised over a Fibonacci set of ``d`` and polished by Nelder-Mead.
    """
    c2 = np.asarray(centre2, dtype=float)
    Q2 = np.asarray(Q2, dtype=float)

    def gap(d):
        d = np.atleast_2d(d)
        d = d / np.linalg.norm(d, axis=1, keepdims=True)
        h1 = np.einsum("ni,ni->n", d, body1.support(d))
        dl = -(d @ Q2)  # Q2^T (-d) as rows
        h2 = np.einsum("ni,ni->n", dl, body2.support(dl))
        return h1 + h2 - d @ c2

    D = fibonacci_sphere(directions)
    g = gap(D)
    i = int(np.argmin(g))
    theta, phi = angles_from_unit(D[i])
    res = minimize(lambda p: float(gap(unit_from_angles(p[0], p[1]))[0]), [theta, phi], method="Nelder-Mead",
                   options={"xatol": 1e-12, "fatol": 1e-14})
    return float(min(res.fun, g[i]))


# ============================================================================================
# The paper's two scenarios (families for Figs. A2 and A4)
# ============================================================================================
@dataclass(frozen=True)
class ScenarioSurface:
    """A scenario family on an octant grid: points to draw (``xyz``), |A F| and eigenvalue there."""

    name: str
    roll: float
    xyz: np.ndarray  # (n, n, 3): contact points (Fig. A2) or centres of particle 2 (Fig. A4)
    accel: np.ndarray  # (n, n)
    lam: np.ndarray
    best: ContactConfig  # grid maximum of |A F| (evaluated through dtcrit.bodies.contact)
    reference: ContactConfig | None  # the orthogonal member of the family, if any


def _octant_grid(n: int) -> np.ndarray:
    t = np.linspace(0.0, math.pi / 2, int(n))
    T, P = np.meshgrid(t, t, indexing="ij")
    return unit_from_angles(T, P)  # (n, n, 3): rows theta (from z), columns phi (from x)


def scenario_centre_moved(search: PairSearch, roll: float, n: int = 31) -> ScenarioSurface:
    """Particle 2 keeps ``paper_base_orientation(roll)``; the contact normal sweeps octant I of particle 1."""
    U = _octant_grid(n)
    normals = U.reshape(-1, 3)
    Q2 = np.broadcast_to(paper_base_orientation(roll), (normals.shape[0], 3, 3)).copy()
    r1, r2 = search.place(normals, Q2)
    acc, lam = search.objectives(search.matrices(r1, r2, Q2))
    i = int(np.argmax(acc))
    best = search.config(normals[i], Q2[i], label=f"centre moved, roll {math.degrees(roll):g} deg: grid max",
                         canonical=False)
    return ScenarioSurface("centre moved", roll, r1.reshape(U.shape), acc.reshape(U.shape[:2]),
                           lam.reshape(U.shape[:2]), best, None)


def scenario_orientation_changed(search: PairSearch, roll: float, n: int = 31, pinned_tip: bool = False) -> ScenarioSurface:
    """Contact at the tip ``(a1, 0, 0)``; particle 2's long axis ``u`` sweeps octant I (then ``roll``).

    ``pinned_tip=False``: particle 2 tangent with opposite normal (admissible).  ``pinned_tip=True``:
    the paper's construction, the tip of particle 2 on the contact point (``r2 = -a2 u``).
    Returned ``xyz`` are the centres of particle 2.
    """
    U = _octant_grid(n)
    us = U.reshape(-1, 3)
    Q2 = np.array([_orientation_with_long_axis(u, roll) for u in us])
    normals = np.tile([1.0, 0.0, 0.0], (us.shape[0], 1))
    r1, r2 = search.place(normals, Q2)
    if pinned_tip:
        r2 = -search.body2.half_lengths[0] * us
    acc, lam = search.objectives(search.matrices(r1, r2, Q2))
    centres = r1 - r2
    i = int(np.argmax(acc))
    name = "orientation changed" + (", paper's pinned tip" if pinned_tip else ", tangent")
    label = f"{name}, roll {math.degrees(roll):g} deg"
    j = int(np.argmin(np.linalg.norm(us - np.array([0.0, 0.0, 1.0]), axis=1)))  # u = z: orthogonal
    if pinned_tip:
        best = _config(search.body1, search.body2, normals[i], Q2[i], r1[i], r2[i],
                       coefficient_matrix_single(search.body1, search.body2, r1[i], r2[i], Q2[i]),
                       search.force, label + ": grid max")
        ref = paper_orthogonal(search.body1, search.body2, roll, search.force)
    else:
        best = search.config(normals[i], Q2[i], label=label + ": grid max", canonical=False)
        ref = search.config(normals[j], Q2[j], label=label + ": long axis of 2 along z (tangent)", canonical=False)
    return ScenarioSurface(name, roll, centres.reshape(U.shape), acc.reshape(U.shape[:2]),
                           lam.reshape(U.shape[:2]), best, ref)


# ============================================================================================
# The whole study
# ============================================================================================
def _margin(found: float, ref: float) -> float:
    return found / ref - 1.0


def appendix_a_study(fine: bool = False, show_progress: bool = False, shapes: tuple[str, ...] | None = None) -> dict:
    """Run Appendix A: scenarios, the full admissible search, and the superquadric/box searches.

    Returns a dict with the ContactConfig/ScenarioSurface objects (``objects``) and a JSON-ready
    ``summary``.
    """
    from dtcrit.bodies.contact import a_bound, a_max

    n_normals, n_orient, seeds, n_side = GRIDS["fine" if fine else "coarse"]
    bodies = comparison_shapes(1.0)
    names = shapes if shapes is not None else tuple(bodies)
    ell = bodies["ellipsoid"]
    search = PairSearch(ell, ell)
    F = search.force
    fnorm = float(np.linalg.norm(F))

    orth = [paper_orthogonal(ell, ell, roll) for roll in (0.0, math.pi / 2)]
    orth_depth = [penetration_depth(ell, ell, o.centre2, np.array(o.orientation)) for o in orth]
    scenarios = {
        "centre_moved": [scenario_centre_moved(search, r, n_side) for r in (0.0, math.pi / 2)],
        "orientation_tangent": [scenario_orientation_changed(search, r, n_side) for r in (0.0, math.pi / 2)],
        "orientation_pinned_tip": [scenario_orientation_changed(search, r, n_side, pinned_tip=True)
                                   for r in (0.0, math.pi / 2)],
    }
    results = {}
    for name in names:
        body = bodies[name]
        s = search if name == "ellipsoid" else PairSearch(body, body)
        res = s.search(n_normals, n_orient, seeds, progress_label=f"appendix A {name}" if show_progress else None)
        amax = float(a_max(body, body))
        abound = float(a_bound(body, body))
        depth_acc = penetration_depth(body, body, res.best_accel.centre2, np.array(res.best_accel.orientation))
        depth_lam = penetration_depth(body, body, res.best_lam.centre2, np.array(res.best_lam.orientation))
        results[name] = {
            "result": res,
            "summary": {
                "shape": repr(body),
                "mass": body.mass,
                "max_arm": body.max_arm,
                "a_max_eq26": amax,
                "a_bound": abound,
                "max_accel": res.best_accel.accel,
                "max_accel_grid": res.grid_accel,
                "accel_bound_eq26": amax * fnorm,
                "max_lambda": res.best_lam.lam,
                "max_lambda_grid": res.grid_lam,
                "eq26_is_upper_bound_lambda": bool(res.best_lam.lam <= amax * (1 + 1e-12)),
                "eq26_is_upper_bound_accel": bool(res.best_accel.accel <= amax * fnorm * (1 + 1e-12)),
                "lambda_over_eq26": res.best_lam.lam / amax,
                "lambda_over_a_bound": res.best_lam.lam / abound,
                "a_bound_holds": bool(res.best_lam.lam <= abound * (1 + 1e-9)),
                "max_accel_config": res.best_accel.describe(),
                "max_lambda_config": res.best_lam.describe(),
                "penetration_of_maximisers": [depth_acc, depth_lam],
                "contacts_evaluated": res.evaluated,
            },
        }
    ell_res = results.get("ellipsoid")
    orth_best = max(orth, key=lambda o: o.accel)
    summary = {
        "setting": "two a=3, b=2, c=1 m ellipsoids, unit density, F = (1, 1, 1) N, zero angular velocity",
        "grid": "fine" if fine else "coarse",
        "orthogonal": orth_best.accel,
        "orthogonal_config": orth_best.describe(),
        "orthogonal_lambda": orth_best.lam,
        "orthogonal_scenarios": {o.label: {"accel": o.accel, "lambda_max": o.lam} for o in orth},
        "orthogonal_penetration_depth": orth_depth,
        "orthogonal_is_admissible": bool(max(orth_depth) <= 1e-9),
    }
    if ell_res is not None:
        res = ell_res["result"]
        summary.update({
            "max_found": res.best_accel.accel,
            "max_config": res.best_accel.describe(),
            "orthogonal_is_max": bool(orth_best.accel >= res.best_accel.accel * (1 - 1e-9)),
            "margin": _margin(res.best_accel.accel, orth_best.accel),
            "max_lambda_found": res.best_lam.lam,
            "max_lambda_config": res.best_lam.describe(),
            "lambda_margin_over_orthogonal": _margin(res.best_lam.lam, orth_best.lam),
            "a_max_eq26": ell_res["summary"]["a_max_eq26"],
            "a_bound": ell_res["summary"]["a_bound"],
            "accel_bound_eq26": ell_res["summary"]["accel_bound_eq26"],
        })
    summary["scenarios"] = {
        key: [{"roll_deg": math.degrees(s.roll), "grid_max": s.best.describe(),
               "orthogonal_member": (s.reference.describe() if s.reference else None)} for s in fams]
        for key, fams in scenarios.items()
    }
    summary["shapes"] = {name: r["summary"] for name, r in results.items()}
    return {
        "summary": summary,
        "objects": {"orthogonal": orth, "scenarios": scenarios, "results": {k: v["result"] for k, v in results.items()}},
    }
