"""Which PETSc build a distributed run loads, chosen before petsc4py is first imported: Debian's build
with 32-bit indices (``PetscInt`` of 32 bits: at most ``2^31 - 1`` rows, 357,913,941 particles at 6 DOFs
each) or its build with 64-bit indices (``python3-petsc4py-64-real``, ``python3-slepc4py-64-real``).

Each compiled petsc4py/slepc4py module links its own PETSc library (Debian's 64-bit one:
``libpetsc64_real``), so the build that runs is the one whose module folders come first on ``sys.path``
when ``petsc4py`` is imported.  ``.venv-mpi``'s ``.pth`` file names the 32-bit folders (the default);
``python3 dev.py mpi-env`` records the 64-bit folders in :data:`RECORD` (:data:`DIRS_ENV` overrides the
record), and :func:`select_build` puts them first when 64 bits are wanted.  A process that has already
loaded the other build cannot switch: :func:`select_build` refuses rather than mix two libraries.

The particle count decides (:func:`index_bits`: 64 bits when ``6 N > 2^31 - 1``, Otsubo et al. 2017's six
DOFs per particle), so it is known before any MPI call: the whole-read route reads its input first, the
partitioned route peeks at the file's header (:func:`peek_count`: the last snapshot found by reading
backwards from the file's end, snapshot ``k >= 0`` by scanning forwards up to its marker).  Without
recorded 64-bit folders, a default petsc4py that is itself a 64-bit-index build (a cluster's own PETSc) is
accepted.  Once a build is loaded, the one index limit is that build's (:func:`index_limit`, from
``PETSc.IntType``), checked by :func:`check_dofs`; the report's ``petsc_index_bits`` is that loaded build's
width, also when ``--petsc-indices 32`` ran on a 64-bit default build.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np

from dtcrit.errors import InputError

__all__ = ["CHOICES", "DIRS_ENV", "LIMITS", "MIN_ROW_BYTES", "PEEK_BLOCK", "RECORD", "UNREAD_BELOW", "check_dofs",
           "default_bits", "index_bits", "index_limit", "loaded_bits", "peek_count", "select_build", "snapshot_offset"]

CHOICES = ("auto", "32", "64")
"""Values of ``--petsc-indices`` (``distributed_packing_step(petsc_indices=...)``)."""
LIMITS = {32: 2**31 - 1, 64: 2**63 - 1}
"""Largest ``PetscInt`` of each build: the DOF count ``6 N`` must not exceed the loaded build's."""
DIRS_ENV = "DTCRIT_PETSC64_DIRS"
"""Environment variable naming the 64-bit build's module folders (``os.pathsep``-separated), instead of :data:`RECORD`."""
RECORD = "dtcrit-petsc64-dirs.txt"
"""File of the environment (``sys.prefix``) naming the 64-bit build's module folders, one a line; written by
``python3 dev.py mpi-env`` (its ``PETSC64_RECORD``), empty when the packages are absent."""
PACKAGES = "python3-petsc4py-64-real python3-slepc4py-64-real"
"""Debian's packages of the 64-bit-index build."""
MIN_ROW_BYTES = 6
"""Fewest bytes of an atom row of a text dump (three one-digit coordinates, two spaces, a newline): a dump
of ``S`` bytes holds at most ``S // 6`` atoms."""
UNREAD_BELOW = MIN_ROW_BYTES * (LIMITS[32] // 6 + 1)
"""A text dump of fewer bytes (``6 x 357,913,942 = 2,147,483,652``) holds at most ``(2^31 - 1) // 6`` atoms,
never needing 64-bit indices: :func:`peek_count` returns its size bound unread."""
PEEK_BLOCK = 1 << 24
"""Bytes :func:`peek_count` scans at a time for snapshot markers (16 MiB), forwards or backwards."""


def limit_error(n: int, limit: int, key: str = "packing") -> InputError:
    """The one-line refusal of ``n`` particles beyond a build's index limit ``limit``.

    Parameters
    ----------
    n : int
        Particles.
    limit : int
        The build's largest index (:data:`LIMITS`).
    key : str
        The ``InputError`` key (``petsc_indices`` when the user chose the width).

    Returns
    -------
    InputError
        ``N particles need 6N DOFs, beyond this PETSc's B-bit index limit 2^(B-1) - 1 = L``.
    """
    bits = int(limit).bit_length() + 1
    hint = "; --petsc-indices auto or 64 loads Debian's 64-bit build" if bits == 32 else ""
    return InputError(key, f"{n} particles need {6 * n} DOFs, beyond this PETSc's {bits}-bit index limit "
                           f"2^{bits - 1} - 1 = {limit} (at most {limit // 6} particles){hint}")


def index_bits(n: int | None, wanted: str = "auto") -> int:
    """The index width a run of ``n`` particles loads: 64 when ``6 n > 2^31 - 1`` or asked, else 32.

    Parameters
    ----------
    n : int or None
        Particles (None: unknown, as for a file the peek could not read; the read then reports).
    wanted : str
        ``"auto"``, ``"32"`` or ``"64"`` (:data:`CHOICES`).

    Returns
    -------
    int
        32 or 64.

    Raises
    ------
    InputError
        An unknown ``wanted``, or ``"32"`` with more DOFs than 32-bit indices number (:func:`limit_error`).
    """
    if str(wanted) not in CHOICES:
        raise InputError("petsc_indices", f"unknown index width {wanted!r}; choose one of {', '.join(CHOICES)}")
    too_many = n is not None and 6 * n > LIMITS[32]
    if str(wanted) == "32" and n is not None and too_many:
        raise limit_error(n, LIMITS[32], "petsc_indices")
    return 64 if str(wanted) == "64" or (str(wanted) == "auto" and too_many) else 32


def build_dirs() -> list[str]:
    """The 64-bit build's module folders: :data:`DIRS_ENV`, else :data:`RECORD` of this environment.

    Returns
    -------
    list of str
        The folders holding its ``petsc4py`` and ``slepc4py`` (empty: not installed).
    """
    given = os.environ.get(DIRS_ENV)
    if given is not None:
        return [d for d in given.split(os.pathsep) if d]
    record = Path(sys.prefix) / RECORD
    return [d.strip() for d in record.read_text().splitlines() if d.strip()] if record.is_file() else []


def loaded_bits() -> int | None:
    """The index width of the PETSc build this process has imported (None: petsc4py not imported yet).

    Returns
    -------
    int or None
        8 times ``PETSc.IntType``'s size in bytes.
    """
    if "petsc4py" not in sys.modules:
        return None
    from petsc4py import PETSc

    return 8 * np.dtype(PETSc.IntType).itemsize


def select_build(bits: int) -> None:
    """Make ``import petsc4py`` load the build of ``bits``-bit indices (module docstring); before its first import.

    Parameters
    ----------
    bits : int
        32 (the environment's default path) or 64 (:func:`build_dirs` put first on ``sys.path``; without
        them, the default petsc4py when :func:`default_bits` finds it a 64-bit-index build).

    Raises
    ------
    InputError
        64 bits wanted and neither the recorded build nor a 64-bit default one (names the Debian packages
        and ``python3 dev.py mpi-env``), or this process has already loaded the other build.
    """
    loaded = loaded_bits()
    if loaded is not None:
        if loaded != bits:
            raise InputError("petsc_indices", f"this process has already loaded the PETSc build of {loaded}-bit "
                                              f"indices; the {bits}-bit one needs a new process")
        return
    if bits == 32:
        return
    dirs = build_dirs()
    if all(any((Path(d) / pkg / "__init__.py").is_file() for d in dirs) for pkg in ("petsc4py", "slepc4py")):
        sys.path[:0] = dirs
        sys.path_importer_cache.clear()
        return
    if default_bits() != 64:
        raise InputError("petsc_indices", f"64-bit PETSc indices need Debian's 64-bit build: apt-get install "
                                          f"{PACKAGES}, then python3 dev.py mpi-env (it records the build in .venv-mpi)")


def default_bits() -> int | None:
    """The index width of the default petsc4py (the one on the path), imported to read it: a cluster's own
    PETSc may be a 64-bit-index build.

    Returns
    -------
    int or None
        :func:`loaded_bits` after the import; None when petsc4py does not import (``mpi_support.petsc``
        then says what to install).
    """
    try:
        from petsc4py import PETSc  # noqa: F401  (starts MPI: the build is then this process's)
    except Exception:  # ImportError, or a NumPy ABI mismatch raised from the compiled module
        return None
    return loaded_bits()


def index_limit() -> int:
    """The largest index of the PETSc build loaded (``PETSc.IntType``'s maximum; imports it if needed).

    Returns
    -------
    int
        ``2^31 - 1`` or ``2^63 - 1``.
    """
    from dtcrit.packing.distributed.mpi_support import petsc

    return int(np.iinfo(petsc()[0].IntType).max)


def check_dofs(n: int) -> None:
    """Refuse ``n`` particles whose ``6 n`` DOFs the loaded build cannot number (:func:`limit_error`).

    Parameters
    ----------
    n : int
        Particles.

    Raises
    ------
    InputError
        ``6 n`` beyond the loaded build's largest index (key ``packing``, the line of :func:`limit_error`).
    """
    limit = index_limit()
    if 6 * n > limit:
        raise limit_error(n, limit)


def peek_count(source, snapshot: int = -1) -> int | None:
    """The particles of ``source``'s chosen snapshot, from its header, without MPI (or a bound that fits 32 bits).

    A ``dtcrit-spheres/1`` file gives its row count (``sphere_npz.open_spheres``); a text dump of fewer
    than :data:`UNREAD_BELOW` bytes holds too few atom rows to need 64-bit indices, and its size bound is
    returned unread; a larger one's snapshot is located by :func:`snapshot_offset` (never the whole file
    read just to count) and its ``ITEM: NUMBER OF ATOMS`` read (``dump_ranges.header_at``).

    Parameters
    ----------
    source : str or os.PathLike or None
        The dump or sphere file.
    snapshot : int
        Snapshot index, Python style.

    Returns
    -------
    int or None
        The count (or the bound); None when the header cannot be read (the partitioned read then
        reports why, on every rank).
    """
    from dtcrit.packing.readers.dump_ranges import header_at
    from dtcrit.packing.readers.sphere_npz import is_sphere_file, open_spheres

    if source is None:
        return None
    try:
        if is_sphere_file(source):
            return len(open_spheres(source).rows)
        size = os.path.getsize(source)
        if isinstance(snapshot, bool) or not isinstance(snapshot, (int, np.integer)):
            return None  # the read names the bad index
        if size < UNREAD_BELOW:
            return size // MIN_ROW_BYTES
        offset = snapshot_offset(source, size, snapshot)
        return None if offset is None else header_at(source, offset, 1).count  # its line names no error here
    except (OSError, ValueError):
        return None


def snapshot_offset(source, size: int, snapshot: int) -> int | None:
    """The byte offset of snapshot ``snapshot``'s ``ITEM: TIMESTEP`` line, scanning :data:`PEEK_BLOCK`
    bytes at a time (``dump_ranges.scan_markers``): from the file's start up to marker ``snapshot`` when
    ``snapshot >= 0``, from its end backwards up to marker ``-snapshot`` from the end when negative (the
    default ``-1``: the last snapshot's bytes only).

    Parameters
    ----------
    source : str or os.PathLike
        The dump file.
    size : int
        Its size in bytes.
    snapshot : int
        Snapshot index, Python style.

    Returns
    -------
    int or None
        The offset; None when the file has too few snapshots.
    """
    from dtcrit.packing.readers.dump_ranges import scan_markers

    backwards = snapshot < 0
    wanted = -snapshot if backwards else snapshot + 1
    found: list[int] = []
    for start in (range(size, 0, -PEEK_BLOCK) if backwards else range(0, size, PEEK_BLOCK)):
        a, b = (max(0, start - PEEK_BLOCK), start) if backwards else (start, min(size, start + PEEK_BLOCK))
        offsets = scan_markers(source, a, b).offsets
        found += offsets[::-1] if backwards else offsets
        if len(found) >= wanted:
            return found[wanted - 1]
    return None
