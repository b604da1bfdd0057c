"""``dtcrit plan --plot FILE.png``: the added mass of each particle against its size.

Left: the mass each free particle gains, ``m (f - 1)`` [kg], against its radius, for the plan (confirmed
stable at the target) and for YADE's ``densityScaling`` rule, with the uniform factor's line.  Right: the
factors ``f`` themselves.  The data are the plan's (:class:`dtcrit.plan.report.SnapshotPlan`); this
module only draws them and writes the PNG atomically (``dtcrit.figures.audit_plot``'s way).
"""
from __future__ import annotations

import os
import tempfile

import numpy as np

from dtcrit.errors import InputError
from dtcrit.figures._output import pyplot
from dtcrit.figures.audit_plot import check_plot_path

__all__ = ["draw_plan_plot", "write_plan_plot"]


def draw_plan_plot(plan):
    """The figure of a plan (module docstring).

    Parameters
    ----------
    plan : dtcrit.plan.report.SnapshotPlan
        The plan.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    plt = pyplot()
    d, packing = plan.density, plan.snapshot.packing
    free = d.free
    r_mm, m = 1e3 * packing.radii[free], packing.masses[free]
    fig, (left, right) = plt.subplots(1, 2, figsize=(10.5, 4.2))
    left.scatter(r_mm, m * (d.factors[free] - 1.0), s=14, color="tab:blue",
                 label=f"plan: {100 * d.added_mass_fraction:.3g} % added (exact step >= target)")
    if d.yade_factors is not None:
        left.scatter(r_mm, m * (d.yade_factors[free] - 1.0), s=14, marker="x", color="tab:orange",
                     label=f"YADE densityScaling (safety {d.yade_safety:g}): {100 * d.yade_rule_added_mass_fraction:.3g} %")
    order = np.argsort(r_mm)
    left.plot(r_mm[order], m[order] * (d.uniform_factor - 1.0), color="tab:gray", lw=1,
              label=f"uniform factor {d.uniform_factor:.3g}: {100 * d.uniform_added_mass_fraction:.3g} %")
    left.set_xlabel("radius [mm]")
    left.set_ylabel("added mass per particle [kg]")
    left.legend(fontsize=7)
    right.scatter(r_mm, d.factors[free], s=14, color="tab:blue", label="plan")
    if d.yade_factors is not None:
        right.scatter(r_mm, d.yade_factors[free], s=14, marker="x", color="tab:orange", label="YADE rule")
    right.set_yscale("log")
    right.set_xlabel("radius [mm]")
    right.set_ylabel("mass factor f")
    right.legend(fontsize=7)
    fig.suptitle(f"density scaling to dt = {plan.target_dt:.4g} s ({plan.target_dt / d.dt_crit:.3g} x dt_crit)", fontsize=10)
    fig.tight_layout()
    return fig


def write_plan_plot(plan, path: str | os.PathLike) -> None:
    """Draw the plan's figure and write it to ``path`` (PNG) atomically.

    Parameters
    ----------
    plan : dtcrit.plan.report.SnapshotPlan
        The plan.
    path : str or os.PathLike
        The PNG to write (checked by :func:`dtcrit.figures.audit_plot.check_plot_path`).

    Raises
    ------
    InputError
        (key ``plot``) For a path that cannot be written.
    """
    target = check_plot_path(path)
    fig = draw_plan_plot(plan)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".png", dir=target.parent if str(target.parent) else ".")
    os.close(fd)
    try:
        mask = os.umask(0)
        os.umask(mask)
        os.chmod(tmp, 0o666 & ~mask)
        fig.savefig(tmp, format="png", dpi=110, metadata={"Software": None})
        os.replace(tmp, target)
    except OSError as exc:
        raise InputError("plot", f"{path} could not be written ({exc.strerror or exc})") from None
    finally:
        pyplot().close(fig)
        if os.path.exists(tmp):
            os.unlink(tmp)
