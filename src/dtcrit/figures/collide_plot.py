"""``dtcrit collide --plot``: the worst error over the entry phase against steps per collision N.

For each contact of the report, the restitution and peak-overlap errors of
``dtcrit.collisions.collision_errors`` on a geometric grid of N, the tolerance as a horizontal line and
the chosen (binding) N of each contact as a vertical line.  Written atomically as PNG (Agg backend).
"""
from __future__ import annotations


import numpy as np

from dtcrit.collisions import collision_errors
from dtcrit.figures._output import pyplot
from dtcrit.figures.audit_plot import check_plot_path, write_plot_png

__all__ = ["collide_curves", "write_collide_plot"]


def collide_curves(report: dict, points: int = 24) -> list[dict]:
    """The error curves of each contact of a ``collide_report``.

    Parameters
    ----------
    report : dict
        From :func:`dtcrit.scenes.collide.collide_report`.
    points : int
        Grid points in N between ``N/4`` and ``4 N`` of the binding N.

    Returns
    -------
    list of dict
        Per contact: ``pair``, ``N`` (array), ``restitution``, ``peak_overlap`` (arrays of relative errors)
        and ``chosen`` (the binding N).
    """
    out = []
    for e in report["pairs"]:
        n0 = e["steps_per_collision"]
        grid = np.geomspace(max(2.0, n0 / 4.0), 4.0 * n0, points)
        errs = [collision_errors(engine=report["integrator"], normal=e["normal"], damping=e["damping"],
                                 restitution=e["restitution"], steps_per_collision=float(n)) for n in grid]
        out.append(dict(pair=e["pair"], N=grid, chosen=n0, restitution=np.array([x["restitution"] for x in errs]),
                        peak_overlap=np.array([x["peak_overlap"] for x in errs])))
    return out


def write_collide_plot(report: dict, path, points: int = 24) -> list[dict]:
    """Draw the error against N for the report's contacts and write it to ``path`` (PNG) atomically.

    Parameters
    ----------
    report : dict
        From :func:`dtcrit.scenes.collide.collide_report`.
    path : str or os.PathLike
        The PNG (``check_plot_path``).
    points : int
        Grid points per curve.

    Returns
    -------
    list of dict
        The curves drawn (``collide_curves``).
    """
    target = check_plot_path(path)
    curves = collide_curves(report, points)
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for c in curves:
        name = str(c["pair"]).replace("$", r"\$")  # a wall's name is text, never mathtext
        line, = ax.loglog(c["N"], np.maximum(c["restitution"], 1e-12), label=f"{name}: restitution")
        ax.loglog(c["N"], np.maximum(c["peak_overlap"], 1e-12), "--", color=line.get_color(), label=f"{name}: peak overlap")
        ax.axvline(c["chosen"], color=line.get_color(), lw=0.8, ls=":")
    ax.axhline(report["tol"], color="k", lw=0.8)
    from matplotlib.ticker import NullFormatter, ScalarFormatter

    ax.xaxis.set_major_formatter(ScalarFormatter())
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("steps per collision N = t_c/dt")
    ax.set_ylabel("worst relative error over the entry phase")
    ax.set_title(f"{report['integrator']}: the chosen step (dotted), tolerance {report['tol']:g}", parse_math=False)
    ax.legend(fontsize=7)
    fig.tight_layout()
    write_plot_png(fig, target, path)
    return curves
