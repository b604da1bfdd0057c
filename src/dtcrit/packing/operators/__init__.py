"""Operators of a packing: sparse global mass and stiffness matrices, and the matrix-free contact operator.

Modules: ``assembly`` (``scipy.sparse`` M, K, C), ``matrix_free`` (``A v`` from the contact list), ``matrix_free_kernels``
(its compiled loops).
"""
