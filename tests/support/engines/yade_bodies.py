"""YADE cases with clumps and bonded chains, on top of ``support.engines.yade`` (same runs, same
classification, same ``yade -n -x`` batches; nothing here imports the project under test).

Cases:

* ``ClumpPairCase`` -- two clumps given by their member spheres ``[x, y, z, r]`` in global
  coordinates (``O.bodies.appendClumped``, YADE's own mass, inertia and principal frame), no
  gravity; member ``contact[0]`` of the first touches member ``contact[1]`` of the second.  A
  preload ``P = kn delta0`` of constant magnitude acts along the *current* centre line of those two
  members, applied at the members' centres (``O.forces.addF`` on a member goes into its clump's
  force and torque, ``Clump::addForceTorqueFromMembers``).  The contact force acts along that same
  line (at the contact point, which lies on it), so force and torque of the preload and of the
  contact's normal force are the same functions of the configuration: the preload holds the pair
  in equilibrium and cancels the contact's geometric stiffness exactly, for any member offsets.
* ``ChainCase`` -- spheres at ``positions`` bonded by YADE's cohesive law (CohFrictMat,
  Ip2_CohFrictMat_CohFrictMat_CohFrictPhys ``setCohesionNow``, Law2_ScGeom6D_CohFrictPhys_CohesionMoment
  with ``momentRotationLaw``: ``kr = alphaKr ks R1 R2``, ``ktw = alphaKtw ks R1 R2``).  After the first
  pass each bond's unloaded penetration ``unp`` is set to its penetration and its forces zeroed:
  the free chain is then at rest with no pre-load (YADE's normal force is ``kn (penetration - unp)``,
  CohesiveFrictionalContactLaw.cpp).  The force scale of the halt criterion is ``kn delta0``.
* ``compress_clumps`` -- a periodic packing of two-sphere clumps: YADE's ``makeCloud`` places
  bounding spheres, each becomes a dumbbell of random orientation inside it, PeriTriaxController
  compresses to ``pressure``, NewtonIntegrator damping relaxes it, the contacts are made sticky and
  the scene is saved (``O.save``) and exported (``yade_export.py``); runs use ``yade.SceneCase``.

Runs: ``one_run`` of ``yade.py``'s script generalised to rigid bodies: the dynamic bodies are the
free spheres and the clumps (members move with their clump); a clump is kicked as a rigid body
(members translated with it, their velocities ``V + Omega x d`` and spins ``Omega`` set as
``Clump::moveMembers`` sets them) and its deviation is ``max(|F|, |T|/r_bound)`` with the net force
and torque NewtonIntegrator gathers from the members (``r_bound`` the clump's bounding radius).
``export_cases`` builds each case, makes its interactions (the first pass of a run) and writes the
``dtcrit-yade-export/1`` file there instead of running it.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from .yade import ENGINE_SCRIPTS, HALT_FRACTION, YADE_SCRIPT, Run, RunResult, YadeError, run_yade_script, _case_dict, _classify

__all__ = ["ClumpPairCase", "ChainCase", "run_batch", "export_cases", "compress_clumps", "bisect_thresholds"]

_TAG = "DTCRIT-YADE "
_MAIN = "# ------------------------------------------------------------------ main\n"


@dataclass(frozen=True)
class ClumpPairCase:
    clumps: tuple  # two tuples of member spheres (x, y, z, r), global coordinates
    contact: tuple[int, int]  # the touching members (index in each clump)
    young: float
    poisson: float
    density: float = 2500.0
    label: str = ""
    kind: str = field(default="clump_pair", init=False)


@dataclass(frozen=True)
class ChainCase:
    positions: tuple  # sphere centres (x, y, z)
    radius: float
    young: float
    poisson: float
    density: float = 2500.0
    alpha_kr: float = 2.0
    alpha_ktw: float = 2.0
    label: str = ""
    kind: str = field(default="chain", init=False)


_EXTRA = r'''
# ------------------------------------------------------------------ rigid bodies (support/engines/yade_bodies.py)
def clump_members(b):
    return [O.bodies[m] for m in b.shape.members.keys()] if b.isClump else []


def body_reach(b):
    if b.isClump:
        return max((m.state.pos - b.state.pos).norm() + m.shape.radius for m in clump_members(b))
    return b.shape.radius


def rigid_bodies():
    return [b for b in O.bodies if b.dynamic and not b.isClumpMember and (b.isClump or isinstance(b.shape, Sphere))]


def build_clump_pair(c):
    mat = O.materials.append(FrictMat(young=c["young"], poisson=c["poisson"], density=c["density"], frictionAngle=1.5))
    touching = []
    for members, k in zip(c["clumps"], c["contact"]):
        cid, ids = O.bodies.appendClumped([sphere(tuple(m[:3]), m[3], material=mat) for m in members])
        touching.append(ids[k])
    a, b = touching
    state = {}

    def after_first_pass():
        it = O.interactions[a, b]
        state["kn"] = it.phys.kn
        state["P"] = it.phys.kn * it.geom.penetrationDepth
        state["d0"] = (O.bodies[b].state.pos - O.bodies[a].state.pos).norm()
        return state["P"]

    def preload():
        x = O.bodies[b].state.pos - O.bodies[a].state.pos
        u = x / x.norm()
        O.forces.addF(a, state["P"] * u)
        O.forces.addF(b, -state["P"] * u)

    def ndev():
        return state["kn"] * abs((O.bodies[b].state.pos - O.bodies[a].state.pos).norm() - state["d0"])

    return frict_loop(), after_first_pass, (preload, ndev)


def build_chain(c):
    mat = O.materials.append(CohFrictMat(young=c["young"], poisson=c["poisson"], density=c["density"],
                                         frictionAngle=1.5, isCohesive=True, normalCohesion=1e30, shearCohesion=1e30,
                                         fragile=False, momentRotationLaw=True, alphaKr=c["alpha_kr"],
                                         alphaKtw=c["alpha_ktw"]))
    for x in c["positions"]:
        O.bodies.append(sphere(tuple(x), c["radius"], material=mat))

    def after_first_pass():
        real = [i for i in O.interactions if i.isReal]
        scale = sum(i.phys.kn * i.geom.penetrationDepth for i in real) / len(real)
        for i in real:  # unloaded bonds: no pre-load, the chain at rest
            i.phys.unp = i.geom.penetrationDepth
            i.phys.normalForce = Vector3(0, 0, 0)
            i.phys.shearForce = Vector3(0, 0, 0)
        return scale

    return coh_loop(), after_first_pass, None


BUILDERS.update({"clump_pair": build_clump_pair, "chain": build_chain})


def kick_bodies(eps, seed):
    rng = random.Random(seed)
    real = [i for i in O.interactions if i.isReal]
    pen = sum(max(i.geom.penetrationDepth, 0.0) for i in real) / max(len(real), 1)
    kmax = max(max(i.phys.kn, i.phys.ks) for i in real)
    dyn = rigid_bodies()
    mmin = min(b.state.mass for b in dyn)
    a = eps * pen
    vs = a * math.sqrt(kmax / mmin)
    u = lambda s: Vector3(rng.uniform(-s, s), rng.uniform(-s, s), rng.uniform(-s, s))
    for b in dyn:
        du = u(a)
        b.state.pos = b.state.pos + du
        b.state.vel = b.state.vel + u(vs)
        b.state.angVel = b.state.angVel + u(vs / body_reach(b))
        for m in clump_members(b):  # as Clump::moveMembers places them
            m.state.pos = m.state.pos + du
            m.state.vel = b.state.vel + b.state.angVel.cross(m.state.pos - b.state.pos)
            m.state.angVel = b.state.angVel
    return {"kick_displacement": a, "kick_velocity": vs, "mean_penetration": pen, "contacts": len(real)}


def setup_case(c):
    """Build the case and make its interactions without moving anything (as one_run does)."""
    O.reset()
    loop, after_first_pass, pair = BUILDERS[c["kind"]](c)
    newton = NewtonIntegrator(damping=0.0, gravity=(0, 0, 0))
    engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()], verletDist=-0.05), loop]
    if pair is not None:
        globals()["_preload"] = pair[0]
        engines.append(PyRunner(command="_preload()", iterPeriod=1))
    engines.append(newton)
    O.engines = engines
    O.dt = 1e-300
    O.step()
    for b in O.bodies:
        b.state.vel = Vector3(0, 0, 0)
        b.state.angVel = Vector3(0, 0, 0)
    return newton, after_first_pass, pair


def one_run(ci, c, ri, r):
    newton, after_first_pass, pair = setup_case(c)
    record = {"dev": [], "ke": [], "dt": []}
    ctl = {"halt_at": None, "halted": False}
    dyn = [(b, body_reach(b)) for b in rigid_bodies()]

    def monitor():
        fm = 0.0
        for b, reach in dyn:  # a clump's entry holds the net force and torque NewtonIntegrator gathered
            fm = max(fm, O.forces.f(b.id).norm(), O.forces.t(b.id).norm() / reach)
        if pair is not None:
            fm = max(fm, pair[1]())
        record["dev"].append(fm)
        record["ke"].append(kineticEnergy())
        record["dt"].append(O.dt)
        if not (fm < ctl["halt_at"]):
            ctl["halted"] = True
            O.pause()

    globals()["_monitor"] = monitor
    O.dt = r["dt"] if r["dt"] is not None else 1e-12
    scale = after_first_pass()
    info = kick_bodies(r["eps"], r["seed"])
    info["force_scale"] = scale
    ctl["halt_at"] = HALT_FRACTION * scale
    O.engines = O.engines[:-1] + [newton, PyRunner(command="_monitor()", iterPeriod=1)]
    O.run(int(r["steps"]), True)
    emit({"case": ci, "run": ri, "steps_run": len(record["dev"]), "halted": ctl["halted"], "info": info, **record})


def export_prepared(entries):
    sys.path.insert(0, PAYLOAD["engine_scripts"])
    import yade_export
    for ci, entry in enumerate(entries):
        _, after_first_pass, _ = setup_case(entry["case"])
        after_first_pass()
        yade_export.export(entry["export"])
        emit({"exported": ci})


def compress_clumps(spec):
    from yade import pack
    O.reset()
    O.periodic = True
    r, s = spec["radius"], spec["spacing"]  # members of radius r at +-s r/2 from the clump's centre
    bound = r * (1.0 + 0.5 * s)
    L = (spec["n"] * 4.0 / 3.0 * math.pi * bound ** 3 / 0.25) ** (1.0 / 3.0)
    O.cell.hSize = Matrix3(L, 0, 0, 0, L, 0, 0, 0, L)
    sp = pack.SpherePack()
    sp.makeCloud((0, 0, 0), (L, L, L), rMean=bound, rRelFuzz=0.0, num=spec["n"], periodic=True, seed=spec["seed"])
    mat = O.materials.append(FrictMat(young=spec["young"], poisson=spec["poisson"], density=spec["density"],
                                      frictionAngle=spec["friction"]))
    rng = random.Random(spec["seed"])
    for centre, _ in sp:
        e = Vector3(rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1))
        e = e / e.norm() * (0.5 * s * r)
        O.bodies.appendClumped([sphere(centre + e, r, material=mat), sphere(centre - e, r, material=mat)])
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
    O.dt = 0.3 * PWaveTimeStep()
    O.run(2000000, True)
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
    for i in O.interactions:
        if i.isReal:
            i.phys.tangensOfFrictionAngle = 1e6
    O.materials[mat].frictionAngle = math.atan(1e6)
    O.engines = O.engines[:3] + [NewtonIntegrator(damping=0.0)]
    O.save(spec["state"])
    sys.path.insert(0, PAYLOAD["engine_scripts"])
    import yade_export
    yade_export.export(spec["export"])
    emit({"compressed": True, "iterations": O.iter, "unbalanced": unbalancedForce(), "cell": O.cell.hSize[0, 0],
          "clumps": sum(1 for b in O.bodies if b.isClump)})


try:
    if "compress_clumps" in PAYLOAD:
        compress_clumps(PAYLOAD["compress_clumps"])
    if "prepare" in PAYLOAD:
        export_prepared(PAYLOAD["prepare"])
except Exception as exc:
    import traceback
    traceback.print_exc()
    emit({"error": repr(exc)})
    sys.exit(1)

'''

if YADE_SCRIPT.count(_MAIN) != 1:  # the harness script changed shape: fail loudly, not silently
    raise ImportError("engine_harness.yade.YADE_SCRIPT has no unique main marker")
SCRIPT = YADE_SCRIPT.replace(_MAIN, _EXTRA + _MAIN)


def _payload_case(case) -> dict:
    if isinstance(case, (ClumpPairCase, ChainCase)):
        d = asdict(case)
        d["kind"] = case.kind
        return d
    return _case_dict(case)


def _run(payload: dict, *, yade: str | None, timeout: float) -> list[dict]:
    payload = {"halt_fraction": HALT_FRACTION, "engine_scripts": str(ENGINE_SCRIPTS), "cases": [], **payload}
    return run_yade_script(SCRIPT, payload, yade=yade, timeout=timeout)[0]


def run_batch(jobs, *, yade: str | None = None, timeout: float = 600.0) -> list[list[RunResult]]:
    """Every ``(case, [Run, ...])`` in one YADE process (clump pairs, chains, saved scenes, and the
    cases of ``support.engines.yade``); results in the same shape."""
    jobs = [(case, list(runs)) for case, runs in jobs]
    cases = [{"case": _payload_case(c), "runs": [asdict(r) for r in runs]} for c, runs in jobs]
    raw = _run({"cases": cases}, yade=yade, timeout=timeout)
    by_key = {(r["case"], r["run"]): r for r in raw if "case" in r}
    out = []
    for ci, (_, runs) in enumerate(jobs):
        if any((ci, ri) not in by_key for ri in range(len(runs))):
            raise YadeError(f"no result for case {ci}")
        out.append([_classify(run, by_key[(ci, ri)]) for ri, run in enumerate(runs)])
    return out


def export_cases(cases, paths, *, yade: str | None = None, timeout: float = 300.0) -> list[str]:
    """Build each case in YADE, make its interactions (a run's first pass, its setup included) and
    write the ``dtcrit-yade-export/1`` file to the matching path; one YADE process."""
    paths = [str(Path(p).resolve()) for p in paths]
    _run({"prepare": [{"case": _payload_case(c), "export": p} for c, p in zip(cases, paths)]}, yade=yade,
         timeout=timeout)
    return paths


def compress_clumps(out_dir, *, n: int = 24, radius: float = 1.0e-3, spacing: float = 1.0, young: float = 1.0e8,
                    poisson: float = 0.25, density: float = 2500.0, pressure_over_young: float = 2.5e-4,
                    friction: float = 0.1, seed: int = 1, yade: str | None = None, timeout: float = 300.0) -> dict:
    """A periodic packing of ``n`` dumbbell clumps (two spheres of ``radius`` whose centres are
    ``spacing * radius`` apart), compressed by YADE (module docstring).  Returns ``{"state": O.save
    file, "export": yade_export JSON, ...}``."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    spec = dict(n=n, radius=radius, spacing=spacing, young=young, poisson=poisson, density=density,
                pressure=pressure_over_young * young, friction=friction, seed=seed,
                state=str((out_dir / "clumps.yade.gz").resolve()), export=str((out_dir / "clumps.json").resolve()))
    raw = _run({"compress_clumps": spec}, yade=yade, timeout=timeout)
    return {**spec, **next(r for r in raw if r.get("compressed"))}


def bisect_thresholds(cases, lo, hi, *, steps: int, rel_tol: float = 1e-3, yade: str | None = None,
                      known_ends: bool = False) -> list[tuple[float, float]]:
    """YADE's threshold of each case, bisected on dt in ``[lo_c, hi_c]`` (each iteration one YADE
    process for all open cases).  ``known_ends``: the ends were already classified (bounded at ``lo``,
    growing at ``hi``), else they are checked first.  Returns each ``(bounded dt, growing dt)``."""
    cases = list(cases)
    lo = [float(v) for v in np.broadcast_to(np.asarray(lo, float), (len(cases),))]
    hi = [float(v) for v in np.broadcast_to(np.asarray(hi, float), (len(cases),))]
    if not known_ends:
        ends = run_batch([(c, [Run(steps, dt=a), Run(steps, dt=b)]) for c, a, b in zip(cases, lo, hi)], yade=yade)
        for k, (a, b) in enumerate(ends):
            if not a.bounded or b.bounded:
                raise ValueError(f"case {k}: bracket [{lo[k]!r}, {hi[k]!r}] does not straddle the threshold")
    while True:
        open_ = [k for k in range(len(cases)) if hi[k] / lo[k] - 1.0 > rel_tol]
        if not open_:
            return list(zip(lo, hi))
        mids = [math.sqrt(lo[k] * hi[k]) for k in open_]
        res = run_batch([(cases[k], [Run(steps, dt=m)]) for k, m in zip(open_, mids)], yade=yade)
        for k, m, (r,) in zip(open_, mids, res):
            if r.bounded:
                lo[k] = m
            else:
                hi[k] = m
