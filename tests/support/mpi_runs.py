"""Running the MPI back-end from tests: ``mpirun -n P .venv-mpi/bin/python ARGS`` on this source tree.

Every test that starts ranks goes through here: the environment (one BLAS thread, Open MPI's settings
for containers and for root, this tree's sources first on the path), the check that ``.venv-mpi`` and
``mpirun`` exist (a failure under ``CI=true``, a skip elsewhere) and the retry of a start-up that fails
inside MPI (seen on a busy machine).
"""
from __future__ import annotations

import os
import shutil
import subprocess

import pytest

from support.ci import in_ci
from support.paths import REPO_ROOT, SRC

MPI_PY = REPO_ROOT / ".venv-mpi" / "bin" / "python"


def mpirun_or_skip() -> str:
    """The path of ``mpirun``; fails (``CI=true``) or skips the test when it or ``.venv-mpi`` is missing."""
    mpirun = shutil.which("mpirun")
    missing = [what for what, ok in ((".venv-mpi (python3 dev.py mpi-env)", MPI_PY.exists()),
                                     ("mpirun (apt-get install openmpi-bin)", mpirun is not None)) if not ok]
    if missing or mpirun is None:
        message = "PETSc/SLEPc back-end: missing " + ", ".join(missing)
        if in_ci():
            pytest.fail(message)
        pytest.skip(message)
    return mpirun


def mpi_env(pythonpath: str = str(SRC), **extra: str) -> dict:
    """The environment of the ranks: this process's, with ``pythonpath`` and ``extra`` set."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV")}
    env.update(PYTHONPATH=pythonpath, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", PYTHONDONTWRITEBYTECODE="1",
               **extra)
    env.setdefault("OMPI_MCA_btl_vader_single_copy_mechanism", "none")  # containers without cross-memory attach
    env.setdefault("OMPI_MCA_rmaps_base_oversubscribe", "1")  # more ranks than the slots counted
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    return env


def run_ranks(ranks: int, *args: str, env: dict | None = None, timeout: float = 300) -> subprocess.CompletedProcess:
    """``mpirun -n ranks .venv-mpi/bin/python ARGS`` from the repository root, retried twice when the
    start-up fails inside MPI.
    """
    cmd = [mpirun_or_skip(), "-n", str(ranks), str(MPI_PY), *args]
    for _ in range(3):
        proc = subprocess.run(cmd, capture_output=True, text=True, env=env or mpi_env(), cwd=REPO_ROOT,
                              timeout=timeout)
        if proc.returncode in (0, 2) or "MPI_Init" not in proc.stdout + proc.stderr:
            break
    return proc


def run_packing(ranks: int, *args: str, env: dict | None = None) -> subprocess.CompletedProcess:
    """``dtcrit packing ARGS --backend slepc`` on ``ranks`` ranks (``run_ranks``)."""
    return run_ranks(ranks, "-m", "dtcrit", "packing", *args, "--backend", "slepc", env=env)
