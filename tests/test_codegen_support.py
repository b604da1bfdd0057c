"""Support for the codegen tests: compile emitted C (system ``cc``) and Fortran (``gfortran`` when
present) into shared libraries called through ctypes, import emitted NumPy, measure ulps."""
import ctypes
import functools
import hashlib
import importlib.util
import math
import shutil
import subprocess
import tempfile
from pathlib import Path

import pytest

from dtcrit.codegen import build_kernel, render

CC = shutil.which("cc") or shutil.which("gcc")
GFORTRAN = shutil.which("gfortran")
FORTRAN_SKIP = "gfortran is not installed on this machine: the emitted Fortran cannot be compiled here (not installed on purpose)"
_BUILD = Path(tempfile.mkdtemp(prefix="dtcrit-codegen-tests-"))


def ulps(got: float, ref) -> float:
    """|got - ref| in units in the last place of float(ref)."""
    r = float(ref)
    if r == 0.0:
        return 0.0 if got == 0.0 else math.inf
    return abs(got - r) / math.ulp(r)


def _build(source: str, suffix: str, command) -> Path:
    digest = hashlib.sha256(source.encode()).hexdigest()[:16]
    src = _BUILD / f"k_{digest}{suffix}"
    lib = _BUILD / f"k_{digest}.so"
    if not lib.exists():
        src.write_text(source)
        subprocess.run(command(src, lib), check=True, capture_output=True, cwd=_BUILD)
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
    lib = _build(source, ".c", lambda s, o: [CC, "-std=c99", "-O2", "-Wall", "-Werror", "-shared", "-fPIC", "-o", str(o), str(s), "-lm"])
    return _bind(lib, name, len(kernel.arguments))


@functools.lru_cache(maxsize=None)
def fortran_function(kernel, name="dtcrit_dt_crit"):
    if GFORTRAN is None:
        pytest.skip(FORTRAN_SKIP)
    source = render(kernel, "fortran", name)
    lib = _build(source, ".f90", lambda s, o: [GFORTRAN, "-std=f2008", "-O2", "-Wall", "-shared", "-fPIC", "-o", str(o), str(s)])
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
