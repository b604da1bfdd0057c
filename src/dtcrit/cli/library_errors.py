"""Library errors as the one line a command prints: a key of the library becomes the flag or the
``SOURCE:key`` that set it, a solver that stopped early is reported with its bracket, and memory that
runs out after all is one line too (``dtcrit.cli.main`` prints ``ValueError``s, exit status 2).
"""
from __future__ import annotations

from typing import Callable

from dtcrit.errors import InputError, NotConvergedError


def run_naming_flags(run: Callable, args, source, flag_of: Callable, not_converged: Callable[[NotConvergedError], str],
                     out_of_memory: str) -> int:
    """``run(args)`` with the library's errors as the one line a command prints.

    An ``InputError`` key is renamed by ``flag_of(key, args)`` (``None``: keep the error as it is); a
    flag ``f"{source}:key"`` is printed as ``SOURCE:key: reason``.

    Parameters
    ----------
    run : callable
        ``run(args) -> int``, the command.
    args : argparse.Namespace
        The parsed flags (``source_label`` is set on it for a ``SOURCE:key`` flag).
    source : str or None
        The input file, as given.
    flag_of : callable
        ``flag_of(key, args) -> str | None``.
    not_converged : callable
        The message of a ``NotConvergedError``.
    out_of_memory : str
        The message of a ``MemoryError``.

    Returns
    -------
    int
        ``run``'s exit status.
    """
    try:
        return run(args)
    except InputError as exc:
        flag = flag_of(exc.key, args)
        if flag is None:
            raise
        prefix = f"{source}:"
        if source is not None and flag.startswith(prefix):
            args.source_label = source
            raise InputError(flag[len(prefix):], exc.reason) from None
        raise InputError(flag, exc.reason) from None
    except NotConvergedError as exc:
        raise ValueError(not_converged(exc)) from None
    except MemoryError:
        raise ValueError(out_of_memory) from None
