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
import math
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

import pytest

from dtcrit.codegen import build_kernel, render

CC = shutil.which("cc") or shutil.which("gcc")
GFORTRAN = shutil.which("gfortran")
FORTRAN_SKIP = ("gfortran is not on PATH, so the emitted Fortran cannot be compiled here (python3 dev.py test installs it "
                "with apt-get when run as root, unless DTCRIT_NO_APT=1)")
C_FLAGS = ("-std=c99", "-pedantic", "-Wall", "-Wextra", "-Werror")
FORTRAN_FLAGS = ("-std=f2008", "-pedantic", "-fimplicit-none", "-Wall", "-Wextra", "-Wno-compare-reals",
                 "-Wconversion-extra", "-Werror")
_BUILD = Path(tempfile.mkdtemp(prefix="dtcrit-codegen-tests-"))


def ulps(got: float, ref) -> float:
    """|got - ref| in units in the last place of float(ref)."""
    r = float(ref)
    if r == 0.0:
        return 0.0 if got == 0.0 else math.inf
    return abs(got - r) / math.ulp(r)


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


def in_ci() -> bool:
    """True under CI (``CI`` set to true, 1 or yes), where a missing compiler fails instead of skipping."""
    return os.environ.get("CI", "").strip().lower() in {"true", "1", "yes"}


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


@functools.lru_cache(maxsize=None)
def numpy_function(kernel, name="dtcrit_dt_crit"):
    source = render(kernel, "numpy", name)
    digest = hashlib.sha256(source.encode()).hexdigest()[:16]
    path = _BUILD / f"k_{digest}.py"
    path.write_text(source)
    spec = importlib.util.spec_from_file_location(f"emitted_{digest}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    f = getattr(module, name)
    return lambda *args: float(f(*args))


@functools.lru_cache(maxsize=None)
def kernel_for(structure):
    return build_kernel(structure)


def test_c_compiler_is_available():
    """The C checks are mandatory: the system compiler must exist."""
    assert CC is not None


def test_fortran_compiler_is_available():
    """Said once, with its reason, when the Fortran checks cannot run (a failure under CI=true)."""
    require_gfortran()
    version = subprocess.run([GFORTRAN, "--version"], capture_output=True, text=True, check=True).stdout
    assert "Fortran" in version
