"""The critical step of a packing on many processes (PETSc/SLEPc under MPI): the API behind
``dtcrit packing --backend slepc``.

Every rank reads or generates the whole packing (``dtcrit.packing.step.packing_input``, before any MPI:
the particle count chooses the PETSc build, ``petsc_build``), keeps its share of the contacts
(``slepc_backend.distribute``) and takes part in the Krylov-Schur solve (``slepc_analysis.analyse_share``);
every rank returns the same numbers, and a caller prints on rank 0 only.  ``dt_crit = 2/omega_max``
(Otsubo et al. 2017, Eq. (13)); the integrator's step at the modal damping ratio comes from
``dtcrit.packing.solvers.integrator_step.integrator_dt``.
"""
from __future__ import annotations

import os
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from dtcrit.errors import InputError
from dtcrit.packing.defaults import DEFAULT_RADIUS

if TYPE_CHECKING:
    from dtcrit.packing.distributed.slepc_backend import SlepcResult

__all__ = ["DistributedStep", "distributed_packing_step"]


@dataclass(frozen=True)
class DistributedStep:
    """The distributed solve's critical step, with the integrator's step beside it.

    Parameters
    ----------
    rank : int
        This process's MPI rank (0 prints).
    omega_max : float
        Largest eigenfrequency of ``M^-1/2 K M^-1/2`` [rad/s].
    dt_crit : float
        ``2 / omega_max`` [s].
    dt_safe : float
        The Gershgorin lower bound ``2/sqrt(|A|_inf)`` [s].
    integrator : str
        The integrator of the damped bound.
    damping_ratio : float
        Modal damping ratio of the highest mode.
    dt_integrator : float
        The integrator's step at that damping ratio [s] (0: no step is stable).
    integrator_formula : str
        The formula of ``dt_integrator``.
    result : SlepcResult
        The solver's figures (sizes, iterations, residual, stage times, memory per rank).

    Examples
    --------
    >>> from dtcrit import distributed_packing_step
    >>> step = distributed_packing_step(lattice="fcc", kn=1e5)  # doctest: +SKIP
    >>> step.to_json()["schema"]  # doctest: +SKIP
    'dtcrit-packing-slepc/1'
    """

    rank: int
    omega_max: float
    dt_crit: float
    dt_safe: float
    integrator: str
    damping_ratio: float
    dt_integrator: float
    integrator_formula: str
    result: SlepcResult = field(repr=False, compare=False)

    def to_json(self) -> dict:
        """The JSON document ``dtcrit packing --backend slepc --json`` prints.

        Returns
        -------
        dict
            The envelope (schema ``dtcrit-packing-slepc/1``, units), the solver's figures and the
            integrator's step; non-finite numbers are ``None``.
        """
        from dtcrit.json_meta import envelope
        from dtcrit.packing.distributed import slepc_backend as sb

        doc = envelope(sb.JSON_SCHEMA, sb.UNITS)
        doc.update(self.result.to_dict(), integrator=self.integrator, damping_ratio=float(self.damping_ratio),
                   dt_integrator=self.dt_integrator, integrator_formula=self.integrator_formula)
        return doc

    def to_text(self) -> str:
        """The text ``dtcrit packing --backend slepc`` prints.

        Returns
        -------
        str
            The solver's report and the integrator's line, without a final newline.
        """
        from dtcrit.packing.distributed import slepc_backend as sb

        return (sb.format_result(self.result) + "\n"
                + f"{self.integrator}, modal damping ratio {self.damping_ratio:g}: dt = {self.dt_integrator:.6g} s"
                + ("  (no step is stable)" if self.dt_integrator == 0 else ""))


def distributed_packing_step(source: str | os.PathLike | None = None, *, lattice: str | None = None, cells: int = 2,
                             random: int | None = None, cn: float = 6.0, sizes: str = "mono", spread: float = 0.0,
                             seed: int = 0, radius: float = DEFAULT_RADIUS, density: float | None = None,
                             kn: float | None = None, ks: float | None = None, youngs: float | None = None,
                             poisson: float = 0.25, snapshot: int = -1, integrator: str = "velocity-verlet",
                             damping_ratio: float = 0.0, partitioned: bool | None = None,
                             matrix: str = "shell", petsc_indices: str = "auto") -> DistributedStep:
    """The critical step of a packing by PETSc and SLEPc on the processes of an MPI launcher (collective).

    Parameters
    ----------
    source, lattice, cells, random, cn, sizes, spread, seed, radius, density, kn, ks, youngs, poisson, snapshot
        The packing and its contact law, as in :func:`dtcrit.packing.step.packing_step`.
    integrator : str
        Integrator of the damped bound.
    damping_ratio : float
        Modal damping ratio of the highest mode (finite, at least 0).
    partitioned : bool or None
        Read ``source`` in pieces, each rank only its Morton slab and halo
        (``dtcrit.packing.distributed.partitioned_input``); None: for a ``.npz`` sphere file only.
    matrix : str
        ``"shell"`` (matrix-free: the contact kernel under a PETSc shell matrix, ``slepc_shell``) or
        ``"assembled"`` (``MPISBAIJ``).
    petsc_indices : str
        ``"auto"`` (Debian's 64-bit-index PETSc build when ``6 N > 2^31 - 1``, else the 32-bit one),
        ``"32"`` or ``"64"`` (``petsc_build``); chosen before petsc4py is first imported in the process.

    Returns
    -------
    DistributedStep
        The same numbers on every rank, with this rank's number.

    Raises
    ------
    InputError
        Bad input, a packing without a vibrating mode, more DOFs than ``petsc_indices="32"`` numbers,
        64-bit indices wanted without Debian's 64-bit build, or a process that already loaded the other build.
    ImportError
        petsc4py or slepc4py is missing (``python3 dev.py mpi-env`` builds ``.venv-mpi``).

    Examples
    --------
    >>> from dtcrit import distributed_packing_step
    >>> step = distributed_packing_step(lattice="sc", kn=1e6)  # doctest: +SKIP
    >>> step.omega_max * step.dt_crit  # doctest: +SKIP
    2.0
    """
    from dtcrit.packing.distributed import slepc_analysis as sa
    from dtcrit.packing.distributed import slepc_backend as sb
    from dtcrit.packing.distributed.mpi_support import world
    from dtcrit.packing.distributed.partitioned_share import partitioned_share, wants_partitioned
    from dtcrit.packing.distributed.petsc_build import index_bits, peek_count, select_build
    from dtcrit.packing.solvers.integrator_step import integrator_dt
    from dtcrit.packing.step import packing_input

    integrator_dt(1.0, integrator, damping_ratio)  # bad names and ratios fail before the work
    if matrix not in sa.MATRICES:
        raise InputError("slepc_matrix", f"unknown matrix {matrix!r}; choose one of {', '.join(sa.MATRICES)}")
    index_bits(None, petsc_indices)  # an unknown width fails before the work
    clock = time.perf_counter()
    if wants_partitioned(source, partitioned):  # the count from the file's header, then MPI
        select_build(index_bits(peek_count(source, snapshot), petsc_indices))
        _, rank, _ = world()
        share, _ = partitioned_share(source, dict(lattice=lattice, random=random, density=density, kn=kn, ks=ks,
                                                  youngs=youngs, poisson=poisson, snapshot=snapshot))
        return _finish(rank, sa.analyse_share(share, matrix=matrix), integrator, damping_ratio)
    given = packing_input(source, lattice=lattice, cells=cells, random=random, cn=cn, sizes=sizes, spread=spread,
                          seed=seed, radius=radius, density=density, kn=kn, ks=ks, youngs=youngs, poisson=poisson,
                          snapshot=snapshot, check_memory=False)  # no MPI yet: the count chooses the build
    select_build(index_bits(given.packing.n, petsc_indices))
    _, rank, _ = world()
    share = sb.distribute(given.packing, given.law, given.contacts, t_input=time.perf_counter() - clock)
    del given  # the O(N) input is not needed by the matrix and the solve
    result = sa.analyse_share(share, matrix=matrix)
    del share
    return _finish(rank, result, integrator, damping_ratio)


def _finish(rank: int, result: SlepcResult, integrator: str, damping_ratio: float) -> DistributedStep:
    """The step of a solved share, with the integrator's step (refusing a packing without a vibrating mode)."""
    from dtcrit.packing.solvers.integrator_step import integrator_dt

    if result.n_contacts == 0:
        raise InputError("packing", "no two particles touch: no contact limits the step (nothing to analyse)")
    if not result.omega_max > 0:
        raise InputError("packing", "every contact has zero stiffness: no vibrating mode, no critical step")
    dt_int, formula = integrator_dt(result.omega_max, integrator, damping_ratio)
    return DistributedStep(rank=rank, omega_max=result.omega_max, dt_crit=result.dt_crit, dt_safe=result.dt_safe,
                           integrator=integrator, damping_ratio=float(damping_ratio), dt_integrator=dt_int,
                           integrator_formula=formula, result=result)
