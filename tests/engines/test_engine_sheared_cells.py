"""``dtcrit audit`` on sheared (triclinic) periodic cells of LAMMPS and YADE, against each engine's own
bisected threshold.

* LAMMPS: 60 polydisperse spheres LAMMPS compressed in a cube, made triclinic and sheared by
  ``fix deform`` to ``xy = 0.3 L``, ``xz = -0.2 L``, ``yz = 0.15 L`` (within LAMMPS's default half-edge
  limit), relaxed and dumped with ``ITEM: BOX BOUNDS xy xz yz`` (``support.engines.lammps_sheared``);
  ``dtcrit audit DUMP --pair-style ...`` reads the dump, LAMMPS runs from it (velocity Verlet,
  ``nve/sphere``).
* YADE: an FCC lattice (2 x 2 x 2 cubes, 32 spheres, neighbours overlapping by 1e-6 R) in a cell with
  ``hSize[0, 1] = hSize[2, 1] = a`` (a general, non-triangular hSize; one cube edge is a translation
  of the crystal, so each sphere keeps its 12 contacts, some only through the sheared images)
  (``support.engines.yade_sheared``); ``dtcrit audit EXPORT --engine yade`` reads its export, YADE
  runs the saved scene (leapfrog ``NewtonIntegrator``, damping off).

Each engine's threshold is bisected to a relative bracket of 1e-4 around dtcrit's printed ``dt_crit``,
which must lie in [0.999, 1] of it: not above the growing end, not below 0.999 of the bounded one.
The printed ratios (``-s``) are dt_crit over the bracket's middle.
"""
from __future__ import annotations

import json
import subprocess
import sys

from support.engines import require_engine
from support.engines.lammps_packing import PackingSpec
from support.engines.lammps_sheared import bisect_threshold, shear
from support.engines.yade import SceneCase, bisect_thresholds
from support.engines.yade_sheared import sheared_lattice

HOOKE = "gran/hooke/history 1e4 NULL 0 NULL 0.5 0"
TILTS = (0.3, -0.2, 0.15)
RTOL = 1e-4


def _audit(*args: str) -> dict:
    done = subprocess.run([sys.executable, "-m", "dtcrit", "audit", *args, "--json"], capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def test_lammps_triclinic_packing_within_its_bisected_threshold(tmp_path):
    """The sheared LAMMPS packing (module docstring): dt_crit in [0.999, 1] of LAMMPS's threshold."""
    require_engine("lammps")
    dump = shear(PackingSpec(solid_fraction=0.66, seed=7), TILTS, tmp_path / "sheared")
    assert dump.splitlines()[4].startswith("ITEM: BOX BOUNDS xy xz yz pp pp pp")
    path = tmp_path / "sheared.dump"
    path.write_text(dump)
    doc = _audit(str(path), "--pair-style", HOOKE)
    dt = doc["dt_crit"]
    lo, hi = bisect_threshold(dump, HOOKE, 0.995 * dt, 1.005 * dt, rel_tol=RTOL)
    print(f"LAMMPS triclinic packing: dt_crit / threshold = {dt / (0.5 * (lo + hi)):.6f} (bracket {lo / dt:.6f}, "
          f"{hi / dt:.6f} x dt_crit; {doc['n_contacts']} contacts)")
    assert 0.999 * lo <= dt <= hi


def test_yade_sheared_cell_within_its_bisected_threshold(tmp_path):
    """The sheared YADE FCC (module docstring): all 12 contacts per sphere found, dt_crit in [0.999, 1]
    of YADE's threshold.
    """
    require_engine("yade")
    scene = sheared_lattice(tmp_path / "fcc", [(0, 1, 1), (2, 1, 1)])
    assert scene["contacts"] == 6 * scene["bodies"] and scene["hsize"][2][1] > 0
    doc = _audit(scene["export"], "--engine", "yade")
    dt = doc["dt_crit"]
    assert doc["n_contacts"] == scene["contacts"]
    ((lo, hi),) = bisect_thresholds([SceneCase(scene["state"])], 0.998 * dt, 1.002 * dt, steps=2000, rel_tol=RTOL)
    print(f"YADE sheared FCC: dt_crit / threshold = {dt / (0.5 * (lo + hi)):.6f} (bracket {lo / dt:.6f}, "
          f"{hi / dt:.6f} x dt_crit)")
    assert 0.999 * lo <= dt <= hi
