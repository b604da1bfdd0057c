"""What the PETSc/SLEPc back-end needs of MPI, through petsc4py alone (no mpi4py): the world,
an all-gather of a few numbers per rank, a collective check point for errors met by some ranks
only, and the process's memory (``dtcrit.packing.distributed.slepc_backend``).

petsc4py and slepc4py are imported inside the functions, so this module imports without them; then
``petsc()`` raises the one-line ``InputError`` that says what to install.
"""
from __future__ import annotations

import os
import resource
import sys

import numpy as np

from dtcrit.errors import InputError

INSTALL = ("--backend slepc needs petsc4py and slepc4py ({why}): apt-get install python3-slepc4py-real "
           "python3-petsc4py-real openmpi-bin, then python3 dev.py mpi-env, and run "
           "mpirun -n P .venv-mpi/bin/dtcrit packing ... --backend slepc")


def petsc():
    """``(PETSc, SLEPc)``, initialised on ``COMM_WORLD``; ``InputError("backend", INSTALL)`` without them.

    Returns
    -------
    tuple
        The ``petsc4py.PETSc`` and ``slepc4py.SLEPc`` modules.
    """
    try:
        from petsc4py import PETSc
        from slepc4py import SLEPc
    except Exception as exc:  # ImportError, or a NumPy ABI mismatch raised from the compiled module
        why = " ".join(str(exc).split()[:12]) or type(exc).__name__
        raise InputError("backend", INSTALL.format(why=why)) from None
    return PETSc, SLEPc


def world():
    """``(comm, rank, size)`` of ``PETSc.COMM_WORLD``; an ``InputError`` when a launcher started several
    processes that do not see each other (an ``mpirun`` of another MPI than petsc4py's).

    Returns
    -------
    tuple
        ``(comm, rank, size)``: the communicator, this process's rank and the number of ranks.
    """
    PETSc, _ = petsc()
    comm = PETSc.COMM_WORLD
    launched = next((int(os.environ[k]) for k in ("OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE")
                     if os.environ.get(k, "").isdigit()), 1)
    if comm.getSize() == 1 and launched > 1:
        raise InputError("backend", f"the launcher started {launched} processes but each sees only itself: run the "
                                    "mpirun of the MPI petsc4py was built with (Debian: openmpi-bin)")
    return comm, comm.getRank(), comm.getSize()


LOCAL_SIZE_KEYS = ("OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS", "PMI_LOCAL_SIZE", "SLURM_NTASKS_PER_NODE")
"""Environment variables in which launchers give the number of ranks on this node (Open MPI, MPICH's
Hydra, PMI, Slurm)."""


def rank_threads() -> int:
    """Threads for this rank's compiled loops: the cores it may run on, shared with the other ranks of
    its node unless the launcher bound it to its own (then its affinity set is its share already).

    Open MPI binds each rank to a core when there are at most two ranks; unbound ranks of one node see
    every core, and ``cores / local ranks`` keeps them from oversubscribing the node.  Without a
    launcher's count of local ranks, every rank of the world is taken to share this node.

    Returns
    -------
    int
        At least 1, at most the cores this process may run on.
    """
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    if cores < (os.cpu_count() or cores):  # bound by the launcher: these cores are this rank's
        return max(1, cores)
    local = next((int(os.environ[k]) for k in LOCAL_SIZE_KEYS if os.environ.get(k, "").isdigit()), 0)
    if local <= 0:
        local = world()[2]
    return max(1, cores // local)


def started_rank() -> int | None:
    """The process's rank once petsc4py has started MPI (``petsc4py.PETSc`` imported), without importing it.

    Returns
    -------
    int or None
        ``COMM_WORLD``'s rank; None before MPI started (the caller then falls back on the launcher's
        environment) or when it cannot be read.
    """
    module = sys.modules.get("petsc4py.PETSc")
    if module is None:
        return None
    try:
        return int(module.COMM_WORLD.getRank())
    except Exception:  # a half-initialised module: the launcher's environment decides
        return None


def allgather(values) -> np.ndarray:
    """Every rank's row of numbers, ``(size, k)``, on every rank (a PETSc vector scattered to all).

    Parameters
    ----------
    values : array_like
        This rank's ``k`` numbers (the same ``k`` on every rank).

    Returns
    -------
    numpy.ndarray
        Shape (size, k): row ``r`` holds rank ``r``'s numbers.
    """
    PETSc, _ = petsc()
    row = np.atleast_1d(np.asarray(values, dtype=float))
    vec = PETSc.Vec().createMPI((row.size, PETSc.DECIDE), comm=PETSc.COMM_WORLD)
    vec.setArray(row)
    scatter, everything = PETSc.Scatter.toAll(vec)
    scatter.scatter(vec, everything, addv=PETSc.InsertMode.INSERT_VALUES, mode=PETSc.ScatterMode.FORWARD)
    out = everything.getArray().copy().reshape(-1, row.size)
    for obj in (scatter, everything, vec):
        obj.destroy()
    return out


def agree(error: Exception | None) -> None:
    """A collective check point: when any rank failed, every rank raises: the lowest failing rank its
    own error, marked ``report_here`` (the one line printed), the others a bare ``SystemExit(2)``.

    Parameters
    ----------
    error : Exception or None
        This rank's error (``None``: it succeeded).
    """
    _, rank, size = world()
    failed = allgather([0.0 if error is None else float(size - rank)])[:, 0]
    if failed.max() == 0:
        return
    if size - int(failed.max()) == rank:  # the lowest failing rank: this one failed
        if error is None:
            raise RuntimeError("agree: the lowest failing rank holds no error")
        setattr(error, "report_here", True)  # the CLI prints this one error's line
        raise error
    raise SystemExit(2)


def release_memory() -> None:
    """Give the heap that freed temporaries leave back to the system (glibc's ``malloc_trim``; a no-op
    elsewhere): otherwise the contact search's and the assembly's small blocks stay resident under
    the solve's basis (measured: 1.1 GiB of 5.1 at 10^6 spheres on one rank).
    """
    try:
        import ctypes

        ctypes.CDLL("libc.so.6").malloc_trim(0)
    except (OSError, AttributeError):
        pass


def peak_mib() -> float:
    """The peak resident memory of this process so far [MiB].

    Returns
    -------
    float
        ``ru_maxrss`` in MiB.
    """
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
