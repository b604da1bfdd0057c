"""`coordination_max`: the dense step never exceeds the exact global step of a packing.

References: the exact largest eigenvalue of the packing's 6-DOF M^-1 K (dtcrit.packing: sparse
assembly, dense or Lanczos solve), an independent route from the per-particle block bound; and
for damped, non-proportional packings the spectral radius of the whole packing's amplification
matrix built from the integrator's update rule (``support.multidof``).  The ratios dense/exact are
in derivations/records/dense_bound.md.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

from support.packing_scene import sphere_sizes_toml
from support.multidof import spectral_radius
from dtcrit.packing import LinearLaw, analyse, apply_law, find_sphere_contacts, lattice, mass_matrix, stiffness_matrix, random_packing
from dtcrit.scenes.dense import DENSE_SCHEMES
from dtcrit.scenes.scene import parse_scene
from dtcrit.scenes.timestep import critical_step

KS_RATIOS = (0.0, 0.1, 2 / 7, 1.0, 2.0)


def _overlap(packing) -> float:
    """The packing's largest overlap as a fraction of R_i + R_j (hypothesis H4 of the sphere bound)."""
    c = find_sphere_contacts(packing)
    return float(np.max(c.overlap / (packing.radii[c.i] + packing.radii[c.j]))) if c.count else 0.0


def _scene_for(packing, kn, ks, z, integrator="velocity-verlet", damping=""):
    sizes, density = sphere_sizes_toml(packing)
    top = f'integrator = "{integrator}"\ncoordination_max = {z}\noverlap_max = {_overlap(packing) * (1 + 1e-9) + 1e-15!r}\n'
    return parse_scene(f'{top}[[particle]]\nshape = "sphere"\n{sizes}'
                       f'density = {density!r}\n[contact]\nmodel = "linear"\nkn = {kn!r}\nks = {ks!r}\n{damping}')


def _exact_dt(packing, kn, ks):
    rep = analyse(packing, LinearLaw(kn, ks), integrator="velocity-verlet", with_estimates=False)
    return rep.dt_crit, int(rep.cn_max)


PACKINGS = {
    "sc": lambda: lattice("sc", 2, radius=1.0, density=1.0),
    "bcc": lambda: lattice("bcc", 2, radius=1.0, density=1.0),
    "fcc": lambda: lattice("fcc", 2, radius=1.0, density=1.0),
    "random-mono": lambda: random_packing(64, cn=5.0, sizes="mono", seed=3),
    "random-uniform": lambda: random_packing(64, cn=5.0, sizes="uniform", spread=0.3, seed=4),
}


@pytest.mark.parametrize("name", sorted(PACKINGS))
@pytest.mark.parametrize("ks_ratio", KS_RATIOS)
def test_dense_step_is_below_the_exact_packing_step(name, ks_ratio):
    packing = PACKINGS[name]()
    kn = 1.0e4
    exact, z = _exact_dt(packing, kn, ks_ratio * kn)
    dense = critical_step(_scene_for(packing, kn, ks_ratio * kn, z)).dt_dense
    assert dense <= exact * (1 + 1e-12), (name, ks_ratio, dense, exact)


def test_dense_step_holds_for_damped_non_proportional_packings():
    """8 spheres (48 DOF), dashpots not proportional to the springs: the whole packing's update-rule
    matrix has spectral radius <= 1 at 0.999 x dt_dense, for every scheme the bound covers."""
    packing = lattice("sc", 2, radius=1.0, density=1.0)
    kn, ks, cn, cs = 1.0e4, 3.0e3, 40.0, 2.0
    contacts = find_sphere_contacts(packing)
    K = stiffness_matrix(packing, apply_law(contacts, LinearLaw(kn, ks))).toarray()
    C = stiffness_matrix(packing, apply_law(contacts, LinearLaw(cn, cs))).toarray()  # dashpots: the same element
    M = mass_matrix(packing).toarray()
    z = 6
    for name in DENSE_SCHEMES:
        res = critical_step(_scene_for(packing, kn, ks, z, name, f"cn = {cn!r}\ncs = {cs!r}\n"))
        assert spectral_radius(name, 0.999 * res.dt_dense, M, K, C) <= 1 + 1e-7, name


def test_scene_output_by_headline_basis():
    """Without packing keys the headline is the step for any packing (at most 13 contacts: the law-of-cosines
    angle at 5 % overlap, acos(1 - 0.95^2/2) = 56.7 deg, lies between the Tammes angles of 14 points, 55.67 deg,
    and 13 points, 57.14 deg); ``isolated = true`` asks for the isolated contact, ``coordination_max`` for its packing."""
    text = ('integrator = "velocity-verlet"\n[[particle]]\nshape = "sphere"\nradius = 0.001\ndensity = 2500.0\n'
            '[contact]\nmodel = "linear"\nkn = 1e5\nks = 2e4\n')
    assert 55.6705700 < math.degrees(math.acos(1 - 0.95**2 / 2)) < 57.1367031
    default = critical_step(parse_scene(text))
    assert default.basis == "any packing" and default.coordination.z == 13 and default.dense.coordination == 13
    assert default.dt_crit == default.dt_dense < default.dt_isolated and default.dense_factors == {}
    assert "at most 13 contacts" in default.holds_for and "sphere-packing bound" in default.dense.reason
    iso = critical_step(parse_scene("isolated = true\n" + text))
    assert iso.basis == "isolated" and iso.dt_crit == iso.dt_isolated == default.dt_isolated
    assert iso.holds_for == "an isolated contact" and iso.dense is None
    assert set(iso.dense_factors) == {4, 6, 12} and all(0 < f < 1 for f in iso.dense_factors.values())
    dense = critical_step(parse_scene("coordination_max = 12\n" + text))
    block = iso.dt_isolated * iso.dense_factors[12]  # the factors come from the block bound
    assert dense.basis == "coordination_max" and dense.coordination is None
    assert dense.dt_crit == dense.dt_dense and block <= dense.dt_dense < iso.dt_isolated
    assert default.dt_crit <= dense.dt_crit  # 13 contacts allowed, not 12
    assert "sphere-packing bound" in dense.dense.reason  # spheres, no walls: the geometric bound is sharper
    assert dense.governing == "dense" and "at most 12 contacts" in dense.holds_for
    # one verdict per estimate, against the headline
    for r in (default, iso, dense):
        for e in r.estimates:
            if e.estimate.dt is not None:
                assert e.unsafe == (e.estimate.dt > r.dt_crit * (1 + 1e-9))
    assert any(e.unsafe for e in default.estimates) and not all(e.unsafe for e in default.estimates if e.unsafe is not None)


def _monolayer(n=3):
    """A periodic hexagonal monolayer of unit spheres (z = 6), n x n rectangular cells of two spheres."""
    from dtcrit.packing import Box, Packing

    pos = [(2 * i + s, 2 * math.sqrt(3) * j + s * math.sqrt(3), 5.0) for i in range(n) for j in range(n) for s in (0, 1)]
    box = Box(np.zeros(3), np.array([2 * n, 2 * math.sqrt(3) * n, 10.0]), (True, True, False))
    return Packing.spheres(np.array(pos), np.ones(len(pos)), masses=np.ones(len(pos)), box=box)


@pytest.mark.parametrize("z,build", [(6, _monolayer), (8, lambda: lattice("bcc", 2, mass=1.0)),
                                     (12, lambda: lattice("fcc", 2, mass=1.0))])
def test_sphere_bound_covers_the_worst_known_arrangements(z, build):
    """Equal unit spheres, ks = kn = 1: the bound lies above the exact omega^2 of the hexagonal monolayer (z = 6),
    BCC (z = 8) and FCC (z = 12) from the packing eigen-solve, and at z = 12 at most the proof's certified 48.91."""
    from dtcrit.scenes.dense_spheres import dense_omega2_bound

    rep = analyse(build(), LinearLaw(1.0, 1.0), integrator="velocity-verlet", with_estimates=False)
    assert int(rep.cn_max) == z
    bound = dense_omega2_bound(1.0, 1.0, [1.0], [1.0], None, z).omega2
    assert rep.omega_max**2 <= bound
    if z == 12:
        assert bound <= 48.91 * (1 + 1e-3)


def _cluster(rng, n, r_centre, r_neighbour):
    """A centre sphere touched by up to ``n`` neighbours at random directions (rejection: no two neighbours overlap)."""
    pos = [np.zeros(3)]
    radii = [r_centre]
    d = r_centre + r_neighbour
    for _ in range(4000):
        if len(pos) == n + 1:
            break
        u = rng.normal(size=3)
        p = d * u / np.linalg.norm(u)
        if all(np.linalg.norm(p - q) >= (r_neighbour + rr) * (1 - 1e-12) for q, rr in zip(pos[1:], radii[1:])):
            pos.append(p)
            radii.append(r_neighbour)
    from dtcrit.packing import Packing

    return Packing.spheres(np.array(pos), np.array(radii), density=1.0)


@settings(max_examples=20)
@given(st.integers(0, 2**32 - 1), st.integers(2, 12), st.sampled_from([(1.0, 1.0), (1.0, 2.0), (1.0, 0.7), (0.5, 3.0)]),
       st.sampled_from(KS_RATIOS))
def test_dense_step_is_below_the_exact_step_of_random_clusters(seed, n, radii, ks_ratio):
    """Random clusters: a sphere touched by up to 12 others of another size; the dense step of the two sizes with
    z = the cluster's largest coordination never exceeds the cluster's exact step."""
    packing = _cluster(np.random.default_rng(seed), n, *radii)
    kn = 1.0e4
    contacts = find_sphere_contacts(packing)
    assume(contacts.count > 0)
    exact, z = _exact_dt(packing, kn, ks_ratio * kn)
    dense = critical_step(_scene_for(packing, kn, ks_ratio * kn, z)).dt_dense
    assert dense <= exact * (1 + 1e-12), (seed, n, radii, ks_ratio, dense, exact)
