"""Searches and rankings whose result must not follow the last bits of floating point.

NumPy's ``sin``/``exp``/``power`` loops and OpenBLAS's kernels differ between processors in the last
bits.  Each case perturbs its input by a few ulps (what another processor does) and requires the
same selection, and checks the robust form against an independent route.
"""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import scipy.linalg as sla

from dtcrit.bodies import Ellipsoid, Superquadric
from dtcrit.packing.operators.assembly import mass_diagonal, scale_symmetric, stiffness_matrix
from dtcrit.packing.detection.overlaps import find_sphere_contacts
from dtcrit.packing.bounds.estimates import single_contact_frequencies
from dtcrit.packing.bounds.rayleigh_trials import _span_quotient, _stiffest, contact_modes, rayleigh
from dtcrit.packing.generators.lattices import lattice
from dtcrit.packing.model import LinearLaw, apply_law
from dtcrit.packing.generators.random_packing import random_packing

ULP = np.finfo(float).eps


def _ulp_noise(x: np.ndarray, seed: int, ulps: float = 4.0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return x * (1.0 + ulps * ULP * rng.uniform(-1.0, 1.0, size=np.shape(x)))


@pytest.mark.parametrize("seed", range(5))
def test_stiffest_ignores_rounding_level_ties(seed):
    w = np.full(40, 3.7e5)
    w[[5, 17, 30]] = 4.1e5  # three clearly stiffer contacts, then 37 equal ones
    picked = _stiffest(_ulp_noise(w, seed), 8)
    assert picked.tolist() == [5, 17, 30, 0, 1, 2, 3, 4]  # ties to the lower index
    assert _stiffest(_ulp_noise(w, seed), 50).tolist() == [5, 17, 30] + [i for i in range(40) if i not in (5, 17, 30)]


def _operator_and_contacts(packing, law):
    contacts = apply_law(find_sphere_contacts(packing), law)
    a = scale_symmetric(stiffness_matrix(packing, contacts), mass_diagonal(packing))
    return a, contacts


@pytest.mark.parametrize("sizes", ["mono", "uniform", "lognormal"])
def test_rayleigh_does_not_follow_the_last_bits(sizes):
    packing = random_packing(60, cn=6, sizes=sizes, spread=0.0 if sizes == "mono" else 0.3, seed=7, max_steps=150)
    a, contacts = _operator_and_contacts(packing, LinearLaw(1.0, 0.5))  # a contact's tangential pair wins
    w = single_contact_frequencies(packing, contacts)
    ref = rayleigh(a, packing, contacts, omega2_c=w)
    for seed in range(4):
        got = rayleigh(a, packing, contacts, omega2_c=_ulp_noise(w, seed))
        assert got.detail == ref.detail
        assert got.omega2 == pytest.approx(ref.omega2, rel=1e-12)
        # the normals a few ulps off: LAPACK's basis of each degenerate tangential pair turns freely
        noisy = dataclasses.replace(contacts, normal=_ulp_noise(contacts.normal, seed))
        got = rayleigh(a, packing, noisy, omega2_c=w)
        assert got.detail == ref.detail
        assert got.omega2 == pytest.approx(ref.omega2, rel=1e-9)
    top = sla.eigvalsh(a.toarray())[-1]  # independent: dense eigen-solve
    assert ref.omega2 <= top * (1 + 1e-12)


def test_lattice_rayleigh_picks_the_first_of_equal_contacts():
    packing = lattice("fcc", 2)
    a, contacts = _operator_and_contacts(packing, LinearLaw(1.0, 0.5))
    w = single_contact_frequencies(packing, contacts)
    assert np.ptp(w) <= 1e-12 * w.max()  # every contact of the lattice is the same
    for seed in range(3):
        assert _stiffest(_ulp_noise(w, seed), 8).tolist() == list(range(8))


@pytest.mark.parametrize("angle", [0.3, 1.1, 2.5])
def test_span_quotient_is_the_ritz_value_of_the_span(angle):
    """Two spheres' tangential mode is a plane: the quotient over it does not depend on the basis
    LAPACK returns, and equals the top eigenvalue of A projected on an orthonormal basis (scipy's
    ``orth`` and the dense matrix)."""
    packing = random_packing(40, cn=5, sizes="uniform", spread=0.3, seed=3, max_steps=150)
    a, contacts = _operator_and_contacts(packing, LinearLaw(1.0, 1.0))
    c = int(np.argmax(single_contact_frequencies(packing, contacts)))
    u, v = contact_modes(packing, contacts, c)  # the degenerate tangential pair
    turned = [np.cos(angle) * u + np.sin(angle) * v, -np.sin(angle) * u + 2.0 * np.cos(angle) * v]
    dense = a.toarray()
    q = sla.orth(np.column_stack([u, v]))
    ritz = sla.eigvalsh(q.T @ dense @ q)[-1]
    assert _span_quotient(a, [u, v]) == pytest.approx(ritz, rel=1e-12)
    assert _span_quotient(a, turned) == pytest.approx(ritz, rel=1e-12)
    assert ritz >= max(x @ dense @ x / (x @ x) for x in (u, v, *turned)) * (1 - 1e-12)
    assert ritz <= sla.eigvalsh(dense)[-1] * (1 + 1e-12)


@pytest.mark.parametrize("make", [
    lambda s: Ellipsoid(3.0 * s, 2.0, 1.0, density=1000.0),
    lambda s: Ellipsoid(0.003 * s, 0.0015, 0.001, density=1100.0),
    lambda s: Superquadric(0.002 * s, 0.0015, 0.001, 0.5, 0.7, density=2650.0),
    lambda s: Superquadric(3.0 * s, 2.0, 1.0, 0.5, 0.5, density=1.0),
], ids=["ellipsoid", "small-ellipsoid", "superquadric", "rounded-box"])
@pytest.mark.parametrize("n", [100, 400, 1500])
def test_surface_samples_do_not_follow_the_last_bits(make, n):
    """A long axis a few ulps longer (what another processor's rounding does to every derived
    length) gives the same samples: no ray hit sits on a thinning cube's face."""
    pts, _ = make(1.0).surface_points(n)
    for ulps in (1, 3, -2):
        other, _ = make(1.0 + ulps * ULP).surface_points(n)
        assert other.shape == pts.shape
        assert np.max(np.abs(other - pts)) <= 1e-12 * np.max(np.abs(pts))


def test_stiffest_in_chunks_equals_one_ranking_of_the_whole(monkeypatch):
    """With chunks of 7 entries the k stiffest are those a ranking of the whole array picks (rounded
    keys, ties to the lower index): many exact ties, ties across chunk borders, k above a chunk."""
    import dtcrit.packing.bounds.rayleigh_trials as trials

    rng = np.random.default_rng(8)
    w = np.round(rng.uniform(1.0, 2.0, 200), 1) * (1.0 + rng.uniform(-1e-12, 1e-12, 200))
    whole = {k: trials._stiffest(w, k) for k in (1, 3, 8, 20)}
    monkeypatch.setattr(trials, "STIFFEST_CHUNK", 7)
    for k, want in whole.items():
        got = trials._stiffest(w, k)
        assert np.array_equal(got, want), k
        key = np.round(w, 6)
        order = sorted(range(w.size), key=lambda i: (-key[i], i))[:k]  # the rule, written out
        assert list(got) == order
    flat = np.full(50, 3.0)  # a perfect lattice: every key equal, the lowest indices win
    assert np.array_equal(trials._stiffest(flat, 4), np.arange(4))
