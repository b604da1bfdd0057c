"""Collide pairs of spheres in YADE (``yade -n -x``, 2023.02a) with its Hertz-Mindlin law.

Each group ``(dt, [Impact, ...])`` of a batch is one ``O.reset()`` scene in one YADE process: every
impact is a pair of spheres with its own ``FrictMat`` (E, nu, friction angle atan(mu)), the pairs 6 radii apart
along y; ``Ip2_FrictMat_FrictMat_MindlinPhys(en=MatchMaker(matches=[(mat, mat, en), ...]))`` gives
each pair its restitution (``en = 1`` -> ``alpha = 0``: no damping), ``Law2_ScGeom_MindlinPhys_Mindlin``
(its damping velocity is the plain relative velocity in 2023.02a),
``NewtonIntegrator(damping=0, gravity=0)``.  Masses and inertias are set on the bodies'
states.  Initial positions and velocities as the LAMMPS harness sets them (YADE's stored velocity
is the half-step one, v_{-1/2}; there is no force before contact, so it equals v_0).  A PyRunner
after NewtonIntegrator records every step's positions, velocities and spins (YADE stores
v_{n+1/2} with x_{n+1}: after the contact both are the free-flight velocity).

Oblique impacts: YADE's tangential law (``Ig2_Sphere_Sphere_ScGeom`` shear increment,
``ks = 8 G* sqrt(R* delta)``, Coulomb limit ``tan(phi) |F_n|``, forces at the contact point, arm
``R - delta/2``) slides like LAMMPS's ``mindlin``; its shear increment scales the translational
slip by ``(R1+R2)/(R1+R2-delta)`` (avoidGranularRatcheting), which does not change the sliding
force, only its direction's sign matters in a plane impact.
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np

from . import engine_executable
from .collisions import Impact, Outcome, measure
from .collisions_lammps import FIRST_CONTACT_STEP, SPACING, _pair_state, _steps

__all__ = ["YadeError", "run_batch", "collide"]


class YadeError(RuntimeError):
    """YADE failed for a reason other than the dynamics."""


SCRIPT = r'''# written by tests/support/engines/collisions_yade.py; run as `yade -n -x collide.py payload.json`
import json, math, sys
P = json.load(open(sys.argv[1]))
for gi, g in enumerate(P["groups"]):
    O.reset()
    mats, matches = [], []
    for k, c in enumerate(g["impacts"]):
        mid = O.materials.append(FrictMat(young=c["young"], poisson=c["poisson"], density=1000.0,
                                                frictionAngle=math.atan(c["friction"])))
        mats.append(mid)
        matches.append((mid, mid, c["en"]))
    ids = []
    for k, c in enumerate(g["impacts"]):
        pair = []
        for (x, v) in c["state"]:
            b = O.bodies.append(sphere(Vector3(*x), c["radius"], material=mats[k]))
            st = O.bodies[b].state
            st.mass = c["mass"]
            i = 0.4 * c["mass"] * c["radius"] ** 2
            st.inertia = Vector3(i, i, i)
            st.vel = Vector3(*v)
            st.angVel = Vector3(0, 0, 0)
            pair.append(b)
        ids.append(pair)
    rec = []
    states = [b.state for b in O.bodies]
    def record():
        rec.append([(tuple(s.pos), tuple(s.vel), tuple(s.angVel)) for s in states])
    globals()["_record"] = record
    O.engines = [
        ForceResetter(),
        InsertionSortCollider([Bo1_Sphere_Aabb()]),
        InteractionLoop([Ig2_Sphere_Sphere_ScGeom()],
                        [Ip2_FrictMat_FrictMat_MindlinPhys(en=MatchMaker(matches=matches, algo="val", val=1.0))],
                        [Law2_ScGeom_MindlinPhys_Mindlin()]),
        NewtonIntegrator(damping=0.0, gravity=(0, 0, 0)),
        PyRunner(command="_record()", iterPeriod=1, initRun=True),
    ]
    O.dt = g["dt"]
    record()
    O.run(g["steps"], True)
    with open("group%d.json" % gi, "w") as fh:
        json.dump([[list(p) + list(v) + list(w) for (p, v, w) in row] for row in rec], fh)
print("DTCRIT-COLLIDE done", flush=True)
'''


def _impact_dict(imp: Impact, dt: float, k: int) -> dict:
    if imp.damping not in ("yade-mindlin", "none") or imp.normal != "hertz":
        raise ValueError(f"YADE harness: Hertz-Mindlin with en only, not {imp.normal}/{imp.damping}")
    return {"young": imp.young, "poisson": imp.poisson, "radius": imp.radius, "mass": imp.mass,
            "en": 1.0 if imp.damping == "none" else imp.coefficient, "friction": imp.friction,
            "state": [list(map(list, s)) for s in _pair_state(imp, dt, k)]}


def run_batch(groups, *, timeout: float = 300.0, keep_dir=None) -> list[list[Outcome]]:
    """Run every ``(dt, [Impact, ...])`` group in one YADE process; outcomes in the same shape."""
    groups = [(float(dt), list(imps)) for dt, imps in groups]
    payload: dict[str, list] = {"groups": []}
    for dt, imps in groups:
        payload["groups"].append({"dt": dt, "steps": _steps(dt, imps),
                                  "impacts": [_impact_dict(i, dt, k) for k, i in enumerate(imps)]})
    exe = engine_executable("yade")
    if exe is None:
        raise YadeError("YADE not found (apt-get install yade)")
    work = Path(tempfile.mkdtemp(prefix="yade_collide_") if keep_dir is None else keep_dir)
    work.mkdir(parents=True, exist_ok=True)
    try:
        (work / "payload.json").write_text(json.dumps(payload))
        (work / "collide.py").write_text(SCRIPT)
        proc = subprocess.run([exe, "-n", "-x", "collide.py", "payload.json"], cwd=work,
                              env=dict(os.environ, OMP_NUM_THREADS="1"), capture_output=True, text=True,
                              timeout=timeout)
        if proc.returncode != 0 or "DTCRIT-COLLIDE done" not in proc.stdout:
            tail = "\n".join((proc.stdout + proc.stderr).splitlines()[-20:])
            raise YadeError(f"yade failed (exit {proc.returncode}):\n{tail}")
        out = []
        for gi, (dt, imps) in enumerate(groups):
            arr = np.array(json.loads((work / f"group{gi}.json").read_text()), dtype=float)
            row = []
            for k, imp in enumerate(imps):
                a1, a2 = arr[:, 2 * k, :], arr[:, 2 * k + 1, :]
                row.append(measure(imp, dt, a1[:, 0:3], a2[:, 0:3], a1[:, 3:6], a2[:, 3:6], a1[:, 6:9], a2[:, 6:9]))
            out.append(row)
        return out
    finally:
        if keep_dir is None:
            shutil.rmtree(work, ignore_errors=True)


def collide(impacts, dt: float, **kw) -> list[Outcome]:
    """Outcomes of ``impacts`` run together at step ``dt`` (one YADE process)."""
    return run_batch([(dt, impacts)], **kw)[0]


assert FIRST_CONTACT_STEP == 1 and SPACING > 4.0  # the layout both harnesses share
