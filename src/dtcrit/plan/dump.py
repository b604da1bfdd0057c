"""``--write-dump``: the snapshot with the planned masses, as a LAMMPS dump ``dtcrit audit`` reads back.

The dump (``ITEM: ATOMS id type x y z radius mass``, every number with 17 significant digits) keeps the
snapshot's particle ids, so a ``--contacts`` table or a ``--local`` contact list of the original still
applies; the reader (``dtcrit.packing.readers.lammps_dump``) takes the ``mass`` column and gives each
sphere the moment ``2/5 m R^2``, so the planned factor scales the inertia with the mass.  Walls added by
``--wall`` are not bodies of the file (give the same ``--wall`` lines again).  The file is written to a
temporary file beside the target and renamed onto it: an error leaves nothing half-written.
"""
from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np

from dtcrit.errors import InputError

__all__ = ["check_dump_target", "format_scaled_dump", "write_scaled_dump"]


def check_dump_target(snapshot, path, *, per_type_law: bool = False) -> None:
    """Refuse, before any work, a snapshot that has no dump form or a path that cannot be written.

    Parameters
    ----------
    snapshot : dtcrit.packing.audit.results.Snapshot
        The snapshot.
    path : str or os.PathLike
        The dump to write.
    per_type_law : bool
        Whether the contact law is read per atom type (a LIGGGHTS input): the dump written keeps no types.

    Raises
    ------
    InputError
        ``write_dump``: a YADE export, bodies other than spheres, a directory that does not exist, or the
        snapshot itself (the same file by any path: the plan would overwrite its own input).
    """
    with open(snapshot.source, "rb") as fh:
        export = fh.read(64).lstrip(b"\xef\xbb\xbf \t\r\n").startswith(b"{")
    if export:
        raise InputError("write_dump", "writes a LAMMPS dump of spheres; a YADE export's planned factors go to YADE "
                                       "through its hook (the JSON's density_scaling.factors)")
    if per_type_law:
        raise InputError("write_dump", "writes every atom as type 1, but a LIGGGHTS input gives the law per atom type: "
                                       "take the planned masses from --json (density_scaling.factors) instead")
    if not snapshot.packing.is_spheres or snapshot.packing.orientations is not None:
        raise InputError("write_dump", "a dump holds spheres only; this snapshot has other bodies")
    if Path(path).exists() and Path(snapshot.source).exists() and os.path.samefile(path, snapshot.source) or \
            Path(path).resolve() == Path(snapshot.source).resolve():
        raise InputError("write_dump", f"{path} is the snapshot itself: write the planned masses to another file")
    parent = Path(path).parent
    if not parent.is_dir():
        raise InputError("write_dump", f"the directory {parent} does not exist")
    if Path(path).is_dir():
        raise InputError("write_dump", f"{path} is a directory")


def format_scaled_dump(packing, factors, free) -> str:
    """The dump text of the free spheres with masses ``f m`` (module docstring).

    Parameters
    ----------
    packing : dtcrit.packing.model.Packing
        The snapshot's bodies.
    factors : array_like
        ``(N,)`` the planned factors.
    free : array_like
        ``(N,)`` which bodies are particles (the others, walls, are left out).

    Returns
    -------
    str
        The text.
    """
    from dtcrit.packing.readers.lammps_dump import _box_bounds
    from dtcrit.packing.model import Box

    keep = np.flatnonzero(np.asarray(free, bool))
    x, r = packing.positions[keep], packing.radii[keep]
    m = packing.masses[keep] * np.asarray(factors, float)[keep]
    box = packing.box
    if box is None:
        box = Box(x.min(axis=0) - r.max(), x.max(axis=0) + r.max(), (False, False, False))
    flags = " ".join("pp" if p else "ff" for p in box.periodic)
    out = ["ITEM: TIMESTEP", "0", "ITEM: NUMBER OF ATOMS", str(keep.size), *_box_bounds(box, flags),
           "ITEM: ATOMS id type x y z radius mass"]
    for k, p in enumerate(keep):
        out.append(f"{packing.particle_id(p)} 1 {x[k, 0]:.17g} {x[k, 1]:.17g} {x[k, 2]:.17g} {r[k]:.17g} {m[k]:.17g}")
    return "\n".join(out) + "\n"


def write_scaled_dump(path, packing, factors, free) -> None:
    """Write :func:`format_scaled_dump` atomically: a temporary file beside ``path``, renamed onto it.

    Parameters
    ----------
    path : str or os.PathLike
        The dump to write.
    packing : dtcrit.packing.model.Packing
        The snapshot's bodies.
    factors, free : array_like
        ``(N,)`` the planned factors and which bodies are particles.
    """
    text = format_scaled_dump(packing, factors, free)
    target = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    try:
        mask = os.umask(0)
        os.umask(mask)
        os.chmod(tmp, 0o666 & ~mask)  # as an ordinary new file, not mkstemp's 0600
        with os.fdopen(fd, "w") as fh:
            fh.write(text)
        os.replace(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
