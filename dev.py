#!/usr/bin/env python3
"""Set-up and task runner for dtcrit: needs only a Python >= 3.11 on the machine.

    python3 dev.py demo       create .venv if missing, install dtcrit (runtime dependencies only), run the main job
    python3 dev.py test       the same set-up with the test extras (pytest, hypothesis, Jupyter, ...), then the suite
    python3 dev.py generate   regenerate the committed generated code and derivation records (test extras)
    python3 dev.py golden     rewrite tests/golden (the outputs of ``dtcrit codegen`` and ``dtcrit step`` on every
                              example) after an intended change of output (test extras); review with git diff
    python3 dev.py mpi-env    create .venv-mpi, the environment of ``dtcrit packing --backend slepc`` (below)
    python3 dev.py audit-figure  redraw the docs' ``dtcrit audit --plot`` figure (docs/howto/audit.md; figures extra)
    python3 dev.py collide-figure  redraw the docs' ``dtcrit collide --plot`` figure (docs/howto/collide.md; figures extra)
    python3 dev.py docs       build the documentation site into docs/_build/html, warnings as errors (test extras);
                              open docs/_build/html/index.html
    python3 dev.py docs-bench rerun the benchmarks the docs' benchmarks page shows (dtcrit bench --quick --json and
                              a small scale benchmark) into docs/benchmarks/data, to commit (test extras; minutes)

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

``mpi-env`` (and ``test``, before the suite) builds ``.venv-mpi`` for the PETSc/SLEPc back-end: Debian's
petsc4py and slepc4py (``python3-petsc4py-real``, ``python3-slepc4py-real``, with ``openmpi-bin``;
installed with ``apt-get`` when missing and we are root, ``DTCRIT_NO_APT=1`` opts out) are built for
Debian's ``python3`` and a NumPy 1.x ABI, which ``.venv`` (NumPy 2) cannot load.  So ``.venv-mpi`` is a
virtual environment of that ``python3`` with ``--system-site-packages``, a ``.pth`` file naming the
real-number builds' module folders, NumPy ``>=1.26,<2`` (a newer 1.x keeps the ABI the modules were
built against), the other runtime dependencies at the pinned versions, and dtcrit itself (editable,
``--no-deps``).  It is used only for ``mpirun -n P .venv-mpi/bin/dtcrit packing ... --backend slepc``.
Debian's 64-bit-index builds (``python3-petsc4py-64-real``, ``python3-slepc4py-64-real``; optional:
``apt-get`` is asked for them only when the environment is (re)built, and once, remembered by
``.venv-mpi/.dtcrit-petsc64-apt-tried``, so a machine without network does not retry at every command)
are not on that path: their module folders are recorded in ``.venv-mpi/dtcrit-petsc64-dirs.txt``, and a
run whose particle count needs them (``6 N > 2^31 - 1``) or that asks for them (``--petsc-indices 64``)
puts them first before petsc4py is imported (``dtcrit.packing.distributed.petsc_build``); without them
that run refuses in one line (unless the default petsc4py is itself a 64-bit-index build).  The stamp's
digest covers both builds' folders, so a change of either rebuilds the environment.
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
AUDIT_FIGURE = ("audit", "examples/packings/random_lognormal_60.dump", "--pair-style",
                "gran/hertz/history 1e9 NULL 0 NULL 0.5 0", "--plot", "derivations/records/figures/audit_random_lognormal_60.png")
"""The ``dtcrit`` arguments that make the figure of ``docs/howto/audit.md`` (``python3 dev.py audit-figure``)."""
COLLIDE_FIGURE = ("collide", "examples/glass_spheres_hertz.toml", "--plot", "derivations/records/figures/collide_glass_spheres_hertz.png")
"""The ``dtcrit`` arguments that make the figure of ``docs/howto/collide.md`` (``python3 dev.py collide-figure``)."""


def run(*cmd: str | os.PathLike, env: dict | None = None) -> int:
    print("+", " ".join(str(c) for c in cmd), flush=True)
    return subprocess.call([str(c) for c in cmd], cwd=ROOT, env=env)


EXTRAS = {"demo": (), "test": ("test",), "generate": ("test",), "mpi-env": (), "golden": ("test",),
          "audit-figure": ("figures",), "collide-figure": ("figures",), "docs": ("test",), "docs-bench": ("test",)}
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


APT_TOOLS = {"gfortran": "gfortran", "lmp": "lammps", "yade": "yade", "chromium": "chromium", "chromedriver": "chromium-driver"}
"""Binaries the tests use -> the Debian package that provides them: gfortran compiles the emitted
Fortran; lmp (LAMMPS, GRANULAR package) and yade (YADE, leapfrog) run the engine cases that dtcrit's
steps are checked on; chromium and chromedriver open the built docs in the browser test."""

APT_FILES = {"/usr/share/javascript/mathjax/MathJax.js": "libjs-mathjax"}
"""Files the docs use -> the Debian package that provides them: MathJax, copied into the built site so
that its formulas render offline (``docs/conf.py``)."""

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
    missing += [pkg for path, pkg in APT_FILES.items() if not Path(path).is_file()]
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


MPI_VENV = ROOT / ".venv-mpi"
MPI_PY = MPI_VENV / "bin" / "python"
MPI_APT = {"python3-petsc4py-real": "usr/lib/petscdir/petsc3.*/*-real/lib/python3/dist-packages/petsc4py",
           "python3-slepc4py-real": "usr/lib/slepcdir/slepc3.*/*-real/lib/python3/dist-packages/slepc4py",
           "openmpi-bin": None}
"""Debian packages of the PETSc/SLEPc back-end -> where their module lands (Debian's layout: the
real-number builds with 32-bit indices, on no interpreter's path by default); ``None``: the package
gives ``mpirun``."""
MPI_APT_64 = {"python3-petsc4py-64-real": "usr/lib/petscdir/petsc64-3.*/*-real/lib/python3/dist-packages/petsc4py",
              "python3-slepc4py-64-real": "usr/lib/slepcdir/slepc64-3.*/*-real/lib/python3/dist-packages/slepc4py"}
"""Debian's real-number builds with 64-bit indices (``PetscInt`` of 64 bits, for ``6 N > 2^31 - 1`` DOFs) ->
where their module lands; optional: their folders go to ``PETSC64_RECORD``, not to the ``.pth`` file."""
PETSC64_RECORD = "dtcrit-petsc64-dirs.txt"
"""The file of ``.venv-mpi`` naming the 64-bit build's module folders, one a line (empty: not installed);
``dtcrit.packing.distributed.petsc_build.RECORD`` reads it."""
PETSC64_TRIED = ".dtcrit-petsc64-apt-tried"
"""The file of ``.venv-mpi`` saying ``apt-get`` was asked once for the 64-bit build (``ensure_mpi_env``)."""
MPI_RUNTIME = ("scipy", "sympy", "mpmath", "tqdm", "numba", "llvmlite")  # at their constraints.txt pins; NumPy 1.x
"""numba (with its llvmlite) runs the contact kernel of the matrix-free SLEPc route (``--slepc-matrix shell``);
its pin supports NumPy >= 1.22, so it loads beside the 1.x NumPy of Debian's petsc4py."""


def _apt_install(packages: list[str], why: str) -> bool:
    """``apt-get install`` of ``packages`` when root (retried after ``apt-get update``); DTCRIT_NO_APT=1 opts out.
    True when it was attempted.
    """
    apt = shutil.which("apt-get")
    if not packages or os.environ.get("DTCRIT_NO_APT") == "1" or not apt or not hasattr(os, "geteuid") or os.geteuid():
        return False
    print(f"installing {', '.join(packages)} with apt-get {why} (DTCRIT_NO_APT=1 opts out)", flush=True)
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    install = (apt, "install", "-y", "-q", "--no-install-recommends", *packages)
    if run(*install, env=env) != 0 and run(apt, "update", "-q", env=env) == 0:
        run(*install, env=env)
    return True


def _found(where):
    """``mpirun``'s path (``where`` None) or the first folder matching the glob ``where`` under ``/``."""
    return shutil.which("mpirun") if where is None else next(Path("/").glob(where), None)


def _petsc64_dirs() -> list[str]:
    """The 64-bit build's module folders (``MPI_APT_64``); [] without both (nothing installed here)."""
    found = [_found(where) for where in MPI_APT_64.values()]
    return [str(f.parent) for f in found] if all(found) else []


def _mpi_digest(dirs: list[str], dirs64: list[str]) -> str:
    """The stamp of ``.venv-mpi``: the project's pins, the module folders and the runtime it installs."""
    return hashlib.sha256((ROOT / "pyproject.toml").read_bytes() + (ROOT / "constraints.txt").read_bytes()
                          + " ".join(dirs + list(MPI_RUNTIME) + ["64:"] + dirs64).encode()).hexdigest()


def ensure_mpi_env() -> str | None:
    """Build or update ``.venv-mpi`` (module docstring); ``None`` when it is ready, else why not.

    The optional 64-bit build is installed with ``apt-get`` only when ``.venv-mpi`` is (re)built and
    only once (``PETSC64_TRIED`` remembers the attempt): a machine without network does not retry it.
    """
    _apt_install([pkg for pkg, where in MPI_APT.items() if not _found(where)], "for the PETSc/SLEPc back-end")
    if not all(_found(where) for where in MPI_APT.values()):
        return "needs apt-get install python3-slepc4py-real python3-petsc4py-real openmpi-bin (as root)"
    dirs = [str(_found(where).parent) for where in MPI_APT.values() if where]
    dirs64 = _petsc64_dirs()
    digest = _mpi_digest(dirs, dirs64)
    stamp = MPI_VENV / ".dtcrit-installed"
    if MPI_PY.exists() and stamp.exists() and stamp.read_text().strip() == digest:
        return None
    tried = MPI_VENV / PETSC64_TRIED
    if not dirs64 and not tried.exists() and _apt_install(list(MPI_APT_64), "for 64-bit PETSc indices (optional)"):
        MPI_VENV.mkdir(exist_ok=True)
        tried.write_text("apt-get install of the 64-bit PETSc build attempted; delete this file to retry\n")
        dirs64 = _petsc64_dirs()
        digest = _mpi_digest(dirs, dirs64)
    system_python = shutil.which("python3", path=os.defpath)  # Debian's, the one its modules are built for
    if not MPI_PY.exists() and (system_python is None
                                or run(system_python, "-m", "venv", "--system-site-packages", MPI_VENV) != 0):
        return "could not create .venv-mpi from the system's python3"
    site = subprocess.run([str(MPI_PY), "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"],
                          capture_output=True, text=True).stdout.strip()
    if not site:
        return ".venv-mpi has no working python (delete it and run again)"
    Path(site, "dtcrit-petsc-slepc.pth").write_text("".join(f"{d}\n" for d in dirs))
    (MPI_VENV / PETSC64_RECORD).write_text("".join(f"{d}\n" for d in dirs64))
    pins = [line.split("#")[0].strip() for line in (ROOT / "constraints.txt").read_text().splitlines()]
    pins = [pin for pin in pins if pin.split("==")[0] in MPI_RUNTIME]
    quiet = ["-q"] if os.environ.get("CI") else []
    check = "from petsc4py import PETSc; from slepc4py import SLEPc; import dtcrit.packing.distributed.slepc_backend"
    check64 = ("from dtcrit.packing.distributed.petsc_build import select_build; select_build(64); "
               "from petsc4py import PETSc; from slepc4py import SLEPc; assert PETSc.IntType().itemsize == 8")
    if (run(MPI_PY, "-m", "pip", "install", *quiet, "numpy>=1.26,<2", *pins)
            or run(MPI_PY, "-m", "pip", "install", *quiet, "--no-deps", "-e", ".") or run(MPI_PY, "-c", check)):
        return "installing dtcrit's runtime into .venv-mpi, or importing petsc4py and slepc4py there, failed"
    if dirs64 and run(MPI_PY, "-c", check64):
        print("the 64-bit-index petsc4py/slepc4py do not import (not fatal: runs that need them refuse)", flush=True)
        (MPI_VENV / PETSC64_RECORD).write_text("")
    stamp.write_text(digest)
    return None


def child_env() -> dict:
    env = dict(os.environ)
    env.setdefault("MPLBACKEND", "Agg")
    env["PATH"] = str(BIN) + os.pathsep + env.get("PATH", "")
    return env


def demo() -> int:
    return run(PY, "-m", "dtcrit", "step", DEMO_SCENE, env=child_env())


def mpi_env() -> int:
    why = ensure_mpi_env()
    if why:
        print(f".venv-mpi: {why}", file=sys.stderr)
        return 1
    print(".venv-mpi ready: mpirun -n P .venv-mpi/bin/dtcrit packing ... --backend slepc", flush=True)
    return 0


def test() -> int:
    ensure_apt_tools()
    why = ensure_mpi_env()
    if why:  # not fatal here: the PETSc/SLEPc tests skip, or fail under CI=true
        print(f".venv-mpi not built ({why}): the PETSc/SLEPc back-end tests will skip", flush=True)
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
    # the collision tables before the records: derivations/collision_findings.py reads them
    return (run(PY, "-m", "dtcrit.symbolic.regenerate", env=env) or run(PY, "-m", "dtcrit.collisions.tables", env=env)
            or run(PY, "-m", "dtcrit.bench.dense_table_writer", env=env)
            or run(PY, "derivations/run_all.py", *sys.argv[2:], env=env))


def golden() -> int:
    """Rewrite the golden files of ``tests/test_golden.py`` from the current code (``tests/support/golden.py``)."""
    return run(PY, "-m", "support.golden", env={**child_env(), "PYTHONPATH": str(ROOT / "tests")})


def audit_figure() -> int:
    """Redraw the docs' ``dtcrit audit --plot`` figure on the example dump (``AUDIT_FIGURE``)."""
    return run(PY, "-m", "dtcrit", *AUDIT_FIGURE, env=child_env())


def collide_figure() -> int:
    """Redraw the docs' ``dtcrit collide --plot`` figure on the Hertz example (``COLLIDE_FIGURE``)."""
    return run(PY, "-m", "dtcrit", *COLLIDE_FIGURE, env=child_env())


DOCS_BUILD = ("-b", "html", "-W", "--keep-going", "-n", "-E", "-q")
"""``sphinx-build`` options of the site (``python3 dev.py docs`` and ``tests/docs/conftest.py``): warnings
are errors (all reported before failing), every cross-reference must resolve, and every page is re-read
(an incremental build would not repeat an unchanged page's warnings); the notebooks' executions are
cached in ``docs/_build/.jupyter_cache``, so they are not re-run."""


def docs() -> int:
    """Build the site (``docs/``) into a fresh ``docs/_build/html`` with ``DOCS_BUILD``'s options."""
    shutil.rmtree(ROOT / "docs" / "_build" / "html", ignore_errors=True)  # no page of an earlier build survives
    return run(PY, "-m", "sphinx", *DOCS_BUILD, *sys.argv[2:], "docs", "docs/_build/html", env=child_env())


def docs_bench() -> int:
    """Rerun the committed benchmarks of the docs (``docs/_gen/benchmarks.py``, ``run_benchmarks``)."""
    code = "import sys; sys.path.insert(0, 'docs/_gen'); import benchmarks; print(benchmarks.run_benchmarks())"
    return run(PY, "-c", code, env=child_env())


TASKS = {"demo": demo, "test": test, "generate": generate, "mpi-env": mpi_env, "golden": golden,
         "audit-figure": audit_figure, "collide-figure": collide_figure, "docs": docs,
         "docs-bench": docs_bench}

if __name__ == "__main__":
    if len(sys.argv) < 2 or sys.argv[1] not in TASKS:
        sys.exit("usage: python3 dev.py {%s} [args]" % "|".join(TASKS))
    ensure_venv(EXTRAS[sys.argv[1]])
    compile_sources()
    sys.exit(TASKS[sys.argv[1]]())
