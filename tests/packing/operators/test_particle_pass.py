"""The bounds' particle pass (dtcrit.packing.operators.particle_pass) against the assembled matrix.

Per particle: the top eigenvalue of the 6 x 6 diagonal block, the diagonal, and the weighted absolute
row sums for the ones and ``sqrt(m)`` -- on rotated non-spherical bodies (unequal principal moments)
with rolling/twisting springs, pre-load and stiffness over many decades, on one-cell lattices whose
contacts are through periodic images (SC: each sphere with its own image), and on spheres.
References: the assembled BSR matrix (``ContactOperator.assembled``) with LAPACK on its dense blocks
and rows; where a pair touches through several images the row sums are per contact, so the reference
sums the assembled per-contact coupling blocks (``assembly.contact_blocks``) instead.  Also: the bits
do not depend on Numba's thread count, a subset of blocks equals the full blocks' rows, and the
incidence lists every contact of a particle once in order.
"""
from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from dtcrit.packing.detection.overlaps import find_sphere_contacts
from dtcrit.packing.generators.lattices import lattice
from dtcrit.packing.generators.random_packing import random_packing
from dtcrit.packing.model import LinearLaw, Packing, apply_law
from dtcrit.packing.operators import matrix_free_kernels, particle_pass
from dtcrit.packing.operators.assembly import contact_blocks
from dtcrit.packing.operators.matrix_free import ContactOperator

PATHS = [False] + ([True] if matrix_free_kernels.available() else [])
needs_numba = pytest.mark.skipif(not matrix_free_kernels.available(), reason="the compiled pass needs Numba")


def _bodies(seed: int, decades: float, n: int = 40):
    """Rotated bodies with masses and moments over ``decades``, every term on the contacts: springs,
    rolling/twisting springs and pre-load over ``decades``, dashpots.
    """
    rng = np.random.default_rng(seed)
    p = random_packing(n, cn=6.0, sizes="lognormal", spread=0.5, seed=seed)
    rot = Rotation.random(p.n, random_state=seed).as_matrix()
    inertia = p.inertia * 10.0 ** rng.uniform(-decades / 2, decades / 2, p.inertia.shape)
    masses = p.masses * 10.0 ** rng.uniform(-decades / 2, decades / 2, p.n)
    q = Packing(p.positions, masses, inertia, p.radii, box=p.box, orientations=rot, label="rotated")
    c = find_sphere_contacts(q)
    nc = c.count

    def spread(lo):
        return 10.0 ** rng.uniform(lo, lo + decades, nc)

    c = c.with_stiffness(spread(0.0), spread(-1.0), kr=spread(-4.0), ktw=spread(-4.0))
    c = c.with_normal_force(rng.uniform(-1.0, 1.0, nc) * spread(-3.0))
    return q, c.with_damping(spread(-2.0), spread(-2.0), cr=spread(-6.0), ctw=spread(-6.0))


def _lattice(kind: str):
    p = lattice(kind, 1)
    return p, apply_law(find_sphere_contacts(p), LinearLaw(3.0, 0.2))


def _spheres(seed: int):
    p = random_packing(60, cn=6.0, sizes="lognormal", spread=0.4, seed=seed)
    return p, apply_law(find_sphere_contacts(p), LinearLaw(2.0, 0.7))


def _sizes(op: ContactOperator) -> np.ndarray:
    """Per contact a bound on its element's terms, ``(|k_n| + |k_s| + |g|)(1 + |a_i| + |a_j|)^2 + |k_r|
    + |k_tw|``: the scale of the rounding of every entry of its blocks (an entry small against it, e.g.
    ``(a x n)`` of a sphere's arm, is a difference of terms that large, rounded differently by the
    compiled element and by the assembled matrices).
    """
    c = op.contacts

    def mag(x):
        return np.zeros(c.count) if x is None else np.abs(x)

    arms = 1.0 + np.linalg.norm(c.arm_i, axis=1) + np.linalg.norm(c.arm_j, axis=1)
    return (mag(op.along) + mag(op.across) + mag(op.preload)) * arms**2 + mag(op.roll) + mag(op.twist)


def _reference(op: ContactOperator, dense: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``|A_pp| w_p`` from the assembled matrix plus ``|s_p K_pq s_q| w_q`` of each contact on its own
    (``assembly.contact_blocks``, a self-image contact none): the row sums when pairs repeat; and their
    rounding scale, the same sums with every entry replaced by its contact's ``_sizes`` scaled.
    """
    n = op.shape[0] // 6
    w6, s = w.reshape(n, 6), op.scale6
    c, m = op.contacts, _sizes(op)
    own = np.bincount(c.i, m, n) + np.bincount(c.j[c.i != c.j], m[c.i != c.j], n)
    out = np.einsum("pab,pb->pa", np.abs(_blocks(dense)), w6)
    size = own[:, None] * s * (s * w6).sum(axis=1)[:, None]
    k_ij = contact_blocks(op.packing, c, slice(0, c.count), op.kind)[2]
    for blk, i, j, mc in zip(k_ij, c.i, c.j, m):
        if i == j:
            continue
        a = np.abs(s[i][:, None] * blk * s[j][None, :])
        out[i] += a @ w6[j]
        out[j] += a.T @ w6[i]
        size[i] += mc * s[i] * (s[j] * w6[j]).sum()
        size[j] += mc * s[j] * (s[i] * w6[i]).sum()
    return out.reshape(-1), size.reshape(-1)


def _blocks(dense: np.ndarray) -> np.ndarray:
    n = dense.shape[0] // 6
    return np.stack([dense[6 * p:6 * p + 6, 6 * p:6 * p + 6] for p in range(n)])


def _check_summary(op: ContactOperator) -> None:
    """The operator's ``block_summary`` against the assembled matrix (module docstring), each value to
    1e-12 of its rounding scale (``_sizes``).
    """
    dense = op.assembled().toarray()
    n = op.shape[0] // 6
    got = op.block_summary()
    c, s = op.contacts, op.scale6
    m = _sizes(op)
    own = np.bincount(c.i, m, n) + np.bincount(c.j[c.i != c.j], m[c.i != c.j], n)
    blocks = _blocks(dense)
    top = np.array([sla.eigvalsh(0.5 * (b + b.T))[-1] for b in blocks])
    assert np.all(np.abs(got.top - top) <= 6e-12 * own * (s**2).max(axis=1))
    assert np.all(np.abs(got.diagonal - np.diag(dense)) <= 1e-12 * (own[:, None] * s**2).reshape(-1))
    pairs = np.sort(np.stack([c.i, c.j], axis=1), axis=1)
    repeated = len(np.unique(pairs, axis=0)) < c.count or np.any(c.i == c.j)
    for w, rows in ((np.ones(op.shape[0]), got.rows_ones), (np.sqrt(op.mass_diag), got.rows_root)):
        want, size = _reference(op, dense, w)
        assert np.all(np.abs(rows - want) <= 1e-12 * size)
        assert np.all(rows >= np.abs(dense) @ w - 1e-12 * size)  # still a Gershgorin bound
        if not repeated:
            assert np.all(np.abs(rows - np.abs(dense) @ w) <= 1e-12 * size)
    assert np.array_equal(op.diagonal(), got.diagonal)
    assert np.array_equal(op.abs_row_sums(), got.rows_ones)
    assert np.array_equal(op.abs_row_sums(np.sqrt(op.mass_diag)), got.rows_root)


@settings(max_examples=12, deadline=None)
@given(seed=st.integers(0, 10_000), decades=st.floats(0.0, 12.0), compiled=st.sampled_from(PATHS),
       kind=st.sampled_from(["stiffness", "damping"]))
def test_summary_of_rotated_bodies_equals_the_assembled_matrix(seed, decades, compiled, kind):
    """Rotated bodies, masses, moments and every coefficient spread over up to 12 decades, springs
    (with pre-load) and dashpots.
    """
    p, c = _bodies(seed, decades)
    assume(c.count > 0)
    _check_summary(ContactOperator(p, c, kind, compiled=compiled))


@pytest.mark.parametrize("compiled", PATHS)
@pytest.mark.parametrize("case", ["fcc", "sc", "bcc", "spheres"])
def test_summary_of_lattices_and_spheres_equals_the_assembled_matrix(case, compiled):
    """One-cell lattices (every contact through an image, several per pair; SC each sphere with its
    own image) and unrotated spheres.
    """
    p, c = _spheres(5) if case == "spheres" else _lattice(case)
    assert np.any(c.i == c.j) == (case == "sc")
    _check_summary(ContactOperator(p, c, compiled=compiled))


@needs_numba
def test_the_bits_do_not_depend_on_the_thread_count():
    """Several tasks of particles (``PARTICLE_BLOCK``) on one thread and on two: the same bits."""
    import numba

    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("one Numba thread: no second thread count to compare")
    p, c = _bodies(11, 9.0, n=3 * particle_pass.PARTICLE_BLOCK)
    runs = []
    before = numba.get_num_threads()
    try:
        for threads in (1, 2):
            numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
            op = ContactOperator(p, c)
            runs.append((op.block_summary(), op.diagonal_blocks()))
    finally:
        numba.set_num_threads(before)
    (one, blocks_one), (two, blocks_two) = runs
    for a, b in zip(one, two):
        assert np.array_equal(a, b)
    assert np.array_equal(blocks_one, blocks_two)


@pytest.mark.parametrize("compiled", PATHS)
@pytest.mark.parametrize("case", ["bodies", "sc"])
def test_the_blocks_of_a_subset_are_the_full_blocks_rows(case, compiled):
    """``diagonal_blocks()`` against the assembled blocks, and ``diagonal_blocks(particles=...)`` (a
    random set in a random order, and none) bit for bit the full blocks' rows.
    """
    p, c = _bodies(3, 6.0) if case == "bodies" else _lattice("sc")
    op = ContactOperator(p, c, compiled=compiled)
    full = op.diagonal_blocks()
    c, s = op.contacts, op.scale6
    m = _sizes(op)
    own = np.bincount(c.i, m, p.n) + np.bincount(c.j[c.i != c.j], m[c.i != c.j], p.n)
    size = own[:, None, None] * s[:, :, None] * s[:, None, :]
    assert np.all(np.abs(full - _blocks(op.assembled().toarray())) <= 1e-12 * size)
    picked = np.random.default_rng(4).permutation(p.n)[:min(p.n, 7)]
    assert np.array_equal(op.diagonal_blocks(particles=picked), full[picked])
    repeated = np.concatenate([picked[:3], picked[:3][::-1]])  # a particle asked twice gets its block twice
    assert np.array_equal(op.diagonal_blocks(particles=repeated), full[repeated])
    assert op.diagonal_blocks(particles=np.zeros(0, dtype=np.int64)).shape == (0, 6, 6)


@needs_numba
def test_the_incidence_lists_each_contact_of_a_particle_once_in_order():
    """Against a direct search of the contact list, for all particles and for a subset in another
    order: BCC (pairs through several images) and SC (every contact a self-image, listed once).
    """
    p, c = _lattice("sc")
    q, d = _lattice("bcc")
    assert np.all(c.i == c.j) and d.count > 0
    for contacts, n, subset in ((d, q.n, np.array([1, 0])), (c, p.n, np.array([0]))):
        for particles in (None, subset):
            indptr, inc = particle_pass.incidence(contacts.i, contacts.j, n, particles)
            assert inc.dtype == np.int32
            rows = range(n) if particles is None else particles
            for r, k in enumerate(rows):
                want = np.flatnonzero((contacts.i == k) | (contacts.j == k))
                assert np.array_equal(inc[indptr[r]:indptr[r + 1]], want)


@pytest.mark.parametrize("compiled", PATHS)
def test_row_sums_of_weights_of_the_wrong_length_are_refused(compiled):
    p, c = _bodies(3, 6.0)
    op = ContactOperator(p, c, compiled=compiled)
    with pytest.raises(ValueError):
        op.abs_row_sums(np.ones(6 * (p.n - 1)))
