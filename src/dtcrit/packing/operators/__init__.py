"""Operators of a packing: sparse global mass and stiffness matrices, and the matrix-free contact operator.

Modules: ``contact_element`` (the 6-DOF contact element, written once: motions, frame law, action),
``element_matrices`` (its matrices ``B``, ``T`` and blocks), ``assembly`` (``scipy.sparse`` M, K, C),
``matrix_free`` (``A v`` from the contact list), ``matrix_free_kernels`` (its compiled loops),
``numba_runtime`` (Numba at run time: the loops' decorator, ``prange``, threads), ``particle_pass``
(the bounds' diagonal blocks and row sums, gathered by particle), ``scattered_pass`` (its NumPy
fallback), ``combined`` (a sum of two operators).
"""
