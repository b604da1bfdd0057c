"""The matrix-free operator (dtcrit.packing.operators.matrix_free) equals the assembled matrices it replaces:
products, diagonal blocks, Gershgorin rows, omega_max of `analyse` and the damped step, on lattices
(self-image contacts included), random packings, rotated bodies, rolling/twisting springs, pre-load
and dashpots.  References: the assembled scipy.sparse matrices (dtcrit.packing.operators.assembly, checked
against dense eigen-solves and simulations in test_packing_assembly.py) and dense scipy.linalg.eigh."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import scipy.linalg as sla
from scipy.spatial.transform import Rotation

from dtcrit.packing.operators import matrix_free_kernels as operator_kernels
from dtcrit.packing.operators.assembly import damping_matrix, mass_diagonal, scale_symmetric, stiffness_matrix
from dtcrit.packing.detection.overlaps import find_sphere_contacts
from dtcrit.packing.solvers.damped_step import damped_critical_dt
from dtcrit.packing.bounds.estimates import block_diagonal, diagonal_stiffness, gershgorin
from dtcrit.packing.generators.lattices import lattice
from dtcrit.packing.model import LinearLaw, Packing, apply_law
from dtcrit.packing.operators.matrix_free import CombinedOperator, ContactOperator
from dtcrit.packing.generators.random_packing import random_packing
from dtcrit.packing.report import analyse

PATHS = [False] + ([True] if operator_kernels.available() else [])


def _rotated(p: Packing, seed: int) -> Packing:
    """The same spheres with random body frames and unequal principal moments (6-DOF kinematics
    with rotations R_p, as for non-spherical bodies)."""
    rng = np.random.default_rng(seed)
    rot = Rotation.random(p.n, random_state=seed).as_matrix()
    inertia = p.inertia * rng.uniform(0.5, 2.0, p.inertia.shape)
    return Packing(p.positions, p.masses, inertia, p.radii, box=p.box, orientations=rot, label="rotated")


def _cases():
    rng = np.random.default_rng(7)
    fcc = lattice("fcc", 1)  # 4 spheres, every contact through a periodic image, several per pair
    c_fcc = apply_law(find_sphere_contacts(fcc), LinearLaw(2.0, 0.7))
    rnd = random_packing(120, cn=6.5, sizes="lognormal", spread=0.4, seed=3)
    c_rnd = find_sphere_contacts(rnd)
    nc = c_rnd.count
    springs = c_rnd.with_stiffness(rng.uniform(1e3, 1e6, nc), rng.uniform(1e2, 1e6, nc))
    full = springs.with_stiffness(springs.kn, springs.ks, kr=rng.uniform(0, 1e-2, nc), ktw=rng.uniform(0, 1e-2, nc))
    full = full.with_normal_force(rng.uniform(-5.0, 20.0, nc))
    full = full.with_damping(rng.uniform(0, 3.0, nc), rng.uniform(0, 3.0, nc), cr=rng.uniform(0, 1e-3, nc),
                             ctw=rng.uniform(0, 1e-3, nc))
    only_roll = replace(springs.with_stiffness(springs.kn, springs.ks, kr=rng.uniform(0, 1e-2, nc)),
                        cn=rng.uniform(0, 3.0, nc))
    return {
        "fcc-self-images": (fcc, c_fcc),
        "random-springs": (rnd, springs),
        "random-all-terms": (rnd, full),
        "random-rolling-only": (rnd, only_roll),
        "rotated-all-terms": (_rotated(rnd, 5), full),
    }


CASES = _cases()


@pytest.mark.parametrize("compiled", PATHS)
@pytest.mark.parametrize("name", sorted(CASES))
def test_products_equal_the_assembled_matrices(name, compiled):
    p, c = CASES[name]
    md = mass_diagonal(p)
    x = np.random.default_rng(1).standard_normal((p.dofs, 3))
    for kind, build in (("stiffness", stiffness_matrix), ("damping", damping_matrix)):
        if kind == "damping" and not c.damped:
            continue
        ref = scale_symmetric(build(p, c), md)
        op = ContactOperator(p, c, kind, mass_diag=md, compiled=compiled)
        got, want = op @ x, ref @ x
        assert np.max(np.abs(got - want)) <= 1e-12 * np.max(np.abs(want))
        assert op.applications == 3


@pytest.mark.parametrize("compiled", PATHS)
@pytest.mark.parametrize("name", ["random-springs", "random-all-terms", "rotated-all-terms"])
def test_bounds_from_the_operator_equal_the_assembled_ones(name, compiled):
    """Diagonal blocks, Gershgorin rows (both similar forms) and the per-DOF diagonal; no pair touches
    through two images here, so the row sums are the assembled ones exactly."""
    p, c = CASES[name]
    md = mass_diagonal(p)
    for kind, build in (("stiffness", stiffness_matrix), ("damping", damping_matrix)):
        ref = scale_symmetric(build(p, c), md)
        op = ContactOperator(p, c, kind, mass_diag=md, compiled=compiled)
        for f in (block_diagonal, diagonal_stiffness):
            assert f(op).omega2 == pytest.approx(f(ref).omega2, rel=1e-12)
        assert gershgorin(op, md).omega2 == pytest.approx(gershgorin(ref, md).omega2, rel=1e-12)
        dense = np.abs(ref.toarray())
        assert np.allclose(op.abs_row_sums(), dense.sum(axis=1), rtol=1e-12, atol=0)
        w = np.random.default_rng(2).uniform(0.1, 3.0, p.dofs)
        assert np.allclose(op.abs_row_sums(w), dense @ w, rtol=1e-12, atol=0)


def test_self_image_row_sums_are_valid_bounds():
    """Where a pair touches through several images the per-contact row sums exceed the assembled
    ones (triangle inequality): the Gershgorin bound stays above lambda_max."""
    p, c = CASES["fcc-self-images"]
    md = mass_diagonal(p)
    ref = scale_symmetric(stiffness_matrix(p, c), md)
    op = ContactOperator(p, c, mass_diag=md)
    assert np.all(op.abs_row_sums() >= np.abs(ref.toarray()).sum(axis=1) * (1 - 1e-12))
    top = sla.eigvalsh(ref.toarray())[-1]
    assert gershgorin(op, md).omega2 >= top
    assert block_diagonal(op).omega2 == pytest.approx(block_diagonal(ref).omega2, rel=1e-12)


@pytest.mark.parametrize("name", sorted(CASES))
def test_analyse_gives_the_same_omega_by_both_routes(name):
    p, c = CASES[name]
    c = replace(c, cn=None, cs=None, cr=None, ctw=None)
    old = analyse(p, contacts=c, route="assembled", certify_step=False)
    new = analyse(p, contacts=c, route="matrix-free", certify_step=False)
    assert (old.route, new.route) == ("assembled", "matrix-free")
    assert new.omega_max == pytest.approx(old.omega_max, rel=1e-9)
    dense = np.sqrt(sla.eigvalsh(scale_symmetric(stiffness_matrix(p, c), mass_diagonal(p)).toarray())[-1])
    assert new.omega_max == pytest.approx(dense, rel=1e-9)
    for key in ("gershgorin", "block_diagonal", "diagonal", "two_particle_exact", "rayleigh"):
        if name != "fcc-self-images" or key != "gershgorin":
            assert new.estimates[key].omega2 == pytest.approx(old.estimates[key].omega2, rel=1e-9), key
    assert new.dt_safe <= new.dt_crit * (1 + 1e-12)


def test_analyse_of_a_larger_lattice_by_both_routes():
    """A 6-DOF lattice above the dense limit (iterative solvers on both routes): same omega_max."""
    p = lattice("bcc", 5)
    c = apply_law(find_sphere_contacts(p), LinearLaw(1e7, 2e6))
    old = analyse(p, contacts=c, route="assembled", certify_step=False)
    new = analyse(p, contacts=c, route="matrix-free", certify_step=False)
    assert old.solver == "eigsh" and new.solver == "lobpcg"
    assert new.omega_max == pytest.approx(old.omega_max, rel=1e-9)


@pytest.mark.parametrize("integrator", ["velocity-verlet", "leapfrog-centred", "forward-euler"])
def test_damped_step_by_both_routes(integrator):
    p, c = CASES["random-all-terms"]
    if integrator == "forward-euler":  # the spectral-radius route: keep it small
        p = random_packing(20, cn=5.0, seed=4)
        c0 = apply_law(find_sphere_contacts(p), LinearLaw(1e5, 5e4))
        c = c0.with_damping(np.full(c0.count, 2.0), np.full(c0.count, 1.0))
    old = damped_critical_dt(p, c, integrator, route="assembled")
    new = damped_critical_dt(p, c, integrator, route="matrix-free")
    assert new.dt == pytest.approx(old.dt, rel=1e-7 if integrator == "forward-euler" else 1e-9)
    assert new.dt_lower == pytest.approx(old.dt_lower, rel=1e-9)
    assert new.dt_undamped == pytest.approx(old.dt_undamped, rel=1e-9)


def test_combined_operator():
    p, c = CASES["random-all-terms"]
    md = mass_diagonal(p)
    k, d = ContactOperator(p, c, mass_diag=md), ContactOperator(p, c, "damping", mass_diag=md)
    x = np.random.default_rng(3).standard_normal(p.dofs)
    want = 0.3 * (d.assembled() @ x) + 0.05 * (k.assembled() @ x)
    assert np.allclose(CombinedOperator(d, 0.3, k, 0.05) @ x, want, rtol=1e-12, atol=1e-12 * np.abs(want).max())


def test_bad_kind_and_missing_stiffness():
    from dtcrit.errors import InputError

    p, c = CASES["random-springs"]
    with pytest.raises(InputError, match="kind"):
        ContactOperator(p, c, "mass")
    with pytest.raises(InputError, match="stiffness"):
        ContactOperator(p, find_sphere_contacts(p))
    with pytest.raises(InputError, match="route"):
        analyse(p, contacts=c, route="gpu")
