"""Direct simulation of a small packing with a fixed contact list and linear springs.

Forces and moments are computed contact by contact (not from the assembled matrix): the relative
displacement of the two material points at the contact point is ``(u_j + theta_j x a_j) - (u_i +
theta_i x a_i)``, the spring force ``f = K_c delta`` pulls ``j`` back and pushes ``i``, and each
force's moment about the centre is ``a x f``.  Small rotations, spheres (isotropic inertia).
Velocity Verlet (the central-difference family) must stay bounded at 0.99 dt_crit and grow at
1.01 dt_crit, where dt_crit = 2/omega_max from the global eigen-analysis.
"""
import numpy as np
import pytest

from dtcrit.packing.detection.overlaps import find_sphere_contacts
from dtcrit.packing.generators.lattices import lattice
from dtcrit.packing.model import LinearLaw, apply_law
from dtcrit.packing.generators.random_packing import random_packing
from dtcrit.packing.report import analyse


def _accelerations(packing, contacts, u, theta):
    kn, ks = contacts.kn[:, None], contacts.ks[:, None]
    i, j = contacts.i, contacts.j
    delta = (u[j] + np.cross(theta[j], contacts.arm_j)) - (u[i] + np.cross(theta[i], contacts.arm_i))
    n = contacts.normal
    dn = np.sum(delta * n, axis=1)[:, None]
    f = kn * dn * n + ks * (delta - dn * n)
    force = np.zeros_like(u)
    torque = np.zeros_like(theta)
    np.add.at(force, i, f)
    np.add.at(force, j, -f)
    np.add.at(torque, i, np.cross(contacts.arm_i, f))
    np.add.at(torque, j, -np.cross(contacts.arm_j, f))
    return force / packing.masses[:, None], torque / packing.inertia


def _velocity_verlet(packing, contacts, dt, steps, seed=0):
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((packing.n, 3)) * packing.radii.mean() * 1e-3
    theta = rng.standard_normal((packing.n, 3)) * 1e-3
    v = np.zeros_like(u)
    w = np.zeros_like(theta)
    acc, alpha = _accelerations(packing, contacts, u, theta)
    start = np.sqrt(np.sum(u**2) / packing.radii.mean() ** 2 + np.sum(theta**2))
    peak = start
    for _ in range(steps):
        v += 0.5 * dt * acc
        w += 0.5 * dt * alpha
        u += dt * v
        theta += dt * w
        acc, alpha = _accelerations(packing, contacts, u, theta)
        v += 0.5 * dt * acc
        w += 0.5 * dt * alpha
        size = np.sqrt(np.sum(u**2) / packing.radii.mean() ** 2 + np.sum(theta**2))
        peak = max(peak, size)
        if size > 1e12 * start:
            break
    return peak / start, size / start


CASES = [
    ("random, kn = ks", lambda: random_packing(24, cn=6.5, seed=3, sizes="uniform", spread=0.3), LinearLaw(1e6, 1e6)),
    ("random, ks < kn", lambda: random_packing(24, cn=5.0, seed=8, sizes="lognormal", spread=0.3), LinearLaw(1e6, 2e5)),
    ("fcc", lambda: lattice("fcc", 1, radius=0.01, density=2500.0), LinearLaw(1e5, 3e4)),
]


@pytest.mark.parametrize("label,make,law", CASES, ids=[c[0] for c in CASES])
def test_bounded_below_and_growing_above_the_critical_step(label, make, law):
    packing = make()
    contacts = apply_law(find_sphere_contacts(packing), law)
    dt = analyse(packing, contacts=contacts, method="dense").dt_crit
    # 0.99 dt_crit: the top mode's amplitude can grow at most by 1/sqrt(1 - 0.99^2) ~ 7
    peak, _ = _velocity_verlet(packing, contacts, 0.99 * dt, 3000)
    assert peak < 30.0
    # 1.01 dt_crit: |lambda| = 1.33 per step for the top mode
    _, final = _velocity_verlet(packing, contacts, 1.01 * dt, 400)
    assert final > 1e6
