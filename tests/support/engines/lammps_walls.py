"""Spheres resting on a LAMMPS ``fix wall/gran`` wall (any style), run in the real `lmp`.

``WallSpheres``: each sphere is pushed onto a ``zplane`` wall by a constant force ``-P e_z`` (``fix addforce``) and
starts at its static overlap (given by the caller: for ``hertz/history`` ``P = Kn delta sqrt(R delta)``),
with tiny random velocities and spins that excite every mode.  The spheres are far apart, so the
pair style never acts.  A run grows when the largest |net force| + |torque|/R of any atom (zero at
equilibrium) exceeds ``GROWTH_LIMIT`` times its size over the first steps; a ``fix halt`` stops a
clearly growing run early.

``Bed``: spheres poured frictionless under gravity and ``fix viscous`` onto a Hertz floor in a box
periodic in x and y (``settle``, LAMMPS's own dump at 17 digits), then run from that dump with friction
on, under gravity, kicked (``grows_bed``): pair contacts with their pre-load and wall contacts together.
Nothing here imports dtcrit: the thresholds are the engine's own.
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
    direction: tuple[float, float, float] = (0.0, 0.0, -1.0)  # of the load
    boundary: str = "f f f"


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
        "units si", "atom_style sphere", f"boundary {case.boundary}", "comm_modify vel yes", "newton off",
        "read_data case.data", *_pair_lines(case.pair_style), "neighbor 1e-4 bin", "neigh_modify delay 0",
        case.fix_line, "fix load all addforce " + " ".join(_g(case.load * c) for c in case.direction),
        "fix move all nve/sphere",
        "compute tq all property/atom tqx tqy tqz radius",
        "variable g atom sqrt(fx*fx+fy*fy+fz*fz)+sqrt(c_tq[1]*c_tq[1]+c_tq[2]*c_tq[2]+c_tq[3]*c_tq[3])/c_tq[4]",
        "compute gm all reduce max v_g", "variable gmax equal c_gm",
        f"fix stop all halt 20 v_gmax > {_g(halt)} error soft",
        f"timestep {_g(dt)}", "thermo_style custom step c_gm", "thermo 20", "thermo_modify norm no",
        f"run {steps}", ""])


def _pair_lines(pair_style: str) -> list[str]:
    """``pair_style`` and ``pair_coeff`` lines (``granular WORDS``: the words go to ``pair_coeff * *``)."""
    name, args = pair_style.split(None, 1)
    if name == "granular":
        return ["pair_style granular", f"pair_coeff * * {args}"]
    return [f"pair_style {pair_style}", "pair_coeff * *"]


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


def bisect_threshold(case, lo: float, hi: float, rel_tol: float = 1e-4, *, steps: int = 6000) -> tuple[float, float]:
    """The engine's threshold bracket ``(stable, growing)`` of relative width below ``rel_tol``.

    ``case`` is a :class:`WallSpheres` or a function ``dt -> grows`` (e.g. of a settled :class:`Bed`).
    """
    test = case if callable(case) else (lambda dt: grows(case, dt, steps))
    if test(lo):
        raise ValueError(f"lower end dt={lo!r} grows")
    if not test(hi):
        raise ValueError(f"upper end dt={hi!r} stays bounded")
    while hi / lo - 1.0 > rel_tol:
        mid = math.sqrt(lo * hi)
        if test(mid):
            hi = mid
        else:
            lo = mid
    return lo, hi


@dataclass(frozen=True)
class Bed:
    """``n`` spheres settled under gravity on a ``zplane`` floor of a box periodic in x and y."""

    n: int = 24
    radius: float = 1e-3
    spread: float = 0.2
    density: float = 2500.0
    kn: float = 1e8  # Hertz Kn [Pa]
    gravity: float = 9.81
    seed: int = 3

    @property
    def side(self) -> float:
        """The box's side in x and y [m]."""
        return 8.0 * self.radius

    def pair_style(self, xmu: float) -> str:
        """The pair style (friction ``xmu``)."""
        return f"gran/hertz/history {_g(self.kn)} NULL 0 NULL {_g(xmu)} 0"

    def fix_line(self, xmu: float) -> str:
        """The floor's ``fix wall/gran`` line (friction ``xmu``)."""
        return f"fix floor all wall/gran hertz/history {_g(self.kn)} NULL 0 NULL {_g(xmu)} 0 zplane 0.0 NULL"


def _bed_data(bed: Bed, positions, radii, velocities=None) -> str:
    top = max(p[2] for p in positions) + 4 * bed.radius
    lines = ["a bed on a floor", "", f"{len(radii)} atoms", "1 atom types", "",
             f"0 {_g(bed.side)} xlo xhi", f"0 {_g(bed.side)} ylo yhi", f"-0.001 {_g(top)} zlo zhi", "",
             "Atoms # sphere", ""]
    for k, (x, r) in enumerate(zip(positions, radii), start=1):
        lines.append(f"{k} 1 {_g(2 * r)} {_g(bed.density)} {_g(x[0])} {_g(x[1])} {_g(x[2])}")
    if velocities is not None:
        lines += ["", "Velocities", ""] + [f"{k} " + " ".join(_g(c) for c in v) for k, v in enumerate(velocities, 1)]
    return "\n".join(lines) + "\n"


def settle(bed: Bed, workdir) -> str:
    """Pour the bed frictionless under ``fix viscous`` and return LAMMPS's dump of it (17 digits)."""
    rng = np.random.default_rng(bed.seed)
    radii = bed.radius * (1.0 + bed.spread * (2.0 * rng.random(bed.n) - 1.0))
    grid = 2.0 * bed.radius * (1.0 + bed.spread) * 1.05
    per = int(bed.side // grid) or 1
    positions = [((k % per + 0.5) * bed.side / per + 1e-5 * rng.standard_normal(),
                  ((k // per) % per + 0.5) * bed.side / per + 1e-5 * rng.standard_normal(),
                  (k // (per * per) + 0.6) * grid) for k in range(bed.n)]
    mass = 4.0 / 3.0 * math.pi * bed.radius**3 * bed.density
    script = "\n".join([
        "units si", "atom_style sphere", "boundary p p f", "comm_modify vel yes", "newton off",
        "read_data case.data", f"pair_style {bed.pair_style(0.0)}", "pair_coeff * *",
        "neighbor 2e-4 bin", "neigh_modify delay 0", bed.fix_line(0.0),
        f"fix g all gravity {_g(bed.gravity)} vector 0 0 -1", f"fix damp all viscous {_g(mass / 0.01)}",
        "fix move all nve/sphere", "timestep 1e-5", "run 60000",
        "write_dump all custom bed.dump id type x y z radius mass modify format float %.17g", ""])
    from pathlib import Path

    work = Path(workdir)
    run_lmp(script, _bed_data(bed, positions, radii), keep_dir=work, timeout=600)
    return (work / "bed.dump").read_text()


def bed_case(bed: Bed, dump: str, xmu: float = 0.5) -> tuple[str, str, float]:
    """``(data, fixes, load)`` of a run from the settled bed with friction on (for ``grows_bed``)."""
    rows = [line.split() for line in dump.splitlines()]
    start = next(k for k, r in enumerate(rows) if r[:2] == ["ITEM:", "ATOMS"]) + 1
    atoms = sorted((int(r[0]), [float(v) for v in r[2:5]], float(r[5])) for r in rows[start:] if r)
    positions, radii = [a[1] for a in atoms], [a[2] for a in atoms]
    return _bed_data(bed, positions, radii), "\n".join([
        bed.fix_line(xmu), f"fix g all gravity {_g(bed.gravity)} vector 0 0 -1"]), min(radii)


def grows_bed(bed: Bed, dump: str, dt: float, steps: int, *, eps: float = 1e-9, seed: int = 7, xmu: float = 0.5) -> bool:
    """Whether the settled bed, kicked, grows at ``dt`` (the growth figure of :func:`grows`)."""
    data, fixes, r_min = bed_case(bed, dump, xmu)
    rng = np.random.default_rng(seed)
    n = sum(1 for line in dump.splitlines()[9:] if line.strip())
    kicks = [(*(eps * rng.standard_normal(3)), *(eps * rng.standard_normal(3) / r_min)) for _ in range(n)]
    head, atoms = data.split("Atoms # sphere", 1)
    data = _bed_data(bed, [[float(v) for v in line.split()[4:7]] for line in atoms.strip().splitlines()],
                     [0.5 * float(line.split()[2]) for line in atoms.strip().splitlines()], kicks)
    weight = 4.0 / 3.0 * math.pi * r_min**3 * bed.density * bed.gravity
    script = "\n".join([
        "units si", "atom_style sphere", "boundary p p f", "comm_modify vel yes", "newton off",
        "read_data case.data", f"pair_style {bed.pair_style(xmu)}", "pair_coeff * *",
        "neighbor 2e-4 bin", "neigh_modify delay 0", fixes, "fix move all nve/sphere",
        "compute tq all property/atom tqx tqy tqz radius",
        "variable g atom sqrt(fx*fx+fy*fy+fz*fz)+sqrt(c_tq[1]*c_tq[1]+c_tq[2]*c_tq[2]+c_tq[3]*c_tq[3])/c_tq[4]",
        "compute gm all reduce max v_g", "variable gmax equal c_gm",
        f"fix stop all halt 20 v_gmax > {_g(0.01 * weight)} error soft",
        f"timestep {_g(dt)}", "thermo_style custom step c_gm", "thermo 20", "thermo_modify norm no",
        f"run {steps}", ""])
    values = _series(run_lmp(script, data))
    if len(values) < 4:
        return True
    return max(values) > GROWTH_LIMIT * max(values[1:4]) or len(values) < steps // 20 + 1
