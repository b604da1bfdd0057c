"""LAMMPS (real engine) agrees with dtcrit's exact critical step of a packing with contact dashpots.

Case: the FCC lattice of ``test_engine_lammps_lattices`` (2 x 2 x 2 cells, 32 equal spheres,
overlap 1e-6 R) with ks = kn and a normal dashpot on every contact, gran/hooke/history
``kn kn gamman 0 1e4 0`` (dampflag 0: no tangential dashpot).  LAMMPS's normal dashpot force is
``meff gamman v_n`` with ``meff = m_i m_j / (m_i + m_j)`` (src/GRANULAR/pair_gran_hooke_history.cpp),
so the contact dashpot is ``cn = meff gamman``; gamman is chosen for a contact damping ratio
``zeta = cn / (2 sqrt(kn meff)) = 0.5`` of the normal spring.

The top undamped mode of this lattice is a pure rotation (three-fold degenerate), which a normal
dashpot does not touch, so its modal damping ratio is 0; the step is governed by another,
damped, translational mode.  dtcrit predicts it with
``dtcrit.packing.solvers.damped_step.damped_critical_dt(packing, contacts.with_damping(cn, 0))``, the exact step
of the whole damped packing.  Checks, LAMMPS being the reference:
  * bounded at 0.99x and growing at 1.01x of that step (and bounded at its lower bound ``dt_lower``);
  * LAMMPS's threshold extrapolated from its growth rates just above it (a damped critical mode
    crosses the unit circle with non-zero speed: ln z linear in dt) equals it to 1e-5;
  * the two routes available before are wrong on this case: the modal route (the top undamped
    mode with its modal damping ratio, ``dtcrit.packing.solvers.integrator_step.integrator_dt``) is 22 % above
    LAMMPS's threshold, where LAMMPS grows; the per-contact zeta applied to that mode is 24 % below.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from support.engines import require_engine
from support.engines.lammps import ContactLaw, Sphere
from support.engines.lammps_lattice import LatticeCase, extrapolated_threshold, run_many

R, RHO, KN = 1.0e-3, 2500.0, 1.0e5
SPHERE = Sphere(radius=R, density=RHO)
ZETA = 0.5  # contact damping ratio of the normal spring
MEFF = SPHERE.m / 2.0  # LAMMPS's meff of two equal spheres
GAMMAN = 2.0 * ZETA * math.sqrt(KN / MEFF)  # zeta = meff gamman / (2 sqrt(kn meff))
CN = MEFF * GAMMAN
CASE = LatticeCase(ContactLaw(KN, kt=KN, gamman=GAMMAN, dampflag=0), "fcc", 2, SPHERE)
STEPS = 4000  # 1.01x halts within ~300 steps (growth rate ~1.035 per step)


def _packing_and_contacts():
    from dtcrit.packing import LinearLaw, apply_law, find_contacts, lattice

    packing = lattice("fcc", CASE.cells, radius=R, density=RHO)
    return packing, apply_law(find_contacts(packing), LinearLaw(KN, KN)).with_damping(CN, 0.0)


@pytest.fixture(scope="module")
def lmp() -> str:
    return require_engine("lammps")


@pytest.fixture(scope="module")
def predicted():
    from dtcrit.packing.solvers.damped_step import damped_critical_dt

    packing, contacts = _packing_and_contacts()
    return damped_critical_dt(packing, contacts, integrator="velocity-verlet")


@pytest.fixture(scope="module")
def lammps_threshold(lmp, predicted):
    threshold, _ = extrapolated_threshold(CASE, [predicted.dt * (1 + e) for e in (2e-4, 5e-4, 1e-3, 2e-3)],
                                          onset="linear", lmp=lmp)
    return threshold


def test_lammps_bounded_below_and_grows_above_the_damped_step(lmp, predicted):
    dt = predicted.dt
    assert 0.0 < predicted.dt_lower <= dt < predicted.dt_undamped
    lower, below, above = run_many([(CASE, predicted.dt_lower, STEPS), (CASE, 0.99 * dt, STEPS),
                                    (CASE, 1.01 * dt, STEPS)], lmp=lmp)
    assert lower.bounded, f"LAMMPS grows at dtcrit's lower bound {predicted.dt_lower:.6e}"
    assert below.bounded, (f"LAMMPS grows at 0.99x dtcrit's damped step {dt:.6e}: growth={below.growth:.3g}, "
                           f"window={below.window_growth:.3g}, halted={below.halted}")
    assert not above.bounded and above.halted and above.rate > 1.01, (
        f"LAMMPS does not grow at 1.01x dtcrit's damped step {dt:.6e}: rate={above.rate}")


def test_lammps_threshold_equals_the_damped_step(predicted, lammps_threshold):
    assert predicted.dt / lammps_threshold == pytest.approx(1.0, abs=1e-5)


def test_modal_route_is_unsafe_and_per_contact_zeta_too_cautious(lmp, predicted, lammps_threshold):
    from dtcrit.packing.solvers.damped_step import scaled_matrices
    from dtcrit.packing.solvers.integrator_step import integrator_dt
    from dtcrit.packing.solvers.largest_mode import largest_mode

    packing, contacts = _packing_and_contacts()
    k, c = scaled_matrices(packing, contacts)
    top = largest_mode(k, "dense")
    space = top.space
    # modal damping ratios over the (degenerate) top undamped eigenspace: phi^T C~ phi / (2 omega)
    zetas = np.linalg.eigvalsh(space.T @ (c @ space)) / (2.0 * top.omega)
    modal = [integrator_dt(top.omega, "velocity-verlet", float(max(z, 0.0)))[0] for z in (zetas[0], zetas[-1])]
    per_contact = integrator_dt(top.omega, "velocity-verlet", ZETA)[0]
    for dt in modal:
        assert dt / lammps_threshold == pytest.approx(1.2218, abs=2e-3)  # 22 % too large
    assert per_contact / lammps_threshold == pytest.approx(0.7551, abs=2e-3)  # 24 % too small
    # LAMMPS itself grows at 0.99x of the modal route's step
    (run,) = run_many([(CASE, 0.99 * min(modal), STEPS)], lmp=lmp)
    assert not run.bounded and run.halted
