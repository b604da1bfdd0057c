"""Walls in ``dtcrit audit`` without an engine: LAMMPS ``fix wall/gran`` lines (``--wall``) and YADE
Wall bodies in an export.  Expected steps are worked out here by hand from the fix's source
(``src/GRANULAR/fix_wall_gran.cpp``: meff = m, arm R, ``polyhertz = sqrt(delta R_eff)``), or from a
direct eigen-solve of the sphere's 6 x 6 problem; refusals are one line naming ``--wall``, exit 2.
The real-engine thresholds are in ``tests/engines/test_engine_walls.py``.
"""
from __future__ import annotations

import json
import math

import jsonschema
import numpy as np
import pytest

from dtcrit.cli import main
from dtcrit.errors import InputError
from dtcrit.packing.audit.run import audit_snapshot
from dtcrit.packing.conventions.lammps_walls import parse_wall
from support.paths import REPO_ROOT as ROOT

R, RHO = 1e-3, 2500.0
MASS = 4.0 / 3.0 * math.pi * R**3 * RHO
INERTIA = 0.4 * MASS * R**2


def _dump(path, rows, flags="pp pp ff", lo=-0.01, hi=0.01):
    lines = ["ITEM: TIMESTEP", "0", "ITEM: NUMBER OF ATOMS", str(len(rows)), f"ITEM: BOX BOUNDS {flags}"]
    lines += [f"{lo!r} {hi!r}"] * 3 + ["ITEM: ATOMS id type x y z radius mass"]
    lines += [" ".join(repr(v) if isinstance(v, float) else str(v) for v in row) for row in rows]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_hooke_history_wall_is_the_sphere_on_an_immovable_plane(tmp_path):
    """One sphere on zplane: normal omega^2 = kn/m, slip-rolling omega^2 = kt (1/m + R^2/I) (meff = m, arm R)."""
    kn, kt = 1e5, 9e4
    dump = _dump(tmp_path / "one.dump", [(5, 1, 0.0, 0.0, R - 1e-6, R, MASS)])
    line = f"fix 2 all wall/gran hooke/history {kn!r} {kt!r} 0 NULL 0.5 0 zplane 0.0 NULL"
    a = audit_snapshot(dump, pair_style="gran/hooke/history 1e5 NULL 0 NULL 0.5 0", walls=[line], dt=1e-6)
    omega2 = max(kn / MASS, kt * (1.0 / MASS + R**2 / INERTIA))
    assert a.dt_crit == pytest.approx(2.0 / math.sqrt(omega2), rel=1e-12)
    assert (a.n_particles, a.n_contacts, a.limiting) == (1, 1, (5,))
    assert a.participation == 1.0 and a.governing_mode.participation_ratio == 1.0  # one particle: the walls hold nothing
    assert a.governing_mode.particle_share.shape == (1,)
    rows = {e.estimate.name: e for e in a.estimators}
    assert rows["collision_time_fraction"].estimate.dt == pytest.approx(math.pi * math.sqrt(MASS / kn) / 50, rel=1e-12)
    assert rows["collision_time_fraction"].estimate.detail.endswith("contact of particle 5 and a wall")
    assert any("wall 1" in note for note in a.notes)


def test_nearer_plane_only_and_hertz_reff_is_the_radius(tmp_path):
    """A ``zplane lo hi`` wall: a sphere near hi touches hi only; Hertz k_n = 3/2 Kn sqrt(R delta) (R_eff = R on a plane)."""
    kn_h, delta = 2e9, 4e-6
    dump = _dump(tmp_path / "top.dump", [(1, 1, 0.0, 0.0, 0.004 - R + delta, R, MASS)])
    line = f"wall/gran hertz/history {kn_h!r} 0 0 NULL 0.5 0 zplane -0.004 0.004"
    a = audit_snapshot(dump, pair_style="gran/hertz/history 2e9 NULL 0 NULL 0.5 0", walls=[line])
    assert a.dt_crit == pytest.approx(2.0 / math.sqrt(1.5 * kn_h * math.sqrt(R * delta) / MASS), rel=1e-9)


def test_zcylinder_matches_a_direct_eigen_solve(tmp_path):
    """A ``zcylinder``: R_eff = R rwall/(rwall + R), LAMMPS's rwall = -2 r_c inside.

    The inward normal turns with the lever rho and stiffens the sphere's translation by F/rho.
    """
    rc, delta, kn_h, kt_h = 0.005, 3e-6, 2e9, 2e9
    rho = rc - R + delta
    dump = _dump(tmp_path / "cyl.dump", [(1, 1, rho, 0.0, 0.0, R, MASS)], flags="ff ff pp")
    line = f"fix w all wall/gran hertz/history {kn_h!r} {kt_h!r} 0 NULL 0.5 0 zcylinder {rc!r}"
    a = audit_snapshot(dump, pair_style="gran/hertz/history 2e9 NULL 0 NULL 0.5 0", walls=[line])
    rwall = -2.0 * rc
    r_eff = R * rwall / (rwall + R)
    s = math.sqrt(delta * r_eff)
    k_n, k_t, force = 1.5 * kn_h * s, kt_h * s, kn_h * delta * s
    # dofs (x, y, z, wx, wy, wz); contact normal +x (towards the wall), arm R +x
    b_slip = np.array([[0, 1, 0, 0, 0, R], [0, 0, 1, 0, -R, 0]], float)  # slip of the contact point (y, z)
    K = k_n * np.outer([1, 0, 0, 0, 0, 0], [1, 0, 0, 0, 0, 0]) + k_t * b_slip.T @ b_slip
    K[1, 1] += force / rho  # the tangential turn of the normal (stiffening)
    K[2, 2] += force / rho  # the model's lever term also acts along z (stiffening: the safe side)
    m = np.array([MASS] * 3 + [INERTIA] * 3)
    omega2 = np.linalg.eigvalsh(K / np.sqrt(np.outer(m, m))).max()
    assert a.dt_crit == pytest.approx(2.0 / math.sqrt(omega2), rel=1e-9)


def test_granular_hertz_material_uses_the_wall_constants(tmp_path):
    """The wall granular hertz/material stores 4/3 E/(2 (1 - nu)) (not pair granular's 1 - nu^2)."""
    e, nu, delta = 1e8, 0.3, 2e-6
    dump = _dump(tmp_path / "g.dump", [(1, 1, 0.0, 0.0, R - delta, R, MASS)])
    line = (f"fix w all wall/gran granular hertz/material {e!r} 0 {nu!r} tangential linear_history 0 0 0 "
            "zplane 0 NULL")
    a = audit_snapshot(dump, pair_style="gran/hooke/history 1e5 NULL 0 NULL 0.5 0", walls=[line])
    coefficient = 4.0 / 3.0 * e / (2.0 * (1.0 - nu))  # fix_wall_gran.cpp literal
    assert a.dt_crit == pytest.approx(2.0 / math.sqrt(1.5 * coefficient * math.sqrt(R * delta) / MASS), rel=1e-9)


@pytest.mark.parametrize("line, word", [
    ("fix 1 all wall/gran hooke 1e5 NULL 0 NULL 0.5 0 zplane 0 NULL wiggle z 1e-3 1", "wiggle"),
    ("fix 1 all wall/gran hooke 1e5 NULL 0 NULL 0.5 0 zplane 0 NULL shear x 1", "shear"),
    ("fix 1 all wall/gran hooke 1e5 NULL 0 NULL 0.5 0 zplane 0 NULL temperature 300", "temperature"),
    ("fix 1 all wall/gran hooke 1e5 NULL 0 NULL 0.5 0 region box", "region"),
    ("fix 1 all wall/gran/region hooke 1e5 NULL 0 NULL 0.5 0 box", "wall/gran/region"),
    ("fix 1 all wall/gran granular dmt 1e8 0 0.3 1 tangential linear_history 0 0 0 zplane 0 NULL", "dmt"),
    ("fix 1 all wall/gran hertz 1e5 NULL 0 NULL 0.5 0 zplane 0 NULL", "hertz"),
    ("fix 1 all wall/gran hooke 1e5 NULL 0 NULL 0.5 0 yplane NULL NULL", "NULL"),
])
def test_refused_in_one_line_naming_it(tmp_path, capsys, line, word):
    """A keyword or wall that is not modelled: one line naming --wall and the word, exit 2."""
    with pytest.raises(InputError) as exc:
        parse_wall(line)
    assert exc.value.key == "--wall" and word in exc.value.reason
    dump = _dump(tmp_path / "one.dump", [(1, 1, 0.0, 0.0, R - 1e-6, R, MASS)])
    rc = main(["audit", str(dump), "--pair-style", "gran/hooke 1e5 NULL 0 NULL 0.5 0", "--wall", line])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and "--wall" in err and word in err


def test_wall_in_a_periodic_dimension_is_refused(tmp_path):
    """LAMMPS refuses a plane across a periodic axis; so does the audit."""
    dump = _dump(tmp_path / "p.dump", [(1, 1, 0.0, 0.0, 0.0, R, MASS)], flags="pp pp pp")
    with pytest.raises(InputError, match="periodic"):
        audit_snapshot(dump, pair_style="gran/hooke 1e5 NULL 0 NULL 0.5 0",
                       walls=["wall/gran hooke 1e5 NULL 0 NULL 0.5 0 zplane 0 NULL"])


def test_contacts_keyword_and_two_walls_json(tmp_path, capsys):
    """``contacts`` only stores output; two walls (repeatable --wall) each add their contacts."""
    dump = _dump(tmp_path / "two.dump", [(1, 1, 0.0, 0.0, -0.004 + R - 1e-6, R, MASS),
                                         (2, 1, 0.0, -0.004 + R - 2e-6, 0.003, R, MASS)], flags="ff ff ff")
    rc = main(["audit", str(dump), "--pair-style", "gran/hooke/history 1e5 NULL 0 NULL 0.5 0", "--json",
               "--wall", "fix 1 all wall/gran hooke/history 1e5 NULL 0 NULL 0.5 0 zplane -0.004 NULL contacts",
               "--wall", "fix 2 all wall/gran hooke/history 2e5 NULL 0 NULL 0.5 0 yplane -0.004 NULL"])
    out = capsys.readouterr().out
    assert rc == 0
    doc = json.loads(out)
    jsonschema.validate(doc, json.loads((ROOT / "src" / "dtcrit" / "schemas" / "dtcrit-audit-1.json").read_text()))
    body = doc.get("audit", doc)
    assert body["n_particles"] == 2 and body["n_contacts"] == 2
    assert body["dt_crit"] == pytest.approx(2.0 / math.sqrt(2e5 / MASS), rel=1e-12)  # the stiffer wall's normal mode


def _yade_export(path, *, dynamic_wall=False, gap=1e-6):
    doc = {"schema": "dtcrit-yade-export/1", "dt": 1e-7, "iter": 1, "periodic": False, "cell_hsize": None,
           "wall_no_ratch": False,
           "bodies": [{"id": 0, "shape": "Wall", "axis": 2, "sense": 0, "pos": [0, 0, 0], "radius": None,
                       "mass": 0.0, "inertia": [0, 0, 0], "clump_id": None, "is_clump": False,
                       "fixed": not dynamic_wall},
                      {"id": 1, "shape": "Sphere", "pos": [0, 0, R - gap], "radius": R, "mass": MASS,
                       "inertia": [INERTIA, INERTIA, INERTIA], "clump_id": None, "is_clump": False, "fixed": False}],
           "interactions": [{"id1": 0, "id2": 1, "kn": 1e5, "ks": 5e4, "normal": [0, 0, 1],
                             "point": [0, 0, 0], "penetration": gap, "radius1": R, "radius2": R,
                             "shift2": [0, 0, 0]}]}
    path.write_text(json.dumps(doc))
    return path


def test_yade_wall_without_ratcheting_uses_the_contact_point(tmp_path):
    """Without noRatch: force and slip at the contact point on the plane, arm R - delta: omega^2 = ks (1/m + (R - delta)^2/I)."""
    a = audit_snapshot(_yade_export(tmp_path / "w.json"))
    omega2 = max(1e5 / MASS, 5e4 * (1.0 / MASS + (R - 1e-6) ** 2 / INERTIA))
    assert a.dt_crit == pytest.approx(2.0 / math.sqrt(omega2), rel=1e-12)
    assert a.n_particles == 1


def test_yade_moving_wall_is_refused(tmp_path):
    """A Wall YADE integrates as a free body is not modelled."""
    with pytest.raises(InputError, match="moving wall"):
        audit_snapshot(_yade_export(tmp_path / "m.json", dynamic_wall=True))


def test_yade_wall_interaction_opening_is_kept_at_zero_overlap(tmp_path):
    """A real interaction YADE has not erased yet (penetration < 0) keeps its springs, arm R, as sphere pairs do."""
    a = audit_snapshot(_yade_export(tmp_path / "o.json", gap=-1e-9))
    omega2 = max(1e5 / MASS, 5e4 * (1.0 / MASS + R**2 / INERTIA))
    assert a.dt_crit == pytest.approx(2.0 / math.sqrt(omega2), rel=1e-12)
