"""Support for the codegen tests: compile emitted C (system ``cc``) and Fortran (``gfortran`` when
present; ``python3 dev.py test`` installs it) into shared libraries called through ctypes, import
emitted NumPy, measure ulps.

Both compilers run in their strictest standard mode with every warning an error.  For gfortran,
``-Wextra`` less ``-Wcompare-reals``: the cubic helper's exact comparisons with zero are deliberate
guards (the C helper has the same ones)."""
import ctypes
import functools
import hashlib
import importlib.util
import shutil
import subprocess
import tempfile
from pathlib import Path

import pytest

from dtcrit.codegen import build_kernel, render
from support.ci import in_ci

CC = shutil.which("cc") or shutil.which("gcc")
GFORTRAN = shutil.which("gfortran")
FORTRAN_SKIP = ("gfortran is not on PATH, so the emitted Fortran cannot be compiled here (python3 dev.py test installs it "
                "with apt-get when run as root, unless DTCRIT_NO_APT=1)")
C_FLAGS = ("-std=c99", "-pedantic", "-Wall", "-Wextra", "-Werror")
FORTRAN_FLAGS = ("-std=f2008", "-pedantic", "-fimplicit-none", "-Wall", "-Wextra", "-Wno-compare-reals",
                 "-Wconversion-extra", "-Werror")
_BUILD = Path(tempfile.mkdtemp(prefix="dtcrit-codegen-tests-"))


def _build(source: str, suffix: str, command) -> Path:
    """Compile once per (source, command); a failure fails the test with the compiler's messages."""
    digest = hashlib.sha256((source + repr(command(Path("s"), Path("o")))).encode()).hexdigest()[:16]
    src = _BUILD / f"k_{digest}{suffix}"
    lib = _BUILD / f"k_{digest}.so"
    if not lib.exists():
        src.write_text(source)
        p = subprocess.run(command(src, lib), capture_output=True, text=True, cwd=_BUILD)
        if p.returncode != 0:
            pytest.fail(f"{' '.join(command(src, lib))} failed:\n{p.stdout}{p.stderr}")
    return lib


def _bind(lib: Path, name: str, nargs: int):
    f = getattr(ctypes.CDLL(str(lib)), name)
    f.restype = ctypes.c_double
    f.argtypes = [ctypes.c_double] * nargs
    return f


@functools.lru_cache(maxsize=None)
def c_function(kernel, name="dtcrit_dt_crit"):
    if CC is None:
        pytest.fail("no system C compiler (cc) found")
    source = render(kernel, "c", name)
    lib = _build(source, ".c", lambda s, o: [CC, *C_FLAGS, "-O2", "-shared", "-fPIC", "-o", str(o), str(s), "-lm"])
    return _bind(lib, name, len(kernel.arguments))


def require_gfortran() -> None:
    """Skip without gfortran (fail under ``CI=true``: the Fortran checks are never skipped there)."""
    if GFORTRAN is None:
        if in_ci():
            pytest.fail(FORTRAN_SKIP + " -- and under CI=true the Fortran checks must run", pytrace=False)
        pytest.skip(FORTRAN_SKIP)


def fortran_library(source: str, extra_flags: tuple[str, ...] = ()) -> Path:
    """Emitted Fortran compiled with ``FORTRAN_FLAGS`` (and ``extra_flags``); skips without gfortran
    (fails under ``CI=true``)."""
    require_gfortran()
    return _build(source, ".f90", lambda s, o: [GFORTRAN, *FORTRAN_FLAGS, "-O2", *extra_flags, "-shared", "-fPIC",
                                                "-o", str(o), str(s)])


@functools.lru_cache(maxsize=None)
def fortran_function(kernel, name="dtcrit_dt_crit", extra_flags: tuple[str, ...] = ()):
    lib = fortran_library(render(kernel, "fortran", name), extra_flags)
    return _bind(lib, name, len(kernel.arguments))


def import_emitted(source: str, name: str, prefix: str = "k"):
    """Import emitted NumPy source from a file in the build folder.

    Parameters
    ----------
    source : str
        The emitted module's text.
    name : str
        The function to return.
    prefix : str
        File-name prefix in the build folder (the digest of the source follows it).

    Returns
    -------
    callable
        The emitted function, its result converted to a Python float.
    """
    digest = hashlib.sha256(source.encode()).hexdigest()[:16]
    path = _BUILD / f"{prefix}_{digest}.py"
    path.write_text(source)
    spec = importlib.util.spec_from_file_location(f"emitted_{prefix}_{digest}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    f = getattr(module, name)
    return lambda *args: float(f(*args))


@functools.lru_cache(maxsize=None)
def numpy_function(kernel, name="dtcrit_dt_crit"):
    return import_emitted(render(kernel, "numpy", name), name)


@functools.lru_cache(maxsize=None)
def kernel_for(structure):
    return build_kernel(structure)
