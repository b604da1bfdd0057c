"""Per-contact values of one number held once (dtcrit.packing.uniform_values) give the bits of full arrays.

A term given as one number (``with_stiffness(1.0, 0.5)``, ``LinearLaw``, a ``gran/hooke`` pair style, the
``R*`` of equal spheres) is a read-only view of stride 0 on the contacts and a length-1 array in the
compiled loops (``contact_element.coefficient_at``).  References: the same values given as full arrays
(``numpy.full``, one entry per contact) through the same loops -- every compiled loop (the general and
the sphere product, one block and two, the particle pass's ``block_summary`` and ``diagonal_blocks``,
the single-contact frequencies) and the NumPy paths must give the same bits -- and the assembled
matrix (``operators.assembly``) times the vector; ``R*`` against ``R_i R_j / (R_i + R_j)`` computed here.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from numpy.lib.array_utils import byte_bounds
from scipy.spatial.transform import Rotation

from dtcrit.errors import InputError
from dtcrit.packing.bounds import estimate_kernels
from dtcrit.packing.bounds.estimates import single_contact_frequencies
from dtcrit.packing.conventions.pair_styles import apply_terms, parse_pair_style
from dtcrit.packing.detection.overlaps import find_sphere_contacts
from dtcrit.packing.distributed.slab_contacts import slab_sphere_contacts
from dtcrit.packing.generators.lattices import lattice
from dtcrit.packing.generators.random_packing import random_packing
from dtcrit.packing.model import HertzMindlinLaw, LinearLaw, Packing, apply_law
from dtcrit.packing.operators import matrix_free_kernels as kernels
from dtcrit.packing.operators.assembly import damping_matrix, mass_diagonal, scale_symmetric, stiffness_matrix
from dtcrit.packing.operators.matrix_free import ContactOperator
from dtcrit.packing.uniform_values import held_bytes, is_uniform, kernel_values, uniform

PATHS = [False] + ([True] if kernels.available() else [])
needs_numba = pytest.mark.skipif(not kernels.available(), reason="the compiled loops need Numba")
TERMS = ("kn", "ks", "cn", "cs", "kr", "ktw", "force_n", "cr", "ctw")


def _one_item(a: np.ndarray) -> bool:
    """``a`` is a uniform view over one float64 of memory."""
    lo, hi = byte_bounds(a)
    return a.ndim == 1 and a.strides == (0,) and hi - lo == 8 and not a.flags.writeable


def _full(contacts):
    """The same contacts with every uniform term as a full array (``numpy.full``, stride 8)."""
    out = {key: np.full(contacts.count, getattr(contacts, key)[0]) for key in TERMS + ("radius_eff",)
           if getattr(contacts, key) is not None and is_uniform(getattr(contacts, key))}
    return replace(contacts, **out)


def _rotated(p: Packing, seed: int) -> Packing:
    rng = np.random.default_rng(seed)
    rot = Rotation.random(p.n, random_state=seed).as_matrix()
    return Packing(p.positions, p.masses, p.inertia * rng.uniform(0.5, 2.0, p.inertia.shape), p.radii, box=p.box,
                   orientations=rot, label="rotated")


def _cases():
    rnd = random_packing(90, cn=6.5, sizes="lognormal", spread=0.4, seed=4)
    c = find_sphere_contacts(rnd)
    rng = np.random.default_rng(9)
    every = c.with_stiffness(3.7e4, 1.3e4, kr=2.1e-2, ktw=0.9e-2).with_normal_force(17.5)
    every = every.with_damping(0.7, 0.3, cr=1e-4, ctw=3e-5)
    fcc = lattice("fcc", 1)
    return {
        "spheres-linear": (rnd, apply_law(c, LinearLaw(2.5e5, 0.9e5))),  # the sphere loop
        "spheres-preload": (rnd, c.with_stiffness(1e5, 4e4).with_normal_force(-3.25)),  # sphere loop, g per contact
        "spheres-mixed": (rnd, c.with_stiffness(1e5, rng.uniform(1e3, 1e5, c.count))),  # one uniform, one full
        "spheres-rolling-only": (rnd, c.with_stiffness(1e5, 4e4, kr=3e-2)),  # general loop, ktw a zero partner
        "spheres-every-term": (rnd, every),
        "rotated-every-term": (_rotated(rnd, 5), every),
        "fcc-self-images": (fcc, apply_law(find_sphere_contacts(fcc), LinearLaw(3.0, 0.2))),
    }


CASES = _cases()


def test_a_law_of_one_value_holds_it_once():
    """A law of one value, a scalar or a stride-0 view give one float64 of memory; full arrays are copied."""
    p, c = CASES["spheres-linear"]
    assert _one_item(c.kn) and _one_item(c.ks) and c.kn.shape == (c.count,)
    assert np.all(c.kn == 2.5e5) and held_bytes(c.kn) == 8
    every = CASES["spheres-every-term"][1]
    assert all(_one_item(getattr(every, key)) for key in TERMS)
    assert _one_item(c.with_stiffness(np.broadcast_to(2.0, (c.count,)), np.float64(1.0)).kn)
    given = np.arange(1.0, c.count + 1.0)
    per = c.with_stiffness(given, given)
    assert per.kn.strides == (8,) and per.kn.flags.writeable and not np.shares_memory(per.kn, given)


def test_one_value_is_checked_as_before():
    """The one value is refused as each entry of a full array is (key named)."""
    c = CASES["spheres-linear"][1]
    for bad in (-1.0, np.nan, np.inf, np.broadcast_to(-2.0, (c.count,))):
        with pytest.raises(InputError, match="kn"):
            c.with_stiffness(bad, 1.0)
    with pytest.raises(InputError, match="cs"):
        c.with_damping(0.0, -1e-9)
    with pytest.raises(InputError, match="force_n"):
        c.with_normal_force(np.inf)
    assert c.with_normal_force(-4.0).force_n[3] == -4.0  # a tensile bond's force may be negative


def test_writes_into_a_uniform_view_raise():
    """A uniform view is read-only: no write changes every contact at once (or silently nothing)."""
    c = CASES["spheres-every-term"][1]
    for key in TERMS:
        a = getattr(c, key)
        with pytest.raises(ValueError, match="read-only"):
            a[0] = 1.0
        with pytest.raises(ValueError, match="read-only"):
            np.multiply(a, 2.0, out=a)


def test_subsets_and_kernel_arrays_stay_one_value():
    """A subset keeps its one value; the loops get a length-1 copy, full float64 arrays as they are."""
    p, c = CASES["spheres-every-term"]
    part = c.subset(c.overlap > np.median(c.overlap))
    assert 0 < part.count < c.count and all(_one_item(getattr(part, key)) for key in TERMS)
    assert part.kn[0] == c.kn[0]
    k = kernel_values(c.kn)
    assert k.shape == (1,) and k.flags.c_contiguous and k[0] == c.kn[0]
    full = np.full(c.count, 2.0)
    assert kernel_values(full) is full  # no copy of a contiguous float64 array
    assert kernel_values(uniform(5.0, 10**12)).nbytes == 8  # never the whole of a view


def _ops(p, c, kind, compiled, threads=None):
    md = mass_diagonal(p)
    return [ContactOperator(p, cc, kind, mass_diag=md, compiled=compiled, threads=threads) for cc in (c, _full(c))]


def _kinds(c):
    return ["stiffness"] + (["damping"] if c.damped else [])


@pytest.mark.parametrize("compiled", PATHS)
@pytest.mark.parametrize("name", sorted(CASES))
def test_products_are_the_bits_of_full_arrays_and_the_assembled_matrix(name, compiled):
    """``A x`` with one value per term: the bits of full arrays, and the assembled matrix to 1e-12."""
    p, c = CASES[name]
    x = np.random.default_rng(1).standard_normal(p.dofs)
    for kind in _kinds(c):
        one, full = _ops(p, c, kind, compiled)
        if compiled:  # the loops do read one value
            assert one._kernel_args[5].shape == (1,) and full._kernel_args[5].shape == (c.count,)
        got = one @ x
        assert np.array_equal(got, full @ x)
        build = stiffness_matrix if kind == "stiffness" else damping_matrix
        ref = scale_symmetric(build(p, _full(c)), mass_diagonal(p)) @ x
        assert np.max(np.abs(got - ref)) <= 1e-12 * np.max(np.abs(ref))
        assert one.memory_bytes() < full.memory_bytes()


@needs_numba
@pytest.mark.parametrize("name", sorted(CASES))
def test_blocks_of_the_product_are_the_bits_of_full_arrays(name):
    """The product on two blocks of contacts (one thread each) with one value per term: the same bits."""
    p, c = CASES[name]
    x = np.random.default_rng(2).standard_normal(p.dofs)
    for kind in _kinds(c):
        one, full = _ops(p, c, kind, True, threads=2)
        assert np.array_equal(one @ x, full @ x)


@needs_numba
def test_both_product_loops_run_on_one_value():
    """The sphere loop and the general loop (called directly on the loop arguments) on the same contacts."""
    p, c = CASES["spheres-preload"]
    one, full = _ops(p, c, "stiffness", True)
    assert one._sphere_args is not None and one._sphere_args[5].shape == (1,) and one._sphere_args[7].shape[0] > 1
    q = np.random.default_rng(3).standard_normal((p.n, 6))
    outs = []
    for op in (one, full):
        for span, args in ((kernels.apply_contacts, op._kernel_args), (kernels.apply_sphere_contacts, op._sphere_args)):
            y = np.zeros_like(q)
            span(q, y, *args)
            outs.append(y)
    assert np.array_equal(outs[0], outs[2]) and np.array_equal(outs[1], outs[3])


@pytest.mark.parametrize("compiled", PATHS)
@pytest.mark.parametrize("name", sorted(CASES))
def test_the_particle_pass_is_the_bits_of_full_arrays(name, compiled):
    """``block_summary``, ``diagonal_blocks`` (all, some) and weighted row sums: the same bits."""
    p, c = CASES[name]
    w = np.random.default_rng(4).uniform(0.1, 3.0, p.dofs)
    for kind in _kinds(c):
        one, full = _ops(p, c, kind, compiled)
        for a, b in zip(one.block_summary(), full.block_summary()):
            assert np.array_equal(a, b)
        assert np.array_equal(one.diagonal_blocks(), full.diagonal_blocks())
        assert np.array_equal(one.diagonal_blocks(np.array([3, 1, 3])), full.diagonal_blocks(np.array([3, 1, 3])))
        assert np.array_equal(one.abs_row_sums(w), full.abs_row_sums(w))


@pytest.mark.parametrize("compiled", PATHS)
@pytest.mark.parametrize("name", ["spheres-linear", "spheres-mixed", "rotated-every-term", "fcc-self-images"])
def test_contact_frequencies_are_the_bits_of_full_arrays(name, compiled):
    """The single-contact frequencies (compiled loop, NumPy path) with one value: the same bits."""
    p, c = CASES[name]
    got = single_contact_frequencies(p, c, compiled=compiled)
    assert np.array_equal(got, single_contact_frequencies(p, _full(c), compiled=compiled))
    if compiled:
        big = estimate_kernels.contact_frequencies(p, c)
        assert np.array_equal(big, got)


def test_the_assembled_matrix_is_the_bits_of_full_arrays():
    """``K`` and ``C`` assembled from uniform views: the same entries as from full arrays."""
    p, c = CASES["rotated-every-term"]
    for build in (stiffness_matrix, damping_matrix):
        a, b = build(p, c), build(p, _full(c))
        assert np.array_equal(a.indices, b.indices) and np.array_equal(a.data, b.data)


@pytest.mark.parametrize("radius", [1.0, 0.37, 6.507176164585076])  # the last: R R / (R + R) != R / 2
def test_equal_spheres_hold_their_effective_radius_once(radius):
    """``R*`` of equal spheres: the bits of ``R_i R_j / (R_i + R_j)`` (not ``R / 2``), found by the
    one-tree search, the every-image search of a narrow box and a rank's slab.
    """
    mono = random_packing(80, cn=6.0, sizes="mono", radius=radius, seed=2)
    narrow = lattice("sc", 1, radius=radius)
    for p in (mono, narrow):
        c = find_sphere_contacts(p)
        r = p.radii
        want = r[c.i] * r[c.j] / (r[c.i] + r[c.j])
        assert c.count > 0 and _one_item(c.radius_eff) and np.array_equal(c.radius_eff, want)
    slab = slab_sphere_contacts(mono, 0, mono.n).contacts
    r = mono.radii
    assert _one_item(slab.radius_eff) and np.array_equal(slab.radius_eff, r[slab.i] * r[slab.j] / (r[slab.i] + r[slab.j]))
    poly = random_packing(80, cn=6.0, sizes="lognormal", spread=0.3, seed=2)
    c = find_sphere_contacts(poly)
    r = poly.radii
    assert not is_uniform(c.radius_eff) and np.array_equal(c.radius_eff, r[c.i] * r[c.j] / (r[c.i] + r[c.j]))


def test_laws_on_one_radius_give_the_bits_of_full_arrays():
    """Hertz-Mindlin on a uniform ``R*`` and ``gran/hooke`` (springs held once): the bits of full arrays."""
    p = random_packing(60, cn=6.0, sizes="mono", radius=0.41, seed=6)
    c = find_sphere_contacts(p)
    law = HertzMindlinLaw(7e7, 0.3)
    for key in ("kn", "ks"):
        assert np.array_equal(getattr(apply_law(c, law), key), getattr(apply_law(_full(c), law), key))
    hooke = parse_pair_style("gran/hooke/history 2e5 NULL 50 NULL 0.5 1")
    terms = apply_terms(c, hooke.terms(p, c), preload=True)
    assert _one_item(terms.kn) and _one_item(terms.ks) and terms.kn[0] == 2e5 and terms.ks[0] == 2.0 / 7.0 * 2e5
    full = apply_terms(_full(c), hooke.terms(p, _full(c)), preload=True)
    for key in ("cn", "cs", "force_n"):
        assert np.array_equal(getattr(terms, key), getattr(full, key))
