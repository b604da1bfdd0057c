"""Density scaling in LAMMPS and YADE: a polydisperse packing at twice (and five times) its critical step.

The packing is LAMMPS's own (``support.engines.lammps_packing.compress``: 30 spheres, radii +-30 %,
relaxed without friction in a periodic box).  The test's model (``support.engines.scaled_packing``:
``gran/hooke`` springs ``kn = 1e4``, ``kt = 2/7 kn`` -- LAMMPS's ``kt`` for ``NULL``, pair_gran docs --
and the normal preload's geometric term, assembled independently) gives the critical step by a
direct eigen-solve and rigorous per-body factors from Gershgorin's discs.  Two factor sets are run:
those, and dtcrit's plan (``dtcrit plan --json`` of LAMMPS's dump; for YADE, of YADE's own export of
the same packing; the engines read the JSON document with the engine script's ``read_plan``).  With either, the model's exact step of the scaled packing
is at least the target ``2 x dt_crit``; applied in the engines by dtcrit's engine script
(``density_scaling``: LAMMPS ``set group all mass`` from an ``atomfile``, also through the LAMMPS
hook in the LAMMPS Python module; YADE ``state.mass`` and ``state.inertia`` through the YADE hook),
runs from a small random kick at the target stay bounded, while the unscaled packing at the same step
blows up.

YADE's own rule (``GlobalStiffnessTimeStepper(targetDt, densityScaling=True)``) runs on the same
packing at the same target: its per-body ``state.densityScaling`` read back after the run equals the
stepper's formula evaluated here from its source (GlobalStiffnessTimeStepper.cpp); the mass it adds
is more than the plan's (numbers printed with ``pytest -s``).
"""
from __future__ import annotations

import json
import subprocess
import sys

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


FACTOR_SETS = ("gershgorin", "plan")


def _plan(snapshot, target: float, *args: str) -> dict:
    """``dtcrit plan SNAPSHOT --target-dt TARGET --json`` (this environment's dtcrit), its document."""
    done = subprocess.run([sys.executable, "-m", "dtcrit", "plan", str(snapshot), *args, "--target-dt", repr(target),
                           "--json"], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


@pytest.fixture(scope="module")
def packing(tmp_path_factory):
    """LAMMPS's packing, the model, its critical step, the target, the Gershgorin factors and dtcrit's plan
    (also written as its JSON document, ``plan.json``).
    """
    require_engine("lammps")
    work = tmp_path_factory.mktemp("scaled")
    dump = compress(SPEC, work)
    (work / "packing.dump").write_text(dump)
    model = model_from_dump(dump, KN, KT)
    dt_crit = critical_step(model)
    target = TARGET * dt_crit
    plan = _plan(work / "packing.dump", target, "--pair-style", STYLE)
    (work / "plan.json").write_text(json.dumps(plan))
    by_id = dict(zip(plan["density_scaling"]["ids"], plan["density_scaling"]["factors"]))
    factors = np.array([by_id.get(k + 1, 1.0) for k in range(len(model.masses))])  # LAMMPS ids 1..N, dump order
    return {"dump": dump, "work": work, "model": model, "dt_crit": dt_crit, "target": target, "plan": plan,
            "factors": {"gershgorin": gershgorin_factors(model, target), "plan": factors}}


@pytest.fixture(scope="module")
def yade_runs(packing):
    """YADE at the target: without factors (writing dtcrit's export first), with the Gershgorin factors,
    with YADE's own density scaling, then with dtcrit's plan of the export (YADE's conventions).
    """
    require_engine("yade")
    target, dump, work = packing["target"], packing["dump"], packing["work"]
    export = work / "packing.json"
    runs = [PackingRun(target, STEPS, export=str(export)),
            PackingRun(target, STEPS, factors=tuple(packing["factors"]["gershgorin"])),
            PackingRun(target, STEPS, yade_target=True, gsts_safety=GSTS_SAFETY)]
    out = dict(zip(("unscaled", "gershgorin", "yade_rule"), packing_runs(dump, KN, KT, runs)))
    plan = _plan(export, target)
    (work / "yade_plan.json").write_text(json.dumps(plan))
    (out["plan"],) = packing_runs(dump, KN, KT, [PackingRun(target, STEPS, plan_file=str(work / "yade_plan.json"))])
    by_id = dict(zip(plan["density_scaling"]["ids"], plan["density_scaling"]["factors"]))
    out["plan_doc"] = plan
    out["plan_factors"] = np.array([by_id.get(k, 1.0) for k in range(len(packing["model"].masses))])  # YADE ids
    return out


def _added(masses, factors) -> float:
    return float(np.sum(masses * (np.asarray(factors) - 1.0)) / np.sum(masses))


@pytest.mark.parametrize("name", FACTOR_SETS)
def test_factors_make_the_exact_step_reach_the_target(packing, name):
    """The scaled packing's exact step (the model's direct eigen-solve) is at least the target."""
    model, factors = packing["model"], packing["factors"][name]
    assert len(model.pairs) > 60 and np.ptp(model.radii) > 0.3 * model.radii.mean()
    assert factors.shape == model.masses.shape and np.all(factors >= 1.0) and factors.max() > 1.0
    assert critical_step(model, factors) >= packing["target"]


def test_plan_reads_the_packing_as_the_model_does(packing):
    """Dtcrit's current step and its scaled step are the model's (independent assembly) to rounding."""
    plan, model, factors = packing["plan"], packing["model"], packing["factors"]["plan"]
    assert plan["target_dt"] == packing["target"]
    assert plan["binding"]["dt_crit"] == pytest.approx(packing["dt_crit"], rel=1e-9)
    assert plan["density_scaling"]["dt_crit_scaled"] == pytest.approx(critical_step(model, factors), rel=1e-9)
    assert plan["density_scaling"]["added_mass_fraction"] == pytest.approx(_added(model.masses, factors), rel=1e-12)


@pytest.mark.parametrize("name", FACTOR_SETS)
def test_lammps_scaled_packing_bounded_at_the_target(packing, name):
    """LAMMPS with the engine script's masses and step (the plan: ``include`` of the file written from its
    JSON by ``write_lammps_include``): bounded at the target, never above it.
    """
    plan_file = packing["work"] / "plan.json" if name == "plan" else None
    scaled, steps_used = growth(packing["dump"], STYLE, packing["target"], STEPS, packing["factors"][name],
                                plan_file=plan_file)
    assert scaled < BOUNDED, f"scaled packing grows at the target (x{scaled:.3g})"
    assert steps_used and max(steps_used) <= packing["target"]


def test_lammps_unscaled_packing_grows_at_the_target(packing):
    """Without the factors the same step blows up; just below the model's critical step it does not."""
    unscaled, _ = growth(packing["dump"], STYLE, packing["target"], STEPS)
    assert unscaled > GROWING, f"unscaled packing bounded at the target (x{unscaled:.3g})"
    below, _ = growth(packing["dump"], STYLE, 0.99 * packing["dt_crit"], STEPS)
    assert below < BOUNDED, "the model's critical step is LAMMPS's: bounded just below it"


@pytest.mark.parametrize("name", FACTOR_SETS)
def test_yade_scaled_packing_bounded_at_the_target(packing, yade_runs, name):
    """YADE with the hook's masses, inertias and step: bounded at the target (the plan: of the YADE export)."""
    run = yade_runs[name]
    factors = packing["factors"][name] if name != "plan" else yade_runs["plan_factors"]
    mass0 = np.array(run.info["mass0"])
    assert np.allclose(run.info["mass"], mass0 * factors, rtol=1e-15, atol=0.0)
    assert run.info["applied"]["dt"] <= packing["target"] and run.dt_max <= packing["target"]
    assert run.bounded, f"YADE grows with the factors at the target (growth {run.growth:.3g})"


def test_yade_unscaled_packing_grows_at_the_target(yade_runs):
    """Without the factors YADE blows up at the target."""
    run = yade_runs["unscaled"]
    assert run.growing, f"YADE bounded without the factors at the target (growth {run.growth:.3g})"


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


def test_yade_density_scaling_against_dtcrit_plan(packing, yade_runs):
    """YADE's rule at its own target: its per-body scaling as its source computes it, whether it is
    stable (the model's exact step of YADE's scaled packing says; YADE's run agrees) and the mass it adds,
    more than dtcrit's plan (whose run above is bounded).
    """
    model, target = packing["model"], packing["target"]
    run, plan = yade_runs["yade_rule"], yade_runs["plan_doc"]["density_scaling"]
    scaling = np.array(run.info["density_scaling"])
    assert scaling == pytest.approx(_gsts_scaling(model, target, GSTS_SAFETY), rel=1e-6)
    assert run.dt_max <= target * (1 + 1e-15)
    yade_factors = 1.0 / scaling  # NewtonIntegrator multiplies the acceleration by densityScaling
    yade_added = _added(model.masses, yade_factors)
    plan_added = _added(model.masses, yade_runs["plan_factors"])
    yade_step = critical_step(model, yade_factors)
    gershgorin = packing["factors"]["gershgorin"]
    print(f"\ndensity scaling to {TARGET:g} x dt_crit = {target:.6e} s, added mass fraction: "
          f"YADE run (densityScaling read back, safety {GSTS_SAFETY}) {yade_added:.4f}, model step "
          f"{yade_step / target:.4f} x target, run {'bounded' if run.bounded else 'growing'} "
          f"(growth {run.growth:.3g}); dtcrit plan of the YADE export {plan_added:.4f} ({plan['family']}), "
          f"of the LAMMPS dump {packing['plan']['density_scaling']['added_mass_fraction']:.4f}; its YADE rule "
          f"{plan['yade_rule_added_mass_fraction']:.4f}; uniform {plan['uniform_added_mass_fraction']:.4f}; "
          f"Gershgorin (test) {_added(model.masses, gershgorin):.4f}")
    assert plan_added < yade_added
    if yade_step > 1.01 * target:
        assert run.bounded
    elif yade_step < 0.99 * target:
        assert run.growing


def test_lammps_hook_applies_the_factors_through_the_python_module(packing):
    """``DtcritLammpsHook.apply_density_scaling(*read_plan("plan.json"))`` (LAMMPS Python module) with the
    output of ``dtcrit plan --json``: the masses LAMMPS holds are the factors times the dump's, the step is the target, the
    run from the kick is bounded.
    """
    python = lammps_python()
    if python is None:
        if in_ci():
            pytest.fail("no Python with the LAMMPS module (apt-get install python3-lammps) -- engine tests are "
                        "never skipped in CI (CI=true)", pytrace=False)
        pytest.skip("no Python with the LAMMPS module (apt-get install python3-lammps)")
    factors = packing["factors"]["plan"]
    out = hook_run(python, packing["dump"], STYLE, packing["work"] / "plan.json", STEPS)
    assert np.allclose(out["mass"], packing["model"].masses * factors, rtol=1e-15, atol=0.0)
    assert out["returned"] == out["dt"] == packing["target"]
    assert out["energy_ratio"] < BOUNDED


def test_plan_yade_rule_is_the_densityscaling_yade_applies(packing, yade_runs):
    """The plan's ``yade_rule_added_mass_fraction`` (of the YADE export) against the mass YADE adds, read
    back after its run (every body is scaled here: no floor at 1 in play).
    """
    measured = 1.0 / np.array(yade_runs["yade_rule"].info["density_scaling"])
    assert measured.min() > 1.0
    planned = yade_runs["plan_doc"]["density_scaling"]["yade_rule_added_mass_fraction"]
    assert planned == pytest.approx(_added(packing["model"].masses, measured), rel=1e-6)


def test_lammps_plan_at_five_times_the_critical_step(packing):
    """Dtcrit's plan for 5 x dt_crit: the model's exact step of the scaled packing reaches it, LAMMPS
    with the engine script's masses is bounded there, and without them grows.
    """
    from dtcrit.plan import plan_density_scaling

    target = 5.0 * packing["dt_crit"]
    plan = plan_density_scaling(packing["work"] / "packing.dump", target, pair_style=STYLE)
    assert critical_step(packing["model"], plan.factors) >= target
    scaled, steps_used = growth(packing["dump"], STYLE, target, STEPS, plan.factors)
    assert scaled < BOUNDED and max(steps_used) <= target
    unscaled, _ = growth(packing["dump"], STYLE, target, STEPS)
    assert unscaled > GROWING
    print(f"\n5 x dt_crit: added mass fraction dtcrit plan {plan.added_mass_fraction:.4f}, "
          f"uniform {plan.uniform_added_mass_fraction:.4f}")


YADE_CHECKS = r"""
import json, sys
sys.path.insert(0, sys.argv[1])
import density_scaling as ds
out = {}
a = O.bodies.append(sphere((0, 0, 0), 1e-3))
b = O.bodies.append(sphere((5e-3, 0, 0), 2e-3))
clump, members = O.bodies.appendClumped([sphere((0, 9e-3, 0), 1e-3), sphere((1.5e-3, 9e-3, 0), 1e-3)])
m0, i0 = O.bodies[b].state.mass, O.bodies[b].state.inertia[0]
O.dt = 1.0
for bad in ({99: 2.0}, {members[0]: 2.0}, {a: -1.0}):
    try:
        ds.apply_yade(bad, 1e-6)
        out[str(bad)] = "applied"
    except ValueError as exc:
        out[str(bad)] = str(exc)
out["dt_untouched"] = O.dt
out["record"] = ds.apply_yade({b: 3.0, clump: 2.0}, 2e-6, safety=0.5)
out["mass_ratio"] = O.bodies[b].state.mass / m0
out["inertia_ratio"] = O.bodies[b].state.inertia[0] / i0
out["dt"] = O.dt
print("CHECKS " + json.dumps(out))
"""


def test_yade_engine_script_refuses_and_scales(tmp_path):
    """Inside YADE: an unknown body, a clump member and a non-positive factor are refused before anything
    changes; a clump and a sphere are scaled (mass and inertia by the factor) and ``O.dt = safety * dt``.
    """
    from support.paths import ENGINE_SCRIPTS

    yade = require_engine("yade")
    (tmp_path / "checks.py").write_text(YADE_CHECKS)
    done = subprocess.run([yade, "-n", "-x", "checks.py", str(ENGINE_SCRIPTS)], cwd=tmp_path, capture_output=True,
                          text=True, timeout=120)
    lines = [ln for ln in done.stdout.splitlines() if ln.startswith("CHECKS ")]
    assert done.returncode == 0 and lines, done.stdout[-2000:] + done.stderr[-2000:]
    out = json.loads(lines[-1][7:])
    refusals = [v for k, v in out.items() if k.startswith("{")]
    assert [("no such body" in refusals[0]), ("clump member" in refusals[1]), ("positive" in refusals[2])] == [True] * 3
    assert out["dt_untouched"] == 1.0
    assert out["record"]["bodies"] == 2 and out["dt"] == 1e-6
    assert out["mass_ratio"] == pytest.approx(3.0, rel=1e-15) and out["inertia_ratio"] == pytest.approx(3.0, rel=1e-15)
