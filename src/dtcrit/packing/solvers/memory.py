"""Refuse, before any work, a packing that cannot fit in the memory this process may use.

Peak memory per sphere, measured by ``dtcrit packing --scale`` (jittered FCC, coordination 12, one run
on a 2-core machine): about 10 KiB with the assembled stiffness matrix (915 MiB at 97,556 spheres)
and 1.3 KiB matrix-free (1,420 MiB at 1,000,188 with the interpreter's fixed ~150 MiB, 1.0 KiB at
10,061,824: 9,980 MiB; with one stiffness value held once, 32-bit indices and the solve's vectors
trimmed, before which these were 1,746 and 13,632 MiB).  The estimate scales these by coordination / 12, adds the fixed part, the certificate's
factor when one is computed (``certificate.factor_bytes``) and a safety margin of 1.15.

It is compared with the *smallest* of the limits on this process: the kernel's ``MemAvailable``,
the address-space limit ``RLIMIT_AS`` (``ulimit -v``, less what the process has mapped already) and
the cgroup limits (v2 ``memory.max``, v1 ``memory.limit_in_bytes``, less their current usage).
"""
from __future__ import annotations

import math
from pathlib import Path

from dtcrit.errors import InputError

BYTES_PER_SPHERE = {"assembled": 10 * 1024, "matrix-free": 1.3 * 1024}
FIXED_BYTES = 150 * 2**20  # the interpreter with NumPy, SciPy and Numba loaded
MARGIN = 1.15
MATRIX_FREE_DOFS = 200_000  # the automatic route switches to matrix-free above this (dtcrit.packing.report)
UNLIMITED = 2**60  # cgroup v1 writes "no limit" as a huge page-rounded number


def _meminfo() -> float | None:
    """MemAvailable from /proc/meminfo (Linux), else None."""
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024.0
    except (OSError, ValueError, IndexError):
        return None
    return None


def _mapped_bytes() -> float:
    """Virtual memory this process has mapped already (``VmSize``), 0 if unknown."""
    try:
        with open("/proc/self/status", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("VmSize:"):
                    return float(line.split()[1]) * 1024.0
    except (OSError, ValueError, IndexError):
        return 0.0
    return 0.0


def _rlimit_as() -> float | None:
    """What ``RLIMIT_AS`` (``ulimit -v``) still allows this process to map, None if unlimited."""
    try:
        import resource

        soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    except (ImportError, OSError, ValueError):
        return None
    if soft == resource.RLIM_INFINITY or soft < 0:
        return None
    return max(float(soft) - _mapped_bytes(), 0.0)


def _read_number(path: Path) -> float | None:
    try:
        text = path.read_text(encoding="ascii").strip()
    except (OSError, UnicodeDecodeError):
        return None
    try:
        value = float(text)
    except ValueError:
        return None  # "max": no limit
    return value if math.isfinite(value) and value < UNLIMITED else None


def _cgroup_dirs(root: Path = Path("/sys/fs/cgroup")) -> list[tuple[str, Path]]:
    """``(version, directory)`` of this process's memory cgroups (v2 unified and v1 ``memory``)."""
    out: list[tuple[str, Path]] = []
    try:
        lines = Path("/proc/self/cgroup").read_text(encoding="ascii").splitlines()
    except (OSError, UnicodeDecodeError):
        return out
    for line in lines:
        parts = line.split(":", 2)
        if len(parts) != 3:
            continue
        _, controllers, rel = parts
        rel = rel.lstrip("/")
        if controllers == "":
            out += [("v2", root / rel), ("v2", root / "unified" / rel), ("v2", root)]
        elif "memory" in controllers.split(","):
            out += [("v1", root / "memory" / rel), ("v1", root / "memory")]
    return out


def _cgroup_room(root: Path = Path("/sys/fs/cgroup")) -> float | None:
    """The smallest ``limit - usage`` over this process's memory cgroups, None if none is limited."""
    room = None
    for version, d in _cgroup_dirs(root):
        limit_name, usage_name = (("memory.max", "memory.current") if version == "v2"
                                  else ("memory.limit_in_bytes", "memory.usage_in_bytes"))
        limit = _read_number(d / limit_name)
        if limit is None:
            continue
        usage = _read_number(d / usage_name) or 0.0
        left = max(limit - usage, 0.0)
        room = left if room is None else min(room, left)
    return room


def available_bytes() -> float | None:
    """Memory this process may still use: the least of the known limits (module docstring).

    Returns
    -------
    float or None
        The smallest of ``MemAvailable``, the ``RLIMIT_AS`` room and the cgroup room [bytes]; ``None``
        when none is known (then no check is made).
    """
    known = [v for v in (_meminfo(), _rlimit_as(), _cgroup_room()) if v is not None]
    return min(known) if known else None


def estimated_bytes(n_spheres: int, coordination: float, route: str = "auto", extra: float = 0.0) -> float:
    """Estimated peak memory of ``dtcrit packing`` on ``n_spheres`` spheres (module docstring).

    ``MARGIN * (FIXED_BYTES + BYTES_PER_SPHERE[route] * n_spheres * max(coordination, 1) / 12 + extra)``.

    Parameters
    ----------
    n_spheres : int
        Number of spheres (6 DOFs each).
    coordination : float
        Mean contacts per sphere; the measured per-sphere cost is at coordination 12.
    route : str
        ``"assembled"``, ``"matrix-free"`` or ``"auto"`` (matrix-free above ``MATRIX_FREE_DOFS`` DOFs).
    extra : float
        Further cost [bytes] added before the margin (the certificate's factor).

    Returns
    -------
    float
        Estimated peak [bytes].
    """
    if route == "auto":
        route = "matrix-free" if 6 * n_spheres > MATRIX_FREE_DOFS else "assembled"
    return MARGIN * (FIXED_BYTES + BYTES_PER_SPHERE[route] * n_spheres * max(coordination, 1.0) / 12.0 + extra)


def check_fits(n_spheres: int, coordination: float, route: str = "auto", key: str = "packing",
               available: float | None = None, extra: float = 0.0, what: str = "") -> None:
    """Refuse a packing whose estimated peak memory exceeds what this process may use.

    Parameters
    ----------
    n_spheres : int
        Number of spheres.
    coordination : float
        Mean contacts per sphere.
    route : str
        ``"assembled"``, ``"matrix-free"`` or ``"auto"`` (see ``estimated_bytes``).
    key : str
        Input key named in the error message.
    available : float or None
        Available memory [bytes]; ``None`` measures it with ``available_bytes``.
    extra : float
        Further cost [bytes] (the certificate's factor).
    what : str
        Name of ``extra`` in the message.

    Raises
    ------
    InputError
        When the estimate exceeds the available memory.
    """
    have = available_bytes() if available is None else available
    need = estimated_bytes(n_spheres, coordination, route, extra)
    if have is not None and need > have:
        plus = f" ({what} {extra / 2**30:.3g} GiB of it)" if extra > 0 and what else ""
        raise InputError(key, f"{n_spheres:,} spheres need about {need / 2**30:.3g} GiB{plus} (measured "
                              f"{BYTES_PER_SPHERE['matrix-free'] / 1024:.2g}-{BYTES_PER_SPHERE['assembled'] / 1024:.2g} "
                              f"KiB per sphere at coordination 12, x{MARGIN} margin), {have / 2**30:.3g} GiB "
                              "available to this process (the least of free memory, ulimit -v and the cgroup limit)")


__all__ = ["check_fits", "estimated_bytes", "available_bytes"]
