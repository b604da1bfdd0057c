"""A minimal progress bar on standard error for the long sweeps (no third-party dependency).

It draws only when standard error is a terminal or ``DTCRIT_PROGRESS=1``; otherwise it is silent,
so tests and piped output stay clean.
"""
from __future__ import annotations

import os
import sys
import time
from typing import Iterable, Iterator, TypeVar

T = TypeVar("T")


def _enabled() -> bool:
    flag = os.environ.get("DTCRIT_PROGRESS")
    if flag is not None:
        return flag not in ("0", "", "no")
    return sys.stderr.isatty()


def progress(items: Iterable[T], total: int | None = None, label: str = "") -> Iterator[T]:
    """Yield from ``items`` while drawing ``label [#####.....] i/total  elapsed`` on stderr."""
    if total is None:
        try:
            total = len(items)  # type: ignore[arg-type]
        except TypeError:
            total = None
    if not _enabled():
        yield from items
        return
    start = time.perf_counter()
    last = 0.0
    width = 30
    i = 0
    for i, item in enumerate(items, 1):
        yield item
        now = time.perf_counter()
        if now - last > 0.1 or (total is not None and i == total):
            last = now
            if total:
                filled = int(width * i / total)
                bar = "#" * filled + "." * (width - filled)
                sys.stderr.write(f"\r{label} [{bar}] {i}/{total}  {now - start:6.1f}s")
            else:
                sys.stderr.write(f"\r{label} {i}  {now - start:6.1f}s")
            sys.stderr.flush()
    sys.stderr.write("\n")
    sys.stderr.flush()
