"""The analysis stage of the distributed back-end: the operator (assembled or shell), the solve, the result.

``analyse_share`` takes a rank's share (``slepc_backend.distribute``), builds ``A`` either as the
assembled ``MPISBAIJ`` matrix (``slepc_backend.assemble``) or as the matrix-free shell
(``slepc_shell``; ``--slepc-matrix``, default shell), solves with Krylov-Schur
(``slepc_backend.solve``) and gathers the figures of every rank into one ``SlepcResult``, with the
rigorous bracket ``[dt_safe, 2/sqrt(theta)]`` of ``dtcrit.packing.solvers.certificate.bracket``
(``theta`` a Rayleigh quotient, so ``2/sqrt(theta)`` is never below the true step; ``dt_safe`` the
serial route's bound for the shell, Gershgorin ``2/sqrt(|A|_inf)`` for the assembled matrix).
"""
from __future__ import annotations

import math
import time

from dtcrit.errors import InputError
from dtcrit.packing.model import Contacts, Packing
from dtcrit.packing.solvers.certificate import bracket
from dtcrit.packing.solvers.largest_mode import DEFAULT_TOL as SERIAL_TOL
from dtcrit.packing.distributed.mpi_support import allgather, peak_mib, petsc, release_memory, world
from dtcrit.packing.distributed.petsc_build import loaded_bits
from dtcrit.packing.distributed.slepc_backend import (NCV, TOLERANCE, RankShare, SlepcResult, _held, _local_figures,
                                                      assemble, distribute, solve)
from dtcrit.packing.distributed.slab_contacts import split_rows

__all__ = ["MATRICES", "DEFAULT_MATRIX", "SHELL_TOLERANCE", "SHELL_NCV", "build_operator", "analyse_share", "analyse"]

MATRICES = ("shell", "assembled")
DEFAULT_MATRIX = "shell"
"""``--slepc-matrix``: the matrix-free shell (``slepc_shell``) or the assembled ``MPISBAIJ``.  The shell
is the default: it stores no matrix, and it was the faster on one rank at every size measured
(``bench.slepc_scaling compare``, jittered FCC, shared 2-core machine): at 10^4 spheres (the CI
size) 1.9 s after the input against 5.5 s for the assembled matrix at its tolerance 1e-12 and 2.3 s
at 1e-6; at 10^5, 6.3 s against 40 s and 15 s (the serial route: 5.1 s)."""
SHELL_TOLERANCE = 10 * SERIAL_TOL
"""Relative residual of the shell route: the serial route's (LOBPCG stops at ``10 tol`` relative,
``largest_mode.DEFAULT_TOL``), whose answer is the bracket ``[dt_safe, 2/sqrt(theta)]``."""
SHELL_NCV = 12
"""Krylov-Schur subspace of the shell route.  Measured on 10^5 jittered FCC spheres at 1e-6, one rank
(``bench.slepc_scaling``, shared machine): 132 products at 8, 102 at 12, 96 at 16 and 24, the solve
about 20 % faster at 12 than at 16 (the orthogonalisation against the basis costs as much as a
product at 16) and its basis 20 MiB smaller."""
START_SEED = 20170601
"""Seed of the random part of the shell route's start vector (one stream over every rank's rows,
``slepc_start.global_uniform``): the serial route's."""
SAFE_ASSEMBLED = "Gershgorin 2/sqrt(|A|_inf)"
SAFE_SHELL = "the larger of the Gershgorin and block-diagonal steps (the serial route's)"


def build_operator(share: RankShare, matrix: str):
    """The operator ``A`` of ``share`` (collective); the share's packing and contacts are dropped then.

    Parameters
    ----------
    share : RankShare
        This rank's share (``distribute``).
    matrix : str
        ``"shell"`` (``slepc_shell``: nothing stored) or ``"assembled"``.

    Returns
    -------
    tuple
        ``(mat, shell, mallocs, nonzeros)``: the PETSc matrix, the shell's context (``None`` when
        assembled), PETSc's mallocs and stored nonzeros on this rank (0 for the shell).
    """
    if matrix == "shell":
        from dtcrit.packing.distributed.slepc_shell import local_layout, shell_matrix

        packing, c = _held(share)
        mat, shell = shell_matrix(local_layout(share.glob, share.lo, share.hi, packing, c), share.n)
        share.packing, share.contacts = None, None  # the shell's operator holds all the solve needs
        return mat, shell, 0, 0
    mat = assemble(share)
    share.packing, share.contacts = None, None  # the matrix holds all the solve needs
    info = mat.getInfo(petsc()[0].Mat.InfoType.LOCAL)
    return mat, None, int(info["mallocs"]), int(info["nz_used"])


def analyse_share(share: RankShare, tolerance: float | None = None, matrix: str = DEFAULT_MATRIX, *,
                  filtered_start: bool = True) -> SlepcResult:
    """Build ``A`` (``matrix``: ``"shell"``, matrix-free, or ``"assembled"``) and solve ``share``
    (collective); the result, identical on every rank.  The share's packing and contacts are dropped
    once the operator holds them.

    Parameters
    ----------
    share : RankShare
        This rank's share (``distribute``).
    tolerance : float or None
        Relative residual tolerance of the eigen-solve (default ``SHELL_TOLERANCE`` for the shell,
        ``TOLERANCE`` for the assembled matrix).
    matrix : str
        One of ``MATRICES``.
    filtered_start : bool
        Start the shell's Krylov-Schur from the Chebyshev-filtered vector (``slepc_start``) rather
        than SLEPc's random one.

    Returns
    -------
    SlepcResult
        The step, its bracket ``[dt_safe, 2/sqrt(theta)]`` and the solver's figures.
    """
    if matrix not in MATRICES:
        raise InputError("slepc_matrix", f"unknown matrix {matrix!r}; choose one of {', '.join(MATRICES)}")
    shell_route = matrix == "shell"
    tolerance = (SHELL_TOLERANCE if shell_route else TOLERANCE) if tolerance is None else tolerance
    _, _, size = world()
    n_local, k_max, m_min = _local_figures(share)
    clock = time.perf_counter()
    mat, shell, mallocs, nonzeros = build_operator(share, matrix)
    release_memory()
    share.times["assembly"] = time.perf_counter() - clock
    share.peaks["assembly"] = peak_mib()
    clock = time.perf_counter()
    start = None
    if shell is not None and filtered_start:  # the serial route's Chebyshev-filtered start (slepc_start)
        from dtcrit.packing.distributed.slepc_start import chebyshev_start, start_vector

        layout = shell.layout

        def start(m):
            return chebyshev_start(m, start_vector(m, layout.packing, layout.n_own, seed=START_SEED))
    top = solve(mat, tolerance, SHELL_NCV if shell_route else NCV, norm=not shell_route, start=start)
    mat.destroy()
    share.times["solve"] = time.perf_counter() - clock
    share.peaks["solve"] = peak_mib()
    if shell is not None:  # the serial route's bounds, after the solve (its basis is freed by then)
        from dtcrit.packing.distributed.slepc_shell import shell_bounds

        clock = time.perf_counter()
        dt_safe, safe_from = shell_bounds(shell), SAFE_SHELL
        shell.free()
        share.times["bounds"] = time.perf_counter() - clock
        share.peaks["bounds"] = peak_mib()
    else:
        dt_safe, safe_from = 2.0 / math.sqrt(top["norm_inf"]) if top["norm_inf"] > 0 else math.inf, SAFE_ASSEMBLED
    del shell
    stages = list(share.times)
    rows = allgather([n_local, k_max, m_min, mallocs, nonzeros, top["matvec_time"],
                      *(share.times[k] for k in stages), *(share.peaks[k] for k in share.peaks)])
    n_contacts, k_max, m_min = int(rows[:, 0].sum()), float(rows[:, 1].max()), float(rows[:, 2].min())
    theta = top["theta"]
    omega = math.sqrt(theta) if theta > 0 else 0.0
    dt = 2.0 / omega if omega > 0 else math.inf
    times = {k: float(rows[:, 6 + i].max()) for i, k in enumerate(stages)}
    peaks = {k: float(rows[:, 6 + len(stages) + i].max()) for i, k in enumerate(share.peaks)}
    per_rank = [{"rank": r, "rows": int(6 * (b - a)), "contacts": int(rows[r, 0]),
                 "peak_rss_mib": float(rows[r, 6 + len(stages):].max())}
                for r, (a, b) in enumerate(split_rows(share.n, size, q) for q in range(size))]
    return SlepcResult(
        label=share.label, law=share.law, ranks=size, n_particles=share.n, dofs=6 * share.n, n_contacts=n_contacts,
        cn_mean=2.0 * n_contacts / share.n, k_max=k_max, m_min=m_min, omega_max=omega, dt_crit=dt, dt_safe=dt_safe,
        alpha=dt / math.sqrt(m_min / k_max) if k_max > 0 and math.isfinite(dt) and math.isfinite(m_min) else math.inf,
        rotational_fraction=float(top["rotational_fraction"]), solver="slepc krylovschur",
        tolerance=float(top["tolerance"]), ncv=int(top["ncv"]), iterations=int(top["iterations"]),
        matvecs=top["matvecs"], residual=float(top["residual"]),
        relative_residual=float(top["residual"] / theta) if theta > 0 else 0.0,
        matrix_mallocs=int(rows[:, 3].sum()), matrix_nonzeros=int(rows[:, 4].sum()),
        matvec_seconds=float(rows[:, 5].max()) / max(top["matvecs"], 1), times=times, peak_rss_mib=peaks,
        per_rank=per_rank, matrix=matrix, dt_safe_from=safe_from,
        dt_bracket=bracket(theta, dt_safe if math.isfinite(dt_safe) else 0.0, None).to_dict(),
        petsc_index_bits=_index_bits())


def analyse(packing: Packing, law=None, contacts: Contacts | None = None, *, tolerance: float | None = None,
            matrix: str = DEFAULT_MATRIX) -> SlepcResult:
    """``distribute`` then ``analyse_share`` (the caller's ``packing`` stays alive meanwhile; the command
    line drops its own reference in between, so that the O(N) input is freed before the matrix).

    Parameters
    ----------
    packing : Packing
        The whole packing (the same on every rank).
    law : object or None
        Contact law; default linear unit springs unless ``contacts`` carry a stiffness.
    contacts : Contacts or None
        A contact list every rank holds (default: found here).
    tolerance : float or None
        Relative residual tolerance of the eigen-solve (default: the route's).
    matrix : str
        ``"shell"`` (matrix-free) or ``"assembled"``.

    Returns
    -------
    SlepcResult
        The step and the solver's figures.
    """
    return analyse_share(distribute(packing, law, contacts), tolerance, matrix)


def _index_bits() -> int:
    """The loaded PETSc build's index width (the solve ran on it, so one is loaded)."""
    bits = loaded_bits()
    assert bits is not None  # petsc4py was imported to solve
    return bits
