"""The helper sources emitted by ``dtcrit codegen`` (dtcrit/codegen/helper_sources) are real source
files: each compiles on its own (gcc -c, gfortran -c, Python compile), and the NumPy primitives are
the error-free transformations of dtcrit.numerics bit for bit.
"""
import shutil
import subprocess
from fractions import Fraction

import numpy as np
import pytest

from dtcrit.codegen.helpers import helper_source
from dtcrit.numerics.eft import two_product, two_sum

C_FILES = ("cubic_positive_root.c", "primitives.c")
FORTRAN_FILES = ("cubic_positive_root.f90", "primitives.f90")
PY_FILES = ("cubic_positive_root.py.txt", "primitives.py.txt")

# module procedures need a module around them (public here: no unused-function warning)
FORTRAN_MODULE = """module helper_sources_check
  use, intrinsic :: iso_c_binding, only: c_double
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
contains
{body}
end module helper_sources_check
"""


@pytest.mark.parametrize("name", C_FILES)
def test_c_helper_compiles(name, tmp_path):
    if shutil.which("gcc") is None:
        pytest.skip("gcc not installed")
    src = tmp_path / name
    src.write_text(helper_source(name))
    run = subprocess.run(["gcc", "-std=c99", "-Wall", "-Wno-unused-function", "-Werror", "-include", "math.h",
                          "-c", str(src), "-o", str(tmp_path / "out.o")], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr


@pytest.mark.parametrize("name", FORTRAN_FILES)
def test_fortran_helper_compiles(name, tmp_path):
    if shutil.which("gfortran") is None:
        pytest.skip("gfortran not installed")
    src = tmp_path / name
    src.write_text(FORTRAN_MODULE.format(body=helper_source(name)))
    run = subprocess.run(["gfortran", "-std=f2008", "-Wall", "-Werror", "-c", str(src), "-o", str(tmp_path / "out.o")],
                         capture_output=True, text=True, cwd=tmp_path)
    assert run.returncode == 0, run.stderr


@pytest.mark.parametrize("name", PY_FILES)
def test_numpy_helper_compiles(name):
    compile(helper_source(name), name, "exec")


def test_numpy_primitives_are_the_library_transforms():
    ns: dict = {"np": np}
    exec(compile(helper_source("primitives.py.txt"), "primitives.py.txt", "exec"), ns)
    rng = np.random.default_rng(17)
    a = rng.normal(size=500) * 2.0 ** rng.integers(-400, 400, size=500)
    b = rng.normal(size=500) * 2.0 ** rng.integers(-400, 400, size=500)
    assert np.array_equal(ns["_two_product_error"](a, b), two_product(a, b)[1])
    assert np.array_equal(ns["_two_sum_error"](a, b), two_sum(a, b)[1])
    m, e = ns["_mantissa"](a), ns["_exponent"](a)
    for x, mi, ei in zip(a[:50], m[:50], e[:50]):
        assert Fraction(float(mi)) * Fraction(2) ** int(ei) == Fraction(float(x))
        assert float(ns["_ldexp"](mi, ei)) == x
