"""Bounds on random packings: Gershgorin dt <= exact dt <= Rayleigh dt <= single-contact dt, and
the sparse solvers against dense ``scipy.linalg.eigh``."""
import math

import numpy as np
import pytest
import scipy.linalg as sla
from hypothesis import assume, given, settings, strategies as st

from dtcrit.packing.operators.assembly import mass_diagonal, scale_symmetric, stiffness_matrix
from dtcrit.packing.detection.overlaps import find_sphere_contacts
from dtcrit.packing.solvers.largest_mode import largest_mode
from dtcrit.packing.model import HertzMindlinLaw, LinearLaw, Packing, apply_law
from dtcrit.packing.generators.random_packing import random_packing
from dtcrit.packing.report import analyse
from support.strategies import log_uniform as decades


packings = st.builds(
    lambda n, cn, sizes, spread, radius, density, seed: random_packing(
        n, cn=cn, sizes=sizes, spread=spread if sizes != "mono" else 0.0, radius=radius, density=density,
        seed=seed, max_steps=80),
    n=st.integers(8, 30), cn=st.floats(1.0, 10.0), sizes=st.sampled_from(["mono", "uniform", "lognormal"]),
    spread=st.floats(0.0, 0.6), radius=decades(-5, 1), density=decades(2, 4), seed=st.integers(0, 2**16),
)


def _dense_top(packing, contacts):
    a = scale_symmetric(stiffness_matrix(packing, contacts), mass_diagonal(packing)).toarray()
    return sla.eigvalsh(a)[-1]


@given(packing=packings, kn=decades(2, 9), ks_ratio=decades(-2, 0.5))
def test_gershgorin_exact_rayleigh_ordering(packing, kn, ks_ratio):
    rep = analyse(packing, LinearLaw(kn, kn * ks_ratio), method="dense")
    exact = 2.0 / np.sqrt(_dense_top(packing, apply_law(find_sphere_contacts(packing), LinearLaw(kn, kn * ks_ratio))))
    assert rep.dt_crit == pytest.approx(exact, rel=1e-10)
    e = rep.estimates
    slack = 1 + 1e-10
    assert e["gershgorin"].dt <= rep.dt_crit * slack
    assert e["block_diagonal"].dt <= rep.dt_crit * slack
    assert rep.dt_crit <= e["rayleigh"].dt * slack
    assert e["rayleigh"].dt <= e["two_particle_exact"].dt * slack
    # with spheres Peng's A_max uses the full radius as the arm (>= R - overlap/2): never larger
    if kn * ks_ratio >= kn:
        assert e["two_particle_amax"].dt <= e["two_particle_exact"].dt * slack
    assert rep.cn_mean == pytest.approx(2 * rep.n_contacts / rep.n_particles)


@settings(max_examples=15)
@given(packing=packings, youngs=decades(6, 11))
def test_ordering_with_hertz_tangent_stiffness(packing, youngs):
    rep = analyse(packing, HertzMindlinLaw(youngs, 0.3), method="dense")
    assume(np.isfinite(rep.dt_crit))  # not when every contact is exactly touching: no stiffness at all
    e = rep.estimates
    assert e["gershgorin"].dt <= rep.dt_crit * (1 + 1e-10) <= e["rayleigh"].dt * (1 + 1e-9)
    assert e["block_diagonal"].dt <= rep.dt_crit * (1 + 1e-10)


@settings(max_examples=8)
@given(seed=st.integers(0, 2**16), cn=st.floats(3.0, 9.0), sizes=st.sampled_from(["mono", "lognormal"]))
def test_sparse_solvers_agree_with_dense_eigh(seed, cn, sizes):
    p = random_packing(100, cn=cn, sizes=sizes, spread=0.3, seed=seed, max_steps=100)
    c = apply_law(find_sphere_contacts(p), LinearLaw(1.0, 0.8))
    a = scale_symmetric(stiffness_matrix(p, c), mass_diagonal(p))
    dense = sla.eigvalsh(a.toarray())[-1]
    for method in ("eigsh", "lobpcg"):
        top = largest_mode(a, method, tol=1e-10)
        assert top.value == pytest.approx(dense, rel=1e-7), method
        assert top.value <= dense * (1 + 1e-12)  # a Ritz value never overshoots
        assert top.residual <= 1e-4 * dense


def test_damped_bound_uses_modal_damping():
    stability = pytest.importorskip("dtcrit.integrators.stability")
    p = random_packing(30, cn=6, seed=4)
    rep = analyse(p, LinearLaw(1e5, 1e5), integrator="velocity-verlet", damping_ratio=0.2)
    w = rep.omega_max
    assert rep.dt_integrator == pytest.approx(stability.critical_dt("velocity-verlet", w * w, 0.4 * w, 1.0).dt, rel=1e-12)
    assert rep.dt_integrator < rep.dt_crit


@pytest.mark.parametrize("direction,ks,diagonal_ratio", [
    ((1, 0, 0), 1.0, math.sqrt(7 / 5)), ((1, 1, 1), 1.0, math.sqrt(2.1)), ((1, 1, 1), 1e-9, math.sqrt(3))])
def test_axis_wise_diagonal_estimate_is_not_a_bound(direction, ks, diagonal_ratio):
    """Counter-examples for the YADE/PFC axis-wise diagonal estimate (with its sqrt(2) factor) on
    two equal spheres, omega_max^2 = 7 ks/m (or 2 kn/m): along x with kn = ks it misses the
    translation-rotation coupling (2 * 2.5 k/m = 5k/m); along (1,1,1) each rotation axis sees only
    2/3 of the sliding stiffness (2 * 5/3 k/m), and with ks -> 0 each translation axis kn/3.  The
    6x6 block version stays a bound and is exact for the equal pair with kn = ks."""
    d = np.array(direction, float) / np.linalg.norm(direction)
    p = Packing.spheres([np.zeros(3), 2.0 * d], 1.0, masses=1.0)
    rep = analyse(p, LinearLaw(1.0, ks))
    e = rep.estimates
    assert e["diagonal"].dt / rep.dt_crit == pytest.approx(diagonal_ratio, rel=1e-6)
    assert e["block_diagonal"].dt <= rep.dt_crit * (1 + 1e-12)
    if ks == 1.0:
        assert e["block_diagonal"].dt == pytest.approx(rep.dt_crit, rel=1e-12)
