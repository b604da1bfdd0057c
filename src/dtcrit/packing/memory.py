"""Refuse, before any work, a packing that cannot fit in this machine's memory.

Peak memory per sphere, measured by ``dtcrit packing --scale`` (jittered FCC, coordination 12, one run
on a 2-core machine): about 10 KiB with the assembled stiffness matrix (915 MiB at 97,556 spheres)
and 1.6 KiB matrix-free (16,029 MiB at 10,061,824; 2,014 MiB at 1,000,188 with the interpreter's
fixed ~150 MiB).  The estimate scales these by coordination / 12, adds the fixed part and a safety
margin of 1.15, and is compared with the memory the kernel says is available.
"""
from __future__ import annotations


from dtcrit.errors import InputError

BYTES_PER_SPHERE = {"assembled": 10 * 1024, "matrix-free": 1.6 * 1024}
FIXED_BYTES = 150 * 2**20  # the interpreter with NumPy, SciPy and Numba loaded
MARGIN = 1.15
MATRIX_FREE_DOFS = 200_000  # the automatic route switches to matrix-free above this (dtcrit.packing.report)


def available_bytes() -> float | None:
    """MemAvailable from /proc/meminfo (Linux), else None (no check)."""
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024.0
    except OSError:
        return None
    return None


def estimated_bytes(n_spheres: int, coordination: float, route: str = "auto") -> float:
    if route == "auto":
        route = "matrix-free" if 6 * n_spheres > MATRIX_FREE_DOFS else "assembled"
    return MARGIN * (FIXED_BYTES + BYTES_PER_SPHERE[route] * n_spheres * max(coordination, 1.0) / 12.0)


def check_fits(n_spheres: int, coordination: float, route: str = "auto", key: str = "packing",
               available: float | None = None) -> None:
    """InputError when the estimated peak exceeds the available memory (module docstring)."""
    have = available_bytes() if available is None else available
    need = estimated_bytes(n_spheres, coordination, route)
    if have is not None and need > have:
        raise InputError(key, f"{n_spheres:,} spheres need about {need / 2**30:.3g} GiB (measured "
                              f"{BYTES_PER_SPHERE['matrix-free'] / 1024:.2g}-{BYTES_PER_SPHERE['assembled'] / 1024:.2g} "
                              f"KiB per sphere at coordination 12, x{MARGIN} margin), {have / 2**30:.3g} GiB available")


__all__ = ["check_fits", "estimated_bytes", "available_bytes"]
