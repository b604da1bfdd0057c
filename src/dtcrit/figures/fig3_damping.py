"""Figure 3: dimensionless critical step dt*sqrt(k/m) of two identical spheres against damping.

Peng et al. 2020, Section 6.1: for two identical spheres ``A_max = 7/m`` (Eq. (26) with
``I = 2/5 m r^2``) and the damping is expressed by ``beta = c/sqrt(m k)``.  The paper plots

* Eq. (58), Belytschko's Eq. (34) rewritten: ``4/sqrt(28 - 49 beta^2)``,
* Eq. (59), Silbert et al.'s Eq. (36) rewritten: ``pi/sqrt(2 - beta^2/4)``,
* Eq. (60), its Eq. (46) rewritten: ``beta + sqrt(beta^2 + 4/7)``.

Beside them this module evaluates each integrator's verified bound (``dtcrit.integrators.stability``) for the
same pair, with ``A`` from ``dtcrit.bodies.contact.a_bound`` (the verified largest eigenvalue of the
contact coefficient matrix, which for spheres equals Eq. (26)'s 7/m; if it did not, both would
be drawn).  Curves that coincide to 1e-12 are merged into one label.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from dtcrit._generated import critical_steps as _gen
from dtcrit.integrators.schemes import NAMES
from dtcrit.figures._output import critical_steps, pyplot, save_figure, write_csv

__all__ = ["Fig3Data", "fig3_data", "plot_fig3", "write_fig3", "BETA_MAX"]

BETA_MAX = 3.0
"""Upper end of the beta axis (beyond Silbert's asymptote at 2*sqrt(2))."""


@dataclass(frozen=True)
class Fig3Data:
    """Curves of Figure 3 on the grid ``beta`` (all dimensionless, dt*sqrt(k/m)).

    Parameters
    ----------
    beta : numpy.ndarray
        Damping parameter grid.
    printed : dict of str to numpy.ndarray
        Eqs. (58)-(60) as printed (NaN where complex).
    verified : dict of str to numpy.ndarray
        Each integrator's bound with ``A = a_bound``.
    verified_eq26 : dict of str to numpy.ndarray
        Each integrator's bound with Eq. (26)'s ``A_max``.
    a_max_times_m : float
        Eq. (26) times m (7 for spheres).
    a_bound_times_m : float
        Verified bound times m.
    groups : list of tuple of str
        Integrators with identical curves.
    """

    beta: np.ndarray
    printed: dict[str, np.ndarray]  # 'eq58', 'eq59', 'eq60' (NaN where the formula is complex)
    verified: dict[str, np.ndarray]  # integrator -> bound with A = a_bound
    verified_eq26: dict[str, np.ndarray]  # integrator -> bound with A = Eq. (26) A_max
    a_max_times_m: float  # Eq. (26) * m  (7 for spheres)
    a_bound_times_m: float  # verified bound * m
    groups: list[tuple[str, ...]] = field(default_factory=list)  # integrators with identical curves


def _sphere_pair_coefficients(mass: float, radius: float) -> tuple[float, float]:
    from dtcrit.bodies.contact import a_bound, a_max
    from dtcrit.bodies import Sphere

    sphere = Sphere(radius, mass=mass)
    return float(a_max(sphere, sphere)), float(a_bound(sphere, sphere))


def _group_identical(curves: dict[str, np.ndarray]) -> list[tuple[str, ...]]:
    groups: list[list[str]] = []
    for name, y in curves.items():
        for g in groups:
            if np.allclose(curves[g[0]], y, rtol=1e-12, atol=0.0, equal_nan=True):
                g.append(name)
                break
        else:
            groups.append([name])
    return [tuple(g) for g in groups]


def fig3_data(n: int = 601, *, betas=None, mass: float = 1.0, stiffness: float = 1.0, radius: float = 1.0,
              integrators: tuple[str, ...] = NAMES) -> Fig3Data:
    """Evaluate Figure 3 on ``n`` equally spaced beta in [0, BETA_MAX] (or on the given ``betas``).

    The result does not depend on ``mass``, ``stiffness`` or ``radius`` (dt*sqrt(k/m) is
    dimensionless); they only set the physical pair fed to the library.

    Parameters
    ----------
    n : int
        Number of grid points.
    betas : array_like, optional
        The grid, instead of n equally spaced points.
    mass : float
        Sphere mass [kg].
    stiffness : float
        Contact stiffness [N/m].
    radius : float
        Sphere radius [m].
    integrators : tuple of str
        Schemes to evaluate.

    Returns
    -------
    Fig3Data
        The curves.
    """
    beta = np.linspace(0.0, BETA_MAX, int(n)) if betas is None else np.atleast_1d(np.asarray(betas, dtype=float))
    a_eq26, a_ver = _sphere_pair_coefficients(mass, radius)
    c = beta * math.sqrt(mass * stiffness)
    scale = math.sqrt(stiffness / mass)
    with np.errstate(invalid="ignore", divide="ignore"):
        printed = {
            "eq58": np.asarray(_gen.beta_eq58(beta), dtype=float),
            "eq59": np.asarray(_gen.beta_eq59(beta), dtype=float),
            "eq60": np.asarray(_gen.beta_eq60(beta), dtype=float),
        }
    verified = {name: critical_steps(name, stiffness, c, a_ver) * scale for name in integrators}
    verified_eq26 = {name: critical_steps(name, stiffness, c, a_eq26) * scale for name in integrators}
    return Fig3Data(beta, printed, verified, verified_eq26, a_eq26 * mass, a_ver * mass, _group_identical(verified))


_PRINTED_LABELS = {
    "eq58": "Eq. (58) as printed (Belytschko, Eq. 34)",
    "eq59": "Eq. (59) as printed (Silbert et al., Eq. 36)",
    "eq60": "Eq. (60) as printed (paper's Eq. 46)",
}


def plot_fig3(data: Fig3Data, path: Path) -> Path:
    """Draw Figure 3: dt sqrt(k/m) against beta, the printed Eqs. (58)-(60) and the verified bounds.

    Parameters
    ----------
    data : Fig3Data
        The curves.
    path : pathlib.Path
        File to write.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 5.0))
    styles = {"eq58": ("k", "--"), "eq59": ("0.45", "-."), "eq60": ("k", ":")}
    for key, y in data.printed.items():
        colour, ls = styles[key]
        ax.plot(data.beta, y, color=colour, ls=ls, lw=2.0, label=_PRINTED_LABELS[key])
    cmap = plt.get_cmap("tab10")
    same_a = math.isclose(data.a_max_times_m, data.a_bound_times_m, rel_tol=1e-12)
    for i, group in enumerate(data.groups):
        ax.plot(data.beta, data.verified[group[0]], color=cmap(i), lw=1.6,
                label="verified: " + " = ".join(group))
        if not same_a:
            ax.plot(data.beta, data.verified_eq26[group[0]], color=cmap(i), lw=1.0, ls="--",
                    label="verified with Eq. (26) A: " + " = ".join(group))
    # Eqs. (58) and (59) have vertical asymptotes (their square roots vanish): drawn and named.  Eq. (58)'s
    # is critical damping, zeta = beta sqrt(7)/2 = 1, where forward Euler's bound has its corner too.
    for x, txt, side in ((2 / math.sqrt(7), r"Eq. (58) asymptote, $\zeta=1$" "\n" r"$\beta=2/\sqrt{7}\approx0.756$", 1),
                         (2 * math.sqrt(2), r"Eq. (59) asymptote" "\n" r"$\beta=2\sqrt{2}\approx2.83$", -1)):
        ax.axvline(x, color="0.6", lw=0.9, ls=(0, (1, 2)), zorder=0)
        ax.text(x + side * 0.03, 3.42, txt, ha="left" if side > 0 else "right", va="top", fontsize=7.5,
                color="0.35", bbox=dict(fc="white", ec="none", pad=1, alpha=0.85))
    ax.plot([], [], color="0.6", lw=0.9, ls=(0, (1, 2)),
            label="vertical asymptotes of Eqs. (58), (59)\n(beyond them the printed forms are undefined)")
    a_txt = (f"A = {data.a_bound_times_m:.6g}/m (Eq. 26 = verified bound)" if same_a else
             f"A = {data.a_bound_times_m:.6g}/m verified, {data.a_max_times_m:.6g}/m Eq. (26)")
    ax.set_title("Fig. 3: two identical spheres, " + a_txt, fontsize=10)
    ax.set_xlabel(r"$\beta = c/\sqrt{mk}$")
    ax.set_ylabel(r"$\Delta t_{cri}\sqrt{k/m}$")
    ax.set_xlim(0, BETA_MAX)
    ax.set_ylim(0, 3.5)
    # outside the axes, so that no curve is hidden behind it
    ax.legend(fontsize=7.5, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0, frameon=False)
    ax.grid(alpha=0.3)
    return save_figure(fig, path)


def write_fig3(out: Path, *, fine: bool = False) -> list[Path]:
    """Write ``fig3_damping.png`` and ``fig3_damping.csv`` into ``out``.

    Parameters
    ----------
    out : pathlib.Path
        Folder to write into.
    fine : bool
        Use the fine grid.

    Returns
    -------
    list of pathlib.Path
        The PNG and CSV.
    """
    data = fig3_data(1201 if fine else 601)
    names = list(data.verified)
    header = ["beta", "eq58_printed", "eq59_printed", "eq60_printed"] + [f"verified_{n}" for n in names]
    rows = zip(data.beta, *data.printed.values(), *(data.verified[n] for n in names))
    csv_path = write_csv(Path(out) / "fig3_damping.csv", header, rows)
    return [plot_fig3(data, Path(out) / "fig3_damping.png"), csv_path]
