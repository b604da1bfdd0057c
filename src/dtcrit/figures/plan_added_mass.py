"""The density-scaling plan drawn: added mass per particle against its size.

Left: each free particle's added mass ``m_p (f_p - 1)`` [kg] against its radius, for dtcrit's plan
(filled), YADE's per-body rule (``NewtonIntegrator.densityScaling`` with
``GlobalStiffnessTimeStepper.targetDt``, open) and the least uniform factor (line markers); right:
the factors ``f_p`` themselves.  The totals (added mass fractions) are in the legend.  The data come
from a :class:`dtcrit.plan.DensityPlan` (``factors``, ``masses``, ``free``, ``yade_factors``,
``uniform_factor``, ``target_dt``) and the snapshot's radii; :func:`added_mass_data` computes them
without Matplotlib, :func:`write_added_mass_figure` draws them and writes the PNG atomically (a
temporary file in the same folder, then a rename).
"""
from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np

from dtcrit.errors import InputError
from dtcrit.figures._output import pyplot
from dtcrit.figures.audit_plot import check_plot_path, write_plot_png

__all__ = ["AddedMassData", "added_mass_data", "draw_added_mass", "write_added_mass_figure"]


@dataclass(frozen=True)
class AddedMassData:
    """What the figure draws, free particles only.

    Parameters
    ----------
    radius : numpy.ndarray
        ``(n,)`` radii [m].
    mass : numpy.ndarray
        ``(n,)`` unscaled masses [kg].
    added : dict of str to numpy.ndarray
        Added mass per particle [kg] of each rule drawn (``dtcrit plan``, ``YADE rule``, ``uniform``).
    factors : dict of str to numpy.ndarray
        The mass factors of the same rules.
    target_dt : float or None
        The target step [s] (the title), when the plan gives it.
    """

    radius: np.ndarray
    mass: np.ndarray
    added: dict
    factors: dict
    target_dt: float | None

    def fraction(self, rule: str) -> float:
        """Added mass of a rule over the free particles' mass.

        Parameters
        ----------
        rule : str
            A key of ``added``.

        Returns
        -------
        float
            ``sum m_p (f_p - 1) / sum m_p`` over the free particles.
        """
        return float(self.added[rule].sum() / self.mass.sum())


def _per_body(values, n: int, name: str) -> np.ndarray:
    out = np.asarray(values, dtype=float)
    if out.shape != (n,) or not np.all(np.isfinite(out)):
        raise InputError("plan", f"{name} must be {n} finite numbers, one per body (got shape {out.shape})")
    return out


def added_mass_data(plan, radii) -> AddedMassData:
    """The figure's data from a density-scaling plan and the snapshot's radii.

    Parameters
    ----------
    plan : dtcrit.plan.DensityPlan
        The plan (any object with ``factors`` and ``masses``; ``free``, ``yade_factors``,
        ``uniform_factor`` and ``target_dt`` are used when present).
    radii : array_like
        ``(N,)`` the bodies' radii [m], in the snapshot's body order (the plan's).

    Returns
    -------
    AddedMassData
        Radii, masses, added masses and factors of the free bodies.

    Raises
    ------
    InputError
        (key ``plan``) Radii, masses or factors that are not one finite number per body, or no free body.
    """
    n = int(np.size(plan.factors))
    factors = _per_body(plan.factors, n, "factors")
    radius, mass = _per_body(radii, n, "radii"), _per_body(plan.masses, n, "masses")
    given = getattr(plan, "free", None)
    free = np.ones(n, dtype=bool) if given is None else np.asarray(given, dtype=bool)
    if free.shape != (n,) or not free.any():
        raise InputError("plan", "no free body to draw")
    rules = {"dtcrit plan": factors}
    if getattr(plan, "yade_factors", None) is not None:
        rules["YADE rule"] = _per_body(plan.yade_factors, n, "yade_factors")
    if getattr(plan, "uniform_factor", None) is not None:
        rules["uniform"] = np.full(n, float(plan.uniform_factor))
    target = getattr(plan, "target_dt", None)
    return AddedMassData(radius=radius[free], mass=mass[free],
                         added={k: (mass * (f - 1.0))[free] for k, f in rules.items()},
                         factors={k: f[free] for k, f in rules.items()},
                         target_dt=None if target is None else float(target))


STYLES = {"dtcrit plan": dict(marker="o", color="tab:blue", s=28),
          "YADE rule": dict(marker="o", facecolors="none", edgecolors="tab:orange", s=40),
          "uniform": dict(marker="_", color="tab:gray", s=60)}


def draw_added_mass(data: AddedMassData):
    """Draw the two panels (module docstring).

    Parameters
    ----------
    data : AddedMassData
        From :func:`added_mass_data`.

    Returns
    -------
    matplotlib.figure.Figure
        The figure (the caller closes it).
    """
    plt = pyplot()
    fig, (left, right) = plt.subplots(1, 2, figsize=(10.0, 4.2))
    for rule, added in data.added.items():
        label = f"{rule} (added {100 * data.fraction(rule):.1f} % of the mass)"
        left.scatter(data.radius, added, label=label, **STYLES.get(rule, {}))
        right.scatter(data.radius, data.factors[rule], **STYLES.get(rule, {}))
    left.set_xlabel("particle radius [m]")
    left.set_ylabel("added mass per particle [kg]")
    right.set_xlabel("particle radius [m]")
    right.set_ylabel("mass and inertia factor")
    right.axhline(1.0, color="black", lw=0.8)
    fig.legend(*left.get_legend_handles_labels(), loc="lower center", ncol=len(data.added), fontsize=8,
               frameon=False)
    title = "density scaling" + ("" if data.target_dt is None else f" to dt = {data.target_dt:.4g} s")
    fig.suptitle(title)
    fig.tight_layout(rect=(0.0, 0.07, 1.0, 1.0))
    return fig


def write_added_mass_figure(plan, radii, path: str | os.PathLike) -> AddedMassData:
    """Draw the plan's added mass per particle against its size and write it to ``path`` (PNG) atomically.

    Parameters
    ----------
    plan : dtcrit.plan.DensityPlan
        The plan (see :func:`added_mass_data`).
    radii : array_like
        ``(N,)`` the bodies' radii [m], in the plan's body order.
    path : str or os.PathLike
        The PNG to write.

    Returns
    -------
    AddedMassData
        The data drawn.

    Raises
    ------
    InputError
        (key ``plot``) A path that cannot be written; (key ``plan``) data that do not fit.
    """
    target = check_plot_path(path)
    data = added_mass_data(plan, radii)
    fig = draw_added_mass(data)
    write_plot_png(fig, target, path)
    return data
