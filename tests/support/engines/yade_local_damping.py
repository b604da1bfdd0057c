"""Run YADE (``yade -n -x``) on an FCC lattice with local damping (``NewtonIntegrator.damping``).

The lattice is that of ``support.engines.yade.LatticeCase``: equal spheres in a periodic cell, the
spacing shortened so every nearest-neighbour contact overlaps by ``overlap * R`` (pre-compressed, in
equilibrium by symmetry), ``kn``, ``ks`` set on every interaction after the collider made them, Coulomb
slip switched off (friction angle 1.5 rad and tiny motions).  One YADE process runs a batch:

* ``exports`` -- the lattice with ``NewtonIntegrator(damping=alpha)``, written with the shipped
  ``yade_export.export`` (so the file carries ``newton_damping``);
* ``runs`` -- the lattice stepped at a fixed ``dt`` with ``NewtonIntegrator(damping=alpha)`` from a
  random start (every sphere displaced by up to ``eps`` times the overlap, with matching random
  velocities and spins) or from a start along a given mode (``mode``: 6 numbers per body, translation
  and rotation; displacement ``a phi_t``, velocity ``2 a phi_t/dt`` and spin ``2 a phi_r/dt``: the
  leapfrog's flip state at the stability limit, whose half-step velocity is ``(x_n - x_{n-1})/dt``);
* ``hooks`` -- the lattice with the shipped ``yade_hook.DtcritHook`` called once (the step it sets).

Each run records, every step after NewtonIntegrator, the largest net force ``|F_i|`` and ``|T_i|/R``
over the bodies (zero at equilibrium) and the kinetic energy; YADE stops a run once the force passes
``HALT_FRACTION`` of the contact force ``kn overlap R`` (well before a contact could open).  A run is
``bounded`` when it was not stopped and its largest force stayed below ``BOUNDED_GROWTH`` times its
largest over the first ten steps; ``growing`` when it was stopped or exceeded ``GROWING_GROWTH``.
It never imports the project under test.
"""
from __future__ import annotations

import math
import os
from dataclasses import asdict, dataclass

import numpy as np

from ..paths import ENGINE_SCRIPTS
from .yade import run_yade_script

__all__ = ["Lattice", "DampedRun", "RunOutcome", "run_batch", "bisect_onset", "hook_steps", "HALT_FRACTION"]

HALT_FRACTION = 1.0e-2
BOUNDED_GROWTH = 10.0
GROWING_GROWTH = 1.0e3
_TAG = "DTCRIT-YADE-LD "


@dataclass(frozen=True)
class Lattice:
    """An FCC lattice of ``4 cells^3`` equal spheres (``kn``, ``ks`` [N/m]; ``overlap`` per radius)."""

    cells: int = 2
    kn: float = 1.0e5
    ks: float = 5.0e4
    radius: float = 1.0e-3
    density: float = 2500.0
    overlap: float = 1.0e-3


@dataclass(frozen=True)
class DampedRun:
    """One run: ``steps`` at ``dt`` with ``NewtonIntegrator.damping = alpha`` from a random start
    (``mode`` None) or along ``mode`` (6 numbers per body by YADE id, translation then rotation, scaled
    so that the largest of ``|phi_t|`` and ``R |phi_r|`` is 1).
    """

    alpha: float
    dt: float
    steps: int
    mode: tuple[float, ...] | None = None
    eps: float = 1.0e-5
    seed: int = 7


@dataclass(frozen=True)
class RunOutcome:
    """What a run did: steps run, whether YADE stopped it, the force growth and the final energy ratio."""

    run: DampedRun
    steps_run: int
    halted: bool
    growth: float
    energy_ratio: float

    @property
    def bounded(self) -> bool:
        return not self.halted and math.isfinite(self.growth) and self.growth < BOUNDED_GROWTH

    @property
    def growing(self) -> bool:
        return self.halted or not math.isfinite(self.growth) or self.growth > GROWING_GROWTH


def _run_yade(payload: dict, *, timeout: float) -> list[dict]:
    return run_yade_script(YADE_SCRIPT, payload, timeout=timeout, tag=_TAG)[0]


def hook_steps(lattice: Lattice, alphas, dtcrit: list[str], *, timeout: float = 300.0) -> list[dict]:
    """For each ``alpha``: the lattice with ``NewtonIntegrator.damping = alpha`` and the shipped
    ``yade_hook.DtcritHook(dtcrit=dtcrit)`` called once; ``{"dt": O.dt after it, "history": hook.history}``.
    """
    payload = {"lattice": asdict(lattice), "engine_scripts": str(ENGINE_SCRIPTS), "halt_fraction": HALT_FRACTION,
               "exports": [], "runs": [], "hooks": [{"alpha": a, "dtcrit": list(dtcrit)} for a in alphas]}
    raw = {r["hook"]: r for r in _run_yade(payload, timeout=timeout) if "hook" in r}
    return [raw[k] for k in range(len(raw))]


def run_batch(lattice: Lattice, runs=(), exports=(), *, timeout: float = 300.0) -> list[RunOutcome]:
    """Write the ``exports`` (``(alpha, path)`` pairs) and run the ``runs`` in one YADE process."""
    runs = list(runs)
    payload = {"lattice": asdict(lattice), "engine_scripts": str(ENGINE_SCRIPTS), "halt_fraction": HALT_FRACTION,
               "exports": [{"alpha": a, "path": os.path.abspath(p)} for a, p in exports],
               "runs": [asdict(r) for r in runs], "hooks": []}
    raw = {r["run"]: r for r in _run_yade(payload, timeout=timeout) if "run" in r}
    out = []
    for k, run in enumerate(runs):
        r = raw[k]
        dev, ke = np.asarray(r["dev"], float), np.asarray(r["ke"], float)
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            ref = float(dev[:10].max()) if dev.size else math.nan
            growth = float(dev.max() / ref) if ref > 0 and np.all(np.isfinite(dev)) else math.inf
            energy = float(ke[-1] / ke[0]) if ke.size and ke[0] > 0 else math.nan
        out.append(RunOutcome(run, int(r["steps_run"]), bool(r["halted"]), growth, energy))
    return out


def bisect_onset(lattice: Lattice, runs_lo, runs_hi, *, rel_tol: float = 1e-4) -> list[tuple[float, float]]:
    """YADE's threshold of each run's start, bisected on ``dt`` between ``runs_lo[k].dt`` (bounded) and
    ``runs_hi[k].dt`` (growing), all open cases in one YADE process per iteration.  A seeded start keeps
    its ``mode`` (its velocity ``2 a phi/dt`` follows ``dt``).  Returns ``(bounded dt, growing dt)`` per case.
    """
    lo = [r.dt for r in runs_lo]
    hi = [r.dt for r in runs_hi]
    base = list(runs_lo)
    while True:
        open_ = [k for k in range(len(base)) if hi[k] / lo[k] - 1.0 > rel_tol]
        if not open_:
            return list(zip(lo, hi))
        trial = [DampedRun(**{**asdict(base[k]), "dt": math.sqrt(lo[k] * hi[k]), "mode": base[k].mode})
                 for k in open_]
        for k, res in zip(open_, run_batch(lattice, trial)):
            if res.bounded:
                lo[k] = res.run.dt
            else:
                hi[k] = res.run.dt


YADE_SCRIPT = r'''# Generated by tests/support/engines/yade_local_damping.py: runs inside YADE.
import json, math, random, sys

PAYLOAD = json.load(open(sys.argv[1]))
C = PAYLOAD["lattice"]
TAG = "DTCRIT-YADE-LD "
BASIS = [(0.0, 0.0, 0.0), (0.5, 0.5, 0.0), (0.5, 0.0, 0.5), (0.0, 0.5, 0.5)]


def emit(obj):
    print(TAG + json.dumps(obj), flush=True)


def build(alpha):
    O.reset()
    R = C["radius"]
    d0 = 2.0 * R - C["overlap"] * R
    a = math.sqrt(2.0) * d0
    n = int(C["cells"])
    O.periodic = True
    O.cell.hSize = Matrix3(n * a, 0, 0, 0, n * a, 0, 0, 0, n * a)
    mat = O.materials.append(FrictMat(young=C["kn"] / R, poisson=0.5, density=C["density"], frictionAngle=1.5))
    for i in range(n):
        for j in range(n):
            for k in range(n):
                for b in BASIS:
                    O.bodies.append(sphere(((i + b[0]) * a, (j + b[1]) * a, (k + b[2]) * a), R, material=mat))
    newton = NewtonIntegrator(damping=alpha, gravity=(0, 0, 0))
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()], verletDist=-0.05),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                 [Law2_ScGeom_FrictPhys_CundallStrack()]), newton]
    O.dt = 1e-300  # a first pass makes the interactions without moving anything
    O.step()
    for it in O.interactions:
        if it.isReal:
            it.phys.kn = C["kn"]
            it.phys.ks = C["ks"]
    for b in O.bodies:
        b.state.vel = Vector3(0, 0, 0)
        b.state.angVel = Vector3(0, 0, 0)


def start(r):
    R = C["radius"]
    amp = r["eps"] * C["overlap"] * R
    if r["mode"] is None:
        rng = random.Random(r["seed"])
        vs = amp * math.sqrt(C["kn"] / O.bodies[0].state.mass)
        u = lambda s: Vector3(rng.uniform(-s, s), rng.uniform(-s, s), rng.uniform(-s, s))
        for b in O.bodies:
            b.state.pos = b.state.pos + u(amp)
            b.state.vel = u(vs)
            b.state.angVel = u(vs / R)
        return
    phi = r["mode"]  # scaled so that max(|phi_t|, R |phi_r|) = 1
    for b in O.bodies:
        p = [amp * x for x in phi[6 * b.id:6 * b.id + 6]]
        b.state.pos = b.state.pos + Vector3(p[0], p[1], p[2])
        b.state.vel = Vector3(p[0], p[1], p[2]) * (2.0 / r["dt"])
        b.state.angVel = Vector3(p[3], p[4], p[5]) * (2.0 / r["dt"])


def one_run(k, r):
    build(r["alpha"])
    record = {"dev": [], "ke": []}
    halt_at = PAYLOAD["halt_fraction"] * C["kn"] * C["overlap"] * C["radius"]
    ctl = {"halted": False}
    R = C["radius"]
    bodies = list(O.bodies)

    def monitor():
        fm = 0.0
        for b in bodies:
            fm = max(fm, O.forces.f(b.id).norm(), O.forces.t(b.id).norm() / R)
        record["dev"].append(fm)
        record["ke"].append(kineticEnergy())
        if not (fm < halt_at):
            ctl["halted"] = True
            O.pause()

    globals()["_monitor"] = monitor
    O.engines = O.engines + [PyRunner(command="_monitor()", iterPeriod=1)]
    O.dt = r["dt"]
    start(r)
    O.run(int(r["steps"]), True)
    emit({"run": k, "steps_run": len(record["dev"]), "halted": ctl["halted"], **record})


try:
    sys.path.insert(0, PAYLOAD["engine_scripts"])
    import yade_export
    for e in PAYLOAD["exports"]:
        build(e["alpha"])
        yade_export.export(e["path"])
        emit({"exported": e["path"]})
    for k, r in enumerate(PAYLOAD["runs"]):
        one_run(k, r)
    for k, h in enumerate(PAYLOAD["hooks"]):
        build(h["alpha"])
        import yade_hook
        hook = yade_hook.DtcritHook(dtcrit=h["dtcrit"], export_path="hook_scene.json")
        hook.update()
        emit({"hook": k, "dt": O.dt, "history": hook.history})
except Exception as exc:
    import traceback
    traceback.print_exc()
    emit({"error": repr(exc)})
    sys.exit(1)
'''
