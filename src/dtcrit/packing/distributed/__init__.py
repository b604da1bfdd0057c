"""The distributed back-end: PETSc matrices and SLEPc Krylov-Schur under MPI (``--backend slepc``).

Modules: ``step`` (``distributed_packing_step``, the API), ``slepc_backend`` (the solve), ``slepc_result`` (what it reports), ``mpi_support`` (MPI through petsc4py), ``slab_contacts`` (the contacts one
rank needs), ``partitioned_input`` (each rank reads a piece of the file and keeps its Morton slab and halo)
and ``partitioned_share`` (the solve's share of a rank from it).
"""
