"""Images and CSV for Appendix A (like the paper's Figs. A2 and A4) and the shape comparison.

* ``figA2_centre_moved``: octant I of particle 1 coloured by ``|xdd_c| = |A F|`` while particle 2
  (fixed orientation, scenarios 1 and 2) touches it at each point.
* ``figA4_orientation_changed``: the surfaces traced by the centre of particle 2 as its orientation
  changes with the contact at the tip (3, 0, 0) of particle 1, coloured by ``|A F|``: top row with
  particle 2 tangent (admissible), bottom row with the paper's construction (tip of particle 2
  pinned to the contact point).
* ``figA_shapes``: for the ellipsoid, the superquadric and the box, the largest eigenvalue found
  over all admissible contacts against Eq. (26)'s ``A_max`` and the verified ``a_bound``.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from dtcrit.figures._output import pyplot, save_figure, write_csv

__all__ = ["write_appendix_a"]


def _surface(ax, xyz, values, norm, cmap):
    colours = cmap(norm(values))
    ax.plot_surface(xyz[..., 0], xyz[..., 1], xyz[..., 2], facecolors=colours, rstride=1, cstride=1,
                    linewidth=0, antialiased=False, shade=False)


def _mark(ax, point, label, colour, marker="o"):
    """A marked point, named in the panel's legend (3-D text labels get clipped by the surfaces and the axes)."""
    ax.scatter([point[0]], [point[1]], [point[2]], color=colour, s=46, marker=marker, depthshade=False,
               edgecolor="k", linewidths=0.9, label=label, zorder=10)


def _tidy_axes(ax, nbins: int = 4) -> None:
    """Few ticks per 3-D axis and the axis names pushed clear of them (no colliding tick labels)."""
    from matplotlib.ticker import MaxNLocator

    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_major_locator(MaxNLocator(nbins=nbins))
    ax.tick_params(labelsize=7.5, pad=1)
    ax.set_xlabel("x [m]", labelpad=4)
    ax.set_ylabel("y [m]", labelpad=4)
    ax.zaxis.set_rotate_label(False)  # otherwise drawn mirrored at some view angles
    ax.set_zlabel("z [m]", labelpad=2, rotation=90)


def _legend_below(ax) -> None:
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, 0.04), fontsize=7.5, frameon=False, ncol=1,
              handletextpad=0.3)


def _point(p) -> str:
    """``(x, y, z)`` to 3 digits, rounding noise (below 1e-9 of the largest component) shown as 0."""
    p = np.asarray(p, dtype=float)
    tiny = 1e-9 * float(np.max(np.abs(p)))
    return "(" + ", ".join(f"{0.0 if abs(v) <= tiny else v:.3g}" for v in p) + ")"


def _plot_a2(fams, path: Path) -> Path:
    plt = pyplot()
    from matplotlib import cm
    from matplotlib.colors import Normalize

    vmin = min(float(f.accel.min()) for f in fams)
    vmax = max(float(f.accel.max()) for f in fams)
    norm, cmap = Normalize(vmin, vmax), plt.get_cmap("jet")
    fig = plt.figure(figsize=(11, 5.6))
    for k, fam in enumerate(fams):
        ax = fig.add_subplot(1, 2, k + 1, projection="3d")
        _surface(ax, fam.xyz, fam.accel, norm, cmap)
        _mark(ax, fam.best.contact_point,
              f"max |A F| on the octant: {fam.best.accel:.4g} m/s^2, contact point {_point(fam.best.contact_point)}",
              "w")
        ax.set_title(f"scenario {k + 1}: particle 2 fixed (45 deg about -y, roll {math.degrees(fam.roll):g} deg)",
                     fontsize=9)
        ax.set_box_aspect((3, 2, 1.2))
        ax.view_init(elev=25, azim=35)
        _tidy_axes(ax)
        _legend_below(ax)
    fig.subplots_adjust(left=0.02, right=0.86, wspace=0.12, bottom=0.12)
    fig.colorbar(cm.ScalarMappable(norm=norm, cmap=cmap), cax=fig.add_axes([0.9, 0.2, 0.018, 0.6]),
                 label="|xdd_c| = |A F| [m/s^2]")
    fig.suptitle("Like Fig. A2: octant I of ellipsoid 1 coloured by |xdd_c| (F = (1,1,1) N, unit density)", fontsize=10)
    return save_figure(fig, path)


def _plot_a4(tangent, pinned, path: Path) -> Path:
    plt = pyplot()
    from matplotlib import cm
    from matplotlib.colors import Normalize

    allf = list(tangent) + list(pinned)
    vmin = min(float(f.accel.min()) for f in allf)
    vmax = max(float(f.accel.max()) for f in allf)
    norm, cmap = Normalize(vmin, vmax), plt.get_cmap("jet")
    fig = plt.figure(figsize=(11, 10.5))
    for row, fams in enumerate((tangent, pinned)):
        for k, fam in enumerate(fams):
            ax = fig.add_subplot(2, 2, 2 * row + k + 1, projection="3d")
            _surface(ax, fam.xyz, fam.accel, norm, cmap)
            _mark(ax, fam.best.centre2, f"max |A F|: {fam.best.accel:.4g} m/s^2, centre of 2 {_point(fam.best.centre2)}",
                  "w")
            if fam.reference is not None:
                _mark(ax, fam.reference.centre2, f"orthogonal long axes: {fam.reference.accel:.4g} m/s^2, "
                      f"centre of 2 {_point(fam.reference.centre2)}", "0.55", marker="s")
            kind = "tangent (admissible)" if row == 0 else "paper: tip of 2 pinned (overlapping)"
            ax.set_title(f"scenario {k + 1} (roll {math.degrees(fam.roll):g} deg), {kind}", fontsize=8.5)
            ax.view_init(elev=20, azim=-60)
            _tidy_axes(ax)
            _legend_below(ax)
    fig.subplots_adjust(left=0.02, right=0.86, wspace=0.12, hspace=0.3, bottom=0.08)
    fig.colorbar(cm.ScalarMappable(norm=norm, cmap=cmap), cax=fig.add_axes([0.9, 0.25, 0.018, 0.5]),
                 label="|xdd_c| = |A F| [m/s^2]")
    fig.suptitle("Like Fig. A4: centres of ellipsoid 2 as its orientation changes, contact at (3, 0, 0)", fontsize=10)
    return save_figure(fig, path)


def _plot_shapes(shapes: dict, path: Path) -> Path:
    plt = pyplot()
    names = list(shapes)
    x = np.arange(len(names))
    found = [shapes[n]["max_lambda"] * shapes[n]["mass"] for n in names]
    eq26 = [shapes[n]["a_max_eq26"] * shapes[n]["mass"] for n in names]
    bound = [shapes[n]["a_bound"] * shapes[n]["mass"] for n in names]
    fig, ax = plt.subplots(figsize=(7, 4.2))
    w = 0.26
    ax.bar(x - w, eq26, w, label="Eq. (26) A_max", color="0.6")
    ax.bar(x, bound, w, label="verified a_bound", color="tab:blue")
    ax.bar(x + w, found, w, label="largest eigenvalue found", color="tab:red")
    for i, n in enumerate(names):
        verdict = "holds" if shapes[n]["eq26_is_upper_bound_lambda"] else "FAILS"
        ax.text(i, max(eq26[i], found[i]) * 1.03, f"Eq. 26 {verdict}\n(found/Eq.26 = {shapes[n]['lambda_over_eq26']:.4f})",
                ha="center", fontsize=7.5)
    ax.set_xticks(x, [shapes[n]["shape"].split(", mass")[0].replace("(", "\n(").replace(", eps1", ",\neps1") + ")"
                      for n in names], fontsize=7.5)
    ax.set_ylabel("eigenvalue x particle mass [-]")
    ax.set_ylim(0, max(eq26 + found) * 1.25)
    ax.legend(fontsize=8, loc="upper right")
    ax.set_title("Largest eigenvalue of the 3x3 coefficient matrix over all admissible contacts", fontsize=9.5)
    return save_figure(fig, path)


def _scenario_rows(fams, family: str):
    for fam in fams:
        n = fam.accel.shape[0]
        t = np.linspace(0.0, math.pi / 2, n)
        for i in range(n):
            for j in range(n):
                p = fam.xyz[i, j]
                yield [family, math.degrees(fam.roll), t[i], t[j], p[0], p[1], p[2], fam.accel[i, j], fam.lam[i, j]]


def write_appendix_a(out: Path, study: dict) -> list[Path]:
    """Write the Appendix A images and CSVs for a finished :func:`appendix_a_study`.

    Parameters
    ----------
    out : pathlib.Path
        Folder to write into.
    study : dict
        The result of ``appendix_a_study``.

    Returns
    -------
    list of pathlib.Path
        The files written.
    """
    out = Path(out)
    sc = study["objects"]["scenarios"]
    files = [_plot_a2(sc["centre_moved"], out / "figA2_centre_moved.png")]
    files.append(write_csv(out / "figA2_centre_moved.csv",
                           ["family", "roll_deg", "theta_normal", "phi_normal", "x_c", "y_c", "z_c", "accel", "lambda_max"],
                           _scenario_rows(sc["centre_moved"], "centre moved")))
    files.append(_plot_a4(sc["orientation_tangent"], sc["orientation_pinned_tip"], out / "figA4_orientation_changed.png"))
    rows = list(_scenario_rows(sc["orientation_tangent"], "tangent")) + list(
        _scenario_rows(sc["orientation_pinned_tip"], "pinned tip (paper)"))
    files.append(write_csv(out / "figA4_orientation_changed.csv",
                           ["family", "roll_deg", "theta_long_axis", "phi_long_axis", "x_2", "y_2", "z_2", "accel",
                            "lambda_max"], rows))
    shapes = study["summary"]["shapes"]
    if shapes:
        files.append(_plot_shapes(shapes, out / "figA_shapes.png"))
        files.append(write_csv(out / "figA_shapes.csv",
                               ["shape", "mass", "max_arm", "a_max_eq26", "a_bound", "max_lambda", "max_accel",
                                "accel_bound_eq26", "eq26_bounds_lambda", "eq26_bounds_accel"],
                               [[s["shape"], s["mass"], s["max_arm"], s["a_max_eq26"], s["a_bound"], s["max_lambda"],
                                 s["max_accel"], s["accel_bound_eq26"], str(s["eq26_is_upper_bound_lambda"]),
                                 str(s["eq26_is_upper_bound_accel"])] for s in shapes.values()]))
    return files
