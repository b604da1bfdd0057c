"""Numba at run time for the compiled loops: whether it imports, the decorator every loop is compiled
with, ``prange``, and the threads the loops use.

Without Numba, ``prange`` is ``range`` and a compiled loop is a stand-in that raises; callers check
``available()`` first and take their NumPy paths.  The loops themselves live in
``matrix_free_kernels``, ``particle_pass``, ``bounds.estimate_kernels`` and
``solvers.filter_updates`` (Numba caches each keyed on its own file).
"""
from __future__ import annotations

from types import ModuleType
from typing import Any, Callable


def _import_numba() -> ModuleType | None:
    try:  # pragma: no cover - exercised by whichever environment runs the tests
        import numba as module
    except ImportError:  # the NumPy path of matrix_free.ContactOperator is used instead
        return None
    return module


numba = _import_numba()


prange = numba.prange if numba is not None else range


def _jit(fn: Callable[..., Any], parallel: bool = False) -> Callable[..., Any]:
    """``fn`` compiled by Numba (machine code cached on disk, GIL released while it runs; ``parallel``:
    its ``prange`` loops run on Numba's threads); without Numba a stand-in that raises (callers
    check ``available()`` first).
    """
    if numba is None:  # pragma: no cover
        def missing(*args: Any) -> Any:
            raise RuntimeError("the compiled loops need Numba (pip install numba)")

        return missing
    return numba.njit(cache=True, nogil=True, parallel=parallel)(fn)


def available() -> bool:
    """Whether the compiled loops can be used (Numba importable).

    Returns
    -------
    bool
        ``True`` when Numba imports.
    """
    return numba is not None


def threads() -> int:
    """Threads the compiled loops may use (``numba.get_num_threads()``: ``NUMBA_NUM_THREADS`` or the
    cores), 1 without Numba.

    Returns
    -------
    int
        The thread count.
    """
    return int(numba.get_num_threads()) if numba is not None else 1


def use_threads(count: int) -> int:
    """Let the compiled loops use ``count`` threads (``numba.set_num_threads``, capped at Numba's pool:
    ``NUMBA_NUM_THREADS`` or the cores), e.g. one rank's share of its node's cores.

    Parameters
    ----------
    count : int
        Threads wanted (at least 1).

    Returns
    -------
    int
        The threads the loops now use (1 without Numba).
    """
    if numba is None:
        return 1
    numba.set_num_threads(max(1, min(int(count), int(numba.config.NUMBA_NUM_THREADS))))
    return threads()
