"""The closed-form critical steps emitted as C, compiled once, called over arrays via ctypes.

``dtcrit.codegen`` emits per-contact kernels for a scene (arguments m, I, r, k, c, ...); the bench
needs the bare critical step of one integrator over arrays of (k, c, A).  This adapter builds it
from the *same* SymPy expression the NumPy kernels are generated from
(``dtcrit.symbolic.stability_codegen.kernel_expr``, dt(omega, gamma)) and prints it with
``dtcrit.codegen.printers.CPrinter`` (``hypot``, ternaries for the pieces, the cubic helper).
Around it, a loop does what ``dtcrit.integrators.stability.scaled_rates`` does in NumPy: split k, c, A into
mantissa and exponent (``frexp``), form omega' = sqrt(mk mA [2]) and gamma' = mc mA/2 2^(ec+eA-s)
and undo the power-of-two scale with ``ldexp`` -- exact, so any float inputs work.

The cubic helper (paper-eq40) follows the generated NumPy preamble's algorithm: Viete's
trigonometric form for three real roots, the hyperbolic forms otherwise, three Newton steps.

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

HELPER = "dtcrit_cubic_positive_root"

_CUBIC_C = r"""
static double HELPER(double a2, double a1, double a0, int largest)
{
    /* smallest (largest if `largest`) positive real root of t^3 + a2 t^2 + a1 t + a0; 0 if none */
    const double pi = 3.14159265358979323846;
    double shift = a2 / 3.0;
    double p = a1 - a2 * shift;
    double q = (2.0 * shift * shift - a1) * shift + a0;
    double cand[3];
    int n = 0;
    if (p < 0.0 && q * q / 4.0 + p * p * p / 27.0 <= 0.0) {
        double r = 2.0 * sqrt(-p / 3.0);
        double arg = r > 0.0 ? 4.0 * q / (r * r * r) : 0.0;
        if (arg > 1.0) arg = 1.0;
        if (arg < -1.0) arg = -1.0;
        double phi = acos(-arg) / 3.0;
        for (int j = 0; j < 3; ++j) cand[n++] = r * cos(phi - 2.0 * pi * j / 3.0) - shift;
    } else {
        double sp3 = sqrt(fabs(p) / 3.0);
        double pos = sp3 > 0.0 ? sp3 : 1.0;
        double one;
        if (p > 0.0) {
            one = -2.0 * sp3 * sinh(asinh(1.5 * q / (fabs(p) * pos)) / 3.0);
        } else if (p < 0.0) {
            double x = 1.5 * fabs(q) / (fabs(p) * pos);
            double sq = (q > 0.0) - (q < 0.0);
            one = -2.0 * sq * sp3 * cosh(acosh(x > 1.0 ? x : 1.0) / 3.0);
        } else {
            one = -cbrt(q);
        }
        cand[n++] = one - shift;
    }
    double t = largest ? -INFINITY : INFINITY;
    for (int j = 0; j < n; ++j) {
        if (cand[j] > 0.0) {
            if (largest ? cand[j] > t : cand[j] < t) t = cand[j];
        }
    }
    for (int it = 0; it < 3; ++it) {
        double g = ((t + a2) * t + a1) * t + a0;
        double dg = (3.0 * t + 2.0 * a2) * t + a1;
        if (isfinite(t) && dg != 0.0) t = t - g / dg;
    }
    return isfinite(t) ? t : 0.0;
}
""".replace("HELPER", HELPER)

_LOOP_C = r"""
void NAME(const double *k, const double *c, const double *A, double *out, long n)
{
    for (long i = 0; i < n; ++i) {
        int ek, ec, eA;
        double mk = frexp(k[i], &ek), mc = frexp(c[i], &ec), mA = frexp(A[i], &eA);
        int e = ek + eA;
        int odd = e & 1;
        double omega = sqrt(mk * mA * (odd ? 2.0 : 1.0));
        int s = (e - odd) / 2;
        double gamma = ldexp(mc * mA * 0.5, ec + eA - s);
        out[i] = ldexp(KERNEL(omega, gamma), -s);
    }
}
"""


def c_name(integrator: str) -> str:
    return "dt_" + integrator.replace("-", "_")


@lru_cache(maxsize=None)
def c_source() -> str:
    """C99 source with one array function ``dt_<integrator>(k, c, A, out, n)`` per integrator."""
    import sympy as sp

    from dtcrit.codegen.kernel import cubic_positive_root
    from dtcrit.codegen.printers import CPrinter
    from dtcrit.symbolic.closed_forms import gamma, omega
    from dtcrit.symbolic.stability_codegen import CUBIC_ROOT, kernel_expr

    printer = CPrinter(HELPER)
    parts = [
        "/* Critical time steps dt(k, c, A) of explicit integrators: emitted by dtcrit.bench.c_kernel",
        "   from dtcrit.symbolic.stability_codegen.kernel_expr (Peng et al. 2020, Eqs. (29)-(30)). */",
        "#include <math.h>",
        _CUBIC_C,
    ]
    w, g = sp.Symbol("omega", positive=True), sp.Symbol("gamma", positive=True)
    for name in NAMES:
        expr = kernel_expr(name).replace(CUBIC_ROOT, cubic_positive_root).subs({omega: w, gamma: g})
        body = printer.doprint(expr)
        kernel = f"kernel_{c_name(name)}"
        parts.append(f"static double {kernel}(double omega, double gamma)\n{{\n    return {body};\n}}")
        parts.append(_LOOP_C.replace("NAME", c_name(name)).replace("KERNEL", kernel))
    return "\n".join(parts) + "\n"


def compiler() -> str | None:
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
    """Critical step [s] by the compiled C kernel, for float arrays k, c, A (broadcast)."""
    k, c, A = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (k, c, A)))
    k, c, A = (np.ascontiguousarray(v.ravel()) for v in (k, c, A))
    out = np.empty(k.size)
    dptr = ctypes.POINTER(ctypes.c_double)
    fn = getattr(_library(), c_name(integrator))
    fn(k.ctypes.data_as(dptr), c.ctypes.data_as(dptr), A.ctypes.data_as(dptr), out.ctypes.data_as(dptr), k.size)
    return out
