"""``dtcrit audit --plot FILE.png``: what governs the step, drawn.

Left: the packing's particles (seen along z, discs of their radii) coloured by their share of the
governing mode's kinetic energy (logarithmic colour bar).  Right: the top of the spectrum as steps
``2/omega_k`` of the largest eigenvalues (and, with dashpots, each mode's step with its own modal
damping), with ``dt_crit``, ``dt_safe`` and the estimators as labelled horizontal lines.  The data
come from :func:`dtcrit.packing.audit.plot_data.audit_figure_data`; this module only draws it and
writes the PNG atomically (a temporary file in the same folder, then a rename: an error leaves no
half-written file).
"""
from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np

from dtcrit.errors import InputError
from dtcrit.figures._output import pyplot
from dtcrit.packing.audit.plot_data import AuditFigureData, audit_figure_data

__all__ = ["check_plot_path", "draw_audit_plot", "label_positions", "write_audit_plot", "write_plot_png"]

SHARE_FLOOR = 1e-6
"""Shares below this fraction of the largest are drawn at the bottom of the colour scale."""
LABELLED = 6
"""How many of the most energetic particles are labelled with their ids."""
LABEL_GAP = 0.045
"""Smallest vertical distance between two mark labels, in axes fractions."""
STYLES = {"dt_crit": ("black", "-", 1.8), "dt_safe": ("tab:green", "--", 1.4),
          "your dt": ("tab:red", "-.", 1.4), "2/omega_max (undamped)": ("tab:gray", ":", 1.2)}


def check_plot_path(path: str | os.PathLike) -> Path:
    """Refuse, before any work, a ``--plot`` path that cannot be written.

    Parameters
    ----------
    path : str or os.PathLike
        The PNG to write.

    Returns
    -------
    pathlib.Path
        The path.

    Raises
    ------
    InputError
        (key ``plot``) When it does not end in ``.png``, its folder does not exist or cannot be
        written, or it is a folder; when Matplotlib is not installed.
    """
    p = Path(path)
    if p.suffix.lower() != ".png":
        raise InputError("plot", f"{path} does not end in .png (the figure is written as PNG)")
    folder = p.parent if str(p.parent) else Path(".")
    if not folder.is_dir():
        raise InputError("plot", f"folder {folder} does not exist")
    if p.is_dir() or not os.access(folder, os.W_OK):
        raise InputError("plot", f"{path} cannot be written")
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise InputError("plot", "needs Matplotlib (pip install 'dtcrit[figures]')") from None
    return p


def write_plot_png(fig, target: Path, path: str | os.PathLike) -> None:
    """Write ``fig`` as the PNG ``target`` atomically (a temporary file beside it, renamed), with an
    ordinary new file's permissions, and close the figure.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    target : pathlib.Path
        Where to write it (``check_plot_path``).
    path : str or os.PathLike
        The path as the user gave it, for the error.

    Raises
    ------
    InputError
        (key ``plot``) When the file cannot be written; nothing is left half-written.
    """
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".png", dir=target.parent if str(target.parent) else ".")
    os.close(fd)
    try:
        mask = os.umask(0)
        os.umask(mask)
        os.chmod(tmp, 0o666 & ~mask)  # as an ordinary new file, not mkstemp's 0600
        fig.savefig(tmp, format="png", dpi=110, metadata={"Software": None})
        os.replace(tmp, target)
    except OSError as exc:
        raise InputError("plot", f"{path} could not be written ({exc.strerror or exc})") from None
    finally:
        pyplot().close(fig)
        if os.path.exists(tmp):
            os.unlink(tmp)


def _particles(ax, fig, d: AuditFigureData) -> None:
    """The x-y projection (seen along z), discs of the particles' radii, the most energetic on top."""
    from matplotlib.collections import EllipseCollection
    from matplotlib.colors import LogNorm

    share = np.maximum(d.share, SHARE_FLOOR * float(np.max(d.share)))
    order = np.argsort(share, kind="stable")  # the most energetic drawn last, on top
    xy, diameter = d.positions[order, :2], 2.0 * d.radii[order]
    discs = EllipseCollection(diameter, diameter, np.zeros(order.size), units="xy", offsets=xy,
                              offset_transform=ax.transData, cmap="viridis", edgecolors="k", linewidths=0.3,
                              norm=LogNorm(vmin=float(share.min()), vmax=float(share.max())))
    discs.set_array(share[order])
    ax.add_collection(discs)
    pad = float(d.radii.max())
    ax.set_xlim(float(xy[:, 0].min()) - pad, float(xy[:, 0].max()) + pad)
    ax.set_ylim(float(xy[:, 1].min()) - pad, float(xy[:, 1].max()) + pad)
    ax.set_aspect("equal")
    for p in order[::-1][:LABELLED]:
        ax.annotate(str(d.ids[p]), d.positions[p, :2], ha="center", va="center", fontsize=7, color="red")
    bar = fig.colorbar(discs, ax=ax, shrink=0.8)
    bar.set_label(f"share of the {d.mode}'s kinetic energy")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"particles (seen along z) by their share of the {d.mode};\n"
                 f"red: ids of the {LABELLED} with the most", fontsize=9)


def _merged(marks) -> list[tuple[str, float]]:
    """Marks at the same step (relative 1e-9) joined into one label, smallest step first."""
    out: list[tuple[str, float]] = []
    for label, dt in sorted(marks, key=lambda m: m[1]):
        if out and abs(dt - out[-1][1]) <= 1e-9 * dt:
            out[-1] = (f"{out[-1][0]} = {label}", out[-1][1])
        else:
            out.append((label, dt))
    return out


def label_positions(fractions, gap: float = LABEL_GAP) -> np.ndarray:
    """Positions (axes fractions) of labels at the sorted ``fractions``, pushed apart to ``gap``.

    Parameters
    ----------
    fractions : array_like
        Ascending heights of the marks in axes fractions.
    gap : float
        Smallest distance between two labels.

    Returns
    -------
    numpy.ndarray
        The labels' heights, ascending, at least ``gap`` apart, kept below 1 when they fit.
    """
    y = np.array(fractions, dtype=float)
    for i in range(1, y.size):
        y[i] = max(y[i], y[i - 1] + gap)
    if y.size and y[-1] > 1.0:  # shifted down from the top, as far as the lowest allows
        y -= min(y[-1] - 1.0, max(y[0], 0.0))
    return y


def _spectrum(ax, d: AuditFigureData) -> None:
    s = d.spectrum
    k = np.arange(1, s.steps.size + 1)
    ax.step(k, s.steps, where="mid", color="tab:blue", label="2/omega_k (undamped, each mode alone)")
    ax.plot(k, s.steps, "o", color="tab:blue", ms=4)
    shown = [s.steps]
    if s.damped_steps is not None:
        ax.plot(k, s.damped_steps, "s", color="tab:orange", ms=4, mfc="none",
                label="each mode with its modal damping")
        shown.append(s.damped_steps)
    marks = _merged(d.marks)
    values = np.concatenate([np.ravel(v) for v in shown] + [np.array([dt for _, dt in marks])])
    values = values[np.isfinite(values) & (values > 0)]
    ax.set_yscale("log")
    lo, hi = float(values.min()) / 1.15, float(values.max()) * 1.15
    ax.set_ylim(lo, hi)
    frac = [(np.log(dt) - np.log(lo)) / (np.log(hi) - np.log(lo)) for _, dt in marks]
    for (label, dt), y in zip(marks, label_positions(frac)):
        color, style, width = STYLES.get(label.split(" = ")[0], ("tab:purple", (0, (1, 2)), 0.9))
        ax.axhline(dt, color=color, ls=style, lw=width)
        ax.annotate(f"{label}  {dt:.4g} s", (1.0, dt), xycoords=("axes fraction", "data"), xytext=(1.04, y),
                    textcoords="axes fraction", va="center", fontsize=7, color=color,
                    arrowprops={"arrowstyle": "-", "color": color, "lw": 0.5})
    ax.set_xlabel("mode k (largest omega_k first)")
    ax.set_ylabel("step [s]")
    ax.set_xticks(k)
    ax.set_title(f"top {s.steps.size} of the spectrum")
    ax.legend(fontsize=7, loc="lower right")


def draw_audit_plot(data: AuditFigureData):
    """The figure of the module docstring.

    Parameters
    ----------
    data : AuditFigureData
        From :func:`dtcrit.packing.audit.plot_data.audit_figure_data`.

    Returns
    -------
    matplotlib.figure.Figure
        The figure (close it when done).
    """
    plt = pyplot()
    fig = plt.figure(figsize=(12.5, 5.4))
    _particles(fig.add_subplot(1, 2, 1), fig, data)
    _spectrum(fig.add_subplot(1, 2, 2), data)
    fig.suptitle(data.title, fontsize=9, parse_math=False)  # a file name is text, never mathtext
    fig.subplots_adjust(left=0.06, right=0.8, wspace=0.35)
    return fig


def write_audit_plot(audit, path: str | os.PathLike, count: int = 10) -> AuditFigureData:
    """Draw the audit's figure and write it to ``path`` (PNG) atomically.

    Parameters
    ----------
    audit : SnapshotAudit
        An audit from :func:`dtcrit.packing.audit.run.audit_snapshot`.
    path : str or os.PathLike
        The PNG to write (checked by :func:`check_plot_path`).
    count : int
        How many of the largest eigenvalues to draw.

    Returns
    -------
    AuditFigureData
        The data drawn.

    Raises
    ------
    InputError
        (key ``plot``) For a path that cannot be written.
    """
    target = check_plot_path(path)
    data = audit_figure_data(audit, count)
    fig = draw_audit_plot(data)
    write_plot_png(fig, target, path)
    return data
