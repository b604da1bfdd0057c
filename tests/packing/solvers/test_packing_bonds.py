"""Bonded assemblies with bending and twisting springs, time-stepped against ``dtcrit.packing``'s step.

A bonded 3 x 3 square lattice and a bonded zig-zag chain (spheres, each bond its own ``kn``, ``ks``,
``kr``, ``ktw``; the rotational springs make the step 30-40 % shorter than the translational
springs alone).  The reference is a simulation: the assembled ``M``, ``K`` (and the dashpot matrix
``C``) stepped with the update rules of ``dtcrit.integrators.schemes`` on ``y = M^(1/2) x``,
``y'' = -K~ y - C~ y'``.  It stays bounded at 0.99x and grows at 1.01x of the packing analysis's
step: ``analyse(...).dt_integrator`` undamped, ``damped_critical_dt`` with the bond dashpots
(``cn``, ``cs``, ``cr``, ``ctw``).
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from dtcrit.integrators.schemes import INTEGRATORS, LinearForce
from dtcrit.packing import Packing, analyse, find_sphere_contacts
from dtcrit.packing.operators.assembly import damping_matrix, mass_diagonal, scale_symmetric, stiffness_matrix
from dtcrit.packing.solvers.damped_step import damped_critical_dt

R, RHO, KN = 1.0e-3, 2500.0, 1.0e5


def _lattice() -> Packing:
    x = np.array([[2.0 * R * a, 2.0 * R * b, 0.0] for a in range(3) for b in range(3)])
    return Packing.spheres(x, R, density=RHO)


def _chain() -> Packing:
    """Seven spheres, each bond 2R long, zig-zagging at 120 degrees in plan and up and down in z."""
    steps = [np.array([math.cos(math.radians(30.0 if k % 2 == 0 else -30.0)),
                       math.sin(math.radians(30.0 if k % 2 == 0 else -30.0)), 0.2 * (-1) ** k]) for k in range(6)]
    bonds = np.array([2.0 * R * s / np.linalg.norm(s) for s in steps])
    return Packing.spheres(np.vstack([np.zeros(3), np.cumsum(bonds, axis=0)]), R, density=RHO)


def _bonds(packing: Packing, seed: int, *, damped: bool):
    contacts = find_sphere_contacts(packing, tolerance=1e-9)
    rng = np.random.default_rng(seed)
    n = contacts.count
    kn = KN * rng.uniform(0.5, 2.0, n)
    ks = kn * rng.uniform(0.2, 0.5, n)
    kr = ks * R * R * rng.uniform(1.0, 4.0, n)  # YADE-like alpha ks R1 R2 with alpha in [1, 4]
    ktw = ks * R * R * rng.uniform(1.0, 4.0, n)
    contacts = contacts.with_stiffness(kn, ks, kr, ktw)
    if damped:
        m = packing.masses[0]
        i_ = 0.4 * m * R * R
        zeta = 0.05
        contacts = contacts.with_damping(2 * zeta * np.sqrt(kn * m / 2), 2 * zeta * np.sqrt(ks * m / 2),
                                         2 * zeta * np.sqrt(kr * i_ / 2), 2 * zeta * np.sqrt(ktw * i_ / 2))
    return contacts


def _simulate(packing, contacts, integrator: str, dt: float, steps: int = 3000, seed: int = 0) -> float:
    """Largest ``|y|`` over the run relative to the start, stepping ``y'' = -K~ y - C~ y'``."""
    md = mass_diagonal(packing)
    k = scale_symmetric(stiffness_matrix(packing, contacts), md).tocsr()
    c = scale_symmetric(damping_matrix(packing, contacts), md).tocsr() if contacts.damped else 0.0
    force = LinearForce(k, c)
    scheme = INTEGRATORS[integrator]
    y = np.random.default_rng(seed).standard_normal(md.size)
    state = [y, np.zeros_like(y)] + ([force(y, np.zeros_like(y))] if len(scheme.state) == 3 else [])
    start, peak = np.linalg.norm(y), 0.0
    for _ in range(steps):
        state = list(scheme.step(state, dt, force))
        peak = max(peak, np.linalg.norm(state[0]) / start)
        if peak > 1e8:
            break
    return peak


ASSEMBLIES = {"lattice": _lattice, "chain": _chain}


@pytest.mark.parametrize("shape", list(ASSEMBLIES))
@pytest.mark.parametrize("integrator", ["leapfrog", "velocity-verlet"])
def test_undamped_bonds_bounded_below_growing_above_the_packing_step(shape, integrator):
    packing = ASSEMBLIES[shape]()
    contacts = _bonds(packing, seed=3, damped=False)
    dt = analyse(packing, contacts=contacts, integrator=integrator, with_estimates=False).dt_integrator
    assert _simulate(packing, contacts, integrator, 0.99 * dt) < 100.0
    assert _simulate(packing, contacts, integrator, 1.01 * dt) > 1e6


@pytest.mark.parametrize("shape", list(ASSEMBLIES))
def test_damped_bonds_bounded_below_growing_above_the_damped_step(shape):
    """Leapfrog with the bonds' four dashpots on the lagged velocity (YADE's NewtonIntegrator)."""
    packing = ASSEMBLIES[shape]()
    contacts = _bonds(packing, seed=5, damped=True)
    step = damped_critical_dt(packing, contacts, "leapfrog")
    assert step.dt < step.dt_undamped, "the dashpots shorten the lagged central difference's step"
    assert _simulate(packing, contacts, "leapfrog", 0.99 * step.dt) < 100.0
    assert _simulate(packing, contacts, "leapfrog", 1.01 * step.dt) > 1e6


@pytest.mark.parametrize("shape", list(ASSEMBLIES))
def test_bending_and_twisting_springs_set_the_step(shape):
    """The cases test the rotational springs: without kr, ktw the step is over 20 % longer, and
    a simulation at the translational-only step grows (the bonds' bending modes are faster)."""
    packing = ASSEMBLIES[shape]()
    contacts = _bonds(packing, seed=3, damped=False)
    dt = analyse(packing, contacts=contacts, integrator="leapfrog", with_estimates=False).dt_integrator
    plain = replace(contacts, kr=None, ktw=None)
    dt_plain = analyse(packing, contacts=plain, integrator="leapfrog", with_estimates=False).dt_integrator
    assert dt_plain / dt > 1.2
    assert _simulate(packing, contacts, "leapfrog", 0.99 * dt_plain) > 1e6
