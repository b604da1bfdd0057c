"""Whether a packing's top mode is rotational or translational: the share of its kinetic energy in the
rotational DOFs (entries 3-5 of each particle's six in mass-scaled coordinates), for one mode or for a
degenerate top eigenspace (``dtcrit.packing.report`` labels the mode of ``largest_mode`` with it).
"""
from __future__ import annotations

import numpy as np

__all__ = ["mode_character", "rotational_fraction"]


def rotational_fraction(vector: np.ndarray) -> float:
    """Share of a mode's kinetic energy in the rotational DOFs.

    In mass-scaled coordinates the kinetic energy of DOF ``i`` is proportional to ``v_i^2``; the
    rotational DOFs are entries 3-5 of each particle's six.

    Parameters
    ----------
    vector : numpy.ndarray
        Mass-scaled mode ``v = M^(1/2) phi``, 6 entries per particle.

    Returns
    -------
    float
        Rotational share in ``[0, 1]`` (0 for a zero vector).
    """
    v2 = np.asarray(vector).reshape(-1, 6) ** 2
    total = v2.sum()
    return float(v2[:, 3:].sum() / total) if total > 0 else 0.0


def mode_character(vector: np.ndarray, space: np.ndarray | None = None) -> str:
    """Whether a mode (or its degenerate eigenspace) is rotational or translational.

    With ``space`` (orthonormal columns spanning a degenerate top eigenspace) the answer is about the
    eigenspace, not the arbitrary member ``vector``: the rotational energy share over unit members
    ranges over the eigenvalues of ``B^T P_rot B``; when that range straddles 1/2 the eigenspace holds
    both kinds of mode.

    Parameters
    ----------
    vector : numpy.ndarray
        Mass-scaled mode, 6 entries per particle.
    space : numpy.ndarray or None
        Orthonormal basis ``B`` of the top eigenspace (used when it has more than one column).

    Returns
    -------
    str
        ``"rotational"`` when most kinetic energy is rotational, ``"translational"``, or
        ``"degenerate: translational and rotational"``.
    """
    if space is not None and space.shape[1] > 1:
        rot = space.reshape(-1, 6, space.shape[1])[:, 3:, :].reshape(-1, space.shape[1])
        share = np.linalg.eigvalsh(rot.T @ rot)
        if share[0] < 0.5 < share[-1]:
            return "degenerate: translational and rotational"
        return "rotational" if share[0] >= 0.5 else "translational"
    return "rotational" if rotational_fraction(vector) > 0.5 else "translational"
