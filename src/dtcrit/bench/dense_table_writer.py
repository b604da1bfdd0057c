"""Write the dense-packing bound's generated table (``_generated/dense_phi_nodes.json``; the format
and its use: ``dtcrit.scenes.dense_tables``): every ``dense_phi._phi_bound`` call that ``dtcrit step``
makes on the example scenes, recorded with the table disabled.  Run by ``python3 dev.py generate``
as ``python3 -m dtcrit.bench.dense_table_writer``.
"""
from __future__ import annotations

import json
import os

from dtcrit.scenes import dense_tables

__all__ = ["build", "main"]


def _recorded_cases(scenes) -> list:
    """The ``_phi_bound`` calls of the critical step of each scene (table disabled while recording)."""
    from dtcrit.scenes import dense_phi
    from dtcrit.scenes.scene import load_scene
    from dtcrit.scenes.timestep import critical_step

    calls: list = []
    original = dense_phi._phi_bound

    def record(*args):
        out = original(*args)
        calls.append((args, out[0]))
        return out

    os.environ[dense_tables.DISABLE] = "1"
    dense_tables.load.cache_clear()
    dense_phi._phi_bound = record
    try:
        for scene in scenes:
            critical_step(load_scene(str(scene)))
    finally:
        dense_phi._phi_bound = original
        os.environ.pop(dense_tables.DISABLE)
        dense_tables.load.cache_clear()
    return calls


def build(scenes) -> dict:
    """The table for the ``_phi_bound`` calls that the critical step of ``scenes`` makes.

    Parameters
    ----------
    scenes : list of pathlib.Path
        Scene files.

    Returns
    -------
    dict
        ``{"derivation_hash": ..., "entries": [...]}``, entries sorted, without repeats.
    """
    seen = {}
    for (z, psi, pars, rtol, n_theta), phi in _recorded_cases(scenes):
        entry = {"z_eff": int(z), "psi": float(psi), "pars": [float(t) for t in pars], "rtol": float(rtol),
                 "n_theta": int(n_theta), "phi": float(phi)}
        seen[json.dumps(entry, sort_keys=True)] = entry
    return {"derivation_hash": dense_tables.source_hash(), "entries": [seen[k] for k in sorted(seen)]}


def main() -> int:
    """Write ``_generated/dense_phi_nodes.json`` from the example scenes of the source tree.

    Returns
    -------
    int
        0.
    """
    from dtcrit.bench.startup import example_scenes

    text = json.dumps(build(example_scenes()), indent=1, sort_keys=True) + "\n"
    path = dense_tables.TABLE_PATH
    if not path.exists() or path.read_text() != text:
        path.write_text(text)
        print(f"wrote src/dtcrit/_generated/{path.name}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
