"""Run under ``mpirun -n P python tests/support/partitioned_probe.py OUT.json FILE...``: each FILE read by
the partitioned input (``dtcrit.packing.distributed.partitioned_input.partitioned_slab``); rank 0
writes, per file, every rank's contacts as ``(id_i, id_j)`` pairs with their overlaps and the most
rows each rank held, for the test to compare with the serial reader.  A FILE that is refused gives
its one-line error instead.
"""
from __future__ import annotations

import json
import sys

import numpy as np
from mpi4py import MPI

from dtcrit.packing.distributed.partitioned_input import partitioned_slab


def probe(path: str) -> dict:
    """One file's contacts (ids, overlaps) and rows held, gathered on rank 0."""
    comm = MPI.COMM_WORLD
    try:
        s = partitioned_slab(path)
    except (ValueError, SystemExit) as exc:
        lines = comm.gather(str(exc) if isinstance(exc, ValueError) else None)
        return {"error": [line for line in lines or [] if line]}
    ids = s.packing.ids
    i = ids[np.searchsorted(s.glob, s.slab.contacts.i)]
    j = ids[np.searchsorted(s.glob, s.slab.contacts.j)]
    mine = {"i": i.tolist(), "j": j.tolist(), "overlap": s.slab.contacts.overlap.tolist(),
            "rows_held": s.rows_held, "n": s.n, "own": s.hi - s.lo}
    every = comm.gather(mine)
    if every is None:
        return {}
    return {"i": sum((e["i"] for e in every), []), "j": sum((e["j"] for e in every), []),
            "overlap": sum((e["overlap"] for e in every), []), "rows_held": [e["rows_held"] for e in every],
            "own": [e["own"] for e in every], "n": every[0]["n"]}


def main() -> None:
    """Probe every FILE of the command line; rank 0 writes the JSON file."""
    out = {path: probe(path) for path in sys.argv[2:]}
    if MPI.COMM_WORLD.Get_rank() == 0:
        with open(sys.argv[1], "w") as handle:
            json.dump(out, handle)


if __name__ == "__main__":
    main()
