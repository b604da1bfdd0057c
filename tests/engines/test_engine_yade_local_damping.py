"""YADE with local (Cundall) damping, ``NewtonIntegrator.damping`` 0.2 and 0.7, against ``dtcrit audit``.

An FCC lattice (32 equal spheres, periodic, pre-compressed, ``ks = kn/2``) is exported from YADE with
its NewtonIntegrator damping (the export's ``newton_damping``), and ``dtcrit audit EXPORT --json``
prints ``dt_crit``, which must be the undamped ``2/omega_max`` times ``1/sqrt(1 + alpha)``
(``derivations/records/local_damping.md``: the onset of instability for YADE's law).  YADE then runs
the lattice (``support.engines.yade_local_damping``) with that damping:

* at 0.99 x the printed step, from a random start and from a start along the top mode (dtcrit's
  governing mode, used only as a seed), it stays bounded;
* at 1.03 x, from the top-mode start, it grows (from random starts YADE's law often decays just above
  the onset: the flip ray is invariant and growing but not attracting);
* bisected on ``dt`` from the top-mode start to a relative bracket of 1e-4, YADE's threshold holds the
  printed step within [0.999, 1] of its growing end;
* the shipped hook (``yade_hook.DtcritHook``) on the damped scene sets ``0.9 x`` the damped step.

The undamped step 2/omega_max (what the audit printed before local damping was read) is 1.095 x the
damped one at 0.2 and 1.30 x at 0.7: it grows from the top-mode start.
"""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from support.engines import require_engine
from support.engines.yade_local_damping import DampedRun, Lattice, bisect_onset, hook_steps, run_batch
from support.paths import SRC

ALPHAS = (0.2, 0.7)
LATTICE = Lattice()
STEPS = 3000
DTCRIT = ["env", f"PYTHONPATH={SRC}", sys.executable, "-m", "dtcrit"]
"""The dtcrit under test as a command, from any working directory (YADE runs the hook in its own)."""


@pytest.fixture(scope="module")
def yade() -> str:
    return require_engine("yade")


def _top_mode(path: str) -> tuple[float, ...]:
    """dtcrit's governing mode of the export in YADE's coordinates (by body id; a seed for the runs only):
    6 numbers per body, scaled so that the largest of ``|phi_t|`` and ``R |phi_r|`` is 1.
    """
    from dtcrit.packing.audit.run import read_snapshot
    from dtcrit.packing.operators.assembly import mass_diagonal
    from dtcrit.packing.solvers.damped_step import damped_critical_dt

    snap = read_snapshot(path)
    step = damped_critical_dt(snap.packing, snap.contacts, "leapfrog")
    phi = (step.vector / np.sqrt(mass_diagonal(snap.packing))).reshape(-1, 6)
    ids = np.array([snap.packing.particle_id(p) for p in range(snap.packing.n)])
    assert sorted(ids) == list(range(len(ids)))
    phi = phi[np.argsort(ids)]
    scale = max(np.abs(phi[:, :3]).max(), LATTICE.radius * np.abs(phi[:, 3:]).max())
    return tuple((phi / scale).reshape(-1).tolist())


@pytest.fixture(scope="module")
def audited(yade, tmp_path_factory):
    """Per alpha: the printed audit (JSON) and the top mode of the export."""
    folder = tmp_path_factory.mktemp("yade_local_damping")
    paths = {a: str(folder / f"fcc_damping_{a}.json") for a in ALPHAS}
    run_batch(LATTICE, exports=[(a, p) for a, p in paths.items()])
    out = {}
    for a, path in paths.items():
        done = subprocess.run([*DTCRIT, "audit", path, "--json"], capture_output=True, text=True, timeout=300,
                              env=dict(os.environ))
        assert done.returncode == 0, done.stderr
        out[a] = (json.loads(done.stdout), _top_mode(path))
    return out


def test_audit_reads_newton_damping_and_lowers_the_step(audited):
    for a in ALPHAS:
        doc, _ = audited[a]
        assert doc["local_damping"]["alpha"] == a and doc["local_damping"]["law"] == "yade"
        assert doc["local_damping"]["status"] == "onset"
        assert doc["dt_crit"] == pytest.approx(doc["dt_undamped"] / math.sqrt(1.0 + a), rel=1e-12)
        assert 0.0 < doc["dt_safe"] <= doc["dt_crit"]


@pytest.fixture(scope="module")
def runs(audited):
    jobs = []
    for a in ALPHAS:
        dt, mode = audited[a][0]["dt_crit"], audited[a][1]
        jobs += [DampedRun(a, 0.99 * dt, STEPS), DampedRun(a, 0.99 * dt, STEPS, mode=mode),
                 DampedRun(a, 1.03 * dt, STEPS, mode=mode),
                 DampedRun(a, audited[a][0]["dt_undamped"], STEPS, mode=mode)]
    out = run_batch(LATTICE, jobs)
    return {a: out[4 * k:4 * k + 4] for k, a in enumerate(ALPHAS)}


@pytest.mark.parametrize("alpha", ALPHAS)
def test_yade_is_bounded_at_099_and_grows_at_103_of_the_printed_step(runs, alpha):
    random_099, mode_099, mode_103, mode_undamped = runs[alpha]
    assert random_099.bounded, f"random start at 0.99x grows (growth {random_099.growth:.3g})"
    assert mode_099.bounded, f"top-mode start at 0.99x grows (growth {mode_099.growth:.3g})"
    assert mode_103.growing, f"top-mode start at 1.03x stays bounded (growth {mode_103.growth:.3g})"
    assert mode_undamped.growing, "the undamped step 2/omega_max stays bounded with local damping"


def test_yade_threshold_from_the_top_mode_is_the_printed_step(audited):
    """Bisected to 1e-4: the printed dt_crit lies in [0.999, 1] of the growing end of YADE's bracket."""
    lo = [DampedRun(a, 0.99 * audited[a][0]["dt_crit"], 2000, mode=audited[a][1]) for a in ALPHAS]
    hi = [DampedRun(a, 1.03 * audited[a][0]["dt_crit"], 2000, mode=audited[a][1]) for a in ALPHAS]
    for a, (bounded, growing) in zip(ALPHAS, bisect_onset(LATTICE, lo, hi, rel_tol=1e-4)):
        dt = audited[a][0]["dt_crit"]
        assert growing / bounded - 1.0 <= 1e-4
        assert 0.999 * growing <= dt <= growing, (a, bounded / dt, growing / dt)


def test_yade_hook_sets_the_damped_step(audited):
    """The hook's export carries the damping, so its step is 0.9 x the damped min(dt_safe, dt_crit)."""
    done = hook_steps(LATTICE, ALPHAS, DTCRIT)
    for a, h in zip(ALPHAS, done):
        doc = audited[a][0]
        (record,) = h["history"]
        assert record.get("error") is None
        assert record["local_damping"]["alpha"] == a
        assert h["dt"] == pytest.approx(0.9 * min(doc["dt_safe"], doc["dt_crit"]), rel=1e-9)
        assert h["dt"] < doc["dt_undamped"] / math.sqrt(1.0 + a)
