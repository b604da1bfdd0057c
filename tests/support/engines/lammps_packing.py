"""LAMMPS-made packings: compress random polydisperse spheres in LAMMPS itself, dump the result, and
run LAMMPS from that dump at a given step to see whether it stays bounded.

Like the rest of the harness this never imports dtcrit: the packing is LAMMPS's own (its contact
list, overlaps and masses come out of its dump), and the threshold is LAMMPS's own behaviour.

* ``compress`` -- N spheres (radii uniform in ``[r (1 - spread), r (1 + spread)]``) placed at random
  (no overlap) in a dilute periodic cube, shrunk by ``fix deform`` to the target solid fraction
  under ``fix viscous`` with frictionless contacts, then relaxed at the final size; written by ``write_dump ... custom id type
  x y z radius mass`` at 17 digits.
* ``kinetic_growth`` -- the dumped positions, masses and radii, a small random kick of the velocities
  and spins (displacements of about ``eps`` times the smallest radius), no other fix than
  ``nve/sphere``.  The run is judged by the largest kinetic energy over its initial value: an unstable
  step grows it exponentially until the motion is no longer small (contacts open), a stable one
  keeps it within a small factor (the relaxed packing's residual forces add little).  A run whose
  energy overflows counts as growing.
"""
from __future__ import annotations

import math
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .lammps import run_lmp

GROWTH_LIMIT = 1e3  # envelope growth of the kinetic energy that counts as growing


def _g(x: float) -> str:
    return repr(float(x))


def _run(script: str, files: dict[str, str], workdir: Path, timeout: float = 300.0) -> str:
    """``lmp`` on ``script`` in ``workdir`` (which keeps its outputs), through ``lammps.run_lmp``
    (Open MPI singleton settings, retried start-up)."""
    return run_lmp(script, files["case.data"], keep_dir=workdir, timeout=timeout)


@dataclass(frozen=True)
class PackingSpec:
    n: int = 60
    radius: float = 1e-3
    spread: float = 0.3
    density: float = 2500.0
    solid_fraction: float = 0.65
    kn: float = 1e4
    seed: int = 7
    style: str = "gran/hooke/history"
    stiffness: float = 1e4  # N/m: sets the compression's step (for Hertz, Kn is in Pa)

    @property
    def pair_style(self) -> str:
        """Compression is frictionless (``xmu = 0``): the relaxed packing is then in equilibrium under
        its normal forces alone, so a later run that starts with empty shear histories (a dump has
        none) starts from equilibrium whatever tangential law it uses."""
        return f"{self.style} {_g(self.kn)} NULL 0 NULL 0 0"


def _dilute_positions(spec: PackingSpec, rng) -> tuple[np.ndarray, np.ndarray, float]:
    radii = spec.radius * rng.uniform(1 - spec.spread, 1 + spec.spread, spec.n)
    volume = (4.0 / 3.0) * math.pi * np.sum(radii**3)
    length = (volume / 0.05) ** (1.0 / 3.0)
    x = np.zeros((spec.n, 3))
    for k in range(spec.n):
        while True:
            trial = rng.uniform(0, length, 3)
            d = x[:k] - trial
            d -= length * np.round(d / length)
            if k == 0 or np.all(np.linalg.norm(d, axis=1) > radii[:k] + radii[k]):
                x[k] = trial
                break
    return x, radii, length


def _data_file(x, radii, density_or_mass, length, velocities=None, *, masses=False) -> str:
    lines = ["LAMMPS data file (engine_harness.lammps_packing)", "", f"{len(x)} atoms", "1 atom types", ""]
    lines += [f"0.0 {_g(length[a] if np.ndim(length) else length)} {ax}lo {ax}hi" for a, ax in enumerate("xyz")]
    lines += ["", "Atoms # sphere", ""]
    for k, (p, r) in enumerate(zip(x, radii), start=1):
        rho = density_or_mass[k - 1] / ((4.0 / 3.0) * math.pi * r**3) if masses else density_or_mass
        lines.append(f"{k} 1 {_g(2 * r)} {_g(rho)} {_g(p[0])} {_g(p[1])} {_g(p[2])}")
    if velocities is not None:
        lines += ["", "Velocities", ""]
        lines += [f"{k} " + " ".join(_g(c) for c in row) for k, row in enumerate(velocities, start=1)]
    return "\n".join(lines) + "\n"


def _pair_lines(pair_style: str) -> list[str]:
    """``pair_style`` and ``pair_coeff`` lines; ``granular ARGS`` puts ARGS on ``pair_coeff * *``."""
    words = pair_style.split()
    if words[0] == "granular":
        return ["pair_style granular", "pair_coeff * * " + " ".join(words[1:])]
    return [f"pair_style {pair_style}", "pair_coeff * *"]


def _header(pair_style: str) -> list[str]:
    return ["units si", "dimension 3", "atom_style sphere", "atom_modify map array sort 0 0.0", "boundary p p p",
            "newton off", "comm_modify vel yes", "read_data case.data", *_pair_lines(pair_style),
            "neighbor 1e-4 bin", "neigh_modify delay 0 every 1 check yes"]


def compress(spec: PackingSpec, workdir: Path) -> str:
    """Text of LAMMPS's dump of the compressed, relaxed packing."""
    rng = np.random.default_rng(spec.seed)
    x, radii, length = _dilute_positions(spec, rng)
    final = ((4.0 / 3.0) * math.pi * np.sum(radii**3) / spec.solid_fraction) ** (1.0 / 3.0)
    m_min = (4.0 / 3.0) * math.pi * radii.min() ** 3 * spec.density
    dt = 0.05 * math.sqrt(m_min / spec.stiffness)
    damp = 0.5 * m_min / dt / 50.0
    script = _header(spec.pair_style) + [
        "fix integ all nve/sphere", f"fix visc all viscous {_g(damp)}", f"timestep {_g(dt)}",
        f"fix shrink all deform 1 x final 0 {_g(final)} y final 0 {_g(final)} z final 0 {_g(final)} remap x",
        "run 20000", "unfix shrink", "run 40000",
        "write_dump all custom packing.dump id type x y z radius mass modify format float %.17g",
    ]
    _run("\n".join(script) + "\n", {"case.data": _data_file(x, radii, spec.density, length)}, workdir)
    return (workdir / "packing.dump").read_text()


def _read_dump(text: str):
    lines = text.splitlines()
    n = int(lines[3])
    lo_hi = np.array([[float(v) for v in lines[5 + a].split()[:2]] for a in range(3)])
    cols = lines[8].split()[2:]
    rows = np.array([[float(v) for v in ln.split()] for ln in lines[9:9 + n]])
    get = {c: rows[:, k] for k, c in enumerate(cols)}
    order = np.argsort(get["id"])
    x = np.stack([get["x"], get["y"], get["z"]], 1)[order] - lo_hi[:, 0]
    return x, get["radius"][order], get["mass"][order], lo_hi[:, 1] - lo_hi[:, 0]


def kinetic_growth(dump_text: str, pair_style: str, dt: float, steps: int, *, eps: float = 1e-6,
                   seed: int = 3) -> float:
    """Largest kinetic energy of a run of ``steps`` at ``dt`` over its initial one (module docstring)."""
    x, radii, masses, length = _read_dump(dump_text)
    v_scale = eps * radii.min() / dt
    rng = np.random.default_rng(seed)
    vel = np.concatenate([rng.standard_normal((len(x), 3)) * v_scale,
                          rng.standard_normal((len(x), 3)) * v_scale / radii[:, None]], axis=1)
    every = max(1, steps // 400)
    script = _header(pair_style) + [
        "fix integ all nve/sphere", f"timestep {_g(dt)}",
        "compute ket all ke", "compute ker all erotate/sphere", "variable etot equal c_ket+c_ker",
        "fix stop all halt 10 v_etot > 1e30 error soft message no",
        "thermo_style custom step v_etot", "thermo_modify format float %.17g norm no lost ignore",
        f"thermo {every}", f"run {int(steps)}",
    ]
    with tempfile.TemporaryDirectory() as tmp:
        log = _run("\n".join(script) + "\n", {"case.data": _data_file(x, radii, masses, length, vel, masses=True)},
                   Path(tmp))
    energies = []
    reading = False
    for ln in log.splitlines():
        parts = ln.split()
        if parts[:2] == ["Step", "v_etot"]:
            reading = True
            continue
        if reading:
            if len(parts) == 2 and parts[0].isdigit():
                energies.append(float(parts[1]))
            elif parts and parts[0] == "Loop":
                break
    e = np.array(energies)
    if e.size < 8 or not np.all(np.isfinite(e)) or e.max() > 1e29:
        return math.inf
    return float(e.max() / e[0]) if e[0] > 0 else math.inf


def grows(dump_text: str, pair_style: str, dt: float, steps: int = 3000, **kw) -> bool:
    return kinetic_growth(dump_text, pair_style, dt, steps, **kw) > GROWTH_LIMIT


def bisect_threshold(dump_text: str, pair_style: str, lo: float, hi: float, rel_tol: float = 2e-4,
                     steps: int = 3000) -> float:
    """LAMMPS's stability threshold on the packing, bisected between a stable ``lo`` and unstable ``hi``."""
    if grows(dump_text, pair_style, lo, steps) or not grows(dump_text, pair_style, hi, steps):
        raise RuntimeError(f"threshold not bracketed by [{lo:.6g}, {hi:.6g}]")
    while hi - lo > rel_tol * hi:
        mid = 0.5 * (lo + hi)
        if grows(dump_text, pair_style, mid, steps):
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


def engine_contact_list(dump_text: str, pair_style: str) -> str:
    """LAMMPS's own contact list of the dumped packing: ``dump local`` of
    ``compute property/local patom1 patom2 cutoff radius`` (pairs closer than ``R_i + R_j``)."""
    x, radii, masses, length = _read_dump(dump_text)
    script = _header(pair_style) + [
        "fix integ all nve/sphere", "timestep 1e-12",
        "compute pairs all property/local patom1 patom2 cutoff radius",
        "dump cl all local 1 contacts.local c_pairs[1] c_pairs[2]",
        "run 0",
    ]
    with tempfile.TemporaryDirectory() as tmp:
        _run("\n".join(script) + "\n", {"case.data": _data_file(x, radii, masses, length, masses=True)}, Path(tmp))
        return (Path(tmp) / "contacts.local").read_text()
