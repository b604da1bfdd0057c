"""YADE writes a dump and a contact table (comment lines in its header, columns in its own order) of a
small compressed cluster; ``dtcrit audit DUMP --engine yade --contacts TABLE`` must give the step of the
same state exported by ``yade_export.py``.  The same run checks that a real export carries exactly the
fields ``dtcrit.packing.readers.yade_terms`` has decisions for, and that a partly blocked body and
NewtonIntegrator's density scaling are refused.
"""
from __future__ import annotations

import json
import subprocess

import pytest

from dtcrit import audit_snapshot
from dtcrit.errors import InputError
from dtcrit.packing.readers import yade_terms as yt
from support.engines import require_engine
from support.engines.yade import ENGINE_SCRIPTS

SCRIPT = r'''
import json, random, sys
sys.path.insert(0, EXPORTER_DIR)
from yade_export import export
random.seed(3)
O.materials.append(FrictMat(young=1e8, poisson=0.3, density=2600))
r0 = 1e-3
for i in range(3):
    for j in range(3):
        for k in range(2):
            r = r0 * (1 + 0.2 * random.random())
            O.bodies.append(sphere((2.1e-3 * i, 2.1e-3 * j, 2.1e-3 * k), r))
O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
             InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                             [Law2_ScGeom_FrictPhys_CundallStrack()]),
             NewtonIntegrator(damping=0.0, gravity=(0, 0, 0))]
O.dt = 1e-8
O.step()
export(OUT + "/export.json")
with open(OUT + "/cluster.dump", "w") as f:
    f.write("ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n%d\nITEM: BOX BOUNDS ff ff ff\n" % len(O.bodies))
    f.write("-0.01 0.02\n-0.01 0.02\n-0.01 0.02\nITEM: ATOMS id type x y z radius mass\n")
    for b in O.bodies:
        p = b.state.pos
        f.write("%d 1 %r %r %r %r %r\n" % (b.id + 1, p[0], p[1], p[2], b.shape.radius, b.state.mass))
with open(OUT + "/contacts.txt", "w") as f:
    f.write("# YADE %s, iteration %d\n# one line per real interaction\n\n# kn ks fn id2 id1\n" % (version, O.iter))
    for i in O.interactions:
        if i.isReal:
            fn = i.phys.normalForce.dot(i.geom.normal)
            f.write("%r %r %r %d %d\n" % (i.phys.kn, i.phys.ks, fn, i.id2 + 1, i.id1 + 1))
            f.write("# a comment between rows\n\n")
O.bodies[4].state.blockedDOFs = "xZ"
export(OUT + "/blocked.json")
O.bodies[4].state.blockedDOFs = ""
O.engines = O.engines[:3] + [GlobalStiffnessTimeStepper(), O.engines[3]]
O.engines[-1].densityScaling = True
export(OUT + "/scaled.json")
print("DTCRIT-DONE")
'''


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    yade = require_engine("yade")
    out = tmp_path_factory.mktemp("yade_table")
    script = out / "write.py"
    script.write_text(f"EXPORTER_DIR = {str(ENGINE_SCRIPTS)!r}\nOUT = {str(out)!r}\n" + SCRIPT)
    done = subprocess.run([yade, "-n", "-x", str(script)], capture_output=True, text=True, timeout=300, cwd=out)
    assert "DTCRIT-DONE" in done.stdout, done.stdout[-2000:] + done.stderr[-2000:]
    return out


def test_dump_and_table_give_the_exports_step(run):
    export = audit_snapshot(run / "export.json")
    table = audit_snapshot(run / "cluster.dump", engine="yade", contact_table=run / "contacts.txt")
    assert table.n_contacts == export.n_contacts > 10
    assert table.dt_crit == pytest.approx(export.dt_crit, rel=1e-9)


def test_a_real_export_has_exactly_the_decided_fields(run):
    doc = json.loads((run / "export.json").read_text())
    assert set(doc) == set(yt.TOP)
    assert {k for b in doc["bodies"] for k in b} == set(yt.BODY)
    assert {k for it in doc["interactions"] for k in it} == set(yt.INTERACTION)
    assert doc["laws"] == [{"class": "Law2_ScGeom_FrictPhys_CundallStrack", "sphericalBodies": True}]


def test_a_partly_blocked_body_and_density_scaling_are_refused(run):
    with pytest.raises(InputError) as info:
        audit_snapshot(run / "blocked.json")
    assert "blocked_dofs" in str(info.value) and "'xZ'" in str(info.value)
    with pytest.raises(InputError) as info:
        audit_snapshot(run / "scaled.json")
    assert "density_scaling" in str(info.value)
