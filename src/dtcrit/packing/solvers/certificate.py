"""A certified critical step: a bracket that holds whether or not the eigen-solver converged.

An iterative eigen-solver returns a Ritz value ``theta``, a Rayleigh quotient of ``A = M^(-1/2) K
M^(-1/2)``, so ``theta <= lambda_max`` always: ``dt = 2/sqrt(theta)`` is a rigorous *upper* bound on
the critical step, but an unconverged (or mis-converged) ``theta`` gives a step that is too large.
Two things close the bracket from below:

* ``dt_safe`` -- the larger of the block-diagonal and Gershgorin steps (``dtcrit.packing.bounds.estimates``),
  rigorous lower bounds on the critical step, always available;
* a **certificate** that no eigenvalue of ``A`` lies above ``sigma = theta (1 + tol)``, i.e. that
  ``sigma I - A`` is positive definite.  By Sylvester's law of inertia a congruence
  ``sigma I - A = P L D L^T P^T`` (``L`` unit lower triangular) has as many negative pivots in ``D`` as
  ``A`` has eigenvalues above ``sigma``.  Routes:

  - ``dense`` (up to ``DENSE_DOFS``): LAPACK ``dsytrf`` (Bunch-Kaufman pivoting,
    backward stable for any symmetric matrix), which counts the eigenvalues above ``sigma``;
  - ``sparse`` (up to ``SPARSE_DOFS``): SuperLU (``scipy.sparse.linalg.splu``) in symmetric mode with
    a symmetric minimum-degree ordering and *no* pivoting (``diag_pivot_thresh=0``), checked to have
    kept the row order equal to the column order (``perm_r == perm_c``): then ``P^T S P = L U`` with
    ``U = D L^T`` is a symmetric elimination, i.e. ``LDL^T``.  Without pivoting the signs of ``D`` are
    trusted only when all are positive: that is a Cholesky factorisation (backward stable), and it
    proves ``sigma I - A`` positive definite.  A non-positive pivot proves nothing either way and is
    reported as "not certified" (the bracket then falls back to ``dt_safe``).  (With partial
    pivoting the signs of ``U``'s diagonal would not give the inertia; that is why pivoting is off
    and checked.)  Measured against ``qdldl`` (AMD, no pivoting): 9 s against 71 s at 24k DOFs of
    jittered FCC, so SciPy's SuperLU is used and no new dependency is needed.

  Rounding: the computed factors are exact for ``sigma I - A + E`` with ``|E|`` of order
  ``n eps |A|`` (Higham, *Accuracy and Stability of Numerical Algorithms*, Thm 10.3 / 11.3), which is
  ``<= 1e-10 lambda_max`` up to ``SPARSE_DOFS``, far inside the margin ``tol = 1e-6``.

Then ``2/sqrt(sigma) <= dt_crit_true <= 2/sqrt(theta)``.  Above ``SPARSE_DOFS`` the factorisation's
fill-in (measured below) makes the certificate too costly; the bracket is ``[dt_safe, 2/sqrt(theta)]``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sps
import scipy.sparse.linalg as spla

DEFAULT_TOL = 1e-6
DENSE_DOFS = 600
"""Up to this many DOFs the dense Bunch-Kaufman LDL^T is used (it also counts the eigenvalues above
sigma).  Measured on FCC: 2.3 s at 1,536 DOFs and 7.5 s at 3,000 (LAPACK ``dsytrf``, loaded 2-core
machine; ``scipy.linalg.ldl`` took 9 s at 1,536) against 0.35 s and 0.8 s for the sparse route, so
the dense route is kept for the small systems the dense eigen-solver also takes."""
SPARSE_DOFS = 100_000
"""Up to this many DOFs the sparse LDL^T is attempted.  Measured on jittered FCC (coordination 12,
the densest pattern): 0.11 s at 3k DOFs, 9.2 s and 30M factor entries at 24k; a random packing
(coordination 6): 1.8 s at 12k.  Fill grows about as n^(4/3) in 3-D, so 1e5 DOFs of FCC cost
minutes and a few GiB: beyond this limit the certificate is declared too costly."""
SPARSE_METHOD = "sparse LDL^T (SuperLU, symmetric mode, no pivoting)"
FACTOR_REF_DOFS = 5184
FACTOR_REF_SECONDS = 4.0
FACTOR_REF_ENTRIES = 4.06e6
FACTOR_TIME_EXPONENT = 2.9
FACTOR_FILL_EXPONENT = 1.84
BYTES_PER_FACTOR_ENTRY = 40.0
"""Cost model of the sparse route, measured on FCC (coordination 12) with SuperLU's MMD ordering on
the 2-core development machine (shared): 5,184 DOFs 4.0 s and 4.06e6 entries in ``L``, 12,288 DOFs
50 s, 1.99e7 entries and a 1.06 GB peak (the eigen-solve took 0.6 s and 5.5 s).  Time grows as
``n^2.9``, fill as ``n^1.84``; ``L`` and ``U`` are both kept (value and index: 24 bytes an entry,
40 with SuperLU's work space).  RCM and COLAMD orderings measured 1.2x more fill and 2-3x the time.
The effective size scales the DOFs by ``(1 + coordination) / 13`` (the nonzeros per row)."""


def _effective_dofs(n: int, coordination: float) -> float:
    return float(n) * (1.0 + max(float(coordination), 0.0)) / 13.0


def factor_seconds(n: int, coordination: float = 12.0) -> float:
    """Estimated time [s] of the certificate on ``n`` DOFs (``FACTOR_*``; the dense route below
    ``DENSE_DOFS`` costs well under a second).
    """
    if n <= DENSE_DOFS:
        return 1e-7 * n ** 2
    return FACTOR_REF_SECONDS * (_effective_dofs(n, coordination) / FACTOR_REF_DOFS) ** FACTOR_TIME_EXPONENT


def factor_bytes(n: int, coordination: float = 12.0) -> float:
    """Estimated memory [bytes] of the certificate's factorisation on ``n`` DOFs (dense: ``n^2``
    doubles for the matrix, its factor and the pivot work).
    """
    if n <= DENSE_DOFS:
        return 3.0 * 8.0 * n * n
    entries = FACTOR_REF_ENTRIES * (_effective_dofs(n, coordination) / FACTOR_REF_DOFS) ** FACTOR_FILL_EXPONENT
    return BYTES_PER_FACTOR_ENTRY * entries


@dataclass(frozen=True)
class Certificate:
    """``certified``: no eigenvalue of ``A`` lies above ``sigma`` [1/s^2] (so ``dt >= 2/sqrt(sigma)``);
    ``method`` how that was decided; ``above`` the number of eigenvalues above ``sigma`` when the
    route counts them (dense LDL^T), else ``None``; ``detail`` one line for people.
    """

    certified: bool
    method: str
    sigma: float
    above: int | None = None
    detail: str = ""

    @property
    def dt_lower(self) -> float | None:
        """``2/sqrt(sigma)``, the certified lower bound on the critical step (``None`` if not certified)."""
        return 2.0 / math.sqrt(self.sigma) if self.certified and self.sigma > 0 else None

    def to_dict(self) -> dict:
        """The certificate as a JSON-ready mapping (its fields and ``dt_lower``)."""
        return {"certified": bool(self.certified), "method": self.method, "sigma": float(self.sigma),
                "above": self.above, "dt_lower": self.dt_lower, "detail": self.detail}


def _shifted(a, sigma: float) -> sps.csc_matrix:
    """``sigma I - A`` as a CSC matrix (``A`` sparse, dense, or a matrix-free operator that can
    assemble itself: ``dtcrit.packing.operators.matrix_free.ContactOperator.assembled``).
    """
    n = a.shape[0]
    if isinstance(a, spla.LinearOperator):
        a = a.assembled()
    m = sps.csc_matrix(a) if sps.issparse(a) else sps.csc_matrix(np.asarray(a))
    return (sps.identity(n, format="csc") * sigma - m).tocsc()


def certify(a, theta: float, tol: float = DEFAULT_TOL, *, dense_dofs: int = DENSE_DOFS,
            sparse_dofs: int = SPARSE_DOFS) -> Certificate:
    """Certificate that ``A`` has no eigenvalue above ``sigma = theta (1 + tol)`` (module docstring)."""
    if not (math.isfinite(theta) and theta > 0):
        return Certificate(False, "none", float(theta), None, "no positive eigenvalue to certify")
    sigma = float(theta) * (1.0 + float(tol))
    n = a.shape[0]
    if n <= dense_dofs:
        above = _sytrf_negative_inertia(_shifted(a, sigma).toarray())
        return Certificate(above == 0, "dense LDL^T (Bunch-Kaufman) inertia of sigma I - A", sigma, above,
                           f"{above} eigenvalue(s) above sigma")
    if n > sparse_dofs:
        return Certificate(False, "none: too costly", sigma, None,
                           f"{n} DOFs exceed the sparse LDL^T limit of {sparse_dofs} (fill-in); "
                           "the bracket's lower end is dt_safe")
    s = _shifted(a, sigma)
    from tqdm import tqdm

    coordination = s.nnz / n / 6.0 - 1.0
    # SuperLU reports no progress: a one-step bar with the estimate, drawn on a terminal only
    ticker = tqdm(total=1, desc=f"certificate: sparse LDL^T (about {factor_seconds(n, coordination):.0f} s)",
                  leave=False, disable=None if factor_seconds(n, coordination) > 2.0 else True)
    try:
        lu = spla.splu(s, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    except RuntimeError as exc:  # an exactly singular pivot: no conclusion
        return Certificate(False, SPARSE_METHOD, sigma, None, f"factorisation failed: {exc}")
    finally:
        ticker.update()
        ticker.close()
    if not np.array_equal(lu.perm_r, lu.perm_c):  # a row pivot was taken: not a congruence
        return Certificate(False, SPARSE_METHOD, sigma, None, "the factorisation pivoted: no inertia")
    d = lu.U.diagonal()
    bad = int(np.count_nonzero(~(d > 0)))
    if bad == 0:
        return Certificate(True, SPARSE_METHOD, sigma, 0, "every pivot of sigma I - A positive: positive definite")
    return Certificate(False, SPARSE_METHOD, sigma, None,
                       f"{bad} non-positive pivot(s): sigma I - A is not shown positive definite")


def _sytrf_negative_inertia(s: np.ndarray) -> int:
    """Negative eigenvalues of the symmetric ``s`` from LAPACK ``dsytrf`` (Bunch-Kaufman
    ``P L D L^T P^T``, lower): ``D``'s 1 x 1 blocks where ``ipiv[k] >= 0`` (0-based), its 2 x 2 blocks
    where ``ipiv[k] = ipiv[k+1] < 0``.  The same factorisation as ``scipy.linalg.ldl``, without that
    function's O(n^2) Python assembly of ``L`` (measured: 9 s against 0.1 s at 1,536 DOFs).
    """
    from scipy.linalg.lapack import dsytrf

    ldu, ipiv, info = dsytrf(s, lower=1, overwrite_a=True)
    if info < 0:
        raise ValueError(f"dsytrf: argument {-info} is invalid")
    n = s.shape[0]
    count, k = 0, 0
    while k < n:
        if ipiv[k] < 0 and k + 1 < n:
            block = np.array([[ldu[k, k], ldu[k + 1, k]], [ldu[k + 1, k], ldu[k + 1, k + 1]]])
            count += int(np.count_nonzero(np.linalg.eigvalsh(block) < 0))
            k += 2
        else:
            count += int(ldu[k, k] < 0)
            k += 1
    return count


def _negative_inertia(d: np.ndarray) -> int:
    """Negative eigenvalues of the block-diagonal ``D`` of ``scipy.linalg.ldl`` (1 x 1 and 2 x 2 blocks)."""
    n = d.shape[0]
    count, k = 0, 0
    while k < n:
        if k + 1 < n and d[k + 1, k] != 0.0:
            count += int(np.count_nonzero(np.linalg.eigvalsh(d[k:k + 2, k:k + 2]) < 0))
            k += 2
        else:
            count += int(d[k, k] < 0)
            k += 1
    return count


@dataclass(frozen=True)
class Bracket:
    """``lower <= dt_crit_true <= upper`` [s]: ``upper = 2/sqrt(theta)`` (a Rayleigh quotient),
    ``lower`` the certified ``2/sqrt(sigma)`` or else ``dt_safe``; ``lower_from`` says which.
    """

    lower: float
    upper: float
    lower_from: str

    def to_dict(self) -> dict:
        """The bracket as a JSON-ready mapping (``lower``, ``upper`` [s], ``lower_from``)."""
        return {"lower": self.lower, "upper": self.upper, "lower_from": self.lower_from}


def bracket(theta: float, dt_safe: float, cert: Certificate | None) -> Bracket:
    """The bracket of the module docstring (the larger valid lower bound is kept)."""
    upper = 2.0 / math.sqrt(theta) if theta > 0 else math.inf
    if cert is not None and cert.dt_lower is not None and cert.dt_lower >= dt_safe:
        return Bracket(cert.dt_lower, upper, "certificate")
    return Bracket(dt_safe, upper, "dt_safe")


__all__ = ["Certificate", "Bracket", "certify", "bracket", "factor_seconds", "factor_bytes", "DEFAULT_TOL",
           "DENSE_DOFS", "SPARSE_DOFS"]
