"""Progress reporting for the long steps of a packing analysis (assembly chunks, eigen-solve).

Assembly chunks use ``dtcrit.progress``; the eigen-solve, whose length is not known in advance,
counts matrix-vector products on one status line.  Both draw only when standard error is a
terminal or ``DTCRIT_PROGRESS=1`` (the convention of ``dtcrit.progress``), so tests and piped output
stay clean.
"""
from __future__ import annotations

import os
import sys
import time
from typing import Iterator

from dtcrit.progress import progress

# below this many contacts / DOFs the work takes well under a second: no bar at all
LONG_WORK = 200_000


def _drawing() -> bool:
    flag = os.environ.get("DTCRIT_PROGRESS")
    if flag is not None:
        return flag not in ("0", "", "no")
    return sys.stderr.isatty()


def chunked(total: int, chunk: int, label: str) -> Iterator[int]:
    """Start offsets ``0, chunk, 2 chunk, ...`` below ``total``, with a bar when the work is long."""
    starts = range(0, total, chunk)
    if total < LONG_WORK:
        return iter(starts)
    return progress(starts, total=len(starts), label=label)


class Ticker:
    """Counts calls (matrix-vector products of an iterative eigen-solver) on a status line."""

    def __init__(self, label: str, enabled: bool):
        self.label = label
        self.count = 0
        self._on = enabled and _drawing()
        self._start = time.perf_counter()
        self._last = 0.0
        self._drawn = False

    def tick(self) -> None:
        self.count += 1
        if not self._on:
            return
        now = time.perf_counter()
        if now - self._last > 0.2:
            self._last = now
            sys.stderr.write(f"\r{self.label}: {self.count} matrix-vector products  {now - self._start:6.1f}s")
            sys.stderr.flush()
            self._drawn = True

    def close(self) -> None:
        if self._drawn:
            now = time.perf_counter()
            sys.stderr.write(f"\r{self.label}: {self.count} matrix-vector products  {now - self._start:6.1f}s\n")
            sys.stderr.flush()
            self._drawn = False
