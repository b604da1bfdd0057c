"""The exact critical step of packings with per-contact dashpots (``dtcrit.packing.solvers.damped_step``).

References, each from another route than the code under test:
* two spheres: the 1-DOF root of the lagged central difference, ``4 - 2 h c A - h^2 k A = 0``,
  solved in mpmath at 50 digits;
* any packing: the eigenvalues of the dense amplification matrix (NumPy ``eigvals``) built by
  applying the scheme's own update rule to the unit states, just below and above the step;
* time-stepping the packing with that update rule: bounded below, growing above;
* proportional damping ``C = beta K``: the top mode's modal damping ratio ``beta omega / 2``.
"""
from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from dtcrit.integrators.schemes import INTEGRATORS
from dtcrit.packing.detection.overlaps import find_contacts
from dtcrit.packing.solvers.damped_step import damped_critical_dt, scaled_matrices
from dtcrit.packing.generators.lattices import lattice
from dtcrit.packing.model import LinearLaw, Packing, apply_law


def _dense_radius(k, c, integrator, h):
    """Largest |lambda| of the amplification matrix, column by column from the update rule."""
    k, c = k.toarray(), c.toarray()
    n = k.shape[0]
    scheme = INTEGRATORS[integrator]
    parts = len(scheme.state)
    force = lambda x, v: -(k @ x) - (c @ v)  # noqa: E731
    cols = []
    for e in np.eye(parts * n):
        cols.append(np.concatenate(scheme.step([e[p * n:(p + 1) * n] for p in range(parts)], h, force)))
    w = np.linalg.eigvals(np.array(cols).T)
    # rigid-body modes (zero frequency) are Jordan blocks at +1: rounding moves them by ~sqrt(eps)
    return float(np.max(np.abs(w[np.abs(w - 1.0) > 1e-5]), initial=0.0))


def _damped_fcc(seed, ks_ratio=2 / 7, scale=1.0):
    p = lattice("fcc", 2, radius=1.0, density=1.0)
    c = apply_law(find_contacts(p, tolerance=1e-6), LinearLaw(1e4 * scale, ks_ratio * 1e4 * scale))
    rng = np.random.default_rng(seed)
    return p, c.with_damping(rng.uniform(0, 40, c.count) * math.sqrt(scale), rng.uniform(0, 10, c.count) * math.sqrt(scale))


def _pair(kn, m, cn):
    p = Packing.spheres([[0, 0, 0], [1.999, 0, 0]], 1.0, masses=m)
    c = apply_law(find_contacts(p, 1e-6), LinearLaw(kn, 0.0))
    return p, c.with_damping(cn, 0.0)


@settings(max_examples=40, deadline=None, derandomize=True)
@given(kn=st.floats(1e-6, 1e12), m=st.floats(1e-9, 1e6), zeta=st.floats(0.0, 50.0))
def test_two_spheres_match_the_50_digit_root(kn, m, zeta):
    mp.mp.dps = 50
    a = 2.0 / m  # relative normal motion: inverse reduced mass
    cn = 2.0 * zeta * math.sqrt(kn / a)
    p, c = _pair(kn, m, cn)
    got = damped_critical_dt(p, c, "velocity-verlet").dt
    K, C = mp.mpf(kn) * mp.mpf(a), mp.mpf(cn) * mp.mpf(a)
    ref = (-C + mp.sqrt(C * C + 4 * K)) / K  # root of 4 - 2hC - h^2 K
    assert abs(got / float(ref) - 1) < 1e-9


@pytest.mark.parametrize("integrator", ["velocity-verlet", "leapfrog", "symplectic-euler"])
@pytest.mark.parametrize("seed", [1, 2])
def test_the_root_is_where_the_amplification_matrix_leaves_the_unit_disk(integrator, seed):
    p, c = _damped_fcc(seed)
    r = damped_critical_dt(p, c, integrator)
    k, cm = scaled_matrices(p, c)
    assert _dense_radius(k, cm, integrator, r.dt * (1 - 1e-6)) <= 1.0 + 1e-7
    assert _dense_radius(k, cm, integrator, r.dt * (1 + 1e-6)) > 1.0 + 1e-6
    assert 0 < r.dt_lower <= r.dt < r.dt_undamped  # the dashpots lower the step below 2/omega_max


def test_a_mode_other_than_the_top_undamped_one_governs():
    """Strong dashpots on the normal springs only: the modal route (top undamped mode and its modal
    damping ratio) is not the answer, the exact one is (checked against the dense matrix above)."""
    from dtcrit.packing.solvers.integrator_step import integrator_dt

    p = lattice("fcc", 2, radius=1.0, density=1.0)
    c = apply_law(find_contacts(p, tolerance=1e-6), LinearLaw(1e4, 1e4))
    m_eff = p.masses[0] / 2
    c = c.with_damping(2 * 0.5 * math.sqrt(1e4 * m_eff), 0.0)  # contact zeta 0.5 on the normal spring
    r = damped_critical_dt(p, c, "velocity-verlet")
    k, cm = scaled_matrices(p, c)
    v = r.vector
    top_k = np.linalg.eigh(k.toarray())
    phi = top_k[1][:, -1]
    zeta_modal = max(0.0, float(phi @ (cm @ phi)) / (2 * math.sqrt(top_k[0][-1])))
    dt_modal, _ = integrator_dt(math.sqrt(top_k[0][-1]), "velocity-verlet", zeta_modal)
    assert abs(dt_modal / r.dt - 1) > 0.02
    assert _dense_radius(k, cm, "velocity-verlet", r.dt * (1 + 1e-6)) > 1.0
    assert _dense_radius(k, cm, "velocity-verlet", r.dt * (1 - 1e-6)) <= 1.0 + 1e-7
    assert abs(np.linalg.norm(v) - 1) < 1e-9


def test_proportional_damping_is_the_modal_answer():
    from dtcrit.packing.solvers.integrator_step import integrator_dt

    p = lattice("bcc", 2, radius=1.0, density=1.0)
    c = apply_law(find_contacts(p, tolerance=1e-6), LinearLaw(1e4, 3e3))
    beta = 2e-3
    c = c.with_damping(beta * c.kn, beta * c.ks)  # C = beta K
    r = damped_critical_dt(p, c, "velocity-verlet")
    omega = 2.0 / r.dt_undamped
    dt_modal, _ = integrator_dt(omega, "velocity-verlet", beta * omega / 2)
    assert abs(r.dt / dt_modal - 1) < 1e-8


@pytest.mark.parametrize("scale", [1e-8, 1.0, 1e8])
def test_time_stepping_the_packing_bounded_below_growing_above(scale):
    p, c = _damped_fcc(3, scale=scale)
    r = damped_critical_dt(p, c, "velocity-verlet")
    k, cm = (m.toarray() for m in scaled_matrices(p, c))
    step = INTEGRATORS["velocity-verlet"].step
    force = lambda x, v: -(k @ x) - (cm @ v)  # noqa: E731
    growth = {}
    for factor in (0.99, 1.01):
        rng = np.random.default_rng(7)
        x = rng.standard_normal(k.shape[0])
        s = [x, np.zeros_like(x), force(x, np.zeros_like(x))]
        start = np.linalg.norm(s[0])
        for _ in range(4000):
            s = list(step(s, factor * r.dt, force))
            if np.linalg.norm(s[0]) > 1e6 * start:
                break
        growth[factor] = np.linalg.norm(s[0]) / start
    assert growth[0.99] < 10.0
    assert growth[1.01] > 1e3


def test_centred_leapfrog_ignores_the_dashpots():
    p, c = _damped_fcc(4)
    r = damped_critical_dt(p, c, "leapfrog-centred")
    assert r.dt == r.dt_undamped
