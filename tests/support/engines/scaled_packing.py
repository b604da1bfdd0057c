"""A LAMMPS-made packing with per-body mass factors: the test's own model, a rigorous per-body rule, and
LAMMPS runs that apply the factors through dtcrit's shipped engine script.

Independent of dtcrit's analysis: the stiffness is assembled here (``gran/hooke``'s linear springs,
normal ``kn`` and tangential ``kt`` at the full-radius arms ``a_i = R_i n``, ``a_j = -R_j n``; the
kinematics of ``support.dense_packing``, with the periodic box's nearest image; plus the geometric
term of the repulsive normal force ``F = kn delta`` turning with the centre line, ``-(F / r) (1 - n n)``
on the relative translation, which makes the model LAMMPS's own linearisation: its critical step
equals ``dtcrit audit``'s to rounding on the 30-sphere packing), the critical step is a direct
eigen-solve, and the factors come from Gershgorin's theorem:

* ``M^-1 K`` (``M`` diagonal) has the eigenvalues of ``D^-1 M^-1 K D`` for any positive diagonal
  ``D``; with ``d = 1`` on translations and ``1 / R_b`` on body ``b``'s rotations (rotations as arc
  lengths: the rows then share units), Gershgorin's theorem bounds every eigenvalue by
  ``max_r rho_r / M_r`` with the weighted absolute row sum ``rho_r = sum_s |K_rs| d_s / d_r``;
* leapfrog is stable at ``dt`` when ``lambda_max dt^2 < 4``: scaling body ``b``'s six masses and
  inertias by ``f_b >= max_{r in b} rho_r dt^2 / (4 M_r)`` (and ``f_b >= 1``) divides its rows by
  ``f_b`` and puts every disc below ``(2 / dt)^2``.

``growth`` runs LAMMPS from the dump with small random velocities and spins (``lammps_packing``'s
kick), the factors applied by ``dtcrit/engine_scripts/density_scaling.py`` (``lammps_factor_file``,
``lammps_commands``: an ``atomfile`` and ``set group all mass``), and returns the largest kinetic
energy over its initial value and the steps LAMMPS ran at.
"""
from __future__ import annotations

import importlib.util
import math
import tempfile
from pathlib import Path

import numpy as np

from ..dense_packing import cross_matrix
from ..paths import ENGINE_SCRIPTS
from .lammps_packing import _data_file, _header, _read_dump
from .lammps import run_lmp

__all__ = ["Model", "model_from_dump", "gershgorin_factors", "critical_step", "growth", "engine_script"]


def engine_script():
    """The ``density_scaling`` engine script of dtcrit, loaded from its file as an engine's Python would."""
    spec = importlib.util.spec_from_file_location("density_scaling", ENGINE_SCRIPTS / "density_scaling.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


class Model:
    """Spheres of a periodic box with their ``6N x 6N`` stiffness and diagonal mass."""

    def __init__(self, x, radii, masses, length, stiffness, pairs):
        self.x, self.radii, self.masses, self.length = x, radii, masses, length
        self.stiffness, self.pairs = stiffness, pairs

    def mass_diagonal(self, factors=None) -> np.ndarray:
        """``(m, m, m, I, I, I)`` per body (``I = 2/5 m R^2``), times the body's factor."""
        m = self.masses * (1.0 if factors is None else np.asarray(factors, float))
        inertia = 0.4 * m * self.radii**2
        return np.column_stack([m, m, m, inertia, inertia, inertia]).ravel()


def model_from_dump(dump_text: str, kn: float, kt: float, preload: bool = True) -> Model:
    """The model of a ``write_dump ... id type x y z radius mass`` of a periodic packing (contacts: pairs
    closer than the sum of their radii, nearest image).
    """
    x, radii, masses, length = _read_dump(dump_text)
    n = len(radii)
    k = np.zeros((6 * n, 6 * n))
    pairs = []
    for i in range(n):
        for j in range(i + 1, n):
            d = x[j] - x[i]
            d -= length * np.round(d / length)
            dist = float(np.linalg.norm(d))
            if dist >= radii[i] + radii[j]:
                continue
            pairs.append((i, j))
            nrm = d / dist
            nn = np.outer(nrm, nrm)
            g = np.zeros((3, 6 * n))
            g[:, 6 * i:6 * i + 3] = -np.eye(3)
            g[:, 6 * i + 3:6 * i + 6] = cross_matrix(radii[i] * nrm)
            g[:, 6 * j:6 * j + 3] = np.eye(3)
            g[:, 6 * j + 3:6 * j + 6] = -cross_matrix(-radii[j] * nrm)
            k += g.T @ (kn * nn + kt * (np.eye(3) - nn)) @ g
            if preload:  # the repulsive normal force kn delta turning with the centre line: -(F / r) (1 - n n)
                t = np.zeros((3, 6 * n))
                t[:, 6 * i:6 * i + 3], t[:, 6 * j:6 * j + 3] = -np.eye(3), np.eye(3)
                k -= t.T @ (kn * (radii[i] + radii[j] - dist) / dist * (np.eye(3) - nn)) @ t
    return Model(x, radii, masses, length, k, pairs)


def gershgorin_factors(model: Model, dt: float) -> np.ndarray:
    """Per-body factors (at least 1) under which Gershgorin's discs of ``M^-1 K`` lie below ``(2/dt)^2``."""
    d = np.column_stack([np.ones((len(model.radii), 3)), np.repeat(1.0 / model.radii[:, None], 3, 1)]).ravel()
    rho = (np.abs(model.stiffness) * d[None, :]).sum(axis=1) / d
    rows = rho * dt**2 / (4.0 * model.mass_diagonal())
    return np.maximum(1.0, rows.reshape(-1, 6).max(axis=1))


def critical_step(model: Model, factors=None) -> float:
    """Leapfrog's critical step ``2 / sqrt(lambda_max(M^-1 K))``, by a direct symmetric eigen-solve."""
    s = 1.0 / np.sqrt(model.mass_diagonal(factors))
    lam = float(np.linalg.eigvalsh(model.stiffness * s[:, None] * s[None, :])[-1])
    return 2.0 / math.sqrt(lam)


def growth(dump_text: str, pair_style: str, dt: float, steps: int, factors=None, *, plan_file=None,
           eps: float = 1e-6, seed: int = 3) -> tuple[float, list[float]]:
    """Largest kinetic energy over its first value, and the distinct steps LAMMPS ran at, for a run of
    ``steps`` at ``dt`` from the dump, scaled by the engine script: ``factors`` by atom id ``1..N``
    (``lammps_factor_file``, ``lammps_commands``), or a ``dtcrit plan --json`` file (``plan_file``:
    ``write_lammps_include`` and ``include``, the plan's own step).
    """
    if plan_file is not None:
        import json

        doc = json.loads(Path(plan_file).read_text())["density_scaling"]
        by_id = dict(zip(doc["ids"], doc["factors"]))
        factors = [by_id.get(k + 1, 1.0) for k in range(len(_read_dump(dump_text)[1]))]
    x, radii, masses, length = _read_dump(dump_text)
    rng = np.random.default_rng(seed)
    v_scale = eps * radii.min() / dt
    vel = np.concatenate([rng.standard_normal((len(x), 3)) * v_scale,
                          rng.standard_normal((len(x), 3)) * v_scale / radii[:, None]], axis=1)
    lines = _header(pair_style) + ["fix integ all nve/sphere", f"timestep {dt!r}"]
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        if plan_file is not None:
            engine_script().write_lammps_include(str(plan_file), str(work / "scaled.in"))
            lines += ["include scaled.in", "write_dump all custom scaled.dump id mass modify format float %.17g"]
        elif factors is not None:
            script = engine_script()
            table = {k + 1: float(f) for k, f in enumerate(factors)}
            (work / "factors.txt").write_text(script.lammps_factor_file(table))
            lines += script.lammps_commands("factors.txt", dt)
            lines.append("write_dump all custom scaled.dump id mass modify format float %.17g")
        every = max(1, steps // 400)
        lines += ["compute ket all ke", "compute ker all erotate/sphere", "variable etot equal c_ket+c_ker",
                  "fix stop all halt 10 v_etot > 1e30 error soft message no",
                  "thermo_style custom step dt v_etot", "thermo_modify format float %.17g norm no lost ignore",
                  f"thermo {every}", f"run {int(steps)}"]
        log = run_lmp("\n".join(lines) + "\n", _data_file(x, radii, masses, length, vel, masses=True),
                      keep_dir=work, timeout=300.0)
        scaled = _dump_masses(work / "scaled.dump") if factors is not None else None
    energies, steps_at = _thermo(log)
    if scaled is not None:
        assert np.allclose(scaled, masses * np.asarray(factors), rtol=1e-15, atol=0.0), "LAMMPS's masses"
    e = np.array(energies)
    if e.size < 8 or not np.all(np.isfinite(e)) or e.max() > 1e29:
        return math.inf, steps_at
    return (float(e.max() / e[0]) if e[0] > 0 else math.inf), steps_at


def _dump_masses(path: Path) -> np.ndarray:
    lines = path.read_text().splitlines()
    n = int(lines[3])
    rows = sorted((int(a), float(b)) for a, b in (ln.split() for ln in lines[9:9 + n]))
    return np.array([m for _, m in rows])


def _thermo(log: str) -> tuple[list[float], list[float]]:
    energies: list[float] = []
    dts: set[float] = set()
    reading = False
    for ln in log.splitlines():
        parts = ln.split()
        if parts[:3] == ["Step", "Dt", "v_etot"]:
            reading = True
            continue
        if reading:
            if len(parts) == 3 and parts[0].isdigit():
                dts.add(float(parts[1]))
                energies.append(float(parts[2]))
            elif parts and parts[0] == "Loop":
                break
    return energies, sorted(dts)


def lammps_python() -> str | None:
    """A Python that imports the LAMMPS module: ``$LAMMPS_PYTHON``, else a ``python3`` on PATH, else this
    environment's base interpreter; None when there is none (``apt-get install python3-lammps``).
    """
    import os
    import shutil
    import subprocess
    import sys

    override = os.environ.get("LAMMPS_PYTHON")
    on_path = [shutil.which("python3", path=d) for d in os.environ.get("PATH", "").split(os.pathsep)]
    found = [override] if override else on_path
    for cand in dict.fromkeys(c for c in [*found, getattr(sys, "_base_executable", None)] if c):
        if subprocess.run([cand, "-c", "import lammps"], capture_output=True, timeout=60).returncode == 0:
            return cand
    return None


_HOOK_DRIVER = r'''
import json, sys
cfg = json.load(open(sys.argv[1]))
sys.path.insert(0, cfg["scripts"])
from lammps import lammps
from lammps_hook import DtcritLammpsHook

lmp = lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"])
lmp.commands_list(cfg["setup"])
hook = DtcritLammpsHook(lmp, cfg["style"], dtcrit=["dtcrit-not-run"], directory=cfg["dir"])
from density_scaling import read_plan
table, dt = read_plan(cfg["plan"])
out = {"returned": hook.apply_density_scaling(table, dt)}
n = lmp.get_natoms()
ids, mass = lmp.gather_atoms("id", 0, 1), lmp.gather_atoms("rmass", 1, 1)
out["mass"] = {int(ids[k]): mass[k] for k in range(n)}
lmp.command("run %d" % cfg["steps"])
out["dt"] = lmp.extract_global("dt")
out["energy"] = lmp.extract_variable("etot", None, 0)
lmp.close()
print("HOOK " + json.dumps(out))
'''


def hook_run(python: str, dump_text: str, pair_style: str, plan_file, steps: int, *, eps: float = 1e-6,
             seed: int = 3) -> dict:
    """``DtcritLammpsHook.apply_density_scaling(*read_plan(plan_file))`` in the LAMMPS Python module on
    the dumped packing (kicked as in ``growth`` at the plan's ``target_dt``), then ``run steps``: the step
    it returned, the masses LAMMPS holds after it (by atom id), the step after the run, and the kinetic
    energy at the end over the scaled initial one.
    """
    import json
    import subprocess

    doc = json.loads(Path(plan_file).read_text())
    dt = float(doc["target_dt"])
    given = dict(zip(doc["density_scaling"]["ids"], doc["density_scaling"]["factors"]))
    x, radii, masses, length = _read_dump(dump_text)
    rng = np.random.default_rng(seed)
    v_scale = eps * radii.min() / dt
    vel = np.concatenate([rng.standard_normal((len(x), 3)) * v_scale,
                          rng.standard_normal((len(x), 3)) * v_scale / radii[:, None]], axis=1)
    factors = np.array([float(given.get(k + 1, 1.0)) for k in range(len(masses))])
    m = masses * factors  # the kinetic energy right after the scaling
    e0 = 0.5 * float(np.sum(m[:, None] * vel[:, :3] ** 2) + np.sum(0.4 * (m * radii**2)[:, None] * vel[:, 3:] ** 2))
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        (work / "case.data").write_text(_data_file(x, radii, masses, length, vel, masses=True))
        setup = [ln.replace("read_data case.data", f'read_data "{work / "case.data"}"') for ln in _header(pair_style)]
        setup += ["fix integ all nve/sphere", "timestep 1e-12", "compute ket all ke", "compute ker all erotate/sphere",
                  "variable etot equal c_ket+c_ker", "thermo_style custom step v_etot"]
        cfg = {"scripts": str(ENGINE_SCRIPTS), "setup": setup, "style": pair_style, "dir": str(work),
               "steps": int(steps), "plan": str(Path(plan_file).resolve())}
        (work / "cfg.json").write_text(json.dumps(cfg))
        (work / "driver.py").write_text(_HOOK_DRIVER)
        done = subprocess.run([python, str(work / "driver.py"), str(work / "cfg.json")], capture_output=True,
                              text=True, timeout=300)
    lines = [ln for ln in done.stdout.splitlines() if ln.startswith("HOOK ")]
    assert done.returncode == 0 and lines, done.stdout[-2000:] + done.stderr[-2000:]
    out = json.loads(lines[-1][5:])
    out["energy_ratio"] = out["energy"] / e0
    out["mass"] = np.array([out["mass"][str(k + 1)] for k in range(len(masses))])
    return out
