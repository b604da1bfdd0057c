"""The paths that make large packings fit and run: chunked sphere contact detection, the compiled
single-contact frequencies, and the Chebyshev start of LOBPCG.  References: an O(N^2) brute-force
pair search over all periodic images, batched LAPACK ``eigvalsh`` of each contact's 3 x 3 matrix and
of its 12 x 12 two-body problem, and dense ``scipy.linalg.eigh`` of the whole packing."""
from __future__ import annotations

import itertools
from dataclasses import replace

import numpy as np
import pytest
import scipy.linalg as sla
from scipy.spatial.transform import Rotation

from dtcrit.packing.bounds import estimate_kernels
from dtcrit.packing.operators.assembly import mass_diagonal, scale_symmetric, stiffness_matrix
from dtcrit.packing.detection.overlaps import find_sphere_contacts
from dtcrit.packing.solvers.largest_mode import chebyshev_start, largest_mode
from dtcrit.packing.bounds.estimates import single_contact_frequencies
from dtcrit.packing.generators.lattices import lattice
from dtcrit.packing.model import Box, LinearLaw, Packing, apply_law
from dtcrit.packing.operators.matrix_free import stiffness_operator
from dtcrit.packing.generators.random_packing import random_packing

FIELDS = ("i", "j", "normal", "arm_i", "arm_j", "overlap", "image", "radius_eff")


def _brute_pairs(p: Packing, tolerance: float = 1e-9) -> set:
    """Every (i, j, image) with i < j whose spheres touch, by checking all pairs and the 27 images."""
    x, r = p.positions, p.radii
    lengths = p.box.lengths if p.box is not None else np.zeros(3)
    periodic = p.box.periodic if p.box is not None else (False,) * 3
    shifts = [s for s in itertools.product(*((-1, 0, 1) if periodic[a] else (0,) for a in range(3)))]
    found = set()
    for s in shifts:
        sep = x[None, :, :] + np.array(s) * lengths - x[:, None, :]
        d = np.linalg.norm(sep, axis=2)
        touch = d <= (r[:, None] + r[None, :]) * (1 + tolerance)
        for i, j in zip(*np.nonzero(touch)):
            if i < j:
                found.add((int(i), int(j), s))
    return found


@pytest.mark.parametrize("periodic", [(True, True, True), (True, False, True), (False, False, False)])
def test_chunked_detection_finds_every_contact_once_in_order(periodic):
    p = random_packing(400, cn=6.5, sizes="lognormal", spread=0.4, seed=11)
    box = Box(p.box.lo, p.box.hi, periodic) if p.box is not None else None
    p = Packing(p.positions, p.masses, p.inertia, p.radii, box=box, label="box variant")
    whole = find_sphere_contacts(p, chunk=10**9)
    for chunk in (1, 37, 128):
        part = find_sphere_contacts(p, chunk=chunk)
        for f in FIELDS:
            assert np.array_equal(getattr(whole, f), getattr(part, f)), (chunk, f)
    got = {(int(i), int(j), tuple(int(v) for v in s)) for i, j, s in zip(whole.i, whole.j, whole.image)}
    assert got == _brute_pairs(p)
    key = whole.i * p.n + whole.j
    assert np.all(np.diff(key) > 0)  # sorted by (i, j), each pair once (wide box: one image per pair)
    assert whole.image.dtype == np.int8


def test_narrow_boxes_keep_every_image():
    fcc = find_sphere_contacts(lattice("fcc", 1))  # 4 spheres: each pair touches through 4 images
    assert fcc.count == 4 * 12 // 2 and len({(int(i), int(j)) for i, j in zip(fcc.i, fcc.j)}) == 6
    sc = find_sphere_contacts(lattice("sc", 1))  # 1 sphere touching its own 6 images: 3 contacts
    assert sc.count == 3 and np.all(sc.i == sc.j)


def _varied(seed: int):
    """A random packing with rotated bodies, unequal principal moments and stiffness over decades,
    plus one-cell lattices whose contacts are through periodic images (SC: each sphere's own)."""
    rng = np.random.default_rng(seed)
    p = random_packing(150, cn=6.0, sizes="lognormal", spread=0.5, seed=seed)
    rot = Rotation.random(p.n, random_state=seed).as_matrix()
    inertia = p.inertia * 10.0 ** rng.uniform(-2, 2, p.inertia.shape)
    masses = p.masses * 10.0 ** rng.uniform(-3, 3, p.n)
    q = Packing(p.positions, masses, inertia, p.radii, box=p.box, orientations=rot, label="rotated")
    c = find_sphere_contacts(q)
    c = c.with_stiffness(10.0 ** rng.uniform(-2, 9, c.count), 10.0 ** rng.uniform(-2, 9, c.count))
    cases = [(q, c)]
    for kind in ("fcc", "sc"):
        f = lattice(kind, 1)
        cases.append((f, apply_law(find_sphere_contacts(f), LinearLaw(3.0, 0.2))))
    return cases


@pytest.mark.skipif(not estimate_kernels.available(), reason="the compiled loop needs Numba")
def test_threaded_single_contact_frequencies_equal_lapack(monkeypatch):
    """Three blocks of contacts, one thread each: every contact's value as the batched LAPACK route
    gives it, and as the default path (blocks from ``PARALLEL_MIN_CONTACTS``, forced to one contact)."""
    from dtcrit.packing.operators.matrix_free_kernels import block_bounds

    monkeypatch.setattr(estimate_kernels, "PARALLEL_MIN_CONTACTS", 1)
    for p, c in _varied(4):
        ref = single_contact_frequencies(p, c, compiled=False)
        assert np.all(np.abs(single_contact_frequencies(p, c, compiled=True) - ref) <= 1e-10 * np.abs(ref).max())
        inv_mass = 1.0 / np.concatenate([np.repeat(p.masses[:, None], 3, axis=1), p.inertia], axis=1)
        rot = np.ascontiguousarray(p.orientations) if p.orientations is not None else np.zeros((1, 3, 3))
        got = np.full(c.count, np.nan)
        estimate_kernels.frequencies_blocks(block_bounds(c.count, 3), c.i, c.j, np.ascontiguousarray(c.normal),
                                            np.ascontiguousarray(c.arm_i), np.ascontiguousarray(c.arm_j),
                                            np.asarray(c.kn, float), np.asarray(c.ks, float), rot, inv_mass,
                                            p.orientations is not None, got)
        assert np.all(np.abs(got - ref) <= 1e-10 * np.abs(ref).max())


@pytest.mark.skipif(not estimate_kernels.available(), reason="the compiled loop needs Numba")
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_compiled_single_contact_frequencies_equal_lapack(seed):
    """Both routes form ``K_c^(1/2) W K_c^(1/2)`` in floating point, which with k_n/k_s up to 1e11
    costs up to ~1e-12 of the top eigenvalue (measured against a 50-digit mpmath solve of the same
    contact: compiled 2.6e-13, LAPACK route 1.2e-12 on the worst contact of seed 1), so the two
    agree to 1e-10; the 50-digit check is the next test."""
    for p, c in _varied(seed):
        fast = single_contact_frequencies(p, c, compiled=True)
        ref = single_contact_frequencies(p, c, compiled=False)  # batched LAPACK eigvalsh
        assert np.max(np.abs(fast - ref) / ref) < 1e-10


@pytest.mark.skipif(not estimate_kernels.available(), reason="the compiled loop needs Numba")
def test_compiled_single_contact_frequency_equals_its_two_body_eigenproblem():
    """Contact c alone: the 12 x 12 problem of its two free bodies, solved densely, and the same
    contact's 3 x 3 matrix formed and solved at 50 digits (mpmath)."""
    import mpmath as mp

    from dtcrit.packing.operators.assembly import contact_kinematics

    p, c = _varied(4)[0]
    fast = single_contact_frequencies(p, c, compiled=True)
    worst = int(np.argmax(np.maximum(c.kn / c.ks, c.ks / c.kn)))
    with mp.workdps(50):
        bi, bj = (mp.matrix(b[0].tolist()) for b in contact_kinematics(p, c, slice(worst, worst + 1)))
        inv = lambda q: mp.diag([1 / mp.mpf(p.masses[q])] * 3 + [1 / mp.mpf(v) for v in p.inertia[q]])  # noqa: E731
        w = bi * inv(int(c.i[worst])) * bi.T + bj * inv(int(c.j[worst])) * bj.T
        n = mp.matrix(c.normal[worst].tolist())
        root = (mp.sqrt(c.kn[worst]) - mp.sqrt(c.ks[worst])) * n * n.T + mp.sqrt(c.ks[worst]) * mp.eye(3)
        top = max(mp.eigsy(root * w * root)[0])
        assert abs(fast[worst] - top) / top < 1e-11
    md = mass_diagonal(p).reshape(-1, 6)
    for k in (0, 7, c.count - 1):
        i, j = int(c.i[k]), int(c.j[k])
        sub = Packing(p.positions[[i, j]], p.masses[[i, j]], p.inertia[[i, j]], p.radii[[i, j]], box=p.box,
                      orientations=p.orientations[[i, j]], label="pair")
        pair = replace(c, i=np.array([0]), j=np.array([1]), normal=c.normal[[k]], arm_i=c.arm_i[[k]],
                       arm_j=c.arm_j[[k]], overlap=c.overlap[[k]], image=c.image[[k]],
                       radius_eff=c.radius_eff[[k]], kn=c.kn[[k]], ks=c.ks[[k]])
        k12 = stiffness_matrix(sub, pair).toarray()
        m = np.concatenate([md[i], md[j]])
        top = sla.eigh(k12, np.diag(m), eigvals_only=True)[-1]
        assert abs(fast[k] - top) / top < 1e-9


def _lattice_operator():
    p = lattice("fcc", 3)
    rng = np.random.default_rng(5)
    c = find_sphere_contacts(p)
    c = c.with_stiffness(10.0 ** rng.uniform(0, 3, c.count), 10.0 ** rng.uniform(0, 3, c.count))
    md = mass_diagonal(p)
    return stiffness_operator(p, c, mass_diag=md), scale_symmetric(stiffness_matrix(p, c), md, inplace=True)


def test_chebyshev_start_then_lobpcg_equals_the_dense_solve():
    op, a = _lattice_operator()
    dense = sla.eigvalsh(a.toarray())[-1]
    top = largest_mode(op, "lobpcg")
    assert abs(top.value - dense) / dense < 1e-10
    assert top.residual <= 1e-6 * dense


def test_chebyshev_start_raises_the_rayleigh_quotient_and_survives_a_zero_operator():
    op, a = _lattice_operator()
    v = np.random.default_rng(1).standard_normal(op.shape[0])
    w = chebyshev_start(op, v)
    rq = lambda u: float(u @ (a @ u)) / float(u @ u)  # noqa: E731
    top = sla.eigvalsh(a.toarray())[-1]
    assert rq(v) < 0.8 * top and rq(w) > rq(v) and rq(w) <= top * (1 + 1e-12)
    zero = np.zeros((30, 30))
    u = chebyshev_start(zero, np.ones(30))
    assert np.all(np.isfinite(u)) and abs(np.linalg.norm(u) - 1) < 1e-15


def test_the_lean_polish_of_very_large_operators_equals_the_dense_solve(monkeypatch):
    """Above ``LEAN_DOFS`` the Chebyshev start is polished by ARPACK on 4 Lanczos vectors."""
    from dtcrit.packing.solvers import largest_mode as eigen

    op, a = _lattice_operator()
    monkeypatch.setattr(eigen, "LEAN_DOFS", 10)
    top = eigen.largest_mode(op)
    dense = sla.eigvalsh(a.toarray())[-1]
    assert top.method == "eigsh" and abs(top.value - dense) / dense < 1e-10


def test_arpack_products_go_into_one_kept_vector(monkeypatch):
    """ARPACK copies each product at once, so the operator writes every one into the same vector
    (``apply_into``, no fresh 6N vector a product); the answer stays the dense one."""
    from dtcrit.packing.solvers import largest_mode as eigen

    op, a = _lattice_operator()
    outputs, fresh = set(), []
    into, matvec = op.apply_into, op._matvec
    monkeypatch.setattr(op, "apply_into", lambda x, out: outputs.add(id(out)) or into(x, out))
    monkeypatch.setattr(op, "_matvec", lambda x: fresh.append(1) or matvec(x))
    monkeypatch.setattr(eigen, "LEAN_DOFS", 10)
    top = eigen.largest_mode(op)
    dense = sla.eigvalsh(a.toarray())[-1]
    assert top.method == "eigsh" and abs(top.value - dense) / dense < 1e-10
    # the Chebyshev start's vectors, ARPACK's one kept vector, and the final residual's one fresh product
    assert len(outputs) <= 6 and top.matvecs > 20 and len(fresh) <= 1


def test_the_sphere_loop_equals_the_general_loop_and_is_chosen_only_for_sphere_contacts():
    from dtcrit.packing.operators import matrix_free_kernels as operator_kernels

    if not operator_kernels.available():
        pytest.skip("the compiled loops need Numba")
    op, a = _lattice_operator()
    assert op._sphere_args is not None
    q = np.random.default_rng(2).standard_normal((op.packing.n, 6))
    fast, general = np.zeros_like(q), np.zeros_like(q)
    operator_kernels.apply_sphere_contacts(q, fast, *op._sphere_args)
    operator_kernels.apply_contacts(q, general, *op._kernel_args)
    assert np.max(np.abs(fast - general)) <= 1e-14 * np.max(np.abs(general))
    p, c = _varied(1)[0]  # rotated bodies: the general loop
    assert stiffness_operator(p, c)._sphere_args is None


def test_above_the_sphere_loop_limit_only_contacts_holding_lengths_take_the_sphere_loop(monkeypatch):
    """Lengths stored with the contacts cost nothing more; lengths projected from arm vectors would."""
    import dtcrit.packing.operators.matrix_free as mf

    monkeypatch.setattr(mf, "SPHERE_LOOP_MAX_DOFS", 10)
    op, a = _lattice_operator()
    c = op.contacts
    vectors = replace(c, arm_i=np.array(np.asarray(c.arm_i)), arm_j=np.array(np.asarray(c.arm_j)))
    wide = stiffness_operator(op.packing, vectors)
    assert (op._sphere_args is not None) == mf.kernels.available() and wide._sphere_args is None
    x = np.random.default_rng(3).standard_normal(a.shape[0])
    np.testing.assert_allclose(op @ x, a @ x, rtol=1e-12, atol=1e-12 * np.abs(a @ x).max())


@pytest.mark.parametrize("seed", [1, 2])
def test_principal_submatrix_equals_the_assembled_rows_and_columns(seed):
    """``principal_submatrix`` against the assembled matrix's rows and columns of the same DOFs: rotated
    bodies with stiffness over decades, and one-cell lattices (contacts through images, SC each sphere
    with its own image), for random particle sets in a random order."""
    from dtcrit.packing.bounds.rayleigh_trials import principal_submatrix

    rng = np.random.default_rng(seed)
    for p, c in _varied(seed):
        md = mass_diagonal(p)
        op = stiffness_operator(p, c, mass_diag=md)
        dense = scale_symmetric(stiffness_matrix(p, c), md, inplace=True).toarray()
        picked = rng.permutation(p.n)[:min(p.n, 7)]
        dofs = (6 * picked[:, None] + np.arange(6)).reshape(-1)
        want = dense[np.ix_(dofs, dofs)]
        assert np.max(np.abs(principal_submatrix(op, picked) - want)) <= 1e-12 * np.max(np.abs(want))


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_rayleigh_of_a_matrix_free_operator_equals_the_quotients_by_products(seed):
    """The local trials' quotients from one principal submatrix equal those from full products
    (the assembled matrix hides the submatrix route), to rounding, with the same trial named."""
    from dtcrit.packing.bounds.rayleigh_trials import rayleigh

    for p, c in _varied(seed):
        md = mass_diagonal(p)
        op = stiffness_operator(p, c, mass_diag=md)
        a = scale_symmetric(stiffness_matrix(p, c), md, inplace=True)
        local, by_products = rayleigh(op, p, c), rayleigh(a, p, c)
        assert abs(local.omega2 - by_products.omega2) <= 1e-12 * by_products.omega2
        assert local.detail == by_products.detail


def test_the_threaded_product_equals_the_assembled_matrix(monkeypatch):
    """Contacts split into 1-4 blocks (one thread each, summed in block order): the product equals the
    assembled matrix's to rounding, on the sphere loop and the general loop, and a fixed block count
    gives the same bits every time."""
    from dtcrit.packing.operators import matrix_free as mf

    if not mf.kernels.available():
        pytest.skip("the compiled loops need Numba")
    monkeypatch.setattr(mf, "PARALLEL_MIN_CONTACTS", 1)
    p = random_packing(600, cn=6.0, sizes="lognormal", spread=0.4, seed=4)
    c = apply_law(find_sphere_contacts(p), LinearLaw(2.0, 0.6))
    md = mass_diagonal(p)
    a = scale_symmetric(stiffness_matrix(p, c), md, inplace=True)
    x = np.random.default_rng(3).standard_normal(a.shape[0])
    want = a @ x
    for threads in (1, 2, 3, 4):
        for sphere_loop in (True, False):
            op = stiffness_operator(p, c, mass_diag=md, threads=threads)
            if not sphere_loop:
                op._sphere_args = None
            assert (op._bounds is None) == (threads == 1)
            got = op.apply_into(x, np.empty_like(x))
            assert np.max(np.abs(got - want)) <= 1e-13 * np.max(np.abs(want)), (threads, sphere_loop)
            assert np.array_equal(op @ x, got)
