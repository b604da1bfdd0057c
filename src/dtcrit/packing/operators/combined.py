"""A linear combination of two operators of the same shape: the damped step's ``2h C~ + h^2 K~``.

Used by ``dtcrit.packing.solvers.damped_step`` on the matrix-free operators of
``dtcrit.packing.operators.matrix_free`` (which re-exports it).
"""
from __future__ import annotations

import numpy as np
import scipy.sparse.linalg as spla


class CombinedOperator(spla.LinearOperator):
    """``alpha * A + beta * B`` of two operators of the same shape (``damped``: ``2h C~ + h^2 K~``).

    Parameters
    ----------
    a, b : scipy.sparse.linalg.LinearOperator
        The two operators (same shape).
    alpha, beta : float
        Their factors.
    """

    def __init__(self, a, alpha: float, b, beta: float):
        super().__init__(dtype=np.dtype(float), shape=a.shape)
        self.a, self.alpha, self.b, self.beta = a, float(alpha), b, float(beta)

    def _matvec(self, x):
        x = np.asarray(x, float).reshape(-1)
        return self.alpha * (self.a @ x) + self.beta * (self.b @ x)

    def _adjoint(self):
        return self
