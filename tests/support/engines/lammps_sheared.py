"""LAMMPS packings in a sheared (triclinic) periodic box, and LAMMPS's stability threshold on them.

Like the rest of the harness this never imports dtcrit.

* ``shear`` -- a packing LAMMPS compressed in a cube (``lammps_packing.compress``) made triclinic
  (``change_box all triclinic``) and sheared by ``fix deform`` to the tilt factors ``xy xz yz`` (a
  fraction of the edge, within LAMMPS's default limit of half an edge) under ``fix viscous`` with
  frictionless contacts (``remap x``: the spheres follow the box), then relaxed at the final shape and
  written by ``write_dump`` (``ITEM: BOX BOUNDS xy xz yz``, 17 digits).
* ``grows`` -- the dumped packing read back into LAMMPS: the bounds converted to ``xlo xhi ...`` and
  the tilt factors as LAMMPS's Howto triclinic gives (``xlo = xlo_bound - min(0, xy, xz, xy + xz)``,
  ``xhi = xhi_bound - max(0, xy, xz, xy + xz)``, ``ylo = ylo_bound - min(0, yz)``,
  ``yhi = yhi_bound - max(0, yz)``), a small random kick of velocities and spins, ``nve/sphere`` only;
  growing when the kinetic energy exceeds ``GROWTH_LIMIT`` times its initial value (as
  ``lammps_packing.kinetic_growth``).
"""
from __future__ import annotations

import math
import tempfile
from pathlib import Path

import numpy as np

from .lammps_packing import GROWTH_LIMIT, PackingSpec, _g, _header, _run, compress


def _read_dump(text: str):
    """Positions, radii, masses, ``(lo, hi, tilts)`` of a dump with a triclinic box."""
    lines = text.splitlines()
    n = int(lines[3])
    assert lines[4].split()[3:6] == ["xy", "xz", "yz"], lines[4]
    b = np.array([[float(v) for v in lines[5 + a].split()] for a in range(3)])
    xy, xz, yz = b[:, 2]
    lo = b[:, 0] - [min(0.0, xy, xz, xy + xz), min(0.0, yz), 0.0]
    hi = b[:, 1] - [max(0.0, xy, xz, xy + xz), max(0.0, yz), 0.0]
    cols = lines[8].split()[2:]
    rows = np.array([[float(v) for v in ln.split()] for ln in lines[9:9 + n]])
    get = {c: rows[:, k] for k, c in enumerate(cols)}
    order = np.argsort(get["id"])
    x = np.stack([get["x"], get["y"], get["z"]], 1)[order]
    return x, get["radius"][order], get["mass"][order], (lo, hi, (xy, xz, yz))


def _data_file(x, radii, masses, box, velocities=None) -> str:
    lo, hi, tilts = box
    lines = ["LAMMPS data file (engine_harness.lammps_sheared)", "", f"{len(x)} atoms", "1 atom types", ""]
    lines += [f"{_g(lo[a])} {_g(hi[a])} {ax}lo {ax}hi" for a, ax in enumerate("xyz")]
    lines += [" ".join(_g(t) for t in tilts) + " xy xz yz", "", "Atoms # sphere", ""]
    for k, (p, r, m) in enumerate(zip(x, radii, masses), start=1):
        lines.append(f"{k} 1 {_g(2 * r)} {_g(m / ((4.0 / 3.0) * math.pi * r**3))} {_g(p[0])} {_g(p[1])} {_g(p[2])}")
    if velocities is not None:
        lines += ["", "Velocities", ""]
        lines += [f"{k} " + " ".join(_g(c) for c in row) for k, row in enumerate(velocities, start=1)]
    return "\n".join(lines) + "\n"


def shear(spec: PackingSpec, tilts: tuple[float, float, float], workdir: Path) -> str:
    """Text of LAMMPS's dump of the packing sheared to tilt factors ``tilts`` (fractions of the edge)."""
    cube = compress(spec, workdir / "cube")
    lines = cube.splitlines()
    n = int(lines[3])
    lo_hi = np.array([[float(v) for v in lines[5 + a].split()[:2]] for a in range(3)])
    cols = lines[8].split()[2:]
    rows = np.array([[float(v) for v in ln.split()] for ln in lines[9:9 + n]])
    get = {c: rows[:, k] for k, c in enumerate(cols)}
    x = np.stack([get["x"], get["y"], get["z"]], 1)
    length = float(lo_hi[0, 1] - lo_hi[0, 0])
    data = _data_file(x, get["radius"], get["mass"], (lo_hi[:, 0], lo_hi[:, 1], (0.0, 0.0, 0.0)))
    m_min = float(get["mass"].min())
    dt = 0.05 * math.sqrt(m_min / spec.stiffness)
    xy, xz, yz = (t * length for t in tilts)
    script = _header(spec.pair_style) + [
        "change_box all triclinic", "fix integ all nve/sphere", f"fix visc all viscous {_g(0.5 * m_min / dt / 50.0)}",
        f"timestep {_g(dt)}", f"fix shear all deform 1 xy final {_g(xy)} xz final {_g(xz)} yz final {_g(yz)} remap x",
        "run 20000", "unfix shear", "run 40000",
        "write_dump all custom sheared.dump id type x y z radius mass modify format float %.17g",
    ]
    workdir.mkdir(parents=True, exist_ok=True)
    _run("\n".join(script) + "\n", {"case.data": data}, workdir)
    return (workdir / "sheared.dump").read_text()


def kinetic_growth(dump_text: str, pair_style: str, dt: float, steps: int, *, eps: float = 1e-6,
                   seed: int = 3) -> float:
    """Largest kinetic energy of a run of ``steps`` at ``dt`` over its initial one (module docstring)."""
    x, radii, masses, box = _read_dump(dump_text)
    v_scale = eps * radii.min() / dt
    rng = np.random.default_rng(seed)
    vel = np.concatenate([rng.standard_normal((len(x), 3)) * v_scale,
                          rng.standard_normal((len(x), 3)) * v_scale / radii[:, None]], axis=1)
    script = _header(pair_style) + [
        "fix integ all nve/sphere", f"timestep {_g(dt)}",
        "compute ket all ke", "compute ker all erotate/sphere", "variable etot equal c_ket+c_ker",
        "fix stop all halt 10 v_etot > 1e30 error soft message no",
        "thermo_style custom step v_etot", "thermo_modify format float %.17g norm no lost ignore",
        f"thermo {max(1, steps // 400)}", f"run {int(steps)}",
    ]
    with tempfile.TemporaryDirectory() as tmp:
        log = _run("\n".join(script) + "\n", {"case.data": _data_file(x, radii, masses, box, vel)}, Path(tmp))
    energies, reading = [], False
    for ln in log.splitlines():
        parts = ln.split()
        if parts[:2] == ["Step", "v_etot"]:
            reading = True
        elif reading and len(parts) == 2 and parts[0].isdigit():
            energies.append(float(parts[1]))
        elif reading and parts and parts[0] == "Loop":
            break
    e = np.array(energies)
    if e.size < 8 or not np.all(np.isfinite(e)) or e.max() > 1e29:
        return math.inf
    return float(e.max() / e[0]) if e[0] > 0 else math.inf


def grows(dump_text: str, pair_style: str, dt: float, steps: int = 3000) -> bool:
    """Whether the kinetic energy grows past ``GROWTH_LIMIT`` times its start in ``steps`` steps at ``dt``."""
    return kinetic_growth(dump_text, pair_style, dt, steps) > GROWTH_LIMIT


def bisect_threshold(dump_text: str, pair_style: str, lo: float, hi: float, rel_tol: float = 1e-4,
                     steps: int = 3000) -> tuple[float, float]:
    """Bracket ``(lo, hi)`` of LAMMPS's threshold: ``lo`` bounded, ``hi`` growing (both checked)."""
    if grows(dump_text, pair_style, lo, steps) or not grows(dump_text, pair_style, hi, steps):
        raise RuntimeError(f"threshold not bracketed by [{lo:.6g}, {hi:.6g}]")
    while hi - lo > rel_tol * hi:
        mid = 0.5 * (lo + hi)
        if grows(dump_text, pair_style, mid, steps):
            hi = mid
        else:
            lo = mid
    return lo, hi
