"""YADE runs of a LAMMPS-made packing with per-body mass factors, and with YADE's own density scaling.

On top of ``support.engines.yade`` (its script, its kick and its classification; nothing here
imports the project under test).  The packing is a ``write_dump`` of LAMMPS's (``lammps_packing``):
YADE gets the same spheres (``state.mass`` and ``state.inertia = 2/5 m R^2`` set from the dump) in the
same periodic cell, and after the first pass every interaction gets ``kn`` and ``ks`` of LAMMPS's
``gran/hooke`` law.  YADE's CundallStrack normal force ``kn * penetrationDepth`` is LAMMPS's hooke
force, so the packing LAMMPS relaxed without friction is in equilibrium in YADE too (friction angle
1.5 rad: no slip under the small kick).

Each run (``PackingRun``) is one of

* ``factors`` (per body id) or ``plan_file`` (a ``dtcrit plan --json`` document, read by the engine
  script's ``read_plan``) given: dtcrit's YADE hook (``DtcritHook.apply_density_scaling``, i.e. the
  engine script ``density_scaling.apply_yade``, from ``dtcrit/engine_scripts``, run inside YADE)
  scales the bodies' mass and inertia and sets ``O.dt`` to the run's ``dt`` (the plan's ``target_dt``);
* ``yade_target``: ``GlobalStiffnessTimeStepper(targetDt=dt, densityScaling=True)`` with
  ``NewtonIntegrator.densityScaling`` (YADE's per-body rule, GlobalStiffnessTimeStepper.cpp:
  ``state.densityScaling = (dt_i / targetDt)^2`` from its diagonal estimate ``dt_i``; the
  acceleration is multiplied by it, NewtonIntegrator.cpp), at ``gsts_safety``;
* neither: the plain packing at ``dt``.

With ``export`` the run first writes the packing as ``dtcrit/engine_scripts/yade_export.py`` sees it
(after a second zero-length pass, so ``normalForce`` is that of the new ``kn``).  The result is the ``RunResult`` of ``support.engines.yade`` (``bounded``, ``growing``), its ``info``
holding the masses before (``mass0``), after (``mass``), YADE's per-body ``density_scaling`` at the
end of the run, and what the engine script returned (``applied``).
"""
from __future__ import annotations

from dataclasses import asdict, dataclass

from . import engine_executable
from .lammps_packing import _read_dump
from .yade import ENGINE_SCRIPTS, HALT_FRACTION, YADE_SCRIPT, Run, RunResult, YadeError, run_yade_script, _classify

__all__ = ["PackingRun", "packing_runs"]

_TAG = "DTCRIT-YADE "
_MAIN = "# ------------------------------------------------------------------ main"


@dataclass(frozen=True)
class PackingRun:
    """One run of the packing (module docstring)."""

    dt: float
    steps: int
    factors: tuple | None = None  # per body, in the dump's id order
    yade_target: bool = False
    gsts_safety: float = 0.8
    export: str | None = None  # write dtcrit's YADE export of the packing here before the kick
    plan_file: str | None = None  # a `dtcrit plan --json` document: its factors and target_dt, by the hook
    eps: float = 1.0e-6
    seed: int = 12345


_EXTRA = r'''
# ------------------------------------------------------------------ scaled packings (support/engines/yade_scaled.py)
def build_dump_packing(p):
    O.periodic = True
    L = p["length"]
    O.cell.hSize = Matrix3(L[0], 0, 0, 0, L[1], 0, 0, 0, L[2])
    mat = O.materials.append(FrictMat(young=1e8, poisson=0.3, density=2500.0, frictionAngle=1.5))
    for x, r, m in zip(p["x"], p["radii"], p["masses"]):
        b = sphere(Vector3(*x), r, material=mat)
        b.state.mass = m
        b.state.inertia = Vector3(1, 1, 1) * (0.4 * m * r * r)
        O.bodies.append(b)


def scaled_run(k, p, r):
    O.reset()
    build_dump_packing(p)
    newton = NewtonIntegrator(damping=0.0, gravity=(0, 0, 0))
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()], verletDist=-0.05), frict_loop(), newton]
    O.dt = 1e-300
    O.step()
    for b in O.bodies:
        b.state.vel = Vector3(0, 0, 0)
        b.state.angVel = Vector3(0, 0, 0)
    real = [i for i in O.interactions if i.isReal]
    for i in real:
        i.phys.kn = p["kn"]
        i.phys.ks = p["ks"]
    O.step()  # dt 1e-300 again: the forces of the new kn (CundallStrack recomputes kn * penetrationDepth)
    scale = sum(p["kn"] * i.geom.penetrationDepth for i in real) / len(real)
    if r["export"] is not None:
        sys.path.insert(0, PAYLOAD["engine_scripts"])
        import yade_export
        yade_export.export(r["export"])
    info = {"mass0": [b.state.mass for b in O.bodies], "contacts": len(real)}
    if r["factors"] is not None or r["plan_file"] is not None:
        sys.path.insert(0, PAYLOAD["engine_scripts"])
        import density_scaling
        import yade_hook  # the hook's method, which calls density_scaling.apply_yade
        hook = yade_hook.DtcritHook(dtcrit=["dtcrit-not-run"], export_path="hook_scene.json")
        if r["plan_file"] is not None:
            info["applied"] = hook.apply_density_scaling(*density_scaling.read_plan(r["plan_file"]))
        else:
            info["applied"] = hook.apply_density_scaling({bid: f for bid, f in enumerate(r["factors"])}, r["dt"])
    else:
        O.dt = r["dt"]
    extra = []
    if r["yade_target"]:
        extra.append(GlobalStiffnessTimeStepper(targetDt=r["dt"], densityScaling=True, timeStepUpdateInterval=1,
                                                timestepSafetyCoefficient=r["gsts_safety"]))
    info.update(kick(r["eps"], r["seed"]))
    record = {"dev": [], "ke": [], "dt": []}
    ctl = {"halted": False, "halt_at": HALT_FRACTION * scale}
    dyn = list(O.bodies)

    def monitor():
        fm = 0.0
        for b in dyn:
            fm = max(fm, O.forces.f(b.id).norm(), O.forces.t(b.id).norm() / b.shape.radius)
        record["dev"].append(fm)
        record["ke"].append(kineticEnergy())
        record["dt"].append(O.dt)
        if not (fm < ctl["halt_at"]):
            ctl["halted"] = True
            O.pause()

    globals()["_monitor"] = monitor
    O.engines = O.engines[:-1] + extra + [newton, PyRunner(command="_monitor()", iterPeriod=1)]
    if r["yade_target"]:
        newton.densityScaling = True  # after the stepper is in O.engines (NewtonIntegrator.set_densityScaling)
    O.run(int(r["steps"]), True)
    info["mass"] = [b.state.mass for b in O.bodies]
    info["density_scaling"] = [b.state.densityScaling for b in O.bodies]
    info["force_scale"] = scale
    emit({"scaled": k, "steps_run": len(record["dev"]), "halted": ctl["halted"], "info": info, **record})


try:
    for k, entry in enumerate(PAYLOAD.get("scaled", [])):
        scaled_run(k, PAYLOAD["packing"], entry)
except Exception as exc:
    import traceback
    traceback.print_exc()
    emit({"error": repr(exc)})
    sys.exit(1)

'''

SCRIPT = YADE_SCRIPT.replace(_MAIN, _EXTRA + _MAIN)


def packing_runs(dump_text: str, kn: float, ks: float, runs, *, yade: str | None = None,
                 timeout: float = 300.0) -> list[RunResult]:
    """Run every ``PackingRun`` of ``runs`` on the dumped packing in one YADE process."""
    exe = yade or engine_executable("yade")
    if exe is None:
        raise YadeError("YADE not found (apt-get install yade)")
    x, radii, masses, length = _read_dump(dump_text)
    runs = list(runs)
    payload = {"halt_fraction": HALT_FRACTION, "engine_scripts": str(ENGINE_SCRIPTS), "cases": [],
               "packing": {"x": x.tolist(), "radii": radii.tolist(), "masses": masses.tolist(),
                           "length": [float(v) for v in length], "kn": kn, "ks": ks},
               "scaled": [{**asdict(r), "factors": None if r.factors is None else [float(f) for f in r.factors]}
                          for r in runs]}
    out = run_yade_script(SCRIPT, payload, yade=exe, timeout=timeout)[0]
    by_run = {r["scaled"]: r for r in out if "scaled" in r}
    return [_classify(Run(r.steps, dt=r.dt, eps=r.eps, seed=r.seed), by_run[k]) for k, r in enumerate(runs)]
