"""Sphere contact arms held as their lengths along the normal (dtcrit.packing.normal_arms).

References: the arms rebuilt from the centres and radii in the test (the contact point in the middle of
the overlap, Peng et al. 2020, Eqs (1)-(2)); and the same contact list with its arms stored as (C, 3)
vectors, through which every compiled loop (product, element pass, single-contact frequencies) must
give the same bits as through the lengths.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from dtcrit.packing.bounds.estimates import single_contact_frequencies
from dtcrit.packing.conventions.engines import with_arms
from dtcrit.packing.detection.overlaps import find_sphere_contacts
from dtcrit.packing.generators.random_packing import random_packing
from dtcrit.packing.model import LinearLaw, Packing, apply_law
from dtcrit.packing.normal_arms import NormalArms, kernel_arms
from dtcrit.packing.operators import matrix_free_kernels as kernels
from dtcrit.packing.operators.matrix_free import ContactOperator

compiled_only = pytest.mark.skipif(not kernels.available(), reason="needs Numba")


def _spheres(seed: int = 3, n: int = 150) -> tuple[Packing, object]:
    p = random_packing(n, cn=6.5, sizes="lognormal", spread=0.4, seed=seed)
    return p, find_sphere_contacts(p)


def _as_vectors(c):
    """The same contacts with arms stored as plain (C, 3) arrays."""
    return replace(c, arm_i=np.array(np.asarray(c.arm_i)), arm_j=np.array(np.asarray(c.arm_j)))


def test_sphere_contacts_hold_lengths_and_give_the_contact_point():
    p, c = _spheres()
    assert isinstance(c.arm_i, NormalArms) and isinstance(c.arm_j, NormalArms)
    r, x, box = p.radii, p.positions, p.box
    sep = x[c.j] + box.shift(c.image) - x[c.i]
    d = np.linalg.norm(sep, axis=1)
    n = sep / d[:, None]
    delta = r[c.i] + r[c.j] - d
    point = x[c.i] + (r[c.i] - 0.5 * delta)[:, None] * n  # middle of the overlap
    np.testing.assert_allclose(np.asarray(c.arm_i), point - x[c.i], rtol=0, atol=1e-12 * r.max())
    np.testing.assert_allclose(np.asarray(c.arm_j), point - (x[c.j] + box.shift(c.image)), rtol=0,
                               atol=1e-12 * r.max())


def test_a_sphere_contact_costs_its_lengths_not_its_vectors():
    _, c = _spheres()
    held = sum(a.nbytes for a in (c.i, c.j, c.normal, c.arm_i, c.arm_j, c.overlap, c.image, c.radius_eff))
    assert held / c.count <= 16 + 24 + 16 + 8 + 8 + 24  # indices, normal, two lengths, overlap, R*, image
    assert c.arm_i.nbytes == 8 * c.count


@given(st.integers(0, 2**32 - 1))
@settings(max_examples=25, deadline=None, derandomize=True)
def test_indexing_functions_and_ufuncs_see_the_vectors(seed):
    rng = np.random.default_rng(seed)
    nc = int(rng.integers(1, 40))
    n = rng.normal(size=(nc, 3))
    n /= np.linalg.norm(n, axis=1)[:, None]
    length = 10.0 ** rng.uniform(-6, 3, nc)
    for sign in (1.0, -1.0):
        arms = NormalArms(length, n, sign)
        plain = sign * (length[:, None] * n)
        assert np.array_equal(np.asarray(arms), plain) and arms.shape == plain.shape and len(arms) == nc
        mask = rng.random(nc) < 0.5
        k = int(rng.integers(nc))
        for key in (slice(1, None), mask, np.flatnonzero(mask), k, (slice(None), 0), (mask, slice(1, 3))):
            assert np.array_equal(arms[key], plain[key])
        assert np.array_equal(arms * 2.0, plain * 2.0) and np.array_equal(-arms, -plain)
        assert np.array_equal(np.einsum("ij,ij->i", arms, n), np.einsum("ij,ij->i", plain, n))
        assert np.array_equal(np.concatenate([arms, arms]), np.concatenate([plain, plain]))
        picked = arms.select(mask, n[mask])
        assert isinstance(picked, NormalArms) and np.array_equal(np.asarray(picked), plain[mask])


def test_subset_keeps_lengths():
    _, c = _spheres()
    mask = np.arange(c.count) % 3 == 0
    sub = c.subset(mask)
    assert isinstance(sub.arm_i, NormalArms) and sub.arm_i.normal is sub.normal
    assert np.array_equal(np.asarray(sub.arm_j), np.asarray(c.arm_j)[mask])


def _convention_lengths(convention, r_i, r_j, delta):
    """The engines' arm lengths written out here (LAMMPS granular: sqrt(R (R - delta/2)); YADE's
    ScGeom: sqrt((R - delta/2) R / alpha), alpha = (R_i + R_j) / (R_i + R_j - delta))."""
    if convention == "mid-overlap":
        return r_i - delta / 2, r_j - delta / 2
    if convention == "radius":
        return r_i, r_j
    if convention == "granular":
        return np.sqrt(r_i * (r_i - delta / 2)), np.sqrt(r_j * (r_j - delta / 2))
    alpha = (r_i + r_j) / (r_i + r_j - delta)
    return np.sqrt((r_i - delta / 2) * r_i / alpha), np.sqrt((r_j - delta / 2) * r_j / alpha)


@pytest.mark.parametrize("convention", ["mid-overlap", "radius", "granular", "yade"])
def test_engine_arm_conventions_hold_lengths_along_the_normal(convention):
    p, c = _spheres(n=60)
    c = apply_law(c, LinearLaw(1e5, 4e4))
    out = with_arms(p, c, convention)
    assert isinstance(out.arm_i, NormalArms) and isinstance(out.arm_j, NormalArms)
    l_i, l_j = _convention_lengths(convention, p.radii[c.i], p.radii[c.j], c.overlap)
    np.testing.assert_allclose(np.asarray(out.arm_i), l_i[:, None] * c.normal, rtol=1e-15, atol=1e-15)
    np.testing.assert_allclose(np.asarray(out.arm_j), -l_j[:, None] * c.normal, rtol=1e-15, atol=1e-15)


def test_arms_are_read_only():
    _, c = _spheres(n=30)
    arms = c.arm_i
    before = np.asarray(arms).copy()
    writes = [lambda: np.add.at(arms, [0], 1.0), lambda: np.copyto(arms, 0.0), lambda: np.put(arms, [0], 1.0),
              lambda: np.multiply(before, 2.0, out=arms), lambda: arms.__iadd__(1.0)]
    for write in writes:
        with pytest.raises(TypeError, match="read-only"):
            write()
    assert np.array_equal(np.asarray(arms), before)


def test_mixed_indices_match_the_vectors():
    _, c = _spheres(n=30)
    plain = np.asarray(c.arm_j)
    rows, cols = np.array([0, 2, 5]), np.array([1, 0, 2])
    for key in ((2, 0), (2, slice(None)), (rows, cols), (slice(None), 1), (slice(1, 4), slice(0, 2)), (-1, -1)):
        assert np.array_equal(c.arm_j[key], plain[key])


def test_subset_after_new_normals_keeps_the_old_arms():
    """Arms held on the old normals are selected as vectors when the list's normals were replaced."""
    _, c = _spheres(n=30)
    flipped = replace(c, normal=-c.normal)
    mask = np.arange(c.count) % 2 == 0
    assert np.array_equal(np.asarray(flipped.subset(mask).arm_i), np.asarray(c.arm_i)[mask])


@compiled_only
@pytest.mark.parametrize("oriented", [False, True])
def test_compiled_loops_give_the_same_bits_from_lengths_and_from_vectors(oriented):
    p, c = _spheres(seed=5)
    rng = np.random.default_rng(1)
    c = apply_law(c, LinearLaw(1e5, 3e4)).with_normal_force(rng.uniform(-1.0, 5.0, c.count))
    if oriented:  # the general loop, with body frames
        rot = Rotation.random(p.n, random_state=2).as_matrix()
        p = Packing(p.positions, p.masses, p.inertia * rng.uniform(0.5, 2.0, p.inertia.shape), p.radii, box=p.box,
                    orientations=rot)
    vectors = _as_vectors(c)
    assert kernel_arms(c)[0].shape == (c.count, 1) and kernel_arms(vectors)[0].shape == (c.count, 3)
    lean, wide = ContactOperator(p, c, compiled=True), ContactOperator(p, vectors, compiled=True)
    x = rng.normal(size=6 * p.n)
    if oriented:
        assert np.array_equal(lean @ x, wide @ x)
    else:  # the sphere loop: the stored lengths, or lengths projected from the vectors (an ulp apart)
        assert lean._sphere_args is not None and wide._sphere_args is not None
        np.testing.assert_allclose(lean @ x, wide @ x, rtol=1e-13, atol=1e-13 * np.abs(wide @ x).max())
    np.testing.assert_allclose(lean @ x, wide.assembled() @ x, rtol=1e-11, atol=1e-11 * np.abs(wide @ x).max())
    assert np.array_equal(lean.abs_row_sums(), wide.abs_row_sums())
    assert np.array_equal(lean.diagonal(), wide.diagonal())
    assert np.array_equal(single_contact_frequencies(p, c, compiled=True),
                          single_contact_frequencies(p, vectors, compiled=True))
    np.testing.assert_allclose(single_contact_frequencies(p, c, compiled=False),
                               single_contact_frequencies(p, vectors, compiled=True), rtol=1e-12)


def test_bad_factors_are_refused():
    with pytest.raises(ValueError):
        NormalArms(np.ones(3), np.ones((2, 3)), 1.0)
    with pytest.raises(ValueError):
        NormalArms(np.ones(2), np.ones((2, 3)), 0.5)
