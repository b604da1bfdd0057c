"""A start vector for the shell route's Krylov-Schur: the serial route's Chebyshev filter, on PETSc vectors.

The serial route starts LOBPCG from ``largest_mode.chebyshev_start`` (Zhou & Saad 2007,
Chebyshev-filtered subspace iteration with one vector): stages of ``T_m(2A/theta - 1)``, ``theta``
the current Rayleigh quotient, until ``theta`` moves by less than ``FILTER_STOP`` (relative).
Each filter product costs three vector updates and one norm, where a Krylov-Schur step
orthogonalises against up to ``ncv`` basis vectors (measured at 10^5 spheres: as costly as the
product itself).  ``chebyshev_start`` here is the same recurrence with the same constants on the
distributed vectors of a PETSc matrix (the inner products and norms are global), started, as the
serial route, from a random vector plus all particles co-rotating about x, y and z
(``rayleigh_trials.co_rotation`` of each rank's own particles: every particle's entry is its own).
The random part is the same whatever the ranks (``global_uniform``: entry ``d`` of the vector is
the ``d``-th draw of one PCG64 stream, each rank jumping to its first row), so that one and several
ranks start from one vector and take about as many products.  It only chooses where Krylov-Schur
starts: the answer and its residual are SLEPc's.
"""
from __future__ import annotations

import numpy as np

from dtcrit.packing.model import Packing
from dtcrit.packing.solvers.largest_mode import FILTER_DEGREE, FILTER_STAGES, FILTER_STOP

__all__ = ["global_uniform", "start_vector", "chebyshev_start"]


def global_uniform(seed: int, lo: int, hi: int) -> np.ndarray:
    """Entries ``lo .. hi - 1`` of one random vector uniform in ``[-1, 1)``: draws ``lo .. hi - 1`` of
    the PCG64 stream of ``seed`` (``advance`` jumps to draw ``lo``; a double takes one 64-bit draw), so
    that the ranks' pieces are one vector whatever their number.

    Parameters
    ----------
    seed : int
        The stream's seed.
    lo, hi : int
        The entries wanted (a rank's rows).

    Returns
    -------
    numpy.ndarray
        ``hi - lo`` values.

    Examples
    --------
    >>> bool((global_uniform(7, 0, 5)[3:] == global_uniform(7, 3, 5)).all())
    True
    """
    stream = np.random.PCG64(seed)
    stream.advance(int(lo))
    return 2.0 * np.random.Generator(stream).random(int(hi) - int(lo)) - 1.0


def start_vector(mat, local: Packing, n_own: int, seed: int):
    """A random vector (``global_uniform``) plus the normalised co-rotation hint, on ``mat``'s rows
    (collective).

    Parameters
    ----------
    mat : petsc4py.PETSc.Mat
        The operator (gives the layout).
    local : Packing
        This rank's local particles, its own ones first in the order of its rows (``slepc_shell.LocalLayout``).
    n_own : int
        Number of own particles.
    seed : int
        Seed of the random part (the same on every rank).

    Returns
    -------
    petsc4py.PETSc.Vec
        The start vector (not normalised).
    """
    from dtcrit.packing.bounds.rayleigh_trials import co_rotation

    v = mat.createVecRight()
    hint = mat.createVecRight()
    v.setArray(global_uniform(seed, *v.getOwnershipRange()))
    rows = 6 * n_own
    hint.setArray((co_rotation(local, 0) + co_rotation(local, 1) + co_rotation(local, 2))[:rows])
    size = hint.norm()
    if size > 0:
        v.scale(1.0 / v.norm())
        v.axpy(1.0 / size, hint)
    hint.destroy()
    return v


def chebyshev_start(mat, v, degree: int = FILTER_DEGREE, stop: float = FILTER_STOP, stages: int = FILTER_STAGES):
    """``v`` filtered toward the top eigenvectors of the symmetric positive semi-definite ``mat``
    (module docstring; ``largest_mode.chebyshev_start`` on PETSc vectors), collective.

    Parameters
    ----------
    mat : petsc4py.PETSc.Mat
        ``A``.
    v : petsc4py.PETSc.Vec
        Initial vector (overwritten by the result).
    degree : int
        Degree of each filter stage.
    stop : float
        Stop when the Rayleigh quotient moves by less than this (relative) in a stage.
    stages : int
        Most filter stages.

    Returns
    -------
    petsc4py.PETSc.Vec
        ``v``, filtered and of unit norm (only normalised when ``A v`` has no positive Rayleigh quotient).
    """
    v.scale(1.0 / v.norm())
    av = v.duplicate()
    mat.mult(v, av)
    theta = v.dot(av)
    if not (theta > 0 and np.isfinite(theta)):
        av.destroy()
        return v
    y0, y1, y2 = v.duplicate(), v.duplicate(), v.duplicate()
    for _ in range(stages):
        v.copy(y0)
        av.copy(y1)
        y1.scale(2.0 / theta)
        y1.axpy(-1.0, v)
        for _k in range(2, degree + 1):
            mat.mult(y1, y2)  # y2 = (4/theta) A y1 - 2 y1 - y0, renormalised with y1
            y2.scale(4.0 / theta)
            y2.axpy(-2.0, y1)
            y2.axpy(-1.0, y0)
            norm = y2.norm()
            if not (norm > 0 and np.isfinite(norm)):
                break
            y2.scale(1.0 / norm)
            y1.scale(1.0 / norm)
            y0, y1, y2 = y1, y2, y0
        y1.copy(v)
        v.scale(1.0 / v.norm())
        mat.mult(v, av)
        new = v.dot(av)
        moved = abs(new - theta) / new if new > 0 else 0.0
        theta = new
        if moved < stop:
            break
    for w in (av, y0, y1, y2):
        w.destroy()
    return v
