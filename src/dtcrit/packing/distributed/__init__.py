"""The distributed back-end: PETSc matrices and SLEPc Krylov-Schur under MPI (``--backend slepc``).

Modules: ``step`` (``distributed_packing_step``, the API), ``slepc_backend`` (the share, the matrix, the solve),
``slepc_analysis`` (operator, solve and result: the stage after the share), ``slepc_shell`` (the
matrix-free shell matrix: the contact kernel on each rank's contacts, the halo through ghosted vectors),
``slepc_start`` (the shell's Chebyshev-filtered start vector), ``slepc_result`` (what it reports),
``mpi_support`` (MPI through petsc4py), ``petsc_build`` (the PETSc build of 32- or 64-bit indices,
chosen before petsc4py is imported), ``slab_contacts`` (the contacts one rank needs),
``partitioned_input`` (each rank keeps its Morton slab and halo of a file read in pieces by
``partitioned_read``) and ``partitioned_share`` (the solve's share of a rank from it).
"""
