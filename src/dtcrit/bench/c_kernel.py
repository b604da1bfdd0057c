"""The careful critical steps emitted as C, compiled once, called over arrays via ctypes.

``dtcrit.codegen.step`` prints the careful step dt(k, c, A) of each integrator
(``dtcrit.symbolic.careful_forms``: the forms of ``dtcrit.integrators.precise`` -- exact
power-of-two scaling from the larger rate, forward Euler's error-free residual, the cubic's
identity -- with NaN for NaN or negative inputs); this adapter adds one loop per integrator,
``dt_<integrator>(k, c, A, out, n)``, over arrays.  It is the same C that ``dtcrit codegen``
emits into the per-contact kernels.

Compiled with the system C compiler (``$CC`` or ``cc``) as ``-O2 -std=c99 -ffp-contract=off``
(IEEE semantics, no fused multiply-add contraction) into a cache directory under the system's
temporary directory, keyed by a hash of the source.  SymPy is needed only to build the source.
"""
from __future__ import annotations

import ctypes
import hashlib
import os
import shutil
import subprocess
import tempfile
from functools import lru_cache
from pathlib import Path

import numpy as np

from dtcrit.integrators.schemes import NAMES

_LOOP_C = r"""
void NAME(const double *k, const double *c, const double *A, double *out, long n)
{
    long i;
    for (i = 0; i < n; ++i) out[i] = STEP(k[i], c[i], A[i]);
}
"""


def c_name(integrator: str) -> str:
    """The C function name of an integrator's emitted step (``dt_`` and the name with ``-`` as ``_``).

    Parameters
    ----------
    integrator : str
        Name of the scheme.

    Returns
    -------
    str
        The C identifier.
    """
    return "dt_" + integrator.replace("-", "_")


@lru_cache(maxsize=None)
def c_source() -> str:
    """C99 source with one array function ``dt_<integrator>(k, c, A, out, n)`` per integrator."""
    from dtcrit.codegen.step import c_function, c_support

    parts = ["/* Careful critical steps dt(k, c, A) of explicit integrators over arrays: emitted by",
             "   dtcrit.codegen.step from dtcrit.symbolic.careful_forms (Peng et al. 2020, Eqs. (29)-(30)). */",
             "#include <math.h>", ""]
    for name in NAMES:
        prefix = f"step_{c_name(name)}"
        parts.append(c_support(name, prefix))
        parts.append(c_function(name, prefix, prefix, True))
        parts.append(_LOOP_C.replace("NAME", c_name(name)).replace("STEP", prefix))
    return "\n".join(parts) + "\n"


def compiler() -> str | None:
    """The C compiler the compiled route uses (``$CC``, else ``cc``), if it is on the path.

    Returns
    -------
    str or None
        Path of the compiler, or None when there is none.
    """
    cc = os.environ.get("CC") or "cc"
    return shutil.which(cc)


@lru_cache(maxsize=None)
def _library() -> ctypes.CDLL:
    cc = compiler()
    if cc is None:
        raise RuntimeError("no C compiler found (set CC or install cc): the emitted-C route cannot run")
    src = c_source()
    digest = hashlib.sha256(src.encode()).hexdigest()[:16]
    folder = Path(tempfile.gettempdir()) / f"dtcrit-bench-c-{digest}"
    lib = folder / "critical_steps.so"
    if not lib.exists():
        folder.mkdir(parents=True, exist_ok=True)
        (folder / "critical_steps.c").write_text(src)
        tmp = folder / f"critical_steps.{os.getpid()}.so"
        cmd = [cc, "-O2", "-std=c99", "-ffp-contract=off", "-fPIC", "-shared", "-o", str(tmp),
               str(folder / "critical_steps.c"), "-lm"]
        done = subprocess.run(cmd, capture_output=True, text=True)
        if done.returncode != 0:
            raise RuntimeError(f"compiling the emitted C failed: {done.stderr.strip()}")
        os.replace(tmp, lib)
    dll = ctypes.CDLL(str(lib))
    dptr = ctypes.POINTER(ctypes.c_double)
    for name in NAMES:
        f = getattr(dll, c_name(name))
        f.argtypes = [dptr, dptr, dptr, dptr, ctypes.c_long]
        f.restype = None
    return dll


def critical_dt_c(integrator: str, k, c, A) -> np.ndarray:
    """Critical step [s] by the compiled C kernel, for float arrays k, c, A (broadcast): 0 where no
    positive float64 step is stable, inf where the step lies beyond float64, NaN for bad input.

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].

    Returns
    -------
    numpy.ndarray
        The critical steps [s], flattened.
    """
    k, c, A = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (k, c, A)))
    k, c, A = (np.ascontiguousarray(v.ravel()) for v in (k, c, A))
    out = np.empty(k.size)
    dptr = ctypes.POINTER(ctypes.c_double)
    fn = getattr(_library(), c_name(integrator))
    fn(k.ctypes.data_as(dptr), c.ctypes.data_as(dptr), A.ctypes.data_as(dptr), out.ctypes.data_as(dptr), k.size)
    return out
