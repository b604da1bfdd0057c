"""The distributed route's share of a rank from the partitioned input (``partitioned_input``): the
same ``slepc_backend.RankShare`` as ``slepc_backend.distribute`` builds from a packing every rank
holds, built from the rank's own Morton slab and halo only.

``distributed_packing_step(..., partitioned=True)`` (``dtcrit packing FILE --backend slepc
--partitioned-read``; automatic for a ``dtcrit-spheres/1`` ``.npz`` file) calls
:func:`partitioned_share` instead of reading the whole packing on every rank.
"""
from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from dtcrit.errors import InputError
from dtcrit.packing.distributed.mpi_support import agree, peak_mib, release_memory
from dtcrit.packing.distributed.partitioned_input import PartitionedSlab, partitioned_slab
from dtcrit.packing.model import Packing, apply_law

__all__ = ["partitioned_share", "wants_partitioned"]

GENERATED = ("lattice", "random")
"""Options that generate a packing: nothing to read in pieces."""


def wants_partitioned(source, partitioned: bool | None) -> bool:
    """Whether the distributed route reads ``source`` in pieces: when asked, or for a ``.npz`` sphere file.

    Parameters
    ----------
    source : str or os.PathLike or None
        The packing's file.
    partitioned : bool or None
        ``--partitioned-read`` (None: decide by the file).

    Returns
    -------
    bool
        True for the partitioned input.
    """
    from dtcrit.packing.readers.sphere_npz import is_sphere_file

    return bool(partitioned) or (partitioned is None and is_sphere_file(source))


def _share(ps: PartitionedSlab, law):
    """``slepc_backend.RankShare`` of a partitioned slab (as ``slepc_backend.distribute`` steps 2-3)."""
    from dtcrit.packing.distributed.slepc_backend import SYMMETRIC, RankShare
    from dtcrit.packing.model import LinearLaw

    c = ps.slab.contacts
    law = LinearLaw(1.0, 1.0) if law is None else law
    c, law_text = apply_law(c, law), law.describe()
    rows, cols = ps.slab.pattern_rows, ps.slab.pattern_cols
    if SYMMETRIC:  # SBAIJ stores the blocks right of the diagonal (and the diagonal blocks)
        rows, cols = rows[cols > rows], cols[cols > rows]
    lo, hi = ps.lo, ps.hi
    own = (cols >= lo) & (cols < hi)
    d_nnz = 1 + np.bincount(rows[own] - lo, minlength=hi - lo)
    o_nnz = np.bincount(rows[~own] - lo, minlength=hi - lo)
    glob = np.unique(np.concatenate([np.arange(lo, hi), c.i, c.j]))
    k = np.searchsorted(ps.glob, glob)
    p = ps.packing
    local = Packing(p.positions[k], p.masses[k], p.inertia[k], p.radii[k], box=p.box, label=ps.label)
    contacts = replace(c, i=np.searchsorted(glob, c.i), j=np.searchsorted(glob, c.j))
    return RankShare(ps.n, lo, hi, local, glob, contacts, d_nnz.astype(np.int32), o_nnz.astype(np.int32), ps.label,
                     law_text)


def partitioned_share(source, options: dict):
    """The calling rank's ``RankShare`` from the partitioned read of ``source`` (collective).

    Parameters
    ----------
    source : str or os.PathLike or None
        The text dump or ``.npz`` sphere file.
    options : dict
        ``distributed_packing_step``'s packing options: ``density``, ``snapshot``, ``kn``, ``ks``,
        ``youngs``, ``poisson``; ``lattice`` and ``random`` must be unset.

    Returns
    -------
    tuple
        ``(share, rows_held)``: the ``slepc_backend.RankShare`` and the most sphere rows this rank held.
    """
    from dtcrit.packing.step_input import _law

    if source is None or any(options.get(k) is not None for k in GENERATED):
        raise InputError("packing", "the partitioned read (--partitioned-read, or a .npz sphere file) reads a "
                                    "FILE: a --lattice or --random packing is generated whole")
    law = _law(options.get("kn"), options.get("ks"), options.get("youngs"), options.get("poisson", 0.25))
    ps = partitioned_slab(source, density=options.get("density"), snapshot=options.get("snapshot", -1))
    peak = peak_mib()
    clock = time.perf_counter()
    share, error = None, None
    try:
        share = _share(ps, law)
    except ValueError as exc:
        error = exc
    agree(error)
    if share is None:  # agree raised on every rank if any failed
        raise RuntimeError("partitioned_share: no share although every rank succeeded")
    held, seconds = ps.rows_held, ps.seconds
    del ps
    release_memory()
    share.times = {"input": seconds["read"] + seconds["exchange"],
                   "contacts": seconds["contacts"] + time.perf_counter() - clock}
    share.peaks = {"input": peak, "contacts": peak_mib()}
    return share, held
