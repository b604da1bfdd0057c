"""The compilers the codegen checks use: the system C compiler (mandatory) and gfortran."""
import subprocess

from support.codegen import CC, GFORTRAN, require_gfortran


def test_c_compiler_is_available():
    """The C checks are mandatory: the system compiler must exist."""
    assert CC is not None


def test_fortran_compiler_is_available():
    """Said once, with its reason, when the Fortran checks cannot run (a failure under CI=true)."""
    require_gfortran()
    version = subprocess.run([GFORTRAN, "--version"], capture_output=True, text=True, check=True).stdout
    assert "Fortran" in version
