"""Density scaling in LAMMPS and YADE: a polydisperse packing at twice its critical step.

The packing is LAMMPS's own (``support.engines.lammps_packing.compress``: 30 spheres, radii +-30 %,
relaxed without friction in a periodic box); its stiffness, critical step and rigorous per-body
factors come from the test's model (``support.engines.scaled_packing``: ``gran/hooke`` springs
``kn = 1e4``, ``kt = 2/7 kn`` -- LAMMPS's ``kt`` for ``NULL``, pair_gran docs -- a direct eigen-solve,
Gershgorin's discs).  With the factors the exact step of the scaled packing is at least the target
``2 x dt_crit``; applied in the engines by dtcrit's engine script (``density_scaling``: LAMMPS
``set group all mass`` from an ``atomfile``, YADE ``state.mass`` and ``state.inertia``), runs from a
small random kick at the target stay bounded, while the unscaled packing at the same step blows up.

YADE's own rule (``GlobalStiffnessTimeStepper(targetDt, densityScaling=True)``) runs on the same
packing at the same target: its per-body ``state.densityScaling`` read back after the run equals the
stepper's formula evaluated here from its source (GlobalStiffnessTimeStepper.cpp), and the mass it
adds is printed beside the factors' (``pytest -s``).
"""
from __future__ import annotations

import numpy as np
import pytest

from support.engines import in_ci, require_engine
from support.engines.lammps_packing import PackingSpec, compress
from support.engines.scaled_packing import (critical_step, gershgorin_factors, growth, hook_run, lammps_python,
                                            model_from_dump)
from support.engines.yade_scaled import PackingRun, packing_runs

KN = 1.0e4
KT = 2.0 / 7.0 * KN
STYLE = f"gran/hooke/history {KN!r} NULL 0 NULL 0.5 0"
SPEC = PackingSpec(n=30, solid_fraction=0.65, seed=7)
TARGET = 2.0  # the target step in units of the packing's critical step
STEPS = 2000
GROWING, BOUNDED = 1e3, 10.0  # LAMMPS: kinetic energy over its initial value
GSTS_SAFETY = 0.8  # YADE's default timestepSafetyCoefficient


@pytest.fixture(scope="module")
def packing(tmp_path_factory):
    """LAMMPS's packing, the model, its critical step, the target and the Gershgorin factors."""
    require_engine("lammps")
    dump = compress(SPEC, tmp_path_factory.mktemp("scaled"))
    model = model_from_dump(dump, KN, KT)
    dt_crit = critical_step(model)
    target = TARGET * dt_crit
    return {"dump": dump, "model": model, "dt_crit": dt_crit, "target": target,
            "factors": gershgorin_factors(model, target)}


@pytest.fixture(scope="module")
def yade_runs(packing):
    """YADE at the target: with the factors, without them, and with YADE's own density scaling."""
    require_engine("yade")
    target, factors = packing["target"], packing["factors"]
    runs = [PackingRun(target, STEPS, factors=tuple(factors)), PackingRun(target, STEPS),
            PackingRun(target, STEPS, yade_target=True, gsts_safety=GSTS_SAFETY)]
    return dict(zip(("scaled", "unscaled", "yade_rule"), packing_runs(packing["dump"], KN, KT, runs)))


def _added(masses, factors) -> float:
    return float(np.sum(masses * (np.asarray(factors) - 1.0)) / np.sum(masses))


def test_factors_make_the_exact_step_reach_the_target(packing):
    """The scaled packing's exact step (direct eigen-solve) is at least the target."""
    model, factors = packing["model"], packing["factors"]
    assert len(model.pairs) > 60 and np.ptp(model.radii) > 0.3 * model.radii.mean()
    assert np.all(factors >= 1.0) and factors.max() > 1.0
    assert critical_step(model, factors) >= packing["target"]


def test_lammps_scaled_packing_bounded_at_the_target_unscaled_grows(packing):
    """LAMMPS with the engine script's masses and step: bounded; without them at the same step: grows."""
    dump, target = packing["dump"], packing["target"]
    scaled, steps_used = growth(dump, STYLE, target, STEPS, packing["factors"])
    assert scaled < BOUNDED, f"scaled packing grows at the target (x{scaled:.3g})"
    assert steps_used and max(steps_used) <= target
    unscaled, _ = growth(dump, STYLE, target, STEPS)
    assert unscaled > GROWING, f"unscaled packing bounded at the target (x{unscaled:.3g})"
    below, _ = growth(dump, STYLE, 0.99 * packing["dt_crit"], STEPS)
    assert below < BOUNDED, "the model's critical step is LAMMPS's: bounded just below it"


def test_yade_scaled_packing_bounded_at_the_target_unscaled_grows(packing, yade_runs):
    """YADE with the engine script's masses, inertias and step: bounded; without them: grows."""
    scaled, unscaled = yade_runs["scaled"], yade_runs["unscaled"]
    mass0 = np.array(scaled.info["mass0"])
    assert np.allclose(scaled.info["mass"], mass0 * packing["factors"], rtol=1e-15, atol=0.0)
    assert scaled.info["applied"]["dt"] <= packing["target"] and scaled.dt_max <= packing["target"]
    assert scaled.bounded, f"YADE grows with the factors at the target (growth {scaled.growth:.3g})"
    assert unscaled.growing, f"YADE bounded without the factors at the target (growth {unscaled.growth:.3g})"


def _gsts_scaling(model, target: float, safety: float) -> np.ndarray:
    """``state.densityScaling`` of GlobalStiffnessTimeStepper.cpp: ``(dt_i / targetDt)^2`` with
    ``dt_i = 1.41044 safety sqrt(min(m / max_k K_kk, min_k I / Kr_kk))``, the diagonal stiffnesses
    summed over a body's contacts: ``(kn - ks) n_k^2 + ks`` and ``ks (1 - n_k^2) R^2`` (refR = R).
    """
    n = len(model.radii)
    trans, rot = np.zeros((n, 3)), np.zeros((n, 3))
    for i, j in model.pairs:
        d = model.x[j] - model.x[i]
        d -= model.length * np.round(d / model.length)
        nn = (d / np.linalg.norm(d)) ** 2
        for b in (i, j):
            trans[b] += (KN - KT) * nn + KT
            rot[b] += KT * (1.0 - nn) * model.radii[b] ** 2
    inertia = 0.4 * model.masses * model.radii**2
    squared = np.minimum(model.masses / trans.max(axis=1), (inertia[:, None] / rot).min(axis=1))
    return (1.41044 * safety * np.sqrt(squared) / target) ** 2


def test_yade_density_scaling_against_the_factors(packing, yade_runs):
    """YADE's rule at its own target: its per-body scaling as its source computes it, the mass it adds
    and whether it is stable (the model's exact step of YADE's scaled packing says; YADE's run agrees).
    """
    model, target, factors = packing["model"], packing["target"], packing["factors"]
    run = yade_runs["yade_rule"]
    scaling = np.array(run.info["density_scaling"])
    assert scaling == pytest.approx(_gsts_scaling(model, target, GSTS_SAFETY), rel=1e-6)
    assert run.dt_max <= target * (1 + 1e-15)
    yade_factors = 1.0 / scaling  # NewtonIntegrator multiplies the acceleration by densityScaling
    yade_added, dtcrit_added = _added(model.masses, yade_factors), _added(model.masses, factors)
    yade_step = critical_step(model, yade_factors)
    print(f"\ndensity scaling to {TARGET:g} x dt_crit = {target:.6e} s: added mass fraction "
          f"YADE rule (safety {GSTS_SAFETY}) {yade_added:.4f}, exact step {yade_step / target:.4f} x target, "
          f"YADE run {'bounded' if run.bounded else 'growing'} (growth {run.growth:.3g}); "
          f"Gershgorin factors {dtcrit_added:.4f}, exact step {critical_step(model, factors) / target:.4f} x target; "
          f"uniform factor {TARGET**2 - 1:.4f}")
    if yade_step > 1.01 * target:
        assert run.bounded
    elif yade_step < 0.99 * target:
        assert run.growing


def test_lammps_hook_applies_the_factors_through_the_python_module(packing):
    """``DtcritLammpsHook.apply_density_scaling`` (LAMMPS Python module): the masses LAMMPS holds are the
    factors times the dump's, the step is the target, and the run from the kick stays bounded.
    """
    python = lammps_python()
    if python is None:
        if in_ci():
            pytest.fail("no Python with the LAMMPS module (apt-get install python3-lammps) -- engine tests are "
                        "never skipped in CI (CI=true)", pytrace=False)
        pytest.skip("no Python with the LAMMPS module (apt-get install python3-lammps)")
    out = hook_run(python, packing["dump"], STYLE, packing["target"], STEPS, packing["factors"])
    assert np.allclose(out["mass"], packing["model"].masses * packing["factors"], rtol=1e-15, atol=0.0)
    assert out["returned"] == out["dt"] == packing["target"]
    assert out["energy_ratio"] < BOUNDED
