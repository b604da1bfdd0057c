"""The two-thread product on the particles' halves (``matrix_free_kernels.halves_of``): no spare
vector, rows written by the two threads disjoint, the crossing contacts added after them.
References: the halves worked out here by a plain loop over the contacts, the assembled matrix
(``assembly``) and the one-thread product."""
from __future__ import annotations

import numba
import numpy as np
import pytest

from dtcrit.bench.packing_scaling import jittered_fcc
from dtcrit.packing.detection.overlaps import find_sphere_contacts
from dtcrit.packing.model import LinearLaw, Packing, apply_law
from dtcrit.packing.operators import matrix_free as mf
from dtcrit.packing.operators.assembly import mass_diagonal, scale_symmetric, stiffness_matrix

pytestmark = pytest.mark.skipif(not mf.kernels.available(), reason="the compiled loops need Numba")


def _halves_by_loop(ci, cj):
    """``(split, middle, crossing)`` by the definition, contact by contact."""
    split = int(ci[len(ci) // 2])
    middle = next(c for c in range(len(ci)) if ci[c] >= split)
    return split, middle, [c for c in range(middle) if cj[c] >= split]


def test_the_halves_of_sorted_contacts_match_their_definition():
    rng = np.random.default_rng(7)
    for _ in range(20):
        n = int(rng.integers(4, 200))
        i = np.sort(rng.integers(0, n, 300))
        j = i + rng.integers(0, 3, 300) * rng.integers(0, 2, 300)
        got = mf.kernels.halves_of(i, j)
        split, middle, cross = _halves_by_loop(i, j)
        if len(cross) > mf.kernels.CROSSING_MAX * len(i):
            assert got is None
            continue
        assert got is not None
        assert got[0].tolist() == [split, middle, len(i)] and got[1].tolist() == cross
        below = [c for c in range(middle) if j[c] < split]
        assert max(max(i[below], default=-1), max(j[below], default=-1)) < split <= min(i[middle:].min(), j[middle:].min())


def test_unsorted_or_much_crossing_contacts_have_no_halves():
    i, j = np.array([0, 2, 1, 3]), np.array([1, 3, 2, 3])
    assert mf.kernels.halves_of(i, j) is None  # not sorted by i
    assert mf.kernels.halves_of(np.array([0, 1, 2]), np.array([1, 0, 2])) is None  # i > j
    assert mf.kernels.halves_of(np.arange(10) % 2, np.full(10, 9)) is None
    spread = np.repeat(np.arange(50), 2)
    assert mf.kernels.halves_of(spread, np.full(100, 99)) is None  # every contact below the middle crosses


def _setup(packing, threads):
    c = apply_law(find_sphere_contacts(packing), LinearLaw(2.0, 0.6))
    md = mass_diagonal(packing)
    return mf.stiffness_operator(packing, c, threads=threads), scale_symmetric(stiffness_matrix(packing, c), md,
                                                                                inplace=True)


@pytest.mark.parametrize("sphere_loop", [True, False])
def test_the_halves_product_equals_the_assembled_matrix_with_no_spare_and_the_same_bits_on_one_thread(sphere_loop):
    op, a = _setup(jittered_fcc(4000), 2)
    assert op._halves is not None and op._halves[1].size < mf.kernels.CROSSING_MAX * op.contacts.count
    if not sphere_loop:
        op._sphere_args = None
    x = np.random.default_rng(3).standard_normal(a.shape[0])
    want = a @ x
    got = op.apply_into(x, np.empty_like(x))
    assert op._spare is None
    assert np.max(np.abs(got - want)) <= 1e-13 * np.max(np.abs(want))
    before = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        alone = op.apply_into(x, np.empty_like(x))
    finally:
        numba.set_num_threads(before)
    assert np.array_equal(alone, got)


def test_an_empty_first_half_and_rotational_springs_on_the_halves(monkeypatch):
    """Every contact on particle 0 (``middle == 0``: all on the second thread) and a lattice with
    rolling and twisting springs (the general loop): the assembled matrix, and the same bits on one thread."""
    monkeypatch.setattr(mf.kernels, "CROSSING_MAX", 1.0)  # a small lattice crosses more than a large one
    star = jittered_fcc(32)
    found = find_sphere_contacts(star)
    first = found.subset(found.i == 0)
    lattice_c = find_sphere_contacts(jittered_fcc(500))
    for packing, c in ((star, first), (jittered_fcc(500), lattice_c)):
        c = c.with_stiffness(2.0, 0.6, kr=0.3, ktw=0.2)
        op = mf.stiffness_operator(packing, c, threads=2)
        assert op._halves is not None and op._sphere_args is None
        md = mass_diagonal(packing)
        a = scale_symmetric(stiffness_matrix(packing, c), md, inplace=True)
        x = np.random.default_rng(8).standard_normal(a.shape[0])
        got = op.apply_into(x, np.empty_like(x))
        assert np.max(np.abs(got - a @ x)) <= 1e-13 * np.max(np.abs(a @ x))
        before = numba.get_num_threads()
        numba.set_num_threads(1)
        try:
            assert np.array_equal(op.apply_into(x, np.empty_like(x)), got)
        finally:
            numba.set_num_threads(before)
    assert mf.stiffness_operator(star, first.with_stiffness(1.0, 1.0), threads=2)._halves[0][1] == 0


def test_a_packing_numbered_at_random_keeps_the_blocks_and_their_spare():
    lattice = jittered_fcc(2000)
    shuffled = np.random.default_rng(4).permutation(lattice.n)
    op, a = _setup(Packing.spheres(lattice.positions[shuffled], 1.002, density=1.0, box=lattice.box), 2)
    assert op._halves is None and op._bounds is not None
    x = np.random.default_rng(5).standard_normal(a.shape[0])
    got = op.apply_into(x, np.empty_like(x))
    assert op._spare is not None
    assert np.max(np.abs(got - a @ x)) <= 1e-13 * np.max(np.abs(a @ x))


def test_the_product_refuses_an_output_overlapping_its_input():
    op, _ = _setup(jittered_fcc(32), 1)
    x = np.ones(op.shape[0])
    with pytest.raises(ValueError, match="overlap"):
        op.apply_into(x, x)
