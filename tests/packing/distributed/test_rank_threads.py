"""The cores a rank's compiled loops use (``mpi_support.rank_threads``), on made-up machines: its own
cores when the launcher bound it, else the node's cores shared among the node's ranks."""
from __future__ import annotations

import os

import pytest

from dtcrit.packing.distributed import mpi_support


@pytest.fixture
def machine(monkeypatch):
    """Set this process's cores, the machine's and the launcher's local rank count."""
    for key in mpi_support.LOCAL_SIZE_KEYS:
        monkeypatch.delenv(key, raising=False)

    def make(affinity: int, cores: int, local: int | None = None, key: str = "OMPI_COMM_WORLD_LOCAL_SIZE"):
        monkeypatch.setattr(os, "sched_getaffinity", lambda pid: set(range(affinity)), raising=False)
        monkeypatch.setattr(os, "cpu_count", lambda: cores)
        if local is not None:
            monkeypatch.setenv(key, str(local))

    return make


@pytest.mark.parametrize("affinity, cores, local, want", [
    (1, 2, 2, 1),    # Open MPI binds two ranks to a core each
    (2, 8, 4, 2),    # bound to two cores (--map-by slot:PE=2): both are the rank's
    (8, 8, 1, 8),    # one unbound rank: the whole node
    (8, 8, 2, 4),    # two unbound ranks share the node
    (8, 8, 3, 2),    # 8 // 3
    (2, 2, 4, 1),    # oversubscribed: at least one thread
])
def test_threads_follow_the_binding_and_the_ranks_of_the_node(machine, affinity, cores, local, want):
    machine(affinity, cores, local)
    assert mpi_support.rank_threads() == want


@pytest.mark.parametrize("key", ["MPI_LOCALNRANKS", "PMI_LOCAL_SIZE", "SLURM_NTASKS_PER_NODE"])
def test_other_launchers_local_rank_counts(machine, key):
    machine(6, 6, 3, key)
    assert mpi_support.rank_threads() == 2


def test_without_a_local_count_the_world_shares_the_node(machine, monkeypatch):
    machine(4, 4)
    monkeypatch.setattr(mpi_support, "world", lambda: (None, 0, 4))
    assert mpi_support.rank_threads() == 1
