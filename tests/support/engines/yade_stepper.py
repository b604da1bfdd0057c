"""YADE's GlobalStiffnessTimeStepper run for one step on prepared scenes: the ``O.dt`` it sets.

On top of ``support.engines.yade_bodies`` (same builders, same ``yade -n -x`` batch; nothing here
imports the project under test).  For each case and each safety coefficient YADE builds the case,
makes its interactions (a run's first pass, ``setup_case``, and the case's own setup after it),
writes the ``dtcrit-yade-export/1`` file of that state (first safety only: every rebuild is the same
state), puts ``GlobalStiffnessTimeStepper(timestepSafetyCoefficient=s)`` first in ``O.engines`` (so it
reads exactly the exported interactions: ``phys.normalForce``, ``kn``, ``ks``, ``geom.normal``,
``refR1``, ``refR2``), steps once and reports ``O.dt``.

Cases besides ``yade_bodies``' ``ClumpPairCase``:

* ``CloudCase`` -- a periodic cloud of ``n`` bodies at YADE's ``makeCloud`` centres (radius
  ``r_mean (1 +- r_fuzz)``), each a sphere of ``grow`` times its cloud radius (neighbours
  overlap), or with ``clump_members`` > 1 a clump of that many spheres of random radii along a
  random axis inside it (``O.bodies.appendClumped``: YADE's own mass, principal inertia and frame);
  ``fixed`` bodies (the first ones) are made non-dynamic.  FrictMat, or with ``moment_law``
  CohFrictMat bonded at the first pass (``setCohesionNow``) with its moment law
  (``kr = alphaKr ks R1 R2``, ``ktw = alphaKtw ks R1 R2``), or with ``moment_rotation`` false the same
  physics without it (CohFrictPhys still holds ``kr``, ``ktw``).
"""
from __future__ import annotations

from dataclasses import asdict, dataclass, field
from pathlib import Path

from .yade import ENGINE_SCRIPTS, HALT_FRACTION, run_yade_script
from .yade_bodies import SCRIPT as BODIES_SCRIPT
from .yade_bodies import _MAIN, _payload_case

__all__ = ["CloudCase", "stepper_dt"]

_TAG = "DTCRIT-YADE "


@dataclass(frozen=True)
class CloudCase:
    """A periodic cloud of overlapping spheres or clumps (module docstring)."""

    n: int
    r_mean: float = 1.0e-3
    r_fuzz: float = 0.3
    grow: float = 1.06
    clump_members: int = 1
    fixed: int = 0
    young: float = 1.0e8
    poisson: float = 0.3
    density: float = 2500.0
    moment_law: bool = False
    moment_rotation: bool = True  # with moment_law: CohFrictMat.momentRotationLaw
    seed: int = 3
    label: str = ""
    kind: str = field(default="cloud", init=False)


_STEPPER = r'''
# ------------------------------------------------------------------ stepper (support/engines/yade_stepper.py)
def build_cloud(c):
    from yade import pack
    rng = random.Random(c["seed"])
    O.periodic = True
    L = (c["n"] * 4.0 / 3.0 * math.pi * c["r_mean"] ** 3 * (1 + c["r_fuzz"] ** 2) / 0.4) ** (1.0 / 3.0)
    O.cell.hSize = Matrix3(L, 0, 0, 0, L, 0, 0, 0, L)
    sp = pack.SpherePack()
    sp.makeCloud((0, 0, 0), (L, L, L), rMean=c["r_mean"], rRelFuzz=c["r_fuzz"], num=c["n"], periodic=True,
                 seed=c["seed"])
    if c["moment_law"]:
        mat = O.materials.append(CohFrictMat(young=c["young"], poisson=c["poisson"], density=c["density"],
                                             frictionAngle=0.5, isCohesive=True, normalCohesion=1e30,
                                             shearCohesion=1e30, momentRotationLaw=c["moment_rotation"],
                                             alphaKr=2.0, alphaKtw=1.5))
        loop = coh_loop()
    else:
        mat = O.materials.append(FrictMat(young=c["young"], poisson=c["poisson"], density=c["density"],
                                          frictionAngle=0.5))
        loop = frict_loop()
    made = []
    for centre, r in sp:
        R = c["grow"] * r
        k = int(c["clump_members"])
        if k <= 1:
            made.append(O.bodies.append(sphere(centre, R, material=mat)))
            continue
        e = Vector3(rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1))
        e = e / e.norm()
        members = []
        for j in range(k):  # radii 0.45..0.6 R along the axis, overlapping neighbours, inside the cloud sphere
            rj = R * rng.uniform(0.45, 0.6)
            s = (j - 0.5 * (k - 1)) * (R - rj) / max(0.5 * (k - 1), 1.0)
            members.append(sphere(centre + s * e, rj, material=mat))
        made.append(O.bodies.appendClumped(members)[0])
    for bid in made[: c["fixed"]]:
        O.bodies[bid].dynamic = False

    def after_first_pass():
        return 1.0

    return loop, after_first_pass, None


BUILDERS.update({"cloud": build_cloud})


def stepper_runs(entries):
    sys.path.insert(0, PAYLOAD["engine_scripts"])
    import yade_export
    for ci, entry in enumerate(entries):
        for si, safety in enumerate(entry["safeties"]):
            newton, after_first_pass, pair = setup_case(entry["case"])
            after_first_pass()
            if si == 0:
                yade_export.export(entry["export"])
            gsts = GlobalStiffnessTimeStepper(timestepSafetyCoefficient=safety, timeStepUpdateInterval=1)
            O.engines = [gsts] + O.engines
            before = O.dt
            O.step()
            emit({"stepper": ci, "safety": safety, "dt": O.dt, "dt_before": before,
                  "contacts": sum(1 for i in O.interactions if i.isReal)})


try:
    if "stepper" in PAYLOAD:
        stepper_runs(PAYLOAD["stepper"])
except Exception as exc:
    import traceback
    traceback.print_exc()
    emit({"error": repr(exc)})
    sys.exit(1)

'''

SCRIPT = BODIES_SCRIPT.replace(_MAIN, _STEPPER + _MAIN)


def _run(payload: dict, *, yade: str | None, timeout: float) -> list[dict]:
    payload = {"halt_fraction": HALT_FRACTION, "engine_scripts": str(ENGINE_SCRIPTS), "cases": [], **payload}
    return run_yade_script(SCRIPT, payload, yade=yade, timeout=timeout)[0]


def stepper_dt(cases, paths, safeties=(0.8,), *, yade: str | None = None, timeout: float = 300.0) -> list[dict]:
    """For each case: write its export to the matching path and run the stepper once per safety.

    Returns one dict per case, ``{safety: O.dt after one step}``.
    """
    paths = [str(Path(p).resolve()) for p in paths]
    entries = [{"case": _case(c), "export": p, "safeties": list(safeties)} for c, p in zip(cases, paths)]
    out: list[dict] = [{} for _ in cases]
    for r in _run({"stepper": entries}, yade=yade, timeout=timeout):
        if "stepper" in r:
            out[r["stepper"]][r["safety"]] = r["dt"]
    return out


def _case(case) -> dict:
    if isinstance(case, CloudCase):
        return {**asdict(case), "kind": case.kind}
    return _payload_case(case)
