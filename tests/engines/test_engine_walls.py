"""Walls in ``dtcrit audit`` against the engines' own thresholds.

* LAMMPS: spheres resting on a ``fix wall/gran hertz/history ... zplane 0 NULL`` wall under a
  constant load (``support.engines.lammps_walls``); the threshold is bisected in the real `lmp` to
  1e-4 and ``dtcrit audit --wall`` (the same fix line, a dump of the same spheres) must give a
  ``dt_crit`` inside ``[0.999 x stable end, unstable end]``.  The bracket starts around the step
  of the governing mode worked out here by hand from the fix's source (meff = m, arm R,
  ``k_n = 3/2 Kn sqrt(R delta)``, ``k_t = Kt sqrt(R delta)``, normal ``A = 1/m``, tangential
  ``A = 1/m + R^2/I = 7/(2m)``).
* LAMMPS: a bed of 24 spheres poured by LAMMPS under gravity onto a Hertz floor (pre-loaded pair
  contacts and wall contacts together), the threshold bisected from LAMMPS's own dump.
* YADE: spheres on a ``utils.wall`` or ``utils.facet`` (``support.engines.yade_walls``), exported by
  ``engine_scripts/yade_export.py``, the threshold bisected inside YADE to 1e-4, the export audited
  (``dt_crit`` inside ``[0.999 x stable end, unstable end]``).
"""
from __future__ import annotations

import math

import pytest

from support.engines import require_engine

from dtcrit.packing.audit.run import audit_snapshot

RHO = 2500.0


def _overlap(load: float, kn: float, radius: float) -> float:
    """Static overlap of ``load = Kn delta sqrt(R delta)`` (LAMMPS hertz/history on a plane)."""
    return (load / (kn * math.sqrt(radius))) ** (2.0 / 3.0)


def _hand_step(load: float, kn: float, kt: float, radius: float) -> float:
    m = 4.0 / 3.0 * math.pi * radius**3 * RHO
    a = math.sqrt(radius * _overlap(load, kn, radius))
    omega2 = max(1.5 * kn * a / m, 3.5 * kt * a / m)
    return 2.0 / math.sqrt(omega2)


LAMMPS_CASES = {
    # one sphere, Kt NULL (2/7 Kn): the normal mode governs
    "one sphere, normal": ((0.01,), 1.0, 1e9, None),
    # three sizes, Kt > Kn: the tangential (slip-rolling) mode of the smallest governs
    "three spheres, tangential": ((0.01, 0.008, 0.012), 2.0, 1e9, 2e9),
}


@pytest.mark.parametrize("name", list(LAMMPS_CASES))
def test_lammps_hertz_wall_threshold(name, tmp_path):
    """The audit with --wall lands inside LAMMPS's bisected threshold bracket on a Hertz wall."""
    require_engine("lammps")
    from support.engines.lammps_walls import WallSpheres, bisect_threshold, dump_text

    radii, load, kn, kt = LAMMPS_CASES[name]
    words = f"{kn!r} {'NULL' if kt is None else repr(kt)} 0 NULL 0.5 0"
    positions = tuple((0.05 * k, 0.0, r - _overlap(load, kn, r)) for k, r in enumerate(radii))
    case = WallSpheres(positions, radii, RHO, load, f"gran/hertz/history {words}",
                       f"fix w all wall/gran hertz/history {words} zplane 0 NULL")
    hand = min(_hand_step(load, kn, 2.0 / 7.0 * kn if kt is None else kt, r) for r in radii)
    lo, hi = bisect_threshold(case, 0.97 * hand, 1.03 * hand, rel_tol=1e-4)
    dump = tmp_path / "wall.dump"
    dump.write_text(dump_text(case))
    audit = audit_snapshot(dump, pair_style=case.pair_style, walls=[case.fix_line])
    print(f"{name}: LAMMPS bracket [{lo:.7g}, {hi:.7g}], dtcrit {audit.dt_crit:.7g}, "
          f"ratio to the stable end {audit.dt_crit / lo:.6f}")
    assert 0.999 * lo <= audit.dt_crit <= hi
    assert audit.dt_safe <= audit.dt_crit
    assert audit.n_particles == len(radii) and audit.n_contacts == len(radii)
    rows = {e.estimate.name: e for e in audit.estimators}
    assert rows["collision_time_fraction"].safe  # meff = m, not a dummy sphere's m/2
    assert rows["gershgorin"].estimate.dt <= audit.dt_crit * (1 + 1e-12)


def test_lammps_granular_hertz_material_wall(tmp_path):
    """The wall's own granular constants hold in lmp (hertz/material with mindlin NULL).

    4/3 E/(2 (1 - nu)) normal and E/4 (2 - nu)(1 + nu) a tangential, read in fix_wall_gran.cpp.
    """
    require_engine("lammps")
    from support.engines.lammps_walls import WallSpheres, bisect_threshold, dump_text

    r, load, e, nu = 0.01, 1.0, 1e8, 0.3
    coeff = 4.0 / 3.0 * e / (2.0 * (1.0 - nu))
    delta = (load / (coeff * math.sqrt(r))) ** (2.0 / 3.0)
    a = math.sqrt(r * delta)
    m = 4.0 / 3.0 * math.pi * r**3 * RHO
    kt = e / 4.0 * (2.0 - nu) * (1.0 + nu) * a
    hand = 2.0 / math.sqrt(max(1.5 * coeff * a / m, 3.5 * kt / m))
    words = f"hertz/material {e!r} 0 {nu!r} tangential mindlin NULL 0 0.5"
    case = WallSpheres(((0.0, 0.0, r - delta),), (r,), RHO, load, f"granular {words}",
                       f"fix w all wall/gran granular {words} zplane 0 NULL")
    lo, hi = bisect_threshold(case, 0.97 * hand, 1.03 * hand, rel_tol=1e-4)
    dump = tmp_path / "g.dump"
    dump.write_text(dump_text(case))
    audit = audit_snapshot(dump, pair_style=case.pair_style, walls=[case.fix_line])
    print(f"granular: LAMMPS bracket [{lo:.7g}, {hi:.7g}], dtcrit {audit.dt_crit:.7g}, ratio {audit.dt_crit / lo:.6f}")
    assert 0.999 * lo <= audit.dt_crit <= hi


def test_lammps_hertz_zcylinder_threshold(tmp_path):
    """A sphere pressed outwards onto a LAMMPS zcylinder from inside: R_eff with rwall = -2 r_c, the lever term."""
    require_engine("lammps")
    from support.engines.lammps_walls import WallSpheres, bisect_threshold, dump_text

    r, rc, load, kn = 0.01, 0.05, 1.0, 1e9
    r_eff = r * (-2 * rc) / (r - 2 * rc)  # fix_wall_gran.cpp: rwall = -2 r_c inside the cylinder
    delta = (load / (kn * math.sqrt(r_eff))) ** (2.0 / 3.0)
    words = f"{kn!r} {kn!r} 0 NULL 0.5 0"
    case = WallSpheres(((rc - r + delta, 0.0, 0.0),), (r,), RHO, load, f"gran/hertz/history {words}",
                       f"fix w all wall/gran hertz/history {words} zcylinder {rc!r}", (1.0, 0.0, 0.0), "f f p")
    m = 4.0 / 3.0 * math.pi * r**3 * RHO
    hand = 2.0 / math.sqrt(3.5 * kn * math.sqrt(r_eff * delta) / m)
    lo, hi = bisect_threshold(case, 0.97 * hand, 1.03 * hand, rel_tol=1e-4)
    dump = tmp_path / "cyl.dump"
    dump.write_text(dump_text(case).replace("ITEM: BOX BOUNDS ff ff ff", "ITEM: BOX BOUNDS ff ff pp"))
    audit = audit_snapshot(dump, pair_style=case.pair_style, walls=[case.fix_line])
    print(f"zcylinder: LAMMPS bracket [{lo:.7g}, {hi:.7g}], dtcrit {audit.dt_crit:.7g}, ratio {audit.dt_crit / lo:.6f}")
    assert 0.999 * lo <= audit.dt_crit <= hi


def test_lammps_bed_on_a_hertz_floor(tmp_path):
    """A bed settled by LAMMPS on a Hertz floor: the audit of LAMMPS's dump lands inside its bracket.

    24 spheres under gravity on a hertz/history floor: pre-loaded pair contacts and wall contacts together.
    """
    require_engine("lammps")
    from support.engines.lammps_walls import Bed, bisect_threshold, grows_bed, settle

    bed = Bed()
    dump = settle(bed, tmp_path)
    (tmp_path / "bed.dump").write_text(dump)
    audit = audit_snapshot(tmp_path / "bed.dump", pair_style=bed.pair_style(0.5), walls=[bed.fix_line(0.5)])
    walls = next(note for note in audit.notes if note.startswith("wall 1"))
    on_floor = int(walls.split("): ", 1)[1].split()[0])
    assert audit.n_particles == bed.n and 0 < on_floor < audit.n_contacts  # floor and pair contacts both
    # the bracket starts around dtcrit's figure; bisection checks both ends in LAMMPS
    lo, hi = bisect_threshold(lambda dt: grows_bed(bed, dump, dt, 6000), 0.95 * audit.dt_crit, 1.05 * audit.dt_crit)
    print(f"bed: LAMMPS bracket [{lo:.7g}, {hi:.7g}], dtcrit {audit.dt_crit:.7g}, ratio {audit.dt_crit / lo:.6f}")
    assert 0.999 * lo <= audit.dt_crit <= hi
    assert audit.dt_safe <= audit.dt_crit


YADE_CASES = {
    # wall: kn = E R (refR1 = R), force at the plane, slip velocity with YADE's ratcheting correction
    "one sphere on utils.wall": ("wall", ((0.0, 0.0, 0.01),), 1.0),
    "three spheres on utils.wall": ("wall", ((0.0, 0.0, 0.01), (0.05, 0.0, 0.008), (0.1, 0.0, 0.012)), 1.0),
    # facet: kn = 4/3 E R (refR1 = 2 R), force and slip at R - delta/2
    "one sphere on utils.facet": ("facet", ((0.3, 0.3, 0.01),), 4.0 / 3.0),
}


@pytest.mark.parametrize("name", list(YADE_CASES))
def test_yade_wall_threshold(name, tmp_path):
    """The audit of a YADE export with a Wall or Facet lands inside YADE's bisected threshold bracket."""
    require_engine("yade")
    from support.engines.yade_walls import bisect

    wall, spheres, factor = YADE_CASES[name]
    young, ratio = 1e8, 0.5
    # hand estimate: the tangential mode A = 1/m + R^2/I = 7/(2m) with ks = 0.5 kn governs (leapfrog 2/omega)
    hand = min(2.0 / math.sqrt(3.5 * ratio * factor * young * r / (4.0 / 3.0 * math.pi * r**3 * RHO))
               for _, _, r in spheres)
    export = tmp_path / "walls.json"
    spec = {"wall": wall, "spheres": spheres, "young": young, "ks_ratio": ratio, "density": RHO, "load": 1.0,
            "overlap_guess": 1e-3, "eps": 1e-9, "steps": 6000, "growth": 1e4, "lo": 0.96 * hand, "hi": 1.04 * hand,
            "rel_tol": 1e-4}
    out = bisect(spec, export)
    audit = audit_snapshot(export)
    lo, hi = out["lo"], out["hi"]
    print(f"{name}: YADE bracket [{lo:.7g}, {hi:.7g}], dtcrit {audit.dt_crit:.7g}, "
          f"ratio to the stable end {audit.dt_crit / lo:.6f}")
    assert 0.999 * lo <= audit.dt_crit <= hi
    assert audit.dt_safe <= audit.dt_crit
    assert audit.n_particles == len(spheres) and audit.n_contacts == len(spheres)
    rows = {e.estimate.name: e.estimate.dt for e in audit.estimators}
    assert rows["yade_gsts"] == pytest.approx(out["gsts"], rel=1e-9)  # the stepper's step as YADE sets it
