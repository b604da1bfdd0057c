"""Figure 4: critical step against contact stiffness k_n = 1e10 ... 1e11 N/m (Peng et al. 2020, Section 6.2).

Two identical a=3, b=2, c=1 m ellipsoids, density 1000 kg/m^3, ``k_n = k_s``, damping
``c = N sqrt(k_n / A_max)``, N = 0..5.  Curves: printed Eq. (46) and the verified bounds of the
scene integrators with Eq. (26)'s ``A_max`` and with the verified ``a_bound``
(see :mod:`dtcrit.figures.ellipsoid_pair`).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from dtcrit.figures.ellipsoid_pair import PairSteps, pair_steps, plot_pair_steps, write_pair_csv

__all__ = ["DENSITY", "STIFFNESS_RANGE", "fig4_data", "write_fig4"]

DENSITY = 1000.0
STIFFNESS_RANGE = (1e10, 1e11)


def fig4_data(n: int = 91) -> PairSteps:
    """Figure 4 on ``n`` equally spaced k_n in [1e10, 1e11] N/m.

    Parameters
    ----------
    n : int
        Number of sweep points.

    Returns
    -------
    PairSteps
        The curves.
    """
    k = np.linspace(*STIFFNESS_RANGE, int(n))
    return pair_steps(k, DENSITY)


def write_fig4(out: Path, *, fine: bool = False) -> list[Path]:
    """Write ``fig4_stiffness.png`` and ``fig4_stiffness.csv`` into ``out``.

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
    data = fig4_data(361 if fine else 91)
    png = plot_pair_steps(
        data, data.stiffness / 1e10, r"$k_n$ [$10^{10}$ N/m]",
        "Fig. 4: ellipsoids a=3, b=2, c=1 m, rho = 1000 kg/m^3, c = N sqrt(k_n/A_max)",
        Path(out) / "fig4_stiffness.png",
    )
    return [png, write_pair_csv(data, Path(out) / "fig4_stiffness.csv")]
