"""Clumps (multi-sphere bodies): a rigid union of overlapping or touching spheres ``[[x, y, z, r], ...]``.

Mass, centre and inertia of the union with overlaps counted once come from
:mod:`dtcrit.bodies.clump_mass`.  The body is stored in its principal frame (origin at the centre of
mass, axes the principal axes with ``I_xx <= I_yy <= I_zz``); ``spheres`` are the members in that
frame, ``frame_rotation`` maps it to the frame the spheres were given in (``x_given = Q x + centre``).

Contacts sit at member surfaces, with arms measured from the clump's centre.  A clump is neither
convex nor centrally symmetric, so the paper's assumption 3 does not apply and is not checked; the
arm supremum used for ``A_bound`` is the generic one:

**Bound.**  For any rigid body and any contact point ``p`` (from the centre of mass, principal frame),
``lambda_max([p]x^T I^-1 [p]x) = max_(|v| = 1) |I^-1/2 (p x v)|^2 <= |p|^2 max |v|^2 / I_min = |p|^2/I_min``
since ``|p x v| <= |p| |v|``.  Every admissible contact point lies on a member surface, at distance at
most ``r_max = max_k (|c_k| + r_k)`` from the centre, so ``S <= r_max^2 / I_min`` and
``A <= 1/m_1 + 1/m_2 + S_1 + S_2``.  The value attained at sampled exposed surface points is
reported as the lower end (``ArmSupremum.lower``).
"""
from __future__ import annotations

import numpy as np

from dtcrit.bodies.arm_terms import ArmSupremum, arm_lambda, fibonacci_sphere
from dtcrit.bodies.base import _Shape
from dtcrit.bodies.checks import _count, _vec3
from dtcrit.bodies.clump_mass import union_mass_properties
from dtcrit.errors import InputError

MAX_SPHERES = 10_000
BOUND_SAMPLES = 2000


def _members(spheres) -> np.ndarray:
    try:
        arr = np.asarray(spheres, dtype=float)
    except (TypeError, ValueError):
        raise InputError("spheres", "must be an array of [x, y, z, r] rows") from None
    if arr.ndim != 2 or arr.shape[1] != 4 or len(arr) == 0:
        raise InputError("spheres", "a clump needs at least one sphere, each [x, y, z, r]")
    if len(arr) > MAX_SPHERES:
        raise InputError("spheres", f"{len(arr)} spheres: at most {MAX_SPHERES}")
    if not np.all(np.isfinite(arr)):
        raise InputError("spheres", "coordinates and radii must be finite")
    bad = np.flatnonzero(arr[:, 3] <= 0)
    if bad.size:
        raise InputError(f"spheres[{bad[0] + 1}]", f"radius {arr[bad[0], 3]:g} must be positive")
    return arr


def _connected(centres: np.ndarray, radii: np.ndarray) -> bool:
    """Whether the members touch or overlap as one piece (a graph search over touching pairs)."""
    n = len(radii)
    d = np.linalg.norm(centres[:, None] - centres[None], axis=-1)
    touch = d <= (radii[:, None] + radii[None]) * (1.0 + 1e-12)
    seen, stack = {0}, [0]
    while stack:
        i = stack.pop()
        for j in np.flatnonzero(touch[i]):
            if int(j) not in seen:
                seen.add(int(j))
                stack.append(int(j))
    return len(seen) == n


class Clump(_Shape):
    """A rigid union of spheres ``[[x, y, z, r], ...]`` with uniform ``density`` (or total ``mass``).

    Parameters
    ----------
    spheres : array_like
        Rows ``(x, y, z, r)`` of the member spheres [m]; the union must be connected.
    density : float, optional
        Density [kg/m^3] (give exactly one of ``density`` and ``mass``).
    mass : float, optional
        Total mass [kg]; overlaps are counted once.
    """

    kind = "clump"
    __slots__ = ("_spheres", "_given_centre", "_rotation", "_mass_method", "_quadrature_error")

    def __init__(self, spheres, density: float | None = None, mass: float | None = None):
        arr = _members(spheres)
        centres, radii = arr[:, :3], arr[:, 3]
        if not _connected(centres, radii):
            raise InputError("spheres", "the spheres do not touch as one piece: a clump is one rigid body")
        props = union_mass_properties(centres, radii)
        moments, axes = np.linalg.eigh(props.inertia_tensor(1.0))
        if np.linalg.det(axes) < 0:
            axes[:, 0] = -axes[:, 0]
        local = (centres - props.centre) @ axes
        self._spheres = np.column_stack([local, radii])
        self._spheres.setflags(write=False)
        self._given_centre = _vec3(props.centre)
        self._rotation = axes
        self._mass_method = props.method
        self._quadrature_error = props.quadrature_error
        half = np.max(np.abs(local) + radii[:, None], axis=0)
        arm = float(np.max(np.linalg.norm(local, axis=1) + radii))
        self._finish(props.volume, density, mass, moments / props.volume, half, arm, "spheres")
        object.__setattr__(self, "_issues", ())  # the paper's assumption 3 is not used for clumps (module docstring)

    def _label(self) -> str:
        return f"Clump({len(self._spheres)} spheres)"

    @property
    def spheres(self) -> np.ndarray:
        """Members ``(N, 4)``: centre in the principal frame and radius [m]."""
        return self._spheres.copy()

    @property
    def centre_of_mass(self) -> tuple[float, float, float]:
        """The centre of mass in the frame the spheres were given in [m]."""
        return self._given_centre

    @property
    def frame_rotation(self) -> np.ndarray:
        """Columns: the principal axes in the frame the spheres were given in."""
        return self._rotation.copy()

    @property
    def inertia_tensor_given(self) -> np.ndarray:
        """The inertia tensor about the centre of mass in the frame the spheres were given in [kg m^2]."""
        return self._rotation @ np.diag(self.inertia) @ self._rotation.T

    @property
    def mass_method(self) -> str:
        """How the union's mass properties were computed: ``"closed form"`` or ``"quadrature"``."""
        return self._mass_method

    @property
    def quadrature_error(self) -> float:
        """Relative change of the quadrature from half resolution (0 for the closed form)."""
        return self._quadrature_error

    def _sample(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """Fibonacci points on every member, those inside another member dropped (exposed surface)."""
        per = max(8, n // len(self._spheres))
        u = fibonacci_sphere(per)
        pts, nrm = [], []
        c, r = self._spheres[:, :3], self._spheres[:, 3]
        for k in range(len(r)):
            p = c[k] + r[k] * u
            d = np.linalg.norm(p[:, None, :] - c[None, :, :], axis=-1)
            inside = np.any((d < r[None, :] * (1.0 - 1e-12)) & (np.arange(len(r)) != k)[None, :], axis=1)
            pts.append(p[~inside])
            nrm.append(u[~inside])
        return np.concatenate(pts), np.concatenate(nrm)

    def support(self, direction) -> np.ndarray:
        """The member surface point farthest along ``direction``: ``c_k + r_k d`` with the largest ``c_k . d + r_k``.

        Parameters
        ----------
        direction : array_like
            A direction (normalised here), local frame.

        Returns
        -------
        numpy.ndarray
            The support point [m].
        """
        d = np.asarray(direction, dtype=float)
        single = d.ndim == 1
        d = np.atleast_2d(d)
        d = d / np.linalg.norm(d, axis=1, keepdims=True)
        c, r = self._spheres[:, :3], self._spheres[:, 3]
        k = np.argmax(d @ c.T + r[None, :], axis=1)
        out = c[k] + r[k, None] * d
        return out[0] if single else out

    def arm_term_bound(self) -> ArmSupremum:
        """``S <= r_max^2 / I_min`` (module docstring), with the value attained at sampled exposed points.

        Returns
        -------
        ArmSupremum
            The crude upper bound and the best sampled lower bound [1/kg].
        """
        upper = self.max_arm**2 / min(self.inertia)
        pts, nrm = self.surface_points(_count(BOUND_SAMPLES))
        lam = arm_lambda(pts, self.inertia)
        i = int(np.argmax(lam))
        lower = min(float(lam[i]), upper)
        return ArmSupremum(upper, lower, _vec3(pts[i]), _vec3(nrm[i]),
                           "clump: r_max^2 / I_min (valid for any rigid body)")


def describe_clump(clump: Clump) -> str:
    """One line for the text report: the number of spheres and how the mass was computed.

    Parameters
    ----------
    clump : Clump
        The clump.

    Returns
    -------
    str
        The description.
    """
    return f"{len(clump.spheres)} spheres, mass by {clump.mass_method}" + (
        "" if clump.quadrature_error == 0 else f" (relative error about {clump.quadrature_error:.1g})")


__all__ = ["Clump", "describe_clump"]
