"""Writing figure data (CSV) and images (PNG) for ``dtcrit figures``.

Matplotlib is imported only inside :func:`pyplot` with the non-interactive Agg backend, so the
data functions of the figure modules work without it (it is the optional ``figures`` extra).
CSV files are plain ``csv`` text: one header row, then numbers written with ``repr`` precision
(``nan`` for a value that does not exist, ``inf`` for an unbounded one).
"""
from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import Iterable, Sequence

import numpy as np

from dtcrit.integrators.stability import critical_dt_array

__all__ = ["pyplot", "write_csv", "save_figure", "fmt_number", "critical_steps"]


def pyplot():
    """``matplotlib.pyplot`` with the Agg backend (no display needed).

    Returns
    -------
    module
        matplotlib.pyplot.
    """
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def fmt_number(x) -> str:
    """A CSV cell: integers as such, floats with full precision, ``nan``/``inf`` spelled out.

    Parameters
    ----------
    x : object
        A string, an integer or a float.

    Returns
    -------
    str
        The cell text (``repr`` precision for floats).
    """
    if isinstance(x, str):
        return x
    if isinstance(x, (int, np.integer)) and not isinstance(x, (bool, np.bool_)):
        return str(int(x))
    v = float(x)
    if math.isnan(v):
        return "nan"
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    return repr(v)


def write_csv(path: Path, header: Sequence[str], rows: Iterable[Sequence]) -> Path:
    """Write ``header`` and ``rows`` to ``path`` (parent folders created).

    Parameters
    ----------
    path : pathlib.Path
        File to write.
    header : sequence of str
        Column names.
    rows : iterable of sequence
        Rows of cells, formatted with ``fmt_number``.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as fh:
        writer = csv.writer(fh, lineterminator="\n")
        writer.writerow(list(header))
        for row in rows:
            writer.writerow([fmt_number(x) for x in row])
    return path


def save_figure(fig, path: Path) -> Path:
    """Save ``fig`` as PNG at ``path`` (no timestamp metadata) and close it.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    path : pathlib.Path
        File to write.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=130, bbox_inches="tight", metadata={"Software": None})
    pyplot().close(fig)
    return path


def critical_steps(integrator: str, k, c, A) -> np.ndarray:
    """``dtcrit.integrators.stability.critical_dt_array`` with its inputs broadcast first, so the result always
    has the broadcast shape (a kernel that ignores the damping would otherwise return fewer values).

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].

    Returns
    -------
    numpy.ndarray
        The critical steps [s], broadcast shape.
    """
    k, c, A = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (k, c, A)))
    return np.asarray(critical_dt_array(integrator, k, c, A), dtype=float)
