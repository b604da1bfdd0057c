"""Figure 6: translation- and rotation-dominant critical steps against ellipsoid aspect ratios.

Peng et al. 2020, Section 6.4: two identical ellipsoids of fixed volume ``V = 4/3 pi a b c = 8 pi``
m^3, density 1000 kg/m^3, ``k_n = k_s = 1e10`` N/m, no damping, ``omega_max = 1`` rad/s, aspect ratios
``e1 = a/b`` and ``e2 = b/c`` in [1, 5].  Hence ``c = (3V/(4 pi e1 e2^2))^(1/3)``, ``b = e2 c``,
``a = e1 b``.

* translation-dominant step, printed: Eq. (48), ``2/sqrt(k_n A_max)`` with Eq. (26)'s ``A_max``;
* translation-dominant step, verified: the undamped critical step of the scene integrator
  (velocity Verlet, ``omega dt = 2``) with the verified bound ``dtcrit.bodies.contact.a_bound``;
* rotation-dominant step: Eq. (56) ``2/(omega_max (B_max1 + B_max2))``, which for identical
  particles is Eq. (57) ``1/(omega_max B_max)`` with Eq. (54)'s ``B_max`` (``dtcrit.bodies.contact.b_max``).
  A sphere (e1 = e2 = 1) has ``B_max = 0``: no rotation-dominant limit (``inf``).

The paper states that the translation-dominant step is "more than four orders of magnitude
smaller" than the rotation-dominant one; :func:`four_orders_region` measures where that holds.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from dtcrit.figures._output import critical_steps, pyplot, save_figure, write_csv

__all__ = [
    "VOLUME",
    "DENSITY",
    "STIFFNESS",
    "OMEGA_MAX",
    "E_RANGE",
    "CLAIM_RATIO",
    "SCENE_INTEGRATOR",
    "ellipsoid_axes",
    "rotation_dominant_dt",
    "AspectRatioData",
    "fig6_data",
    "ratio_at",
    "four_orders_region",
    "write_fig6",
]

VOLUME = 8.0 * math.pi
DENSITY = 1000.0
STIFFNESS = 1e10
OMEGA_MAX = 1.0
E_RANGE = (1.0, 5.0)
CLAIM_RATIO = 1e4
"""'More than four orders of magnitude' (Section 6.4)."""
SCENE_INTEGRATOR = "velocity-verlet"
B_ZERO = 1e-13
"""B_max below this (rounding of equal moments) is taken as exactly zero: a sphere."""


def ellipsoid_axes(e1, e2, volume: float = VOLUME):
    """Semi-axes ``(a, b, c)`` with ``a/b = e1``, ``b/c = e2`` and ``4/3 pi a b c = volume``.

    Parameters
    ----------
    e1, e2 : array_like
        Aspect ratios ``a/b`` and ``b/c``.
    volume : float
        Volume [m^3].

    Returns
    -------
    tuple of numpy.ndarray
        ``(a, b, c)`` [m].
    """
    e1 = np.asarray(e1, dtype=float)
    e2 = np.asarray(e2, dtype=float)
    c = np.cbrt(3.0 * volume / (4.0 * math.pi) / (e1 * e2 * e2))
    b = e2 * c
    return e1 * b, b, c


def rotation_dominant_dt(b_max_1: float, b_max_2: float, omega_max: float = OMEGA_MAX) -> float:
    """Peng et al. 2020, Eq. (56): ``2/(omega_max (B_max1 + B_max2))`` (Eq. (57) when equal); inf if both are 0.

    Parameters
    ----------
    b_max_1, b_max_2 : float
        Eq. (54) of each particle.
    omega_max : float
        Largest angular speed [rad/s].

    Returns
    -------
    float
        The step [s].
    """
    total = b_max_1 + b_max_2
    return math.inf if total <= 0.0 else 2.0 / (omega_max * total)


def _body(e1: float, e2: float):
    from dtcrit.bodies import Ellipsoid

    a, b, c = (float(v) for v in ellipsoid_axes(e1, e2))
    return Ellipsoid(a, b, c, density=DENSITY)


def _printed_point(e1: float, e2: float) -> tuple[float, float]:
    """``(A_max of Eq. (26), B_max of Eq. (54))`` for two identical ellipsoids at (e1, e2)."""
    from dtcrit.bodies.contact import a_max, b_max

    body = _body(e1, e2)
    bm = float(b_max(body))
    return float(a_max(body, body)), (0.0 if bm < B_ZERO else bm)


def _a_bound_point(e1: float, e2: float) -> float:
    from dtcrit.bodies.contact import a_bound

    body = _body(e1, e2)
    return float(a_bound(body, body))


def ratio_at(e1: float, e2: float, *, verified: bool = False) -> float:
    """rotation-dominant / translation-dominant step at one (e1, e2); ``verified`` uses a_bound.

    Parameters
    ----------
    e1, e2 : float
        Aspect ratios.
    verified : bool
        Use ``a_bound`` instead of Eq. (26).

    Returns
    -------
    float
        The ratio.
    """
    amax, bm = _printed_point(e1, e2)
    A = _a_bound_point(e1, e2) if verified else amax
    trans = float(critical_steps(SCENE_INTEGRATOR, STIFFNESS, 0.0, A))
    return rotation_dominant_dt(bm, bm) / trans


@dataclass(frozen=True)
class AspectRatioData:
    """Figure 6 on the grid ``e1 x e2`` (arrays indexed ``[i_e1, i_e2]``); steps in seconds.

    Every quantity, the verified one included, is evaluated at every grid point (``a_bound`` of an
    ellipsoid is a closed form, :func:`dtcrit.bodies.contact.a_bound`).

    Parameters
    ----------
    e1, e2 : numpy.ndarray
        The grid's aspect ratios.
    a_max : numpy.ndarray
        Eq. (26) [1/kg].
    b_max : numpy.ndarray
        Eq. (54).
    translation_printed : numpy.ndarray
        Eq. (48) with A_max [s].
    rotation : numpy.ndarray
        Eq. (56)/(57) [s].
    a_bound : numpy.ndarray
        Verified bound [1/kg].
    translation_verified : numpy.ndarray
        Velocity Verlet, undamped, ``A = a_bound`` [s].
    """

    e1: np.ndarray
    e2: np.ndarray
    a_max: np.ndarray
    b_max: np.ndarray
    translation_printed: np.ndarray  # Eq. (48) with A_max
    rotation: np.ndarray  # Eq. (56)/(57)
    a_bound: np.ndarray  # verified bound [1/kg]
    translation_verified: np.ndarray  # velocity Verlet, undamped, A = a_bound

    @property
    def ratio_printed(self) -> np.ndarray:
        """Rotation-dominant over translation-dominant step with Eq. (26)'s ``A_max``."""
        return self.rotation / self.translation_printed

    @property
    def ratio_verified(self) -> np.ndarray:
        """Rotation-dominant over translation-dominant step with the verified ``a_bound``."""
        return self.rotation / self.translation_verified

    def fall_from_sphere(self, verified: bool) -> float:
        """Fraction by which the translation-dominant step falls from the sphere (1, 1) to (5, 5).

        Parameters
        ----------
        verified : bool
            Use the verified step instead of the printed one.

        Returns
        -------
        float
            The fraction.
        """
        t = self.translation_verified if verified else self.translation_printed
        return float(1.0 - t[-1, -1] / t[0, 0])

    def ratio_stats(self, verified: bool = False) -> dict:
        """Smallest and largest ratio over the grid, and how many points exceed 1e4.

        Parameters
        ----------
        verified : bool
            Use the verified ratio instead of the printed one.

        Returns
        -------
        dict
            JSON-ready statistics.
        """
        r = self.ratio_verified if verified else self.ratio_printed
        finite = r[np.isfinite(r)]
        return {
            "min_ratio": float(np.min(r)),
            "max_ratio": float(np.max(r)),
            "max_finite_ratio": float(np.max(finite)) if finite.size else None,
            "fraction_over_1e4": float(np.count_nonzero(r > CLAIM_RATIO) / r.size),
            "points_over_1e4": int(np.count_nonzero(r > CLAIM_RATIO)),
            "points": int(r.size),
        }


_CACHE: dict[int, AspectRatioData] = {}


def fig6_data(n: int = 41, progress_label: str | None = None) -> AspectRatioData:
    """Evaluate Figure 6 on an ``n x n`` grid of (e1, e2) in [1, 5]^2 (both ends included).

    The grid of one size is computed once per process and reused (the summary and the image share it).

    Parameters
    ----------
    n : int
        Grid points per axis.
    progress_label : str, optional
        Label of a progress bar (none when omitted).

    Returns
    -------
    AspectRatioData
        The grid's quantities.
    """
    key = int(n)
    if key not in _CACHE:
        _CACHE[key] = _fig6_grid(key, progress_label)
    return _CACHE[key]


def _fig6_grid(n: int, progress_label: str | None) -> AspectRatioData:
    e = np.linspace(*E_RANGE, int(n))
    amax = np.empty((e.size, e.size))
    bmax = np.empty_like(amax)
    for i in range(e.size):
        for j in range(e.size):
            amax[i, j], bmax[i, j] = _printed_point(e[i], e[j])
    trans_p = 2.0 / np.sqrt(STIFFNESS * amax)  # Eq. (48)
    with np.errstate(divide="ignore"):
        rot = np.where(bmax > 0, 2.0 / (OMEGA_MAX * 2.0 * np.where(bmax > 0, bmax, 1.0)), np.inf)
    pts = [(i, j) for i in range(e.size) for j in range(e.size)]
    if progress_label:
        from tqdm import tqdm

        pts = tqdm(pts, total=len(pts), desc=progress_label, disable=None)
    abnd = np.empty_like(amax)
    for i, j in pts:
        abnd[i, j] = _a_bound_point(e[i], e[j])
    trans_v = critical_steps(SCENE_INTEGRATOR, STIFFNESS, 0.0, abnd)
    return AspectRatioData(e, e.copy(), amax, bmax, trans_p, rot, abnd, trans_v)


def four_orders_region(verified: bool = False, directions: int = 19) -> dict:
    """Where the ratio exceeds 1e4, measured along rays from the sphere point (1, 1).

    Along each ray ``(1 + t cos phi, 1 + t sin phi)``, phi in [0, pi/2], the ratio falls from
    infinity (t = 0); the crossing ``t*`` with ratio = 1e4 is found by Brent's method.  Returns the
    smallest and largest ``t*`` and whether the ratio stays below 1e4 on the rest of the ray
    (checked at 40 points out to the edge of [1, 5]^2).

    Parameters
    ----------
    verified : bool
        Use the verified ratio.
    directions : int
        Number of rays.

    Returns
    -------
    dict
        The crossing distances and the check.
    """
    crossings = []
    beyond_ok = True
    for phi in np.linspace(0.0, math.pi / 2, int(directions)):
        cphi, sphi = math.cos(phi), math.sin(phi)
        t_edge = (E_RANGE[1] - 1.0) / max(cphi, sphi)

        def g(t):
            return math.log(ratio_at(1 + t * cphi, 1 + t * sphi, verified=verified) / CLAIM_RATIO)

        lo, hi = 1e-6, 1e-3
        while g(hi) > 0 and hi < t_edge:
            lo, hi = hi, min(2 * hi, t_edge)
        if g(hi) > 0:
            crossings.append(math.inf)
            continue
        t_star = brentq(g, lo, hi, xtol=1e-12, rtol=1e-10)
        crossings.append(t_star)
        ts = np.linspace(t_star, t_edge, 41)[1:]
        beyond_ok &= all(g(t) < 0 for t in ts)
    return {"t_min": float(min(crossings)), "t_max": float(max(crossings)), "monotone_beyond": bool(beyond_ok)}


def _csv_rows(d: AspectRatioData):
    for i, e1 in enumerate(d.e1):
        for j, e2 in enumerate(d.e2):
            a, b, c = (float(v) for v in ellipsoid_axes(e1, e2))
            yield [e1, e2, a, b, c, d.a_max[i, j], d.b_max[i, j], d.translation_printed[i, j], d.rotation[i, j],
                   d.ratio_printed[i, j], d.a_bound[i, j], d.translation_verified[i, j], d.ratio_verified[i, j]]


def plot_fig6(d: AspectRatioData, path: Path) -> Path:
    """Four panels on the full grid: the translation-dominant step with Eq. (26)'s ``A_max`` (Eq. (48)) and
    with the verified ``a_bound`` on one colour scale (so their fall with aspect ratio compares directly),
    the rotation-dominant step (Eq. (57)) and the ratio of Eq. (57) to Eq. (48).

    Parameters
    ----------
    d : AspectRatioData
        The grid's quantities.
    path : pathlib.Path
        File to write.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    plt = pyplot()
    from matplotlib.colors import LogNorm, Normalize

    E1, E2 = np.meshgrid(d.e1, d.e2, indexing="ij")
    fig, axes = plt.subplots(2, 2, figsize=(11, 9))
    trans_ms = (d.translation_printed * 1e3, d.translation_verified * 1e3)
    shared = Normalize(vmin=float(min(np.min(t) for t in trans_ms)), vmax=float(max(np.max(t) for t in trans_ms)))
    fall_p, fall_v = 100 * d.fall_from_sphere(False), 100 * d.fall_from_sphere(True)
    panels = [
        (axes[0, 0], trans_ms[0], "translation-dominant, Eq. (48) with Eq. (26) A_max [ms]\n"
         f"falls {fall_p:.1f} % from the sphere (1, 1) to (5, 5)", "viridis", shared),
        (axes[0, 1], trans_ms[1], f"translation-dominant, verified ({SCENE_INTEGRATOR}, A = a_bound) [ms]\n"
         f"falls {fall_v:.1f} % from the sphere (1, 1) to (5, 5)", "viridis", shared),
        (axes[1, 0], np.where(np.isfinite(d.rotation), d.rotation, np.nan),
         "rotation-dominant, Eq. (57), omega_max = 1 rad/s [s]\n(unbounded at the sphere e1 = e2 = 1)", "magma", "log"),
        (axes[1, 1], np.where(np.isfinite(d.ratio_printed), d.ratio_printed, np.nan),
         "ratio rotation / translation (Eq. 57 / Eq. 48)", "cividis", "log"),
    ]
    for ax, z, title, cmap, norm in panels:
        lo, hi = float(np.nanmin(z)), float(np.nanmax(z))
        log = norm == "log"
        if log:
            norm = LogNorm(vmin=lo, vmax=hi)
        mesh = ax.pcolormesh(E1, E2, z, shading="nearest", cmap=cmap, norm=norm)
        levels = np.geomspace(lo, hi, 8)[1:-1] if log else np.linspace(lo, hi, 7)[1:-1]
        cs = ax.contour(E1, E2, z, levels=levels, colors="w", linewidths=0.6)
        ax.clabel(cs, fontsize=7, fmt="%.3g")
        fig.colorbar(mesh, ax=ax)
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("e1 = a/b")
        ax.set_ylabel("e2 = b/c")
    ax = axes[1, 1]
    r = d.ratio_printed
    over = r > CLAIM_RATIO
    if np.any(over):
        ax.scatter(E1[over], E2[over], s=14, c="r", marker="x", label="ratio > 1e4")
    ax.plot([1.5], [2.0], "w*", ms=10, label="a=3, b=2, c=1 (ratio %.3g)" % r[
        int(np.argmin(np.abs(d.e1 - 1.5))), int(np.argmin(np.abs(d.e2 - 2.0)))])
    ax.legend(fontsize=7.5, loc="upper right")
    stats = d.ratio_stats()
    fig.suptitle(
        "Fig. 6: ellipsoids of volume 8 pi m^3, rho = 1000 kg/m^3, k_n = 1e10 N/m, no damping -- "
        f"ratio > 1e4 on {stats['points_over_1e4']} of {stats['points']} grid points",
        fontsize=10,
    )
    fig.tight_layout()
    return save_figure(fig, path)


def write_fig6(out: Path, *, fine: bool = False, show_progress: bool = True) -> list[Path]:
    """Write ``fig6_aspect_ratio.png`` and ``fig6_aspect_ratio.csv`` into ``out``.

    Parameters
    ----------
    out : pathlib.Path
        Folder to write into.
    fine : bool
        Use the fine grid.
    show_progress : bool
        Show a progress bar.

    Returns
    -------
    list of pathlib.Path
        The PNG and CSV.
    """
    d = fig6_data(161 if fine else 41, progress_label="fig6 a_bound" if show_progress else None)
    header = ["e1", "e2", "a", "b", "c", "A_max_eq26", "B_max_eq54", "dt_translation_eq48", "dt_rotation_eq57",
              "ratio_eq57_over_eq48", "A_bound", "dt_translation_verified", "ratio_eq57_over_verified"]
    csv_path = write_csv(Path(out) / "fig6_aspect_ratio.csv", header, _csv_rows(d))
    return [plot_fig6(d, Path(out) / "fig6_aspect_ratio.png"), csv_path]
