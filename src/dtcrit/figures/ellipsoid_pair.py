"""The Section 6 scene shared by Figures 4 and 5: two identical a=3, b=2, c=1 m ellipsoids.

Peng et al. 2020, Sections 6.2-6.3: ``k_n = k_s``, damping ``c_n = c_s = N sqrt(k_n / A_max)`` with
``N = 0..5`` and ``A_max`` from Eq. (26).  With ``A = A_max`` the damping ratio is exactly
``zeta = c A / (2 sqrt(k A)) = N / 2``.

For every point this module evaluates

* the printed Eq. (46) with Eq. (26)'s ``A_max`` (what the paper plots),
* the verified critical step of each integrator (``dtcrit.integrators.stability.critical_dt_array``) with
  Eq. (26)'s ``A_max`` and with the verified bound ``dtcrit.bodies.contact.a_bound`` on the largest
  eigenvalue of the contact coefficient matrix.  The physical damping ``c`` is the paper's (defined
  with ``A_max``) in both cases.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from dtcrit.integrators.schemes import NAMES
from dtcrit.integrators.stability import paper_eq46

from dtcrit.figures._output import critical_steps, pyplot, save_figure, write_csv

__all__ = [
    "PAPER_AXES",
    "N_VALUES",
    "SCENE_INTEGRATORS",
    "REFERENCE_DENSITY",
    "PairSteps",
    "pair_coefficients",
    "pair_steps",
    "plot_pair_steps",
    "write_pair_csv",
    "describe_trend",
]

PAPER_AXES = (3.0, 2.0, 1.0)
"""Semi-axes a, b, c [m] of the paper's ellipsoids (Section 3, Figure 2; Section 6)."""
N_VALUES = (0, 1, 2, 3, 4, 5)
"""The paper's damping numbers N (Section 6.2)."""
SCENE_INTEGRATORS = ("velocity-verlet", "leapfrog-centred")
"""Integrators whose verified bounds are drawn (all seven are written to the CSV)."""


REFERENCE_DENSITY = 1000.0
"""Density at which ``a_bound`` is computed; other densities scale it exactly by rho_ref/rho."""


def _body(density: float, axes: tuple[float, float, float]):
    from dtcrit.bodies import Ellipsoid

    return Ellipsoid(*axes, density=float(density))


@lru_cache(maxsize=None)
def _a_bound(density: float, axes: tuple[float, float, float]) -> float:
    from dtcrit.bodies.contact import a_bound

    body = _body(density, axes)
    return float(a_bound(body, body))


def pair_coefficients(density: float, axes: tuple[float, float, float] = PAPER_AXES) -> tuple[float, float]:
    """``(A_max of Eq. (26), verified a_bound)`` [1/kg] for two identical ellipsoids of ``density``.

    ``A_max`` is evaluated at ``density``.  ``a_bound`` is evaluated
    once at ``REFERENCE_DENSITY`` and scaled by ``REFERENCE_DENSITY / density``: mass and inertia are
    both proportional to the density, so every term of the coefficient matrix scales as 1/rho
    exactly (checked against direct evaluations in tests/figures/test_figures_sections.py).

    Parameters
    ----------
    density : float
        Density [kg/m^3].
    axes : tuple of float
        Semi-axes [m].

    Returns
    -------
    tuple of float
        ``(A_max, a_bound)`` [1/kg].
    """
    from dtcrit.bodies.contact import a_max

    a1, a2, a3 = (float(a) for a in axes)
    axes = (a1, a2, a3)
    body = _body(density, axes)
    return float(a_max(body, body)), _a_bound(REFERENCE_DENSITY, axes) * (REFERENCE_DENSITY / float(density))


@dataclass(frozen=True)
class PairSteps:
    """Critical steps [s] on a 1-D sweep; 2-D arrays are indexed ``[N index, sweep index]``.

    Parameters
    ----------
    stiffness : numpy.ndarray
        k_n per sweep point [N/m].
    density : numpy.ndarray
        Density per sweep point [kg/m^3].
    n_values : tuple of int
        Damping numbers N (``c = N sqrt(k_n/A_max)``).
    a_max : numpy.ndarray
        Eq. (26) per sweep point [1/kg].
    a_bound : numpy.ndarray
        Verified bound per sweep point [1/kg].
    damping : numpy.ndarray
        c per N and sweep point [N s/m].
    printed_eq46 : numpy.ndarray
        Eq. (46) with ``A_max`` [s].
    verified_a_max : dict of str to numpy.ndarray
        Each integrator's critical step with ``A_max`` [s].
    verified_a_bound : dict of str to numpy.ndarray
        Each integrator's critical step with ``a_bound`` [s].
    """

    stiffness: np.ndarray  # k_n [N/m] per sweep point
    density: np.ndarray  # rho [kg/m^3] per sweep point
    n_values: tuple[int, ...]
    a_max: np.ndarray  # Eq. (26) per sweep point [1/kg]
    a_bound: np.ndarray  # verified bound per sweep point [1/kg]
    damping: np.ndarray  # c [N s/m]
    printed_eq46: np.ndarray  # Eq. (46) with A_max
    verified_a_max: dict[str, np.ndarray]
    verified_a_bound: dict[str, np.ndarray]


def pair_steps(stiffness, density, n_values=N_VALUES, integrators=NAMES) -> PairSteps:
    """Evaluate the Section 6 curves for arrays ``stiffness`` and ``density`` (broadcast together).

    Parameters
    ----------
    stiffness : array_like
        k_n [N/m].
    density : array_like
        Density [kg/m^3].
    n_values : sequence of int
        Damping numbers N.
    integrators : sequence of str
        Schemes to evaluate.

    Returns
    -------
    PairSteps
        The curves.
    """
    k, rho = np.broadcast_arrays(np.asarray(stiffness, dtype=float), np.asarray(density, dtype=float))
    k, rho = k.ravel().copy(), rho.ravel().copy()
    coeffs = np.array([pair_coefficients(float(r)) for r in rho])  # a_max cheap, a_bound scaled
    a_max, a_bnd = coeffs[:, 0], coeffs[:, 1]
    nn = np.asarray(n_values, dtype=float)[:, None]
    c = nn * np.sqrt(k / a_max)[None, :]
    printed = np.array([[paper_eq46(kk, cc, aa) for kk, cc, aa in zip(k, row, a_max)] for row in c])
    ver_max = {name: critical_steps(name, k[None, :], c, a_max[None, :]) for name in integrators}
    ver_bnd = {name: critical_steps(name, k[None, :], c, a_bnd[None, :]) for name in integrators}
    return PairSteps(k, rho, tuple(int(v) for v in n_values), a_max, a_bnd, c, printed, ver_max, ver_bnd)


def write_pair_csv(steps: PairSteps, path: Path) -> Path:
    """Long-format CSV: one row per (sweep point, N).

    Parameters
    ----------
    steps : PairSteps
        The curves.
    path : pathlib.Path
        File to write.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    names = list(steps.verified_a_max)
    header = ["k_n", "density", "N", "c", "A_max_eq26", "A_bound", "dt_eq46_printed"]
    header += [f"dt_{n}_A_max" for n in names] + [f"dt_{n}_A_bound" for n in names]
    rows = []
    for j in range(steps.stiffness.size):
        for i, n in enumerate(steps.n_values):
            rows.append(
                [steps.stiffness[j], steps.density[j], n, steps.damping[i, j], steps.a_max[j], steps.a_bound[j],
                 steps.printed_eq46[i, j]]
                + [steps.verified_a_max[m][i, j] for m in names]
                + [steps.verified_a_bound[m][i, j] for m in names]
            )
    return write_csv(path, header, rows)


def plot_pair_steps(steps: PairSteps, x: np.ndarray, xlabel: str, title: str, path: Path,
                    integrators=SCENE_INTEGRATORS) -> Path:
    """Panels: the printed Eq. (46), then each integrator's verified bound (A_max solid, a_bound dashed).

    Each panel has its own y-range (the printed Eq. (46) grows with N, the verified bounds do not, so a
    shared range would squeeze them); one legend below the panels gives the colour of each damping
    number N (the same in every panel) and the two line styles of the verified panels.

    Parameters
    ----------
    steps : PairSteps
        The curves.
    x : numpy.ndarray
        Abscissa per sweep point.
    xlabel : str
        Label of the abscissa.
    title : str
        Title of the figure.
    path : pathlib.Path
        File to write.
    integrators : sequence of str
        Schemes with a verified panel.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    plt = pyplot()
    from matplotlib.lines import Line2D

    panels = 1 + len(integrators)
    fig, axes = plt.subplots(1, panels, figsize=(4.6 * panels, 4.4))
    cmap = plt.get_cmap("viridis")
    colours = [cmap(i / max(1, len(steps.n_values) - 1) * 0.9) for i in range(len(steps.n_values))]
    ms = 1e3
    ax = axes[0]
    for i, n in enumerate(steps.n_values):
        ax.plot(x, steps.printed_eq46[i] * ms, color=colours[i], lw=1.6)
    ax.set_title("Eq. (46) as printed, A = A_max (Eq. 26)", fontsize=9.5)
    tops = [float(np.nanmax(steps.printed_eq46)) * ms]
    ratio = float(np.median(steps.a_bound / steps.a_max))
    for ax, name in zip(axes[1:], integrators):
        for i, n in enumerate(steps.n_values):
            ax.plot(x, steps.verified_a_max[name][i] * ms, color=colours[i], lw=1.6)
            ax.plot(x, steps.verified_a_bound[name][i] * ms, color=colours[i], lw=1.2, ls="--")
        same = all(np.allclose(steps.verified_a_max[name][i], steps.verified_a_max[name][0], rtol=1e-12)
                   for i in range(len(steps.n_values)))
        ax.set_title(f"verified bound: {name}" + (" (the same for every N)" if same else ""), fontsize=9.5)
        tops.append(float(max(np.nanmax(steps.verified_a_max[name]), np.nanmax(steps.verified_a_bound[name]))) * ms)
    for ax, top in zip(axes, tops):
        ax.set_xlabel(xlabel)
        ax.set_ylim(0.0, 1.06 * top)
        ax.grid(alpha=0.3)
        ax.set_ylabel(r"$\Delta t_{cri}$ [ms]")
    handles = [Line2D([], [], color=colours[i], lw=2.0, label=f"N = {n} (zeta = {n / 2:g} with A_max)")
               for i, n in enumerate(steps.n_values)]
    handles += [Line2D([], [], color="0.3", lw=1.6, label="verified, A = A_max (Eq. 26)"),
                Line2D([], [], color="0.3", lw=1.2, ls="--", label=f"verified, A = a_bound ({ratio:.4g} A_max)")]
    fig.suptitle(title, fontsize=10.5)
    fig.tight_layout(rect=(0.0, 0.1, 1.0, 1.0))
    fig.legend(handles=handles, loc="lower center", ncol=4, fontsize=8.5, frameon=False,
               title="damping c = N sqrt(k_n/A_max): colour; A: line style (verified panels)", title_fontsize=8.5)
    return save_figure(fig, path)


def describe_trend(values: np.ndarray) -> str:
    """'increases' / 'decreases' / 'is constant' for a 1-D array along N.

    Parameters
    ----------
    values : numpy.ndarray
        Values along N.

    Returns
    -------
    str
        The trend in words ("is not monotone" otherwise).
    """
    d = np.diff(values)
    if np.all(np.abs(d) <= 1e-12 * np.max(np.abs(values))):
        return "is constant"
    if np.all(d > 0):
        return "increases"
    if np.all(d < 0):
        return "decreases"
    return "is not monotonic"
