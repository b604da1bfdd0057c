"""Run YADE (``yade -n -x``, Debian 2023.02a) on sphere lattices, pairs and saved packings.

The harness writes one YADE script and a JSON list of cases, runs ``yade -n -x`` once for the
whole batch in a temporary directory (YADE takes about a second to start), and parses the lines
``DTCRIT-YADE {json}`` the script prints, one per run.  It never imports the project under test.

Cases:

* ``LatticeCase`` -- an SC, BCC or FCC lattice of equal spheres in a periodic cell, the spacing
  shortened so each nearest-neighbour contact overlaps by ``overlap * R``: the lattice is
  pre-compressed by its own contacts, in equilibrium by symmetry, and its contacts stay closed
  under the small kick.  ``kn``, ``ks`` are set on every interaction after the collider made them
  (``ks = 0`` cannot come from FrictMat: Ip2_FrictMat_FrictMat_FrictPhys would divide 0 by 0).
* ``PairCase`` -- two equal spheres along ``direction``, no gravity, kept in contact by a preload
  of constant magnitude ``P = kn * delta0`` along the *current* centre line (a PyRunner adds
  ``+-P e`` every step before NewtonIntegrator; a preload of fixed direction makes the pair
  buckle).  YADE's own law: FrictMat (kn = E R, ks = poisson kn for equal spheres) or, with
  ``bonded``, CohFrictMat bonded at the start (Ip2_CohFrictMat_CohFrictMat_CohFrictPhys
  ``setCohesionNow``, Law2_ScGeom6D_CohFrictPhys_CohesionMoment; with ``moment_law`` the rolling
  and twisting springs kr = ktw = alpha R1 R2 ks act).
* ``SceneCase`` -- a scene saved by YADE (``O.save``), e.g. the packing ``compress_packing``
  compresses with PeriTriaxController; its own interactions and per-contact kn, ks are kept.

Each ``Run`` sets ``O.dt`` (or lets GlobalStiffnessTimeStepper at ``gsts_safety``, or the dtcrit
hook, choose it), switches NewtonIntegrator's damping off, kicks every body with random
displacements of ``eps`` times the mean overlap and matching velocities and spins, and steps.

Classification (``RunResult.bounded``): every step a PyRunner after NewtonIntegrator records the
deviation ``dev`` = the largest of |F_i| and |T_i|/R_i over the bodies (net force and torque,
preload included: both vanish at equilibrium) and, for a pair, kn |d - d0| (normal spring force
deviation), and the kinetic energy.  The growth figure is max(dev)/dev_ref (dev_ref: the largest
``dev`` of the first ten steps) and the square root of the kinetic energy ratio to its first
value.  Forces are watched as well as the energy because at the boundary the critical mode has
~zero on-step velocity.  A run also counts as growing when the envelope of ``dev`` over its last
quarter exceeds ``WINDOW_LIMIT`` times that of its second quarter, and when YADE stopped it
(``halted``) because ``dev`` passed ``HALT_FRACTION`` of the contact force scale (the preload,
kn*delta0, or the mean normal force), well before any contact could open.

YADE conventions (2023.02a; sources pkg/dem/ of YADE): NewtonIntegrator is leapfrog
(v_{n+1/2} = v_{n-1/2} + dt F(x_n)/m, velocities stored at half steps; spheres' spins likewise
with I = 2/5 m R^2); its default damping 0.2 is switched off here.  Ig2_Sphere_Sphere_ScGeom puts
the contact point at x1 + (R1 - delta/2) n; CundallStrack and CohesionMoment apply the force there
(torque arms R_i - delta/2); with avoidGranularRatcheting (default) the shear increment is the
tangential part of (alpha (v2 - v1) + R2 n x w2 + R1 n x w1) dt, alpha = (R1+R2)/(R1+R2-delta).
GlobalStiffnessTimeStepper: dt = 1.41044 * safety * sqrt(min over bodies of m/K_ii and I/K_rot_ii)
from per-body diagonal stiffnesses, contacts with zero normal force skipped, dt growing by at most
5 % a step (GlobalStiffnessTimeStepper.cpp).
"""
from __future__ import annotations

import json
import math
import os
import subprocess
import tempfile
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from . import engine_executable
from ..paths import ENGINE_SCRIPTS

__all__ = [
    "LatticeCase", "PairCase", "SceneCase", "Run", "RunResult", "YadeError", "run_batch", "run_case",
    "compress_packing", "bisect_thresholds", "ENGINE_SCRIPTS", "GROWTH_LIMIT", "WINDOW_LIMIT",
    "HALT_FRACTION",
]

#: growth figure above which a run counts as growing (stable runs stay O(1..10))
GROWTH_LIMIT = 1.0e3
#: envelope of the last quarter over that of the second quarter above which a run grows
WINDOW_LIMIT = 10.0
#: deviation, as a fraction of the contact force scale, at which YADE stops a run
HALT_FRACTION = 1.0e-2
#: where the scripts dtcrit ships for YADE live (the harness runs them inside YADE only)
_TAG = "DTCRIT-YADE "


class YadeError(RuntimeError):
    """YADE failed for a reason other than the dynamics (bad script, missing binary...)."""


@dataclass(frozen=True)
class LatticeCase:
    lattice: str  # "sc", "bcc", "fcc"
    cells: int
    kn: float
    ks: float
    radius: float = 1.0e-3
    density: float = 2500.0
    overlap: float = 1.0e-6  # nearest-neighbour overlap / R
    label: str = ""
    kind: str = field(default="lattice", init=False)


@dataclass(frozen=True)
class PairCase:
    young: float
    poisson: float
    radius: float = 1.0e-3
    density: float = 2500.0
    direction: tuple[float, float, float] = (1.0, 0.0, 0.0)
    overlap: float = 0.01  # delta0 / R
    bonded: bool = False
    moment_law: bool = True
    alpha_kr: float = 2.0
    alpha_ktw: float = 2.0
    label: str = ""
    kind: str = field(default="pair", init=False)


@dataclass(frozen=True)
class SceneCase:
    state: str  # a file written by O.save
    label: str = ""
    kind: str = field(default="scene", init=False)


Case = LatticeCase | PairCase | SceneCase


@dataclass(frozen=True)
class Run:
    """One run: ``dt`` fixed, or chosen by GSTS (``gsts_safety``) or by the dtcrit hook (``hook``:
    keyword arguments of ``yade_hook.dtcrit_runner``; ``dt`` is then the initial step)."""

    steps: int
    dt: float | None = None
    gsts_safety: float | None = None
    hook: dict | None = None
    eps: float = 1.0e-6
    seed: int = 12345


@dataclass
class RunResult:
    run: Run
    steps_run: int
    halted: bool
    growth: float
    force_growth: float
    energy_growth: float
    window_growth: float
    rate: float
    dt_first: float
    dt_last: float
    dt_max: float
    series: dict[str, np.ndarray] = field(repr=False, default_factory=dict)
    info: dict = field(repr=False, default_factory=dict)

    @property
    def bounded(self) -> bool:
        return (not self.halted and math.isfinite(self.growth) and self.growth < GROWTH_LIMIT
                and self.window_growth < WINDOW_LIMIT)

    @property
    def growing(self) -> bool:
        """Clearly unstable: not bounded, and the envelope grows (or YADE had to stop it)."""
        return not self.bounded and (self.halted or self.rate > 1.0)


def _window_growth(dev: np.ndarray, nsteps: int) -> float:
    if not np.all(np.isfinite(dev)):
        return math.inf
    step = np.arange(1, dev.size + 1)
    w1 = (step >= 0.25 * nsteps) & (step <= 0.5 * nsteps)
    w2 = step >= 0.75 * nsteps
    if not w1.any() or not w2.any():
        return math.nan
    a, b = float(dev[w1].max()), float(dev[w2].max())
    return b / a if a > 0 else (math.inf if b > 0 else 1.0)


def _rate(dev: np.ndarray) -> float:
    """Growth factor per step fitted to the log of the running-max envelope (second half)."""
    ok = np.isfinite(dev) & (dev > 0)
    if ok.sum() < 4:
        return math.nan
    st = np.flatnonzero(ok).astype(float)
    g = np.maximum.accumulate(dev[ok])
    half = st >= st[0] + 0.5 * (st[-1] - st[0])
    if half.sum() < 2 or st[half][-1] == st[half][0]:
        return math.nan
    return float(math.exp(np.polyfit(st[half], np.log(g[half]), 1)[0]))


def _classify(run: Run, raw: dict) -> RunResult:
    dev = np.asarray(raw["dev"], dtype=float)
    ke = np.asarray(raw["ke"], dtype=float)
    dts = np.asarray(raw["dt"], dtype=float)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        ref = float(np.max(dev[:10])) if dev.size else math.nan
        fg = float(np.max(dev) / ref) if ref > 0 and np.all(np.isfinite(dev)) else math.inf
        k0 = float(ke[0]) if ke.size else math.nan
        eg = float(math.sqrt(np.max(ke) / k0)) if k0 > 0 and np.all(np.isfinite(ke)) else math.inf
    halted = bool(raw["halted"])
    return RunResult(
        run=run, steps_run=int(raw["steps_run"]), halted=halted, growth=max(fg, eg), force_growth=fg,
        energy_growth=eg, window_growth=math.inf if halted else _window_growth(dev, run.steps),
        rate=_rate(dev), dt_first=float(dts[0]), dt_last=float(dts[-1]), dt_max=float(dts.max()),
        series={"dev": dev, "ke": ke, "dt": dts}, info=raw.get("info", {}),
    )


def _case_dict(case: Case) -> dict:
    d = asdict(case)
    d["kind"] = case.kind
    if isinstance(case, SceneCase):
        d["state"] = os.path.abspath(case.state)
    return d


def run_yade_script(script: str, payload: dict, *, yade: str | None = None, timeout: float, keep_dir=None,
                    tag: str = _TAG) -> tuple[list[dict], str]:
    """``yade -n -x case.py cases.json`` with ``script`` and ``payload`` in a temporary folder (or
    ``keep_dir``), one thread; the JSON records the script prints after ``tag``, and its stdout.
    A failed run, or a record carrying ``error``, raises ``YadeError`` with the output's tail.
    """
    exe = yade or engine_executable("yade")
    if exe is None:
        raise YadeError("YADE not found (apt-get install yade)")
    env = dict(os.environ, OMP_NUM_THREADS="1")
    with tempfile.TemporaryDirectory(prefix="yade_case_") as tmp:
        work = Path(keep_dir) if keep_dir is not None else Path(tmp)
        work.mkdir(parents=True, exist_ok=True)
        (work / "cases.json").write_text(json.dumps(payload))
        (work / "case.py").write_text(script)
        proc = subprocess.run([exe, "-n", "-x", "case.py", "cases.json"], cwd=work, env=env,
                              capture_output=True, text=True, timeout=timeout)
    out = [json.loads(line[len(tag):]) for line in proc.stdout.splitlines() if line.startswith(tag)]
    if proc.returncode != 0 or any("error" in r for r in out):
        tail = "\n".join((proc.stdout + proc.stderr).splitlines()[-25:])
        raise YadeError(f"yade failed (exit {proc.returncode}):\n{tail}")
    return out, proc.stdout


def _run_yade(payload: dict, *, yade: str | None, timeout: float, keep_dir=None) -> tuple[list[dict], str]:
    return run_yade_script(YADE_SCRIPT, payload, yade=yade, timeout=timeout, keep_dir=keep_dir)


def run_batch(jobs, *, yade: str | None = None, timeout: float = 600.0, keep_dir=None) -> list[list[RunResult]]:
    """Run every ``(case, [Run, ...])`` of ``jobs`` in one YADE process; results in the same shape."""
    jobs = [(case, list(runs)) for case, runs in jobs]
    payload = {"halt_fraction": HALT_FRACTION, "engine_scripts": str(ENGINE_SCRIPTS),
               "cases": [{"case": _case_dict(c), "runs": [asdict(r) for r in runs]} for c, runs in jobs]}
    raw, _ = _run_yade(payload, yade=yade, timeout=timeout, keep_dir=keep_dir)
    by_key = {(r["case"], r["run"]): r for r in raw if "case" in r}
    out = []
    for ci, (_, runs) in enumerate(jobs):
        row = []
        for ri, run in enumerate(runs):
            if (ci, ri) not in by_key:
                raise YadeError(f"no result for case {ci} run {ri}")
            row.append(_classify(run, by_key[(ci, ri)]))
        out.append(row)
    return out


def run_case(case: Case, run: Run, **kw) -> RunResult:
    return run_batch([(case, [run])], **kw)[0][0]


def compress_packing(out_dir, *, n: int = 100, r_mean: float = 1.0e-3, r_fuzz: float = 0.3, young: float = 1.0e8,
                     poisson: float = 0.25, density: float = 2500.0, pressure_over_young: float = 2.5e-4,
                     friction: float = 0.1, seed: int = 1, yade: str | None = None, timeout: float = 300.0) -> dict:
    """Compress ``n`` spheres (radii ``r_mean (1 +- r_fuzz)``, YADE's ``makeCloud``) in a periodic cell
    with PeriTriaxController to the isotropic stress ``pressure_over_young * young``, relax it with
    NewtonIntegrator damping until ``unbalancedForce() < 1e-5``, zero the velocities, make every
    contact sticky (``tangensOfFrictionAngle`` 1e6: no Coulomb slip in the runs), and save it.

    Returns ``{"state": path of the O.save file, "export": path of the yade_export JSON, ...}``.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    spec = dict(n=n, r_mean=r_mean, r_fuzz=r_fuzz, young=young, poisson=poisson, density=density,
                pressure=pressure_over_young * young, friction=friction, seed=seed,
                state=str((out_dir / "packing.yade.gz").resolve()), export=str((out_dir / "packing.json").resolve()))
    payload = {"compress": spec, "engine_scripts": str(ENGINE_SCRIPTS), "cases": []}
    raw, _ = _run_yade(payload, yade=yade, timeout=timeout)
    info = next(r for r in raw if r.get("compressed"))
    return {**spec, **info}


def bisect_thresholds(cases, lo, hi, *, steps: int, rel_tol: float = 1e-4, yade: str | None = None,
                      **run_kw) -> list[tuple[float, float]]:
    """YADE's stability threshold of each case, bisected on dt in ``[lo_c, hi_c]`` (lists or scalars).

    Every iteration runs all the cases' midpoints in one YADE process.  Returns each case's final
    bracket ``(bounded dt, growing dt)``, of relative width below ``rel_tol``.
    """
    cases = list(cases)
    lo = list(np.broadcast_to(np.asarray(lo, float), (len(cases),)))
    hi = list(np.broadcast_to(np.asarray(hi, float), (len(cases),)))
    ends = run_batch([(c, [Run(steps, dt=a, **run_kw), Run(steps, dt=b, **run_kw)]) for c, a, b in zip(cases, lo, hi)],
                     yade=yade)
    for k, (a, b) in enumerate(ends):
        if not a.bounded or b.bounded:
            raise ValueError(f"case {k}: bracket [{lo[k]!r}, {hi[k]!r}] does not straddle the threshold")
    while True:
        open_ = [k for k in range(len(cases)) if hi[k] / lo[k] - 1.0 > rel_tol]
        if not open_:
            return list(zip(lo, hi))
        mids = [math.sqrt(lo[k] * hi[k]) for k in open_]
        res = run_batch([(cases[k], [Run(steps, dt=m, **run_kw)]) for k, m in zip(open_, mids)], yade=yade)
        for k, m, (r,) in zip(open_, mids, res):
            if r.bounded:
                lo[k] = m
            else:
                hi[k] = m


# ----------------------------------------------------------------------------- the script YADE runs

YADE_SCRIPT = r'''# Generated by tests/support/engines/yade.py: runs inside YADE (`yade -n -x case.py cases.json`).
import json, math, random, sys

PAYLOAD = json.load(open(sys.argv[1]))
HALT_FRACTION = PAYLOAD.get("halt_fraction", 1e-2)
TAG = "DTCRIT-YADE "


def emit(obj):
    print(TAG + json.dumps(obj), flush=True)


def frict_loop():
    return InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                           [Law2_ScGeom_FrictPhys_CundallStrack()])


def coh_loop():
    return InteractionLoop([Ig2_Sphere_Sphere_ScGeom6D()], [Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionNow=True)],
                           [Law2_ScGeom6D_CohFrictPhys_CohesionMoment()])


# ------------------------------------------------------------------ scenes
LATTICE_BASIS = {
    "sc": ([(0.0, 0.0, 0.0)], 1.0),
    "bcc": ([(0.0, 0.0, 0.0), (0.5, 0.5, 0.5)], 2.0 / math.sqrt(3.0)),
    "fcc": ([(0.0, 0.0, 0.0), (0.5, 0.5, 0.0), (0.5, 0.0, 0.5), (0.0, 0.5, 0.5)], math.sqrt(2.0)),
}


def build_lattice(c):
    """Returns (interaction loop, setup after the first collider pass, force scale, pair info)."""
    R = c["radius"]
    d0 = 2.0 * R - c["overlap"] * R  # nearest-neighbour distance
    basis, edge_per_d = LATTICE_BASIS[c["lattice"]]
    a = edge_per_d * d0
    n = int(c["cells"])
    O.periodic = True
    O.cell.hSize = Matrix3(n * a, 0, 0, 0, n * a, 0, 0, 0, n * a)
    mat = O.materials.append(FrictMat(young=c["kn"] / R, poisson=0.5, density=c["density"], frictionAngle=1.5))
    for i in range(n):
        for j in range(n):
            for k in range(n):
                for b in basis:
                    O.bodies.append(sphere(((i + b[0]) * a, (j + b[1]) * a, (k + b[2]) * a), R, material=mat))

    def after_first_pass():
        for it in O.interactions:
            if it.isReal:
                it.phys.kn = c["kn"]
                it.phys.ks = c["ks"]
        return c["kn"] * c["overlap"] * R

    return frict_loop(), after_first_pass, None


def build_pair(c):
    R = c["radius"]
    e = Vector3(*c["direction"])
    e = e / e.norm()
    d0 = 2.0 * R - c["overlap"] * R
    if c["bonded"]:
        mat = CohFrictMat(young=c["young"], poisson=c["poisson"], density=c["density"], frictionAngle=1.5,
                          isCohesive=True, normalCohesion=1e30, shearCohesion=1e30, fragile=False,
                          momentRotationLaw=bool(c["moment_law"]), alphaKr=c["alpha_kr"], alphaKtw=c["alpha_ktw"])
        loop = coh_loop()
    else:
        mat = FrictMat(young=c["young"], poisson=c["poisson"], density=c["density"], frictionAngle=1.5)
        loop = frict_loop()
    mid = O.materials.append(mat)
    O.bodies.append(sphere(-0.5 * d0 * e, R, material=mid))
    O.bodies.append(sphere(0.5 * d0 * e, R, material=mid))
    state = {}

    def after_first_pass():
        it = O.interactions[0, 1]
        state["kn"] = it.phys.kn
        state["P"] = it.phys.kn * it.geom.penetrationDepth
        state["d0"] = (O.bodies[1].state.pos - O.bodies[0].state.pos).norm()
        return state["P"]

    def preload():
        x = O.bodies[1].state.pos - O.bodies[0].state.pos
        u = x / x.norm()
        O.forces.addF(0, state["P"] * u)
        O.forces.addF(1, -state["P"] * u)

    def ndev():
        return state["kn"] * abs((O.bodies[1].state.pos - O.bodies[0].state.pos).norm() - state["d0"])

    return loop, after_first_pass, (preload, ndev)


def build_scene(c):
    O.load(c["state"])
    loop = [e for e in O.engines if type(e).__name__ == "InteractionLoop"][0]

    def after_first_pass():
        fn = [abs(i.phys.normalForce.dot(i.geom.normal)) for i in O.interactions if i.isReal]
        return sum(fn) / len(fn)

    return loop, after_first_pass, None


BUILDERS = {"lattice": build_lattice, "pair": build_pair, "scene": build_scene}


# ------------------------------------------------------------------ one run
def kick(eps, seed):
    rng = random.Random(seed)
    real = [i for i in O.interactions if i.isReal]
    pen = sum(max(i.geom.penetrationDepth, 0.0) for i in real) / max(len(real), 1)
    kmax = max(max(i.phys.kn, i.phys.ks) for i in real)
    dyn = [b for b in O.bodies if b.dynamic and isinstance(b.shape, Sphere)]
    mmin = min(b.state.mass for b in dyn)
    a = eps * pen
    vs = a * math.sqrt(kmax / mmin)
    u = lambda s: Vector3(rng.uniform(-s, s), rng.uniform(-s, s), rng.uniform(-s, s))
    for b in dyn:
        b.state.pos = b.state.pos + u(a)
        b.state.vel = b.state.vel + u(vs)
        b.state.angVel = b.state.angVel + u(vs / b.shape.radius)
    return {"kick_displacement": a, "kick_velocity": vs, "mean_penetration": pen, "contacts": len(real)}


def one_run(ci, c, ri, r):
    O.reset()
    loop, after_first_pass, pair = BUILDERS[c["kind"]](c)
    newton = NewtonIntegrator(damping=0.0, gravity=(0, 0, 0))
    record = {"dev": [], "ke": [], "dt": []}
    ctl = {"halt_at": None, "halted": False}
    dyn = [b for b in O.bodies if b.dynamic and isinstance(b.shape, Sphere)]

    def monitor():
        fm = 0.0
        for b in dyn:
            fm = max(fm, O.forces.f(b.id).norm(), O.forces.t(b.id).norm() / b.shape.radius)
        if pair is not None:
            fm = max(fm, pair[1]())
        record["dev"].append(fm)
        record["ke"].append(kineticEnergy())
        record["dt"].append(O.dt)
        if not (fm < ctl["halt_at"]):
            ctl["halted"] = True
            O.pause()

    globals()["_monitor"] = monitor
    # a small Verlet distance: the runs move by ~1e-6 R, and the 2-cell lattices are narrow
    engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()], verletDist=-0.05), loop]
    if pair is not None:
        globals()["_preload"] = pair[0]
        engines.append(PyRunner(command="_preload()", iterPeriod=1))
    engines.append(newton)
    O.engines = engines
    # a first pass makes the interactions without moving anything (dt = 1e-300: positions do not
    # change; a pass with NewtonIntegrator dead instead leaves the force container unsized, and
    # forces added from Python in the next step land on the wrong bodies)
    O.dt = 1e-300
    O.step()
    for b in O.bodies:
        b.state.vel = Vector3(0, 0, 0)
        b.state.angVel = Vector3(0, 0, 0)
    O.dt = r["dt"] if r["dt"] is not None else 1e-12
    scale = after_first_pass()
    info = kick(r["eps"], r["seed"])
    info["force_scale"] = scale
    ctl["halt_at"] = HALT_FRACTION * scale
    extra = []
    if r["gsts_safety"] is not None:
        extra.append(GlobalStiffnessTimeStepper(timestepSafetyCoefficient=r["gsts_safety"], timeStepUpdateInterval=1))
        O.dt = r["dt"] if r["dt"] is not None else 0.8 * PWaveTimeStep()
    hook = None
    if r["hook"] is not None:
        sys.path.insert(0, PAYLOAD["engine_scripts"])
        import yade_hook
        hook = yade_hook.DtcritHook(**{"export_path": "hook_scene.json", **r["hook"]})  # in the run's directory
    O.engines = O.engines[:-1] + extra + [newton] + ([hook.runner()] if hook is not None else []) + [
        PyRunner(command="_monitor()", iterPeriod=1)]
    if hook is not None:
        hook.update()  # the step of the scene as it is now, before the first step
    O.run(int(r["steps"]), True)
    info["hook"] = hook.history if hook is not None else None
    emit({"case": ci, "run": ri, "steps_run": len(record["dev"]), "halted": ctl["halted"], "info": info, **record})


# ------------------------------------------------------------------ packing
def compress(spec):
    from yade import pack
    O.reset()
    O.periodic = True
    L = (spec["n"] * 4.0 / 3.0 * math.pi * spec["r_mean"] ** 3 * (1 + spec["r_fuzz"] ** 2) / 0.3) ** (1.0 / 3.0)
    O.cell.hSize = Matrix3(L, 0, 0, 0, L, 0, 0, 0, L)
    sp = pack.SpherePack()
    sp.makeCloud((0, 0, 0), (L, L, L), rMean=spec["r_mean"], rRelFuzz=spec["r_fuzz"], num=spec["n"], periodic=True,
                 seed=spec["seed"])
    mat = O.materials.append(FrictMat(young=spec["young"], poisson=spec["poisson"], density=spec["density"],
                                      frictionAngle=spec["friction"]))
    sp.toSimulation(material=mat)
    p = spec["pressure"]
    done = {"ok": False}

    def compressed():
        done["ok"] = True
        O.pause()

    globals()["_compressed"] = compressed
    triax = PeriTriaxController(goal=(-p, -p, -p), stressMask=7, dynCell=True, maxStrainRate=(1, 1, 1),
                                maxUnbalanced=1e-3, relStressTol=1e-3, doneHook="_compressed()")
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]), frict_loop(), triax,
                 NewtonIntegrator(damping=0.4)]
    O.dt = 0.5 * PWaveTimeStep()
    O.run(1000000, True)
    if not done["ok"]:
        raise RuntimeError("PeriTriaxController did not reach the target stress")
    triax.dead = True
    for _ in range(200):
        if unbalancedForce() < 1e-5:
            break
        O.run(500, True)
    for b in O.bodies:
        b.state.vel = Vector3(0, 0, 0)
        b.state.angVel = Vector3(0, 0, 0)
    O.materials[mat].frictionAngle = math.atan(1e6)
    for i in O.interactions:
        if i.isReal:
            i.phys.tangensOfFrictionAngle = 1e6
    O.engines = O.engines[:3] + [NewtonIntegrator(damping=0.0)]
    O.save(spec["state"])
    sys.path.insert(0, PAYLOAD["engine_scripts"])
    import yade_export
    yade_export.export(spec["export"])
    emit({"compressed": True, "iterations": O.iter, "unbalanced": unbalancedForce(), "cell": O.cell.hSize[0, 0],
          "stress": [triax.stress[k] for k in range(3)]})


# ------------------------------------------------------------------ main
try:
    if "compress" in PAYLOAD:
        compress(PAYLOAD["compress"])
    for ci, entry in enumerate(PAYLOAD["cases"]):
        for ri, run in enumerate(entry["runs"]):
            one_run(ci, entry["case"], ri, run)
except Exception as exc:
    import traceback
    traceback.print_exc()
    emit({"error": repr(exc)})
    sys.exit(1)
'''
