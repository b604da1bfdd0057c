#!/usr/bin/env python3
"""Set-up and task runner for dtcrit: needs only a Python >= 3.11 on the machine.

    python3 dev.py demo       create .venv if missing, install dtcrit (runtime dependencies only), run the main job
    python3 dev.py test       the same set-up with the test extras (pytest, hypothesis, Jupyter, ...), then the suite
    python3 dev.py generate   regenerate the committed generated code and derivation records (test extras)

Every task creates the virtual environment ``.venv`` beside this file when it is missing,
(re)installs the package whenever ``pyproject.toml`` or ``constraints.txt`` (the pinned versions)
changed since the last install or the task needs extras the last install did not have (``demo``
needs none: NumPy, SciPy, SymPy, mpmath, tqdm; ``test`` and ``generate`` the ``test`` extra), and
byte-compiles ``src`` (cheap when up to date), so that with ``PYTHONDONTWRITEBYTECODE=1`` dtcrit
is not recompiled at every start.  ``test`` also installs ``gfortran``, LAMMPS (``lmp``, and its Python
module for the system's ``python3``) and YADE (``yade``) with ``apt-get`` when they are missing and we
are root, so the emitted Fortran is compiled and the engine cases and hooks run (never fatal here:
without them those tests skip, except under ``CI=true``, where the engine tests fail;
``DTCRIT_NO_APT=1`` opts out).
"""
from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent
VENV = ROOT / ".venv"
BIN = VENV / ("Scripts" if os.name == "nt" else "bin")
PY = BIN / ("python.exe" if os.name == "nt" else "python")
STAMP = VENV / ".dtcrit-installed"

DEMO_SCENE = "examples/paper_ellipsoids.toml"


def run(*cmd: str | os.PathLike, env: dict | None = None) -> int:
    print("+", " ".join(str(c) for c in cmd), flush=True)
    return subprocess.call([str(c) for c in cmd], cwd=ROOT, env=env)


EXTRAS = {"demo": (), "test": ("test",), "generate": ("test",)}
"""The optional dependency groups of pyproject.toml each task installs: the demo runs on the runtime
dependencies alone; the tests (and the derivation scripts behind ``generate``) need the ``test`` extra."""


def _installed() -> tuple[str, set[str]]:
    """(digest of pyproject.toml + constraints.txt, extras) of the last install, from the stamp."""
    if not STAMP.exists():
        return "", set()
    digest, _, extras = STAMP.read_text().strip().partition(" ")
    return digest, set(filter(None, extras.split(",")))


def ensure_venv(extras: tuple[str, ...] = ()) -> None:
    if sys.version_info < (3, 11):
        sys.exit("dtcrit needs Python >= 3.11 (found %s)" % sys.version.split()[0])
    if not PY.exists():
        if run(sys.executable, "-m", "venv", VENV) != 0:
            sys.exit("could not create the virtual environment .venv")
    digest = hashlib.sha256((ROOT / "pyproject.toml").read_bytes() + (ROOT / "constraints.txt").read_bytes()).hexdigest()
    done, had = _installed()
    if done == digest and set(extras) <= had:
        return
    wanted = sorted(set(extras) | (had if done == digest else set()))
    quiet = ["-q"] if os.environ.get("CI") else []
    if run(PY, "-m", "pip", "install", *quiet, "--upgrade", "pip") != 0:
        sys.exit("pip upgrade failed")
    target = "." + (f"[{','.join(wanted)}]" if wanted else "")
    if run(PY, "-m", "pip", "install", *quiet, "-c", "constraints.txt", "-e", target) != 0:
        sys.exit("installing dtcrit" + (f" with {', '.join(wanted)} extras" if wanted else "") + " failed")
    STAMP.write_text(f"{digest} {','.join(wanted)}")


def compile_sources() -> None:
    """Write the bytecode of ``src`` (compileall skips modules whose .pyc is up to date)."""
    if run(PY, "-m", "compileall", "-q", "src") != 0:
        print("byte-compiling src failed (not fatal: Python compiles on import)", flush=True)


APT_TOOLS = {"gfortran": "gfortran", "lmp": "lammps", "yade": "yade"}
"""Binaries the tests use -> the Debian package that provides them: gfortran compiles the emitted
Fortran; lmp (LAMMPS, GRANULAR package) and yade (YADE, leapfrog) run the engine cases that dtcrit's
steps are checked on."""

APT_PYTHON_MODULES = {"lammps": ("python3-lammps", "liblammps-dev")}
"""Modules of the system's ``python3`` (not this environment's) the tests use -> the Debian packages
that provide them: the LAMMPS Python module runs the LAMMPS hook (``engine_scripts/lammps_hook.py``)."""


def system_python_has(module: str) -> bool:
    """True when a ``python3`` on PATH outside ``.venv`` imports ``module`` (Debian's python3-* packages
    install for the system's interpreter, which dtcrit's environment does not see)."""
    for folder in os.environ.get("PATH", "").split(os.pathsep):
        exe = shutil.which("python3", path=folder) if folder else None
        if exe is None or Path(exe).parent.resolve() == BIN.resolve():
            continue
        try:
            if subprocess.run([exe, "-c", f"import {module}"], capture_output=True, timeout=60).returncode == 0:
                return True
        except (OSError, subprocess.TimeoutExpired):
            continue
    return False


def ensure_apt_tools() -> None:
    """Install the missing ``APT_TOOLS`` with apt-get (root only; DTCRIT_NO_APT=1 opts out).

    Never fatal here: a test that needs a missing tool skips, saying how to install it, except in CI
    (``CI=true``), where the engine tests fail instead.
    """
    missing = [pkg for tool, pkg in APT_TOOLS.items() if not shutil.which(tool)]
    missing += [pkg for module, pkgs in APT_PYTHON_MODULES.items() if not system_python_has(module) for pkg in pkgs]
    if not missing or os.environ.get("DTCRIT_NO_APT") == "1":
        return
    apt = shutil.which("apt-get")
    if apt is None or not hasattr(os, "geteuid") or os.geteuid() != 0:
        print(f"missing {', '.join(missing)} and cannot install here (needs apt-get as root): "
              "the tests that need them will skip", flush=True)
        return
    print(f"installing {', '.join(missing)} with apt-get for the tests (DTCRIT_NO_APT=1 opts out)", flush=True)
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    install = (apt, "install", "-y", "-q", "--no-install-recommends", *missing)
    if run(*install, env=env) == 0:
        return
    if run(apt, "update", "-q", env=env) == 0 and run(*install, env=env) == 0:
        return
    print(f"installing {', '.join(missing)} failed (not fatal): the tests that need them will skip", flush=True)


def child_env() -> dict:
    env = dict(os.environ)
    env.setdefault("MPLBACKEND", "Agg")
    env["PATH"] = str(BIN) + os.pathsep + env.get("PATH", "")
    return env


def demo() -> int:
    return run(PY, "-m", "dtcrit", "step", DEMO_SCENE, env=child_env())


def test() -> int:
    ensure_apt_tools()
    env = child_env()
    env.setdefault("HYPOTHESIS_PROFILE", "ci")
    # two pytest workers on two cores: BLAS's own threads would only compete with them
    for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        env.setdefault(var, "1")
    workers = os.environ.get("DTCRIT_TEST_WORKERS", "2")
    rc = run(PY, "-m", "pytest", "-q", "-n", workers, "--dist", "loadfile", *sys.argv[2:], env=env)
    return 0 if rc == 5 else rc  # 5: no tests collected


def generate() -> int:
    env = child_env()
    return run(PY, "-m", "dtcrit.symbolic.regenerate", env=env) or run(PY, "derivations/run_all.py", *sys.argv[2:], env=env)


TASKS = {"demo": demo, "test": test, "generate": generate}

if __name__ == "__main__":
    if len(sys.argv) < 2 or sys.argv[1] not in TASKS:
        sys.exit("usage: python3 dev.py {%s} [args]" % "|".join(TASKS))
    ensure_venv(EXTRAS[sys.argv[1]])
    compile_sources()
    sys.exit(TASKS[sys.argv[1]]())
