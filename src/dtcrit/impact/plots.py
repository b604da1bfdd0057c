"""Figures of the impact study (matplotlib, imported on use): exit speed against ``omega dt``, the Hertz
study, and exit speed against entry phase.
"""
from __future__ import annotations

import numpy as np

from dtcrit.impact.exact import exact_impact
from dtcrit.impact.stepped import ImpactRun
from dtcrit.impact.sweep import linear_bound

# ---------------------------------------------------------------------------------------------
# figures (matplotlib, Agg canvas: no global backend state)
# ---------------------------------------------------------------------------------------------

def _figure(width: float, height: float):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=110)
    FigureCanvasAgg(fig)
    return fig


def plot_sweep(report: dict, path) -> None:
    """v_exit/v_entry vs omega*dt per damping ratio: min-max band over phases, mean, on-step, exact.

    Parameters
    ----------
    report : dict
        A sweep made by ``impact_report`` (its private ``_runs`` arrays).
    path : str or pathlib.Path
        File to write (format from the suffix).
    """
    name = report["integrator"]
    runs = report["_runs"]
    zs = sorted(runs)
    fig = _figure(7.0, 2.4 * len(zs) + 0.6)
    axes = [fig.add_subplot(len(zs), 1, i + 1) for i in range(len(zs))]
    for ax, z in zip(axes, zs):
        grid, stats = runs[z]
        lo = np.array([s.min for s in stats])
        hi = np.array([s.max for s in stats])
        ax.fill_between(grid, np.minimum(lo, 5), np.minimum(hi, 5), color="C0", alpha=0.25, lw=0, label="min-max over phases")
        ax.plot(grid, [s.mean for s in stats], color="C0", lw=1.2, label="mean over phases")
        ax.plot(grid, [s.on_step for s in stats], color="C1", lw=0.8, ls="--", label="contact begins on a step")
        ex = exact_impact(z)
        ax.axhline(ex.exit_ratio, color="k", lw=1.0, label="exact")
        ax.axhline(1.0, color="0.5", lw=0.6, ls=":", label="v_exit = v_entry")
        tau_star = linear_bound(name, z)
        if tau_star > 0:
            ax.axvline(tau_star, color="C3", lw=0.8, ls="-.", label="linear bound")
        ax.set_ylim(0, 2.0)
        ax.set_xlim(0, float(grid[-1]))
        ax.set_ylabel("v_exit / v_entry")
        ax.set_title(f"{name}, zeta = {z:g}", fontsize=9)
    axes[-1].set_xlabel("omega dt")
    axes[0].legend(fontsize=7, loc="upper left", ncol=2)
    fig.tight_layout()
    fig.savefig(path)


def plot_hertz(study: dict, path) -> None:
    """Hertz impact: v_exit/v_entry band over phases vs omega_t dt, and the energy error vs the step
    (Hertz in omega_t dt, linear contact in omega dt) with the threshold and the linearised bound.

    Parameters
    ----------
    study : dict
        A study made by ``hertz_study`` (its private ``_grid`` array and ``numerical`` rows).
    path : str or pathlib.Path
        File to write (format from the suffix).
    """
    grid = study["_grid"]
    rows = study["numerical"]
    fig = _figure(7.0, 5.6)
    ax0 = fig.add_subplot(2, 1, 1)
    lo = np.array([np.inf if r["min"] is None else r["min"] for r in rows])
    hi = np.array([np.inf if r["max"] is None else r["max"] for r in rows])
    ax0.fill_between(grid, np.minimum(lo, 5), np.minimum(hi, 5), color="C0", alpha=0.25, lw=0, label="min-max over phases")
    ax0.plot(grid, [np.nan if r["mean"] is None else r["mean"] for r in rows], color="C0", lw=1.2, label="mean over phases")
    ax0.plot(grid, [np.nan if r["on_step"] is None else r["on_step"] for r in rows], color="C1", lw=0.8, ls="--",
             label="contact begins on a step")
    ax0.axhline(1.0, color="k", lw=1.0, label="exact")
    ax0.set_ylim(0, 2.0)
    ax0.set_xlim(0, float(grid[-1]))
    ax0.set_ylabel("v_exit / v_entry")
    ax0.set_title(f"{study['integrator']}: undamped Hertz impact, step in 1/omega_t (tangent at max overlap)", fontsize=9)
    ax = fig.add_subplot(2, 1, 2)
    floor = 1e-17
    ax.semilogy(grid, np.maximum(study["_energy_error"], floor), label="Hertz (omega_t dt)")
    ax.semilogy(grid, np.maximum(study["_linear_energy_error"], floor), ls="--", label="linear, zeta = 0 (omega dt)")
    ax.axhline(study["energy_threshold"], color="k", lw=0.8, ls=":", label="threshold")
    for a in (ax0, ax):
        if study["linearised_bound"] > 0:
            a.axvline(study["linearised_bound"], color="C3", lw=0.8, ls="-.", label="linearised bound")
    ax.set_ylim(1e-8, 1e3)
    ax.set_xlim(0, float(grid[-1]))
    ax.set_xlabel("omega dt")
    ax.set_ylabel("max |v_e^2/v_0^2 - 1| over phases")
    ax0.legend(fontsize=7, loc="upper left", ncol=2)
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(path)


def plot_phase_curve(report: dict, path) -> None:
    """v_exit/v_entry vs entry phase at the single step of a report made with ``omega_dt``: one marker per
    simulated entry phase, the exact impact and the line v_exit = v_entry, every one named in the legend.

    Parameters
    ----------
    report : dict
        A single-step report made by ``impact_report`` with ``omega_dt`` (its private ``_run``).
    path : str or pathlib.Path
        File to write (format from the suffix).
    """
    run: ImpactRun = report["_run"]
    fig = _figure(6.0, 3.4)
    ax = fig.add_subplot(1, 1, 1)
    ax.plot(run.phases, run.ratios[0], marker=".", ms=3, lw=0.8, color="C0",
            label=f"time-stepped, one marker per entry phase ({len(run.phases)} phases)")
    ax.axhline(report["exact"]["exit_ratio"], color="k", lw=1.0, label="exact impact")
    ax.axhline(1.0, color="0.5", lw=0.6, ls=":", label="v_exit = v_entry (above: energy created)")
    ax.set_xlabel("entry phase phi")
    ax.set_ylabel("v_exit / v_entry")
    ax.set_title(f"{report['integrator']}, zeta = {report['zeta']:g}, omega dt = {run.omega_dt[0]:g}", fontsize=9)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(0.0, -0.2), ncol=1, frameon=False)
    fig.tight_layout()
    fig.savefig(path, bbox_inches="tight")
