"""Density scaling plans checked independently: the scaled packing's critical step from a dense
``scipy.linalg.eigh`` of the assembled ``M^-1/2 K M^-1/2`` with the factors applied (``2/sqrt(lambda_max)``
for the undamped central difference; with dashpots the positive definiteness of ``4FM - 2hC - h^2 K``),
and YADE's ``densityScaling`` rule computed here as YADE 2023.02a applies it (read back from
``state.densityScaling`` after a real run, ``tests/engines/test_engine_density_scaling.py``):
``densityScaling = (dt_b / targetDt)^2`` with ``dt_b = 1.41044 safety sqrt(min(m / max_a K_a, min_a I_a / K_rot,a))``.

Packings: ``examples/packings/random_lognormal_60.dump`` under linear springs, dashpots and Hertz, and a
polydisperse packing generated here; targets 2x and 5x today's critical step.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg as sla

from dtcrit.packing.audit.run import read_snapshot
from dtcrit.packing.generators.random_packing import random_packing
from dtcrit.packing.operators.assembly import damping_matrix, stiffness_matrix
from dtcrit.packing.readers.lammps_dump import write_dump
from dtcrit.plan import plan_density_scaling
from support.paths import REPO_ROOT as ROOT

EXAMPLE = ROOT / "examples" / "packings" / "random_lognormal_60.dump"
HOOKE = "gran/hooke/history 1e5 NULL 0 NULL 0.5 0"
YADE_SAFETY = 0.8  # GlobalStiffnessTimeStepper.hpp: timestepSafetyCoefficient default
YADE_SQRT2 = 1.41044  # GlobalStiffnessTimeStepper.cpp: the constant it writes for sqrt(2)


def _mass_rows(packing, factors):
    m = np.concatenate([np.repeat(packing.masses[:, None], 3, axis=1), packing.inertia], axis=1)
    return (m * np.asarray(factors)[:, None]).reshape(-1)


def _omega2(snapshot, factors) -> float:
    """lambda_max of M^-1/2 K M^-1/2, dense, with the factors on every mass and moment."""
    k = stiffness_matrix(snapshot.packing, snapshot.contacts).toarray()
    s = 1.0 / np.sqrt(_mass_rows(snapshot.packing, factors))
    return float(sla.eigh(s[:, None] * k * s[None, :], eigvals_only=True)[-1])


def _scaled_dashpots(snapshot, factors):
    """The contacts with every gran/* dashpot m_eff gamma at the scaled masses (LAMMPS recomputes m_eff each step)."""
    from dataclasses import replace

    m, f = snapshot.packing.masses, np.asarray(factors, float)
    i, j = snapshot.contacts.i, snapshot.contacts.j
    ratio = (m[i] * f[i] * m[j] * f[j] / (m[i] * f[i] + m[j] * f[j])) / (m[i] * m[j] / (m[i] + m[j]))
    c = snapshot.contacts
    return replace(c, cn=None if c.cn is None else c.cn * ratio, cs=None if c.cs is None else c.cs * ratio)


def _stable_lagged(snapshot, factors, h) -> bool:
    """4FM - 2hC(F) - h^2 K positive definite (the lagged central difference's stability condition), the
    gran/* dashpots m_eff gamma at the scaled masses.
    """
    k = stiffness_matrix(snapshot.packing, snapshot.contacts).toarray()
    c = damping_matrix(snapshot.packing, _scaled_dashpots(snapshot, factors)).toarray()
    s = 1.0 / np.sqrt(_mass_rows(snapshot.packing, factors))
    a = 4.0 * np.eye(k.shape[0]) - s[:, None] * (2.0 * h * c + h * h * k) * s[None, :]
    return bool(sla.eigh(a, eigvals_only=True)[0] > 0)


def _yade_factors(snapshot, target, safety=YADE_SAFETY):
    """YADE's first-call mass factors 1/densityScaling, bodies needing none at 1 (module docstring)."""
    p, c = snapshot.packing, snapshot.contacts
    n2 = c.normal**2
    k_t, k_r = np.zeros((p.n, 3)), np.zeros((p.n, 3))
    across = np.stack([n2[:, 1] + n2[:, 2], n2[:, 0] + n2[:, 2], n2[:, 0] + n2[:, 1]], axis=1)
    for side in (c.i, c.j):
        np.add.at(k_t, side, n2 * (c.kn - c.ks)[:, None] + c.ks[:, None])
        np.add.at(k_r, side, across * (c.ks * p.radii[side] ** 2)[:, None])
    with np.errstate(divide="ignore"):  # a body without contacts: YADE skips it (inf)
        sq = np.minimum(p.masses / k_t.max(axis=1), (p.inertia / k_r).min(axis=1))
    dt_b = YADE_SQRT2 * safety * np.sqrt(sq)
    return 1.0 / np.minimum(1.0, (dt_b / target) ** 2)


def _added(snapshot, factors) -> float:
    m = snapshot.packing.masses
    return float(np.sum(m * (factors - 1.0)) / m.sum())


@pytest.fixture(scope="module")
def polydisperse(tmp_path_factory):
    """An 80-sphere lognormal packing (sigma 0.45) made by the FIRE generator, as a dump read back."""
    packing = random_packing(80, cn=6.0, sizes="lognormal", spread=0.45, radius=1e-3, density=2500.0, seed=3)
    path = tmp_path_factory.mktemp("plan") / "poly.dump"
    write_dump(path, packing)
    return read_snapshot(path, pair_style="gran/hooke/history 2e5 NULL 0 NULL 0.5 0")


CASES = {"example-hooke": (EXAMPLE, HOOKE), "example-hertz": (EXAMPLE, "gran/hertz/history 1e9 NULL 0 NULL 0.5 0")}


@pytest.mark.parametrize("times", [2.0, 5.0])
@pytest.mark.parametrize("case", ["example-hooke", "example-hertz", "polydisperse"])
def test_scaled_packing_meets_target_with_less_mass_than_yade(case, times, polydisperse):
    """The dense solve of the scaled packing meets the target; less mass than YADE's rule and a uniform factor."""
    snap = polydisperse if case == "polydisperse" else read_snapshot(CASES[case][0], pair_style=CASES[case][1])
    dt_now = 2.0 / math.sqrt(_omega2(snap, np.ones(snap.packing.n)))
    target = times * dt_now
    plan = plan_density_scaling(snap, target)
    assert plan.dt_crit == pytest.approx(dt_now, rel=1e-9)
    assert np.all(plan.factors >= 1.0) and plan.factors.shape == (snap.packing.n,)
    dt_scaled = 2.0 / math.sqrt(_omega2(snap, plan.factors))  # independent dense solve
    assert dt_scaled >= target
    assert dt_scaled == pytest.approx(plan.dt_crit_scaled, rel=1e-9)
    yade = _yade_factors(snap, target)
    assert plan.yade_rule_added_mass_fraction == pytest.approx(_added(snap, yade), rel=1e-12)
    assert plan.added_mass_fraction < _added(snap, yade)
    # the uniform factor is exactly (target/dt_now)^2 for springs alone, and costs more mass
    assert plan.uniform_factor == pytest.approx(times**2, rel=1e-5)
    assert plan.added_mass_fraction < plan.uniform_added_mass_fraction


@pytest.mark.parametrize("case", ["example-hooke", "polydisperse"])
def test_bound_factors_alone_are_stable(case, polydisperse):
    """The Gershgorin/block-diagonal start is stable at the target without any eigen-solve."""
    snap = polydisperse if case == "polydisperse" else read_snapshot(EXAMPLE, pair_style=HOOKE)
    target = 3.0 * 2.0 / math.sqrt(_omega2(snap, np.ones(snap.packing.n)))
    plan = plan_density_scaling(snap, target)
    assert 2.0 / math.sqrt(_omega2(snap, plan.bound_factors)) >= target
    assert plan.added_mass_fraction <= plan.bound_added_mass_fraction


def test_dashpots_plan_is_stable_by_the_lagged_condition():
    """With dashpots: 4FM - 2hC - h^2 K is positive definite with the plan, not without it, and not with 10 % less."""
    snap = read_snapshot(EXAMPLE, pair_style="gran/hooke/history 1e5 NULL 50 NULL 0.5 0")
    assert snap.contacts.damped
    target = 2.0 * 2.0 / math.sqrt(_omega2(snap, np.ones(snap.packing.n)))
    plan = plan_density_scaling(snap, target)
    assert _stable_lagged(snap, plan.factors, target)
    assert not _stable_lagged(snap, np.ones(snap.packing.n), target)
    # a little less mass on every body that was scaled is already unstable: the plan is tight
    assert not _stable_lagged(snap, 1.0 + 0.9 * (plan.factors - 1.0), target)


def _yade_export(path, damping):
    """Five spheres of a YADE export (``dtcrit-yade-export/1``) with loaded contacts and local damping."""
    import json

    r, rho = 1e-3, 2650.0
    mass = 4.0 / 3.0 * math.pi * r**3 * rho
    d = 2 * r - 2e-6
    pos = [(0.0, 0.0, 0.0), (d, 0.0, 0.0), (2 * d, 0.0, 0.0), (d, d, 0.0), (d, 0.6 * d, 0.8 * d)]
    springs = ((1e5, 3e4), (2e5, 5e4), (7e4, 6e4), (1.5e5, 2e4))
    bodies = [{"id": k, "pos": list(p), "radius": r, "mass": mass * (1 + 0.3 * k),
               "inertia": [0.4 * mass * (1 + 0.3 * k) * r * r] * 3, "clump_id": None, "is_clump": False,
               "fixed": False, "ori": [1, 0, 0, 0]} for k, p in enumerate(pos)]
    inters = [{"id1": a, "id2": b, "kn": kn, "ks": ks, "kr": None, "ktw": None, "cn": None, "cs": None,
               "fn": kn * 2e-6, "penetration": 2e-6, "shift2": [0.0, 0.0, 0.0],
               "normal": list((np.subtract(pos[b], pos[a]) / np.linalg.norm(np.subtract(pos[b], pos[a]))).tolist())}
              for (a, b), (kn, ks) in zip([(0, 1), (1, 2), (1, 3), (1, 4)], springs)]
    path.write_text(json.dumps({"schema": "dtcrit-yade-export/1", "yade_version": "2023.02a", "dt": 1e-7, "iter": 3,
                                "newton_damping": damping, "periodic": False, "cell_hsize": None,
                                "avoid_granular_ratcheting": True, "bodies": bodies, "interactions": inters}))
    return path


def test_yade_export_with_local_damping(tmp_path):
    """A YADE export with newton_damping 0.2: the plan's step is the audit's (times 1/sqrt(1.2)) and meets the target."""
    snap = read_snapshot(_yade_export(tmp_path / "export.json", 0.2))
    factor = 1.0 / math.sqrt(1.2)
    dt_now = factor * 2.0 / math.sqrt(_omega2(snap, np.ones(snap.packing.n)))
    plan = plan_density_scaling(snap, 2.0 * dt_now)
    assert plan.dt_crit == pytest.approx(dt_now, rel=1e-9)
    assert factor * 2.0 / math.sqrt(_omega2(snap, plan.factors)) >= 2.0 * dt_now
    assert plan.yade_factors is not None and plan.added_mass_fraction < plan.yade_rule_added_mass_fraction


@pytest.mark.parametrize("seed,spread,gamma,times", [(11, 0.2, 0.0, 1.5), (12, 0.5, 80.0, 3.0), (13, 0.35, 20.0, 6.0)])
def test_random_packings_with_and_without_dashpots(tmp_path, seed, spread, gamma, times):
    """Small generated packings, dashpots or none: the plan and the bound's factors alone are stable at the
    target by the lagged condition, the unscaled packing is not.
    """
    packing = random_packing(24, cn=6.0, sizes="lognormal", spread=spread, radius=1e-3, density=2500.0, seed=seed)
    path = tmp_path / "p.dump"
    write_dump(path, packing)
    snap = read_snapshot(path, pair_style=f"gran/hooke/history 1e5 NULL {gamma!r} NULL 0.5 0")
    dt_now = _lagged_step(snap)
    plan = plan_density_scaling(snap, times * dt_now)
    assert plan.dt_crit == pytest.approx(dt_now, rel=1e-8)  # the audit's damped step, found independently
    n = snap.packing.n
    assert _stable_lagged(snap, plan.factors, plan.target_dt)
    assert _stable_lagged(snap, plan.bound_factors, plan.target_dt)
    assert not _stable_lagged(snap, np.ones(n), plan.target_dt)
    assert plan.added_mass_fraction <= plan.uniform_added_mass_fraction


def _lagged_step(snapshot) -> float:
    """The critical step by bisection of the lagged condition (dense), to 1e-10."""
    lo, hi = 0.0, 2.0 / math.sqrt(_omega2(snapshot, np.ones(snapshot.packing.n)))
    while hi - lo > 1e-10 * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _stable_lagged(snapshot, np.ones(snapshot.packing.n), mid) else (lo, mid)
    return lo
