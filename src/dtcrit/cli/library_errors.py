"""Library errors as the one line a command prints: a key of the library becomes the flag or the
``SOURCE:key`` that set it, a solver that stopped early is reported with its bracket, and memory that
runs out after all is one line too (``dtcrit.cli.main`` prints ``ValueError``s, exit status 2).
"""
from __future__ import annotations

from typing import Callable

from dtcrit.errors import InputError, NotConvergedError


def run_naming_flags(run: Callable, args, source, flag_of: Callable, not_converged: Callable[[NotConvergedError], str],
                     out_of_memory: str) -> int:
    """``run(args)``, with its ``InputError`` keys renamed by ``flag_of(key, args)`` (``None``: keep the
    error as it is); a flag ``f"{source}:key"`` is printed as ``SOURCE:key: reason``.
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
