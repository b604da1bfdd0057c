"""Spheres resting on a LAMMPS ``fix wall/gran`` wall (any style), run in the real `lmp`.

Each sphere is pushed onto a ``zplane`` wall by a constant force ``-P e_z`` (``fix addforce``) and
starts at its static overlap (given by the caller: for ``hertz/history`` ``P = Kn delta sqrt(R delta)``),
with tiny random velocities and spins that excite every mode.  The spheres are far apart, so the
pair style never acts.  A run grows when the largest |net force| + |torque|/R of any atom (zero at
equilibrium) exceeds ``GROWTH_LIMIT`` times its size over the first steps; a ``fix halt`` stops a
clearly growing run early.  Nothing here imports dtcrit: the thresholds are the engine's own.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from support.engines.lammps import run_lmp

GROWTH_LIMIT = 1.0e4


@dataclass(frozen=True)
class WallSpheres:
    """Spheres at ``positions`` (radii, densities) on the wall of ``fix_line``, each loaded by ``load``."""

    positions: tuple[tuple[float, float, float], ...]
    radii: tuple[float, ...]
    density: float
    load: float
    pair_style: str
    fix_line: str  # 'fix w all wall/gran ... zplane 0 NULL'


def _g(x: float) -> str:
    return repr(float(x))


def data_file(case: WallSpheres, eps: float, seed: int) -> str:
    """LAMMPS data (atom style sphere) with small random velocities and spins."""
    rng = np.random.default_rng(seed)
    lines = ["spheres on a wall", "", f"{len(case.radii)} atoms", "1 atom types", "",
             "-1 1 xlo xhi", "-1 1 ylo yhi", "-1 1 zlo zhi", "", "Atoms # sphere", ""]
    for k, (x, r) in enumerate(zip(case.positions, case.radii), start=1):
        lines.append(f"{k} 1 {_g(2 * r)} {_g(case.density)} {_g(x[0])} {_g(x[1])} {_g(x[2])}")
    lines += ["", "Velocities", ""]
    for k, r in enumerate(case.radii, start=1):
        v = eps * rng.standard_normal(3)
        w = eps * rng.standard_normal(3) / r
        lines.append(f"{k} " + " ".join(_g(c) for c in (*v, *w)))
    return "\n".join(lines) + "\n"


def dump_text(case: WallSpheres) -> str:
    """The same spheres as a LAMMPS text dump (with the mass LAMMPS computes, 4/3 pi R^3 rho)."""
    rows = [f"{k} 1 {_g(x[0])} {_g(x[1])} {_g(x[2])} {_g(r)} {_g(4.0 / 3.0 * math.pi * r**3 * case.density)}"
            for k, (x, r) in enumerate(zip(case.positions, case.radii), start=1)]
    return "\n".join(["ITEM: TIMESTEP", "0", "ITEM: NUMBER OF ATOMS", str(len(rows)), "ITEM: BOX BOUNDS ff ff ff",
                      "-1 1", "-1 1", "-1 1", "ITEM: ATOMS id type x y z radius mass", *rows]) + "\n"


def script(case: WallSpheres, dt: float, steps: int, halt: float) -> str:
    """The input script: nve/sphere, the wall, the load, the growth figure every 20 steps."""
    return "\n".join([
        "units si", "atom_style sphere", "boundary f f f", "comm_modify vel yes", "newton off",
        "read_data case.data", f"pair_style {case.pair_style.split(None, 1)[0]} {case.pair_style.split(None, 1)[1]}",
        "pair_coeff * *", "neighbor 1e-4 bin", "neigh_modify delay 0",
        case.fix_line, f"fix load all addforce 0 0 {_g(-case.load)}", "fix move all nve/sphere",
        "compute tq all property/atom tqx tqy tqz radius",
        "variable g atom sqrt(fx*fx+fy*fy+fz*fz)+sqrt(c_tq[1]*c_tq[1]+c_tq[2]*c_tq[2]+c_tq[3]*c_tq[3])/c_tq[4]",
        "compute gm all reduce max v_g", "variable gmax equal c_gm",
        f"fix stop all halt 20 v_gmax > {_g(halt)} error soft",
        f"timestep {_g(dt)}", "thermo_style custom step c_gm", "thermo 20", "thermo_modify norm no",
        f"run {steps}", ""])


def grows(case: WallSpheres, dt: float, steps: int, *, eps: float = 1e-9, seed: int = 7) -> bool:
    """Whether the run at ``dt`` grows (module docstring); it halts at 1 % of the load."""
    values = _series(run_lmp(script(case, dt, steps, 0.01 * case.load), data_file(case, eps, seed)))
    if len(values) < 4:
        return True
    g0 = max(values[1:4])
    return max(values) > GROWTH_LIMIT * g0 or len(values) < steps // 20 + 1


def _series(log: str) -> list[float]:
    out, on = [], False
    for line in log.splitlines():
        words = line.split()
        if words[:2] == ["Step", "c_gm"]:
            on = True
            continue
        if on:
            try:
                out.append(float(words[1]))
            except (IndexError, ValueError):
                on = False
    return out


def bisect_threshold(case: WallSpheres, lo: float, hi: float, rel_tol: float = 1e-4, *, steps: int = 6000) -> tuple[float, float]:
    """The engine's threshold bracket ``(stable, growing)`` of relative width below ``rel_tol``."""
    if grows(case, lo, steps):
        raise ValueError(f"lower end dt={lo!r} grows")
    if not grows(case, hi, steps):
        raise ValueError(f"upper end dt={hi!r} stays bounded")
    while hi / lo - 1.0 > rel_tol:
        mid = math.sqrt(lo * hi)
        if grows(case, mid, steps):
            hi = mid
        else:
            lo = mid
    return lo, hi
