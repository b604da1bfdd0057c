"""32-bit particle indices in the contact list (dtcrit.packing.contact_set.index_dtype) where ``6 N < 2^31``.

The sphere detection gives int32 ``i``, ``j``; the compiled loops take them uncopied (one more compiled
version of a loop, no more).  References: the same contacts with int64 indices through the same loops
and the assembled matrix -- the same bits -- and, for the index arithmetic near the limit (``36 p``,
``p N + q``), the exact values in Python integers.
"""
from __future__ import annotations

from collections import Counter
from dataclasses import replace

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from dtcrit.packing.bounds import estimate_kernels
from dtcrit.packing.bounds.estimates import single_contact_frequencies
from dtcrit.packing.contact_set import INDEX_LIMIT, Contacts, index_dtype
from dtcrit.packing.detection.overlaps import find_sphere_contacts
from dtcrit.packing.distributed.slab_contacts import slab_of_list
from dtcrit.packing.generators.lattices import lattice
from dtcrit.packing.generators.random_packing import random_packing
from dtcrit.packing.model import LinearLaw, Packing, apply_law
from dtcrit.packing.operators import matrix_free_kernels as kernels
from dtcrit.packing.operators import particle_pass
from dtcrit.packing.operators.assembly import damping_matrix, mass_diagonal, stiffness_matrix
from dtcrit.packing.operators.matrix_free import ContactOperator
from dtcrit.packing.operators.scattered_pass import row_entries

PATHS = [False] + ([True] if kernels.available() else [])
needs_numba = pytest.mark.skipif(not kernels.available(), reason="the compiled loops need Numba")
LAST = (INDEX_LIMIT - 1) // 6  # the largest N of int32 indices


def _wide(c: Contacts) -> Contacts:
    return replace(c, i=c.i.astype(np.int64), j=c.j.astype(np.int64))


def _cases():
    rnd = random_packing(90, cn=6.5, sizes="lognormal", spread=0.4, seed=8)
    c = find_sphere_contacts(rnd)
    rng = np.random.default_rng(3)
    nc = c.count
    every = c.with_stiffness(rng.uniform(1e3, 1e6, nc), rng.uniform(1e2, 1e6, nc), kr=rng.uniform(0, 1e-2, nc),
                             ktw=rng.uniform(0, 1e-2, nc)).with_normal_force(rng.uniform(-5.0, 20.0, nc))
    every = every.with_damping(rng.uniform(0, 3.0, nc), 0.4, cr=rng.uniform(0, 1e-3, nc), ctw=1e-4)
    rot = Rotation.random(rnd.n, random_state=2).as_matrix()
    rotated = Packing(rnd.positions, rnd.masses, rnd.inertia * rng.uniform(0.5, 2.0, rnd.inertia.shape), rnd.radii,
                      box=rnd.box, orientations=rot)
    fcc = lattice("fcc", 1)
    return {
        "spheres-linear": (rnd, apply_law(c, LinearLaw(2.5e5, 0.9e5))),  # the sphere loop
        "spheres-every-term": (rnd, every),  # the general loop
        "rotated-every-term": (rotated, every),
        "fcc-self-images": (fcc, apply_law(find_sphere_contacts(fcc), LinearLaw(3.0, 0.2))),
    }


CASES = _cases()


def test_the_index_dtype_is_int32_exactly_while_every_dof_index_fits():
    """``6 N < 2^31``: every DOF index ``6 p + 5`` of the last particle fits int32, one more does not."""
    assert index_dtype(0) == np.int32 and index_dtype(LAST) == np.int32 and index_dtype(LAST + 1) == np.int64
    assert 6 * (LAST - 1) + 5 <= np.iinfo(np.int32).max < 6 * LAST + 6
    assert int(np.int32(LAST - 1) * 6 + 5) == 6 * (LAST - 1) + 5  # the kernels' 6 p + k stays exact in int32


def test_the_sphere_detection_gives_int32_indices():
    """Both searches (one tree; every image of a narrow box) give int32 indices of the right particles."""
    for p in (CASES["spheres-linear"][0], lattice("sc", 1), lattice("fcc", 2)):  # one tree; every image
        c = find_sphere_contacts(p)
        assert c.count > 0 and c.i.dtype == np.int32 and c.j.dtype == np.int32
        assert c.i.max() < p.n and c.j.max() < p.n and np.all(np.diff(c.i) >= 0)


def test_the_loops_take_int32_uncopied_and_mixed_as_int64():
    """int32 indices reach the loops as they are; an int32/int64 mix as two int64 arrays (one version)."""
    c = CASES["spheres-linear"][1]
    ci, cj = kernels.kernel_indices(c)
    assert ci is c.i and cj is c.j
    mixed = kernels.kernel_indices(replace(c, j=c.j.astype(np.int64)))
    assert mixed[0].dtype == mixed[1].dtype == np.int64 and np.array_equal(mixed[0], c.i)


def _ops(p, c, kind, compiled, threads=None):
    md = mass_diagonal(p)
    return [ContactOperator(p, cc, kind, mass_diag=md, compiled=compiled, threads=threads) for cc in (c, _wide(c))]


def _kinds(c):
    return ["stiffness"] + (["damping"] if c.damped else [])


@pytest.mark.parametrize("compiled", PATHS)
@pytest.mark.parametrize("name", sorted(CASES))
def test_int32_indices_give_the_bits_of_int64_ones(name, compiled):
    """Products (one block and two), the particle pass and the single-contact frequencies."""
    p, c = CASES[name]
    x = np.random.default_rng(1).standard_normal(p.dofs)
    w = np.random.default_rng(2).uniform(0.1, 3.0, p.dofs)
    for kind in _kinds(c):
        narrow, wide = _ops(p, c, kind, compiled)
        if compiled:
            assert narrow._kernel_args[0].dtype == np.int32 and wide._kernel_args[0].dtype == np.int64
        assert np.array_equal(narrow @ x, wide @ x)
        for a, b in zip(narrow.block_summary(), wide.block_summary()):
            assert np.array_equal(a, b)
        assert np.array_equal(narrow.diagonal_blocks(), wide.diagonal_blocks())
        assert np.array_equal(narrow.abs_row_sums(w), wide.abs_row_sums(w))
        if compiled:
            blocks = _ops(p, c, kind, True, threads=2)
            assert np.array_equal(blocks[0] @ x, blocks[1] @ x)
    f32, f64 = (single_contact_frequencies(p, cc, compiled=compiled) for cc in (c, _wide(c)))
    assert np.array_equal(f32, f64)


@pytest.mark.parametrize("name", sorted(CASES))
def test_the_assembled_matrix_of_int32_indices_is_that_of_int64(name):
    """``K`` and ``C`` assembled (BSR data, indices, indptr) from int32 indices: those of int64 ones."""
    p, c = CASES[name]
    for build in (stiffness_matrix, damping_matrix):
        a, b = build(p, c), build(p, _wide(c))
        for part in ("data", "indices", "indptr"):
            assert np.array_equal(getattr(a, part), getattr(b, part))


@needs_numba
def test_each_loop_is_compiled_for_int32_and_int64_indices_at_most(monkeypatch):
    """Run every loop on both widths; then the signatures of each loop that differ only in the index
    width number two at most (``ci``, ``cj`` share theirs: ``kernel_indices``).
    """
    for name in ("spheres-linear", "rotated-every-term"):
        p, c = CASES[name]
        for cc in (c, _wide(c)):
            op = ContactOperator(p, cc, "stiffness", compiled=True)
            op @ np.ones(p.dofs)
            op.block_summary()
            op.diagonal_blocks(np.array([0, 2]))
            estimate_kernels.contact_frequencies(p, cc)
            ContactOperator(p, cc, "stiffness", compiled=True, threads=2) @ np.ones(p.dofs)
            with monkeypatch.context() as m:  # the frequencies' blocks too
                m.setattr(estimate_kernels, "PARALLEL_MIN_CONTACTS", 0)
                estimate_kernels.contact_frequencies(p, cc)
    monkeypatch.setattr(kernels, "CROSSING_MAX", 1.0)  # a small lattice crosses more than a large one
    fcc = lattice("fcc", 4)  # sorted contacts: the halves' drivers
    spheres = apply_law(find_sphere_contacts(fcc), LinearLaw(1.0, 1.0))
    for cc in (spheres, _wide(spheres)):
        for sphere_loop in (True, False):
            op = ContactOperator(fcc, cc, "stiffness", compiled=True, threads=2)
            assert op._halves is not None
            if not sphere_loop:
                op._sphere_args = None
            op @ np.ones(fcc.dofs)
    loops = [kernels.apply_span, kernels.apply_spheres_span, kernels.apply_blocks_general, kernels.apply_blocks_spheres,
             kernels.apply_halves_general, kernels.apply_halves_spheres,
             particle_pass._count_c, particle_pass._fill_c, particle_pass._summary_c, particle_pass._blocks_c,
             estimate_kernels.frequencies_span, estimate_kernels.frequencies_blocks]
    for loop in loops:
        sigs = [tuple(str(t) for t in s) for s in loop.signatures]
        assert sigs, loop
        widths = Counter(tuple(t.replace("int32", "int64") for t in s) for s in sigs)
        assert max(widths.values()) <= 2, (loop, sigs)


def test_flat_row_indices_near_the_limit_are_exact():
    """``36 p + k`` (the NumPy path's scatter of 6 x 6 blocks) for int32 ``p`` near ``2^31 / 6``."""
    idx = np.array([0, LAST - 1, LAST // 2], dtype=np.int32)
    got = row_entries(idx, 36)
    assert got.dtype == np.int64
    assert got.tolist() == [[36 * int(p) + k for k in range(36)] for p in idx]
    assert int((idx[1:2] * 36)[0]) != 36 * (LAST - 1)  # what int32 arithmetic would have given


def test_a_rank_pattern_of_int32_indices_near_the_limit_is_exact():
    """``slab_of_list``'s block keys ``row N + col`` for a list of int32 indices near ``2^31 / 6``."""
    n = LAST
    i = np.array([n - 3, n - 2, 5], dtype=np.int32)
    j = np.array([n - 1, n - 1, n - 2], dtype=np.int32)
    normal = np.tile([1.0, 0.0, 0.0], (3, 1))
    c = Contacts(i, j, normal, normal.copy(), normal.copy(), np.zeros(3), np.zeros((3, 3), np.int64), np.ones(3))
    slab = slab_of_list(c, n, n - 3, n, 0, 1)
    want = sorted({(int(a), int(b)) for a, b in zip(np.concatenate([i, j]), np.concatenate([j, i])) if n - 3 <= a < n})
    assert list(zip(slab.pattern_rows.tolist(), slab.pattern_cols.tolist())) == want
