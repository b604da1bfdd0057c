"""Peng et al. 2020, Appendix A, reproduced: which contact maximises the relative acceleration.

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
from typing import Any
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize

from dtcrit.figures._rotations import (
    align_x_to,
    angles_from_unit,
    fibonacci_sphere,
    quaternion_matrix,
    rotation_about,
    unit_from_angles,
)
from dtcrit.figures.appendix_a_contacts import ContactConfig, _config
from dtcrit.figures.appendix_a_search import (
    FORCE,
    GRIDS,
    PAPER_BASE_QUATERNION,
    PairSearch,
    coefficient_matrix_single,
    comparison_shapes,
)


# ============================================================================================
# Reference configurations and the overlap measure
# ============================================================================================
def paper_base_orientation(roll: float = 0.0) -> np.ndarray:
    """Particle 2 in Appendix A's 'change centre' scenario: 45 deg about -y, then ``roll`` about its local x.

    Scenario 1 is ``roll = 0``, scenario 2 ``roll = pi/2`` ("a 90 degree rotation of ellipsoid 2
    around its local x axis").

    Parameters
    ----------
    roll : float
        Rotation about particle 2's local x axis [rad].

    Returns
    -------
    numpy.ndarray
        Particle 2's body-to-world matrix.
    """
    return quaternion_matrix(PAPER_BASE_QUATERNION) @ rotation_about((1.0, 0.0, 0.0), roll)


def _orientation_with_long_axis(u, roll: float) -> np.ndarray:
    """Long (local x) axis along ``u``, reached from the axis-aligned pose by the smallest rotation,
    after a ``roll`` about the local x axis.  For ``u`` in the x-z plane the local y axis stays on
    global y (roll 0), as in the paper's 'rotation about -y' (scenario 1).
    """
    return align_x_to(u) @ rotation_about((1.0, 0.0, 0.0), roll)


def paper_orthogonal(body1, body2, roll: float = 0.0, force=FORCE) -> ContactConfig:
    """The paper's orthogonal tip-to-tip configuration (Fig. 2(A), Eq. (22); Fig. A3(B, D)).

    Contact at the tip ``(a1, 0, 0)`` of particle 1; particle 2's long axis along global z with its
    tip on the contact point, centre at ``(a1, 0, a2)``; ``roll = 0`` is scenario 1 (its local y on
    global y), ``roll = pi/2`` scenario 2.  The outward normals there are +x and -z: not opposite.

    Parameters
    ----------
    body1, body2 : object
        The two ellipsoids.
    roll : float
        Rotation of particle 2 about its long axis [rad].
    force : array_like
        The applied contact force [N].

    Returns
    -------
    ContactConfig
        The configuration with its coefficient matrix, ``|A F|`` and largest eigenvalue.
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

    Parameters
    ----------
    body1, body2 : object
        The two convex bodies.
    centre2 : array_like
        Centre of particle 2 [m].
    Q2 : array_like
        Orientation of particle 2, body to world.
    directions : int
        Number of Fibonacci directions searched before polishing.

    Returns
    -------
    float
        Penetration depth [m] (negative: the gap).
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
    """A scenario family on an octant grid: points to draw (``xyz``), |A F| and eigenvalue there.

    Parameters
    ----------
    name : str
        Name of the scenario family.
    roll : float
        Roll of particle 2 [rad].
    xyz : numpy.ndarray
        (n, n, 3) contact points (Fig. A2) or centres of particle 2 (Fig. A4) [m].
    accel : numpy.ndarray
        ``|A F|`` on the grid [m/s^2].
    lam : numpy.ndarray
        Largest eigenvalue of ``A`` on the grid [1/kg].
    best : ContactConfig
        Grid maximum of ``|A F|``.
    reference : ContactConfig or None
        The orthogonal member of the family, if any.
    """

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
    """Particle 2 keeps ``paper_base_orientation(roll)``; the contact normal sweeps octant I of particle 1.

    Parameters
    ----------
    search : PairSearch
        The pair of bodies.
    roll : float
        Roll of particle 2 [rad].
    n : int
        Grid points per side of the octant.

    Returns
    -------
    ScenarioSurface
        The scenario on the grid.
    """
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

    Parameters
    ----------
    search : PairSearch
        The pair of bodies.
    roll : float
        Roll of particle 2 [rad].
    n : int
        Grid points per side of the octant.
    pinned_tip : bool
        The paper's construction (tip on the contact point) instead of the admissible tangent contact.

    Returns
    -------
    ScenarioSurface
        The scenario on the grid.
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

    Parameters
    ----------
    fine : bool
        Use the fine grids.
    show_progress : bool
        Show progress bars.
    shapes : tuple of str, optional
        Shapes to search (``comparison_shapes`` keys); all when omitted.

    Returns
    -------
    dict
        ``objects`` and ``summary``.
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
    results: dict[str, Any] = {}
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
