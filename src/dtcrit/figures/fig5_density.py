"""Figure 5: critical step against particle density 500 ... 5000 kg/m^3 (Peng et al. 2020, Section 6.3).

The ellipsoids of Figure 4 at ``k_n = k_s = 1e10`` N/m; damping ``c = N sqrt(k_n / A_max)``, N = 0..5.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from dtcrit.figures.ellipsoid_pair import PairSteps, pair_steps, plot_pair_steps, write_pair_csv

__all__ = ["STIFFNESS", "DENSITY_RANGE", "fig5_data", "write_fig5"]

STIFFNESS = 1e10
DENSITY_RANGE = (500.0, 5000.0)


def fig5_data(n: int = 91) -> PairSteps:
    """Figure 5 on ``n`` equally spaced densities in [500, 5000] kg/m^3.

    Parameters
    ----------
    n : int
        Number of sweep points.

    Returns
    -------
    PairSteps
        The curves.
    """
    rho = np.linspace(*DENSITY_RANGE, int(n))
    return pair_steps(STIFFNESS, rho)


def write_fig5(out: Path, *, fine: bool = False) -> list[Path]:
    """Write ``fig5_density.png`` and ``fig5_density.csv`` into ``out``.

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
    data = fig5_data(361 if fine else 91)
    png = plot_pair_steps(
        data, data.density, r"density $\rho$ [kg/m$^3$]",
        "Fig. 5: ellipsoids a=3, b=2, c=1 m, k_n = 1e10 N/m, c = N sqrt(k_n/A_max)",
        Path(out) / "fig5_density.png",
    )
    return [png, write_pair_csv(data, Path(out) / "fig5_density.csv")]
