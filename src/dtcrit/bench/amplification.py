"""Spectral radii for the bench's direct routes: re-exports ``dtcrit.integrators.amplification``.

``spectral_radius_eigvals`` is the batched ``numpy.linalg.eigvals`` route (LAPACK geev);
``spectral_radius_mp`` the ``mpmath.eig`` route at the current working precision.
"""
from __future__ import annotations

import numpy as np

from dtcrit.integrators.amplification import matrices, matrix_mp, spectral_radius_mp

__all__ = ["matrices", "matrix_mp", "spectral_radius_eigvals", "spectral_radius_mp"]


def spectral_radius_eigvals(name: str, tau, zeta) -> np.ndarray:
    """Spectral radius max |lambda| by batched ``numpy.linalg.eigvals`` of the float64 matrices, flattened.

    Parameters
    ----------
    name : str
        Name of the scheme.
    tau : array_like
        Steps tau = omega dt.
    zeta : array_like
        Damping ratios.

    Returns
    -------
    numpy.ndarray
        Spectral radius of each update-rule matrix, flattened.
    """
    tau, zeta = np.broadcast_arrays(np.asarray(tau, dtype=float), np.asarray(zeta, dtype=float))
    return np.max(np.abs(np.linalg.eigvals(matrices(name, tau.ravel(), zeta.ravel()))), axis=1)
