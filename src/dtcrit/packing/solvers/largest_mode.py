"""The largest eigenfrequency of a packing: ``K phi = omega^2 M phi`` (Otsubo et al. 2017, Eq. (13)).

Solved in the symmetric standard form ``A = M^(-1/2) K M^(-1/2)``, ``A v = omega^2 v``,
``phi = M^(-1/2) v``.  Methods:

* ``"dense"``  -- ``scipy.linalg.eigh`` on the full matrix (small systems, the reference);
* ``"eigsh"``  -- ARPACK implicitly restarted Lanczos, ``which="LA"`` (the default above
  ``DENSE_LIMIT`` DOFs: measured the fastest reliable choice, see ``dtcrit.bench.packing_scaling``);
* ``"lobpcg"`` -- ``scipy.sparse.linalg.lobpcg`` for the largest eigenpair.

An iterative answer is a Ritz value, i.e. a Rayleigh quotient, so it can only be *below* the
true ``omega_max^2`` (a ``dt`` *above* the true critical step); the returned residual norm
``|A v - theta v|`` bounds the distance from ``theta`` to some eigenvalue of ``A``.
"""
from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sps
import scipy.sparse.linalg as spla

from dtcrit.errors import InputError, NotConvergedError
from dtcrit.packing.solvers import filter_updates
from tqdm import tqdm

LONG_WORK = 200_000  # DOFs below which the solve takes well under a second: no counter drawn
DENSE_LIMIT = 600  # DOFs up to which the dense solver is used by "auto"
LEAN_DOFS = 20_000_000
LEAN_NCV = 4
"""Above ``LEAN_DOFS`` DOFs "auto" on a matrix-free operator polishes the Chebyshev start with ARPACK
on ``LEAN_NCV`` Lanczos vectors (nine vectors of 6N through the iteration: these four, ARPACK's
three work vectors, its residual, which is the start vector itself with NumPy >= 2.1
(``_HandedOver``), and the products' one output vector; at the end SciPy adds an (n, ``LEAN_NCV``)
array of which ARPACK writes one column, the only one resident, and a copy of it, the result;
``LEAN_NCV = 3`` took 17 % more products at 6e6 DOFs for one vector less) instead of LOBPCG, whose
iteration holds about seventeen (measured: +850 MiB over the contact arrays at 6e6 DOFs, so
8.5 GB at 6e7, which with the contacts would not fit in 16 GiB), to the same relative residual as
LOBPCG's (``10 tol``).  Measured at 6e6 DOFs from the same Chebyshev start: 101 products against
LOBPCG's 34, values within 2e-10 of each other (ARPACK at ``tol`` itself took 437)."""
OPERATOR_METHOD = "lobpcg"
"""What "auto" uses on a matrix-free operator above ``DENSE_LIMIT``: LOBPCG (block size 1) keeps a
handful of vectors where ARPACK keeps 24, and measured 1.6x faster on 585k DOFs of the jittered FCC
benchmark (113 against 121 products, its basis work much smaller), to the same value within 1e-12."""
METHODS = ("auto", "dense", "eigsh", "lobpcg")


@dataclass(frozen=True)
class TopMode:
    """Largest eigenpair of ``A = M^(-1/2) K M^(-1/2)`` and how it was found.

    Parameters
    ----------
    value : float
        ``omega_max^2`` [1/s^2] (a Ritz value, ``<= lambda_max``, for the iterative solvers).
    vector : numpy.ndarray
        Unit eigenvector in the mass-scaled coordinates ``v = M^(1/2) phi`` (6 entries per particle).
    method : str
        Solver used: ``"dense"``, ``"eigsh"`` or ``"lobpcg"``.
    matvecs : int
        Matrix-vector products spent (0 for the dense solver).
    residual : float
        ``|A v - value v|`` [1/s^2]; bounds the distance from ``value`` to an eigenvalue of ``A``.
    space : numpy.ndarray or None
        Orthonormal basis of the top eigenspace (dense: eigenvalues within ``DEGENERATE_RTOL`` of the
        top one; ``eigsh`` up to ``ITERATIVE_SPACE_LIMIT`` DOFs: Ritz vectors within
        ``ITERATIVE_DEGENERATE_RTOL``), ``None`` if not computed.  In a degenerate eigenspace ``vector``
        is an arbitrary member.
    """

    value: float
    vector: np.ndarray
    method: str
    matvecs: int
    residual: float
    space: np.ndarray | None = None

    @property
    def omega(self) -> float:
        """``omega_max = sqrt(max(value, 0))`` [rad/s], the largest angular eigenfrequency."""
        return float(np.sqrt(max(self.value, 0.0)))


def _start_vector(n: int) -> np.ndarray:
    """A fixed, generic start vector (reproducible runs; no eigenvector is orthogonal to it
    except on a set of measure zero).
    """
    rng = np.random.default_rng(20170601)
    return rng.standard_normal(n)


def _residual(a, v, theta) -> float:
    return float(np.linalg.norm(a @ v - theta * v))


DEGENERATE_RTOL = 1e-9
"""Eigenvalues within this relative distance of the largest belong to the top eigenspace."""
TOP_SPACE_MAX = 24
"""Most eigenpairs the dense solver computes to find the top eigenspace."""
DEFAULT_TOL = 1e-7  # ARPACK residual tolerance; the Ritz value itself is then good to ~1e-9 (measured)
ITERATIVE_SPACE_LIMIT = 200_000
"""Up to this many DOFs ``eigsh`` computes the ``ITERATIVE_SPACE_K`` largest eigenpairs, so that a
degenerate top eigenspace is seen (and labelled) as it is by the dense route; above it, only the top one."""
ITERATIVE_SPACE_K = 12
ITERATIVE_DEGENERATE_RTOL = 1e-7  # Ritz values this close to the top one count as the same eigenvalue


def largest_mode(a, method: str = "auto", *, tol: float = DEFAULT_TOL, maxiter: int | None = None,
                 hint: np.ndarray | Callable[[], np.ndarray] | None = None) -> TopMode:
    """Largest eigenvalue and eigenvector of the symmetric positive semi-definite matrix ``a``.

    The standard form of ``K phi = omega^2 M phi`` (Otsubo et al. 2017, Eq. (13)); methods in the
    module docstring.  ``"auto"``: dense up to ``DENSE_LIMIT`` DOFs, else ``eigsh`` on a matrix and
    ``OPERATOR_METHOD`` (LOBPCG from a Chebyshev start) on a matrix-free operator, ARPACK with
    ``LEAN_NCV`` vectors above ``LEAN_DOFS``.

    Parameters
    ----------
    a : array_like, scipy.sparse matrix or LinearOperator
        ``A = M^(-1/2) K M^(-1/2)`` [1/s^2].
    method : str
        One of ``METHODS``.
    tol : float
        ARPACK residual tolerance (LOBPCG and the lean route stop at ``10 tol`` relative).
    maxiter : int or None
        Iteration cap of the iterative solvers (``None``: their default; LOBPCG 500).
    hint : numpy.ndarray or callable or None
        A vector believed rich in the top mode (e.g. all particles co-rotating), or a function
        returning it (then only the solver holds it); the iterative solvers start from the fixed
        random vector plus the normalised hint, measured ~40 % fewer products on large lattices
        and never more on random packings.

    Returns
    -------
    TopMode
        The eigenpair, solver, product count, residual and (when computed) top eigenspace.

    Raises
    ------
    InputError
        For an unknown ``method``.
    NotConvergedError
        When ARPACK stops early; it carries the bracket of Rayleigh quotient and row-sum bound.
    """
    if method not in METHODS:
        raise InputError("method", f"unknown eigen-solver {method!r}; choose one of {', '.join(METHODS)}")
    n = a.shape[0]
    operator = isinstance(a, spla.LinearOperator)
    lean = False
    if method == "auto":
        method = "dense" if n <= DENSE_LIMIT else (OPERATOR_METHOD if operator else "eigsh")
        if operator and n > LEAN_DOFS:
            method, lean = "eigsh", True
    if n < 3 and method != "dense":
        method = "dense"
    if operator:
        zero = bool(getattr(a, "is_zero", False))
    else:  # explicitly stored zeros (a Hertz contact at zero overlap) count as zero: ARPACK cannot start
        zero = not np.any(a.data) if sps.issparse(a) else not np.any(a)
    if zero:
        v = np.zeros(n)
        v[0] = 1.0
        return TopMode(0.0, v, method, 0, 0.0)
    if method == "dense":
        dense = (a @ np.eye(n) if operator else a.toarray() if sps.issparse(a) else np.asarray(a))
        dense = 0.5 * (dense + dense.T) if operator else dense
        w, vecs = sla.eigh(dense, subset_by_index=[max(0, n - TOP_SPACE_MAX), n - 1])
        v = vecs[:, -1]
        top = w >= w[-1] - DEGENERATE_RTOL * max(abs(float(w[-1])), np.finfo(float).tiny)
        return TopMode(float(w[-1]), v, "dense", 0, _residual(dense, v, w[-1]), vecs[:, top])
    start = _start_vector(n)
    hint = hint() if callable(hint) else hint  # a callable keeps the caller from holding the vector
    if hint is not None and np.linalg.norm(hint) > 0:
        start /= np.linalg.norm(start)
        start += np.asarray(hint, float) / np.linalg.norm(hint)
    del hint
    # tqdm draws only on a terminal (disable=None); the count is kept whether drawn or not
    ticker = tqdm(desc="eigen-solve", unit=" matrix-vector products", disable=None if n >= LONG_WORK else True,
                  leave=False)
    count = 0

    def matvec(x):
        nonlocal count
        count += x.shape[1] if x.ndim == 2 else 1
        ticker.update()
        return a @ x

    def product(x, out):
        nonlocal count
        count += 1
        ticker.update()
        return a.apply_into(x, out) if hasattr(a, "apply_into") else np.copyto(out, a @ x) or out

    op = spla.LinearOperator(a.shape, matvec=matvec, matmat=matvec, dtype=float)
    try:
        space = None
        if method == "eigsh":
            op = _reusing(op, product, a)
            k = ITERATIVE_SPACE_K if n <= ITERATIVE_SPACE_LIMIT and n > ITERATIVE_SPACE_K + 2 and not lean else 1
            ncv = min(n - 1, 24 if k == 1 else 48)
            v0: np.ndarray | _HandedOver = start
            lower: np.ndarray | float = start  # what the bracket's lower end comes from
            if lean:  # the residual LOBPCG stops at (10 tol relative): see LEAN_DOFS
                start, lower = chebyshev_filter(product, start)
                ncv, v0 = LEAN_NCV, _HandedOver(start)
                del start  # ARPACK's own residual vector from here on
            try:
                w, vecs = spla.eigsh(op, k=k, which="LA", tol=tol * 10 if lean else tol, v0=v0,
                                     maxiter=maxiter, ncv=ncv)
            except spla.ArpackNoConvergence as exc:
                raise _not_converged(a, lower, exc.eigenvalues, count) from None
            top_index = int(np.argmax(w))
            theta, v = float(w[top_index]), vecs[:, top_index]
            if k > 1:
                close = w >= theta - ITERATIVE_DEGENERATE_RTOL * abs(theta)
                space = np.linalg.qr(vecs[:, close])[0]
        else:
            start = chebyshev_start(product, start)
            x0 = start[:, None]
            # lobpcg's tol is an absolute residual norm: make it relative to the start's Rayleigh
            # quotient (<= lambda_max, so never looser than tol * 10 relative)
            scale = float(start @ (a @ start)) / float(start @ start)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", UserWarning)  # "not reaching the tolerance": residual kept
                w, vecs = spla.lobpcg(op, x0, largest=True, tol=tol * 10 * max(scale, np.finfo(float).tiny),
                                      maxiter=maxiter or 500)
            theta, v = float(w[0]), vecs[:, 0]
    finally:
        ticker.close()
    v = v / np.linalg.norm(v)
    return TopMode(theta, v, method, count, _residual(a, v, theta), space)


def _reusing(op: spla.LinearOperator, product, a) -> spla.LinearOperator:
    """``op`` for ARPACK, writing each product of an operator with ``apply_into`` into one kept vector.

    ARPACK (``scipy.sparse.linalg.eigsh``) copies every product into its own work array at once, so one
    output vector serves all of them: no fresh 6N vector per product (0.5 GB at 1e7 particles; at 1e6
    a fresh vector costs about a third of the product's time).  LOBPCG keeps its products, so it keeps
    ``op`` as it is.
    """
    if not hasattr(a, "apply_into"):
        return op
    kept = np.empty(a.shape[0])

    def into_kept(x):
        return product(np.asarray(x, float).reshape(-1), kept)

    return spla.LinearOperator(a.shape, matvec=into_kept, dtype=float)


def row_sum_bound(a) -> float:
    """Gershgorin bound ``max_i sum_j |a_ij|`` on every eigenvalue of the symmetric ``a``.

    Parameters
    ----------
    a : array_like, scipy.sparse matrix or LinearOperator
        The symmetric matrix.

    Returns
    -------
    float
        The bound (units of ``a``); ``inf`` for a matrix-free operator (not known here).
    """
    if isinstance(a, spla.LinearOperator):
        return math.inf
    if sps.issparse(a):
        return float(np.max(np.asarray(abs(a).sum(axis=1)), initial=0.0))
    return float(np.abs(np.asarray(a)).sum(axis=1).max(initial=0.0))


class _HandedOver:
    """``v0`` for ``scipy.sparse.linalg.eigsh`` that hands ARPACK the start vector itself.

    scipy copies ``v0`` into ARPACK's residual array (``np.array(v0, copy=True)``); ``__array__``
    returns the vector and forgets it, so that the residual array is the start vector and no copy is
    made (one 6N vector less during the solve: 0.5 GB at 1e7 particles).  NumPy >= 2.1 takes an array
    returned for ``copy=True`` as the copy; older versions copy it again (checked with NumPy 1.26:
    ARPACK then works on the copy), so only the saving is lost.
    """

    def __init__(self, vector: np.ndarray):
        self._vector: np.ndarray | None = vector

    def __array__(self, dtype=None, copy=None):
        vector, self._vector = self._vector, None
        if vector is None:
            raise RuntimeError("the start vector was handed over already")
        return vector if dtype is None else vector.astype(dtype, copy=False)


def _not_converged(a, start: np.ndarray | float, ritz, count: int) -> NotConvergedError:
    """The bracket ARPACK leaves when it stops early: every Rayleigh quotient (the start's, given or
    computed here from the start vector; the converged Ritz values) is a lower bound on
    ``lambda_max``; the row-sum bound an upper one.
    """
    if isinstance(start, np.ndarray):
        lower = float(start @ (a @ start)) / float(start @ start)
    else:  # the start's Rayleigh quotient, 0 (A is positive semi-definite) when there was none
        lower = float(start) if math.isfinite(start) else 0.0
    if ritz is not None and len(ritz):
        lower = max(lower, float(np.max(np.real(ritz))))
    return NotConvergedError("omega_max^2 [1/s^2]", max(lower, 0.0), row_sum_bound(a), "ARPACK eigsh",
                             f"{count} matrix-vector products")


FILTER_DEGREE = 16
FILTER_STOP = 1e-6
FILTER_STAGES = 12
"""The Chebyshev start of LOBPCG: stages of a degree-``FILTER_DEGREE`` filter until the Rayleigh
quotient moves by less than ``FILTER_STOP`` (relative), at most ``FILTER_STAGES``.  Measured on the
jittered FCC benchmark (585k DOFs): 6 stages (103 products) then 33 LOBPCG iterations, against 88
LOBPCG iterations from the raw start, to the same value within 1e-11; each filter product costs
three vector updates where a LOBPCG iteration costs dozens (whose fresh arrays dominate above 1e6 DOFs)."""


def chebyshev_start(product, v: np.ndarray, degree: int = FILTER_DEGREE, stop: float = FILTER_STOP,
                    stages: int = FILTER_STAGES) -> np.ndarray:
    """A start vector rich in the top eigenvectors of a symmetric positive semi-definite ``A``.

    ``v`` filtered by ``T_m(2A/theta - 1)``, ``T_m`` the Chebyshev polynomial of degree ``m`` and
    ``theta`` the current Rayleigh quotient (Zhou & Saad 2007, Chebyshev-filtered subspace
    iteration, with one vector).  ``theta <= lambda_max`` always, so ``|T_m| <= 1`` on the
    eigenvalues at or below ``theta`` while those above grow like ``exp(m arccosh(2 lambda/theta - 1))``:
    repeated, the filter is an accelerated power method.  It only chooses where LOBPCG starts; the
    answer and its residual are LOBPCG's.  The three-term recurrence is renormalised at each
    degree (no overflow).

    Parameters
    ----------
    product : callable or matrix or LinearOperator
        ``product(x, out)`` writing ``A x`` into ``out`` and returning it, or ``A`` itself.
    v : numpy.ndarray
        Initial vector (copied, not modified).
    degree : int
        Degree ``m`` of each filter stage.
    stop : float
        Stop when the Rayleigh quotient moves by less than this (relative) in a stage.
    stages : int
        Most filter stages.

    Returns
    -------
    numpy.ndarray
        The filtered unit vector (``v`` normalised if ``A v`` has no positive Rayleigh quotient).
    """
    return chebyshev_filter(product, v, degree, stop, stages)[0]


def chebyshev_filter(product, v: np.ndarray, degree: int = FILTER_DEGREE, stop: float = FILTER_STOP,
                     stages: int = FILTER_STAGES) -> tuple[np.ndarray, float]:
    """``chebyshev_start`` with the Rayleigh quotient of the vector it returns (a lower bound on
    ``lambda_max``; ``nan`` when ``A v`` has no positive Rayleigh quotient).

    Parameters
    ----------
    product : callable or matrix or LinearOperator
        As ``chebyshev_start``.
    v : numpy.ndarray
        Initial vector (copied, not modified).
    degree, stop, stages : int, float, int
        As ``chebyshev_start``.

    Returns
    -------
    vector : numpy.ndarray
        The filtered unit vector.
    value : float
        Its Rayleigh quotient ``v . A v``.
    """
    if hasattr(product, "shape"):  # a matrix or LinearOperator (the latter is also callable)
        matrix = product

        def matrix_product(x, out):
            np.copyto(out, matrix @ x)
            return out

        product = matrix_product
    v = np.array(v, dtype=float, copy=True)
    v /= np.linalg.norm(v)
    av = product(v, np.empty_like(v))
    theta = float(v @ av)
    if not (theta > 0 and np.isfinite(theta)):
        return v, math.nan
    y0, y1, y2 = np.empty_like(v), np.empty_like(v), np.empty_like(v)
    for _ in range(stages):
        y0[:] = v
        np.multiply(av, 2.0 / theta, out=y1)
        y1 -= v
        for _k in range(2, degree + 1):
            product(y1, y2)  # y2 = (4/theta) A y1 - 2 y1 - y0, renormalised with y1
            filter_updates.three_term(y2, y1, y0, 4.0 / theta)
            norm = np.linalg.norm(y2)
            if not (norm > 0 and np.isfinite(norm)):
                return v, theta
            filter_updates.divide_both(y2, y1, float(norm))
            y0, y1, y2 = y1, y2, y0
        v[:] = y1
        v /= np.linalg.norm(v)
        product(v, av)
        new = float(v @ av)
        moved = abs(new - theta) / new if new > 0 else 0.0
        theta = new
        if moved < stop:
            break
    return v, theta
