"""Collide pairs of spheres in LAMMPS (``lmp``, ``pair_style granular``) and measure the outcomes.

A *batch* is a list of ``(dt, [Impact, ...])`` groups.  One LAMMPS process runs them all: each
group is one block of the input (``clear`` between blocks) with its own data file and time step;
every impact of a group is a pair of atoms of its own atom type, the pairs 6 radii apart along y
(they never meet), so each type pair gets its own ``pair_coeff``.  Every step is dumped
(``dump custom`` of x, v, omega at ``%.17g``) and ``collisions.measure`` reads the outcome.

Law text (``pair_coeff i i``) per ``Impact.damping``, for this build (29Sep2021 update 2, Debian
20220106, no ``coeff_restitution``):

* ``lammps-tsuji``: ``hertz/material E e nu`` (or ``hooke kn e``) ``damping tsuji``;
* ``lammps-coeff-restitution``: ``damping coeff_restitution`` where the build has it
  (``has_coeff_restitution``), else ``tsuji`` with the coefficient ``e'`` of ``tsuji_coefficient_for``
  (``tsuji`` and ``coeff_restitution`` share the form ``damp*sqrt(meff*F/delta)``);
* ``lammps-mass-velocity``: ``hooke kn gamma damping mass_velocity``;
* ``none``: the coefficient 0 with ``damping mass_velocity`` (no dashpot).

Tangential: ``linear_nohistory 0 0`` for head-on impacts (no tangential force), ``mindlin NULL
gammat_ratio mu`` for oblique ones.  ``Impact.clip`` adds ``limit_damping``.
"""
from __future__ import annotations

import functools
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np

from . import engine_executable
from .collisions import Impact, Outcome, coeff_restitution_prefactor, measure, tsuji_coefficient_for
from .lammps import LammpsError

__all__ = ["law_text", "has_coeff_restitution", "collide", "run_batch", "LammpsError"]

FIRST_CONTACT_STEP = 1  # the contact starts phase*dt before step 1
SPACING = 6.0  # pair spacing along y, in radii


def _g(x: float) -> str:
    return repr(float(x))


@functools.lru_cache(maxsize=None)
def has_coeff_restitution() -> bool:
    """Whether this LAMMPS build knows ``damping coeff_restitution`` (a one-step probe run)."""
    probe = ("units si\natom_style sphere\nregion b block 0 1 0 1 0 1\ncreate_box 1 b\n"
             "pair_style granular\npair_coeff * * hertz/material 1e7 0.5 0.3 damping coeff_restitution "
             "tangential linear_nohistory 0.0 0.0\n")
    try:
        work = _run(probe, {}, timeout=60.0)["dir"]
    except LammpsError:
        return False
    shutil.rmtree(work, ignore_errors=True)
    return True


def law_text(imp: Impact) -> str:
    """``pair_coeff`` model text of ``imp`` for this LAMMPS build.

    ``lammps-coeff-restitution`` is written natively where the build has it, else as ``tsuji`` with
    the coefficient of ``tsuji_coefficient_for`` (the 2021 ``tsuji`` prefactor, factor 1).
    """
    if imp.damping == "lammps-tsuji":
        coef, model = imp.coefficient, "tsuji"
    elif imp.damping == "lammps-coeff-restitution" and has_coeff_restitution():
        coef, model = imp.coefficient, "coeff_restitution"
    elif imp.damping == "lammps-coeff-restitution":
        coef, model = tsuji_coefficient_for(coeff_restitution_prefactor(imp.coefficient, imp.normal)), "tsuji"
    elif imp.damping == "lammps-mass-velocity":
        coef, model = imp.coefficient, "mass_velocity"
    elif imp.damping == "none":
        coef, model = 0.0, "mass_velocity"
    else:
        raise ValueError(f"LAMMPS has no damping {imp.damping!r}")
    if imp.normal == "hertz":
        normal = f"hertz/material {_g(imp.young)} {_g(coef)} {_g(imp.poisson)}"
    else:
        normal = f"hooke {_g(imp.kn)} {_g(coef)}"
    if imp.tangential_speed > 0.0:
        tang = f"tangential mindlin NULL {_g(imp.gammat_ratio)} {_g(imp.friction)}"
    else:
        tang = "tangential linear_nohistory 0.0 0.0"
    return f"{normal} damping {model} {tang}" + (" limit_damping" if imp.clip else "")


def _steps(dt: float, impacts) -> int:
    """Steps until every pair has surely separated (entry + 3 elastic durations + margin)."""
    return FIRST_CONTACT_STEP + int(max(3.0 * i.contact_time / dt for i in impacts)) + 20


def _pair_state(imp: Impact, dt: float, k: int):
    """Initial centres and velocities of pair k: along x, closing speed v, contact at (1-phase) dt."""
    t_in = (FIRST_CONTACT_STEP - imp.phase) * dt
    g0 = imp.speed * t_in
    y = k * SPACING * imp.radius
    vt = imp.tangential_speed
    # relative tangential velocity of 2 w.r.t. 1 is -vt along y; the y offset vanishes at t_in
    x1 = (-(imp.radius + 0.5 * g0), y - 0.5 * vt * t_in, 0.0)
    x2 = (imp.radius + 0.5 * g0, y + 0.5 * vt * t_in, 0.0)
    v1 = (0.5 * imp.speed, 0.5 * vt, 0.0)
    v2 = (-0.5 * imp.speed, -0.5 * vt, 0.0)
    return (x1, v1), (x2, v2)


def _block(dt: float, impacts, b: int) -> tuple[str, str, int]:
    """(input block, data file text, steps) of one group."""
    n = len(impacts)
    rmax = max(i.radius for i in impacts)
    # a slab just wide enough (the pairs move by a few overlaps): a cubic box of the pairs' span
    # would hold ~n^3 neighbour bins
    w, ylo, yhi = 4.0 * rmax, -SPACING * rmax, (n + 1) * SPACING * rmax
    data = [f"collisions block {b}", "", f"{2 * n} atoms", f"{n} atom types", "",
            f"{_g(-w)} {_g(w)} xlo xhi", f"{_g(ylo)} {_g(yhi)} ylo yhi", f"{_g(-w)} {_g(w)} zlo zhi", "",
            "Atoms # sphere", ""]
    vel = ["", "Velocities", ""]
    for k, imp in enumerate(impacts):
        rho = imp.mass / (4.0 / 3.0 * np.pi * imp.radius**3)
        for j, (x, v) in enumerate(_pair_state(imp, dt, k)):
            aid = 2 * k + j + 1
            data.append(f"{aid} {k + 1} {_g(2 * imp.radius)} {_g(rho)} {_g(x[0])} {_g(x[1])} {_g(x[2])}")
            vel.append(f"{aid} {_g(v[0])} {_g(v[1])} {_g(v[2])} 0.0 0.0 0.0")
    steps = _steps(dt, impacts)
    lines = ["clear", "units si", "dimension 3", "atom_style sphere", "atom_modify map array sort 0 0.0",
             "boundary f f f", "newton off", "comm_modify vel yes", f"read_data block{b}.data",
             "pair_style granular",
             # every cross-type pair: no force (they never meet); then each type's own law
             "pair_coeff * * hooke 0.0 0.0 tangential linear_nohistory 0.0 0.0 damping mass_velocity"]
    lines += [f"pair_coeff {k + 1} {k + 1} {law_text(imp)}" for k, imp in enumerate(impacts)]
    lines += [f"neighbor {_g(0.5 * rmax)} bin", "neigh_modify delay 0 every 1 check yes",
              f"timestep {_g(dt)}", "fix integ all nve/sphere",
              f"dump d all custom 1 block{b}.dump id x y z vx vy vz omegax omegay omegaz",
              "dump_modify d sort id format float %.17g", f"run {steps}", "undump d"]
    return "\n".join(lines) + "\n", "\n".join(data + vel) + "\n", steps


def _read_dump(path: Path, natoms: int) -> np.ndarray:
    """Array [step, atom, 9] of x, v, omega from a ``dump custom`` sorted by id."""
    rows = []
    with open(path) as fh:
        lines = fh.read().splitlines()
    i = 0
    while i < len(lines):
        if lines[i].startswith("ITEM: ATOMS"):
            rows.extend(lines[i + 1:i + 1 + natoms])
            i += 1 + natoms
        else:
            i += 1
    arr = np.array([r.split() for r in rows], dtype=float)
    return arr.reshape(-1, natoms, 10)[:, :, 1:]


def _run(script: str, files: dict[str, str], *, timeout: float, keep_dir=None) -> dict[str, Path]:
    exe = engine_executable("lammps")
    if exe is None:
        raise LammpsError("LAMMPS binary `lmp` not found (apt-get install lammps)")
    env = dict(os.environ, OMP_NUM_THREADS="1", OMPI_MCA_ess_singleton_isolated="1")
    tmp = tempfile.mkdtemp(prefix="lmp_collide_") if keep_dir is None else str(keep_dir)
    work = Path(tmp)
    work.mkdir(parents=True, exist_ok=True)
    (work / "in.collide").write_text(script)
    for name, text in files.items():
        (work / name).write_text(text)
    for _ in range(3):  # an Open MPI singleton start-up can fail on a busy machine: retry
        proc = subprocess.run([exe, "-in", "in.collide", "-log", "log.lammps", "-screen", "none", "-nocite"],
                              cwd=work, env=env, capture_output=True, text=True, timeout=timeout)
        log = (work / "log.lammps").read_text() if (work / "log.lammps").exists() else ""
        if not (proc.returncode != 0 and not log and "MPI_Init" in proc.stdout + proc.stderr):
            break
    if proc.returncode != 0 or "ERROR" in log:
        tail = "\n".join((log or proc.stdout + proc.stderr).splitlines()[-15:])
        if keep_dir is None:
            shutil.rmtree(work, ignore_errors=True)
        raise LammpsError(f"lmp failed (exit {proc.returncode}):\n{tail}")
    return {"dir": work}


def run_batch(groups, *, timeout: float = 300.0, keep_dir=None) -> list[list[Outcome]]:
    """Run every ``(dt, [Impact, ...])`` group in one LAMMPS process; outcomes in the same shape."""
    groups = [(float(dt), list(imps)) for dt, imps in groups]
    script, files = "", {}
    for b, (dt, imps) in enumerate(groups):
        text, data, _ = _block(dt, imps, b)
        script += text
        files[f"block{b}.data"] = data
    work = _run(script, files, timeout=timeout, keep_dir=keep_dir)["dir"]
    try:
        out = []
        for b, (dt, imps) in enumerate(groups):
            arr = _read_dump(work / f"block{b}.dump", 2 * len(imps))
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
    """Outcomes of ``impacts`` run together at step ``dt`` (one LAMMPS process)."""
    return run_batch([(dt, impacts)], **kw)[0]
