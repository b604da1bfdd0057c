"""What the eigen-solve of a very large packing holds: ARPACK is handed the filtered start vector
itself (no copy), and the matrix-free operator holds its scale, not the mass diagonal.  References:
the bytes NumPy reports to ``tracemalloc`` (one 6N vector is ``48 N`` bytes), the assembled matrix's
dense eigenvalue, and ``assembly.mass_diagonal``."""
from __future__ import annotations

import tracemalloc

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse.linalg as spla

from dtcrit.bench.packing_scaling import jittered_fcc
from dtcrit.packing.detection.overlaps import find_sphere_contacts
from dtcrit.packing.model import LinearLaw, apply_law
from dtcrit.packing.operators.assembly import mass_diagonal, scale_symmetric, stiffness_matrix
from dtcrit.packing.operators.matrix_free import stiffness_operator
from dtcrit.packing.solvers import largest_mode as eigen


def _numpy_takes_the_array_as_the_copy() -> bool:
    """Whether ``np.array(obj, copy=True)`` keeps what ``obj.__array__(copy=True)`` returns (NumPy >= 2.1)."""
    probe = np.zeros(3)

    class Hands:
        def __array__(self, dtype=None, copy=None):
            return probe

    return np.shares_memory(np.array(Hands(), copy=True, dtype="d"), probe)


HANDS_OVER = _numpy_takes_the_array_as_the_copy()
needs_hand_over = pytest.mark.skipif(not HANDS_OVER, reason="this NumPy copies what __array__ returns for copy=True")


def _operator(n: int):
    packing = jittered_fcc(n)
    return packing, stiffness_operator(packing, apply_law(find_sphere_contacts(packing), LinearLaw(1.0, 1.0)))


def _lean_peak(monkeypatch, op, hand_over: bool) -> tuple[float, int]:
    """``omega_max^2`` by the lean route and the traced peak of the solve above what was held before."""
    monkeypatch.setattr(eigen, "LEAN_DOFS", 10)
    if not hand_over:
        monkeypatch.setattr(eigen, "_HandedOver", lambda v: v)
    op.apply_into(np.ones(op.shape[0]), np.empty(op.shape[0]))  # the operator's own buffers exist before
    tracemalloc.start()
    try:
        base = tracemalloc.get_traced_memory()[0]
        top = eigen.largest_mode(op)
        peak = tracemalloc.get_traced_memory()[1] - base
    finally:
        tracemalloc.stop()
    return top.value, peak


@needs_hand_over
def test_arpack_is_handed_the_start_vector_itself(monkeypatch):
    """With the hand-over the solve's peak is one 6N vector lower, and the answer the same to the bit."""
    _, op = _operator(4000)
    vector = 8 * op.shape[0]
    _lean_peak(monkeypatch, op, True)  # once before: first calls allocate what later calls reuse
    handed, peak_handed = _lean_peak(monkeypatch, op, True)
    monkeypatch.undo()
    copied, peak_copied = _lean_peak(monkeypatch, op, False)
    assert handed == copied
    assert peak_copied - peak_handed >= 0.95 * vector


def test_the_lean_route_matches_the_dense_solve_with_the_hand_over(monkeypatch):
    packing, op = _operator(500)
    monkeypatch.setattr(eigen, "LEAN_DOFS", 10)
    top = eigen.largest_mode(op)
    md = mass_diagonal(packing)
    dense = sla.eigvalsh(scale_symmetric(stiffness_matrix(packing, op.contacts), md, inplace=True).toarray())[-1]
    # a Ritz value lies below lambda_max, and (top eigenvalue isolated to within the residual) within it
    assert top.method == "eigsh" and top.value <= dense * (1 + 1e-12)
    assert dense - top.value <= top.residual and top.residual <= 1e-5 * dense


def test_a_start_vector_is_handed_over_once():
    vector = np.arange(4.0)
    handed = eigen._HandedOver(vector)
    assert np.shares_memory(np.array(handed, copy=True, dtype="d"), vector) == HANDS_OVER
    with pytest.raises(RuntimeError, match="handed over"):
        np.asarray(handed)


def test_an_unconverged_lean_solve_still_brackets_with_the_start_s_rayleigh_quotient(monkeypatch):
    """ARPACK stopped after one restart: the lower end is the filtered start's Rayleigh quotient (the
    start itself went to ARPACK), below the dense top eigenvalue and above zero."""
    packing, op = _operator(500)
    monkeypatch.setattr(eigen, "LEAN_DOFS", 10)
    with pytest.raises(eigen.NotConvergedError) as caught:
        eigen.largest_mode(op, maxiter=1, tol=1e-300)
    md = mass_diagonal(packing)
    dense = sla.eigvalsh(scale_symmetric(stiffness_matrix(packing, op.contacts), md, inplace=True).toarray())[-1]
    lower = caught.value.lower
    assert 0.5 * dense < lower <= dense * (1 + 1e-12)


def test_the_operator_holds_its_scale_not_the_mass_diagonal():
    packing, op = _operator(500)
    assert op._given_mass is None
    md = mass_diagonal(packing)
    assert np.array_equal(op.mass_diag, md) and op.mass_diag is not op.mass_diag
    assert np.array_equal(op.scale6.reshape(-1), 1.0 / np.sqrt(md))
    given = stiffness_operator(packing, op.contacts, mass_diag=2.0 * md)
    assert np.array_equal(given.mass_diag, 2.0 * md)
    x = np.random.default_rng(3).standard_normal(op.shape[0])
    assert isinstance(op, spla.LinearOperator)
    y = op @ x
    assert np.allclose(given @ x, 0.5 * y, rtol=1e-13, atol=1e-13 * np.abs(y).max())
