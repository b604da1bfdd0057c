"""The LAMMPS hook (``dtcrit/engine_scripts/lammps_hook.py``) in real LAMMPS.

A packing LAMMPS compressed itself (``support.engines.lammps_packing.compress``) is run from its dump
with small random velocities and spins at a user step 1.5 x dtcrit's critical step: without the hook
its kinetic energy explodes; with the hook (the LAMMPS Python module, run by the Python that has it,
not this environment's) it stays bounded, and every step the hook sets is
``safety * min(dt_safe, dt_crit)`` of a separate ``dtcrit audit`` call on the same snapshot.  The
second route (the ``lmp`` binary, a python-style variable and ``run N every M``) is checked the same
way, and stand-ins for dtcrit show that the step is capped at ``dt_crit`` and that a failing audit
raises or keeps the step.
"""
from __future__ import annotations

import json
import math
import os
import shutil
import stat
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from support.engines import in_ci, require_engine
from support.engines.lammps_packing import PackingSpec, compress
from support.paths import ENGINE_SCRIPTS as SCRIPTS

STYLE = "gran/hooke/history 1e4 NULL 0 NULL 0.5 0"
SPEC = PackingSpec(n=30, solid_fraction=0.65, seed=7)
USER_FACTOR = 1.5  # the user's step, in units of dtcrit's critical step
STEPS, EVERY = 1500, 500
EPS = 1e-6  # velocity kick: displacements of about EPS x the smallest radius per step
GROWING, BOUNDED = 1e3, 10.0  # kinetic energy over its initial value
MODULE_HINT = "apt-get install python3-lammps liblammps-dev"

DRIVER = r'''
import json, sys
cfg = json.load(open(sys.argv[1]))
sys.path.insert(0, cfg["scripts"])
from lammps import lammps
from lammps_hook import DtcritLammpsHook

lmp = lammps(cmdargs=["-log", cfg["log"], "-screen", "none", "-nocite"])
lmp.commands_list(cfg["setup"])
out = {}
if cfg["hook"] is None:
    lmp.command("run %d" % cfg["steps"])
else:
    hook = DtcritLammpsHook(lmp, cfg["style"], **cfg["hook"])
    try:
        if cfg["steps"]:
            hook.run(cfg["steps"])
        else:
            out["returned"] = hook.update()
    except RuntimeError as exc:
        out["raised"] = str(exc)
    out.update(history=hook.history, dump=hook.dump_path, local=hook.local_path)
out["dt"] = lmp.extract_global("dt")
out["step"] = lmp.extract_global("ntimestep")
lmp.close()
print(json.dumps(out))
'''


def _lammps_python() -> str:
    """A Python that imports the LAMMPS module ($LAMMPS_PYTHON, else python3 on PATH, else the base
    interpreter of this environment); skip, or fail in CI, when there is none."""
    override = os.environ.get("LAMMPS_PYTHON")
    on_path = [shutil.which("python3", path=d) for d in os.environ.get("PATH", "").split(os.pathsep)]
    found = [override] if override else on_path
    candidates = list(dict.fromkeys(c for c in [*found, getattr(sys, "_base_executable", None)] if c))
    for cand in candidates:
        probe = subprocess.run([cand, "-c", "import lammps"], capture_output=True, timeout=60)
        if probe.returncode == 0:
            return cand
    msg = f"no Python with the LAMMPS module (tried {', '.join(candidates)}); install it with: {MODULE_HINT}"
    if in_ci():
        pytest.fail(msg + " -- engine tests are never skipped in CI (CI=true)", pytrace=False)
    pytest.skip(msg)


def _dtcrit_command() -> list[str]:
    """This environment's dtcrit: the script beside its Python, else ``python -m dtcrit``."""
    exe = Path(sys.executable).with_name("dtcrit")
    return [str(exe)] if exe.is_file() else [sys.executable, "-m", "dtcrit"]


def _audit(dump, *args: str) -> dict:
    done = subprocess.run([*_dtcrit_command(), "audit", str(dump), "--pair-style", STYLE, *args, "--json"],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def _kicked_data_file(dump_text: str, dt: float, seed: int = 3) -> str:
    """A LAMMPS data file (atom_style sphere) of the dump's atoms, box shifted to the origin, with random
    velocities and spins moving each atom about EPS x the smallest radius per step of ``dt``."""
    lines = dump_text.splitlines()
    n = int(lines[3])
    box = np.array([[float(v) for v in lines[5 + a].split()[:2]] for a in range(3)])
    cols = lines[8].split()[2:]
    table = np.array([[float(v) for v in ln.split()] for ln in lines[9:9 + n]])
    atoms = {c: table[:, k] for k, c in enumerate(cols)}
    order = np.argsort(atoms["id"])
    x = np.stack([atoms[c] for c in "xyz"], 1)[order] - box[:, 0]
    radius, mass = atoms["radius"][order], atoms["mass"][order]
    rng = np.random.default_rng(seed)
    v = rng.standard_normal((n, 3)) * EPS * radius.min() / dt
    w = rng.standard_normal((n, 3)) * EPS * radius.min() / dt / radius[:, None]
    out = ["LAMMPS data file (kicked packing)", "", f"{n} atoms", "1 atom types", ""]
    out += [f"0.0 {hi - lo!r} {a}lo {a}hi" for (lo, hi), a in zip(box.tolist(), "xyz")]
    out += ["", "Atoms # sphere", ""]
    out += [f"{k + 1} 1 {2 * r!r} {m / (4 / 3 * math.pi * r**3)!r} {p[0]!r} {p[1]!r} {p[2]!r}"
            for k, (r, m, p) in enumerate(zip(radius.tolist(), mass.tolist(), x.tolist()))]
    out += ["", "Velocities", ""]
    out += [f"{k + 1} " + " ".join(repr(c) for c in row) for k, row in enumerate(np.hstack([v, w]).tolist())]
    return "\n".join(out) + "\n"


@pytest.fixture(scope="module")
def packing(tmp_path_factory):
    """LAMMPS's dump of its compressed packing, dtcrit's audit of it, and a data file of the same atoms
    with small random velocities and spins (scaled to the user's step)."""
    require_engine("lammps")
    work = tmp_path_factory.mktemp("hook")
    dump = work / "packing.dump"
    dump.write_text(compress(SPEC, work))
    audit = _audit(dump)
    dt_user = USER_FACTOR * audit["dt_crit"]
    (work / "case.data").write_text(_kicked_data_file(dump.read_text(), dt_user))
    return {"work": work, "dump": dump, "audit": audit, "dt_user": dt_user}


@pytest.fixture(scope="module")
def lammps_python():
    return _lammps_python()


def _setup(packing, thermo_every: int = 10) -> list[str]:
    data = packing["work"] / "case.data"
    return ["units si", "dimension 3", "atom_style sphere", "atom_modify map array sort 0 0.0", "boundary p p p",
            "newton off", "comm_modify vel yes", f'read_data "{data}"', f"pair_style {STYLE}", "pair_coeff * *",
            "neighbor 1e-4 bin", "neigh_modify delay 0 every 1 check yes", "fix integ all nve/sphere",
            f"timestep {packing['dt_user']!r}", "compute ket all ke", "compute ker all erotate/sphere",
            "variable etot equal c_ket+c_ker", "fix stop all halt 10 v_etot > 1e30 error soft message no",
            "thermo_style custom step dt v_etot", "thermo_modify format float %.17g norm no lost ignore",
            f"thermo {thermo_every}"]


def _energies(log: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(step, dt, kinetic energy) of every thermo row of the log (``thermo_style custom step dt v_etot``)."""
    rows, inside = [], False
    for line in log.splitlines():
        s = line.split()
        if s[:3] == ["Step", "Dt", "v_etot"]:
            inside = True
        elif inside and len(s) == 3 and s[0].isdigit():
            rows.append([float(t) for t in s])
        else:
            inside = False
    arr = np.array(rows).reshape(-1, 3)
    return arr[:, 0], arr[:, 1], arr[:, 2]


def _growth(energy: np.ndarray) -> float:
    ok = energy.size > 1 and np.all(np.isfinite(energy)) and energy[0] > 0
    return float(energy.max() / energy[0]) if ok else math.inf


def _drive(python: str, packing, name: str, hook: dict | None, steps: int = STEPS) -> tuple[dict, str]:
    """The driver script run by ``python`` (the one with the LAMMPS module): its JSON output and LAMMPS's log."""
    work = packing["work"]
    cfg = {"scripts": str(SCRIPTS), "log": str(work / f"{name}.log"), "setup": _setup(packing),
           "style": STYLE, "steps": steps, "hook": None if hook is None else {"directory": str(work / name), **hook}}
    (work / f"{name}.json").write_text(json.dumps(cfg))
    (work / "driver.py").write_text(DRIVER)
    done = subprocess.run([python, str(work / "driver.py"), str(work / f"{name}.json")],
                          capture_output=True, text=True, timeout=300, cwd=work,
                          env=dict(os.environ, OMP_NUM_THREADS="1", OMPI_MCA_ess_singleton_isolated="1"))
    log = (work / f"{name}.log").read_text() if (work / f"{name}.log").exists() else ""
    assert done.returncode == 0, (done.stderr + log)[-2000:]
    return json.loads(done.stdout.splitlines()[-1]), log


def test_hook_keeps_a_packing_stable_at_a_step_that_blows_it_up(packing, lammps_python):
    """1.5 x dt_crit: the kinetic energy grows by more than 1e3 unhooked, stays within 10x hooked; the
    hook audits before each chunk of 500 steps and sets safety * min(dt_safe, dt_crit) exactly."""
    audit = packing["audit"]
    _, plain_log = _drive(lammps_python, packing, "plain", None)
    _, _, e_plain = _energies(plain_log)
    assert _growth(e_plain) > GROWING, f"unhooked run at {USER_FACTOR} x dt_crit did not grow"

    hooked, log = _drive(lammps_python, packing, "hooked", {"every": EVERY, "dtcrit": _dtcrit_command()})
    steps, dts, energy = _energies(log)
    assert _growth(energy) < BOUNDED, f"hooked run grew by {_growth(energy):.3g}"
    assert hooked["step"] == STEPS and steps[-1] == STEPS

    history = hooked["history"]
    assert [h["step"] for h in history] == list(range(0, STEPS, EVERY))
    assert [h.get("error") for h in history] == [None] * len(history)
    assert history[0]["dt_before"] == packing["dt_user"]
    for h in history:
        assert 0 < h["dt_safe"] <= h["dt_crit"] and h["dt"] == 0.9 * min(h["dt_safe"], h["dt_crit"])
        assert h["dt"] < h["dt_crit"] < packing["dt_user"]
        assert set(dts[(steps > h["step"]) & (steps < h["step"] + EVERY)]) == {h["dt"]}  # LAMMPS ran at it
    # the first audit is of the starting packing: LAMMPS's own dump, audited separately
    first = history[0]
    assert first["dt_crit"] == pytest.approx(audit["dt_crit"], rel=1e-9)
    assert first["dt"] == pytest.approx(0.9 * min(audit["dt_safe"], audit["dt_crit"]), rel=1e-9)
    # the last audit, repeated on the files the hook left, with the engine's contact list and without
    for extra in (("--local", hooked["local"]), ()):
        again = _audit(hooked["dump"], *extra)
        assert history[-1]["dt"] == 0.9 * min(again["dt_safe"], again["dt_crit"])
    assert hooked["dt"] == history[-1]["dt"]


LMP_ROUTE = [
    "variable dtcrit_now equal dt",
    "variable dtcrit_dt python dtcrit_dt",
    'python dtcrit_dt input 1 v_dtcrit_now return v_dtcrit_dt format ff here """',
    "import sys; sys.path.insert(0, {scripts!r})",
    "from lammps_hook import timestep_function",
    "dtcrit_dt = timestep_function({style!r}, 'dtcrit.dump', dtcrit={dtcrit!r})",
    '"""',
    "write_dump all custom dtcrit.dump id type x y z radius mass modify format float %.17g",
    "timestep $(v_dtcrit_dt:%.17g)",
    'run {steps} every {every} "write_dump all custom dtcrit.dump id type x y z radius mass modify format float '
    '%.17g" &',
    '                       "timestep $(v_dtcrit_dt:%.17g)"',
    'print "dtcrit-final-dt $(dt:%.17g)"',
]


def test_lmp_binary_route_with_a_python_variable(packing):
    """The recipe for the ``lmp`` binary (no LAMMPS Python module in the loop): bounded at a user step of
    1.5 x dt_crit, each chunk at 0.9 min(dt_safe, dt_crit), the last equal to a separate audit's."""
    lmp = require_engine("lammps")
    work = packing["work"] / "lmp_route"
    work.mkdir()
    text = "\n".join(_setup(packing) + [ln.format(scripts=str(SCRIPTS), style=STYLE, dtcrit=_dtcrit_command(),
                                                  steps=STEPS, every=EVERY) for ln in LMP_ROUTE]) + "\n"
    (work / "in.hooked").write_text(text)
    done = subprocess.run([lmp, "-in", "in.hooked", "-log", "log.lammps", "-screen", "none", "-nocite"], cwd=work,
                          capture_output=True, text=True, timeout=300,
                          env=dict(os.environ, OMP_NUM_THREADS="1", OMPI_MCA_ess_singleton_isolated="1"))
    log = (work / "log.lammps").read_text()
    assert done.returncode == 0 and "ERROR" not in log, log[-2000:]
    steps, dts, energy = _energies(log)
    assert _growth(energy) < BOUNDED and steps[-1] == STEPS
    chunks = [sorted(set(dts[(steps > s) & (steps < s + EVERY)])) for s in range(0, STEPS, EVERY)]
    assert all(len(c) == 1 and c[0] < packing["audit"]["dt_crit"] for c in chunks)
    assert chunks[0][0] == pytest.approx(0.9 * min(packing["audit"]["dt_safe"], packing["audit"]["dt_crit"]),
                                         rel=1e-9)
    # LAMMPS keeps a python variable's value as 15 significant digits: the step is the bound rounded down
    final = float(next(ln.split()[1] for ln in log.splitlines() if ln.startswith("dtcrit-final-dt")))
    again = _audit(work / "dtcrit.dump")
    bound = 0.9 * min(again["dt_safe"], again["dt_crit"])
    assert bound * (1 - 1e-14) < final <= bound and float(f"{final:.15g}") == final


def _fake_dtcrit(path: Path, dt_crit: float, dt_safe: float, fail: bool = False) -> str:
    """A stand-in for the dtcrit command: checks the command line and the files it is given."""
    path.write_text(f"""#!{sys.executable}
import json, sys
args = sys.argv[1:]
assert args[0] == "audit" and args[2:5] == ["--pair-style", {STYLE!r}, "--json"] and args[5] == "--local", args
assert open(args[1]).read().startswith("ITEM: TIMESTEP") and "ITEM: ENTRIES" in open(args[6]).read()
if {fail!r}:
    sys.stderr.write(args[1] + ":12: a stand-in's failure\\n")
    sys.exit(2)
print(json.dumps({{"dt_crit": {dt_crit!r}, "dt_safe": {dt_safe!r}}}))
""")
    path.chmod(path.stat().st_mode | stat.S_IXUSR)
    return str(path)


def test_hook_never_exceeds_dt_crit_and_raises_or_keeps_on_failure(packing, lammps_python, tmp_path):
    """Against stand-ins for dtcrit: a dt_safe above dt_crit is capped at dt_crit (safety 1); a failing
    audit raises with dtcrit's message, or with ``on_error="keep"`` keeps the user's step."""
    dt = packing["audit"]["dt_crit"]
    over = _fake_dtcrit(tmp_path / "over", dt_crit=dt, dt_safe=1.5 * dt)
    failing = _fake_dtcrit(tmp_path / "failing", dt_crit=dt, dt_safe=dt, fail=True)
    capped, _ = _drive(lammps_python, packing, "capped", {"dtcrit": over, "safety": 1.0}, steps=0)
    assert capped["returned"] == dt and capped["dt"] == dt
    kept, _ = _drive(lammps_python, packing, "kept", {"dtcrit": failing, "on_error": "keep", "every": 5}, steps=10)
    assert kept["dt"] == packing["dt_user"] and kept["step"] == 10
    assert len(kept["history"]) == 2 and all("a stand-in's failure" in h["error"] for h in kept["history"])
    raised, _ = _drive(lammps_python, packing, "raised", {"dtcrit": failing}, steps=10)
    assert "dtcrit hook at step 0:" in raised["raised"] and "a stand-in's failure" in raised["raised"]
    assert raised["step"] == 0 and raised["dt"] == packing["dt_user"]
