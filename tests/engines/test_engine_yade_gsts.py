"""YADE's GlobalStiffnessTimeStepper (real engine) against the audit's ``yade_gsts`` rows.

Each scene is built in YADE (``yade -n -x``, Debian 2023.02a; ``support.engines.yade_stepper``), its
interactions made, exported with ``yade_export.py``, and ``GlobalStiffnessTimeStepper`` (first in
``O.engines``, so it reads the exported state) steps once at YADE's default safety 0.8 and at 0.5.
YADE's ``O.dt`` is the reference; dtcrit's rows come from ``audit_snapshot`` on the export (what
``dtcrit audit EXPORT`` prints).  Both compute the same sums in double precision, in nearly the same
order: they agree to the last bit or two, asserted at 1e-12 relative.

Scenes: two dumbbell clumps with unequal members touching at arms far off the normal (the case the
old row rated safe), the dumbbell pair of ``test_engine_yade_clumps_springs_bonds.py``, a periodic
cloud of 30 overlapping spheres (FrictPhys, two of them fixed), the same with CohFrictPhys bonds and
their moment springs (rotation about a body axis sets the step), and periodic clouds of clumps
(three unequal members, one clump fixed; dumbbells).

The clump pair is then run in YADE at the step its stepper sets (default safety): it grows, while at
0.99x dtcrit's ``dt_crit`` it stays bounded, and the audit rates the ``yade_gsts`` row UNSAFE.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from support.engines import require_engine
from support.paths import SRC
from support.engines.yade import Run
from support.engines.yade_bodies import ClumpPairCase, run_batch
from support.engines.yade_stepper import CloudCase, stepper_dt

R, E = 1.0e-3, 1.0e8
SAFETIES = (0.8, 0.5)
STEPS = 2000


def _unit(v) -> np.ndarray:
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def _sphere(p, r) -> tuple:
    return (*map(float, p), float(r))


def _unequal_pair() -> ClumpPairCase:
    """Member 0 of each touches along x; the second members sit off to the side (YADE's stepper turns
    the clumps about the touching member's radius only).
    """
    ra, rb = R, 0.6 * R
    a0, b0 = np.zeros(3), np.array([ra + rb - 0.01 * R, 0.0, 0.0])
    a1 = np.array([-1.3, -0.75, 0.15]) * R
    b1 = b0 + np.array([0.85, 0.35, 1.2]) * R
    return ClumpPairCase(clumps=((_sphere(a0, ra), _sphere(a1, 0.7 * R)), (_sphere(b0, rb), _sphere(b1, R))),
                         contact=(0, 0), young=E, poisson=0.49, label="unequal dumbbells")


def _dumbbell_pair() -> ClumpPairCase:
    a0, b0 = np.zeros(3), np.array([2.0 * R - 0.01 * R, 0.0, 0.0])
    a1 = a0 + 1.5 * R * _unit((-0.3, 1.0, 0.2))
    b1 = b0 + 1.5 * R * _unit((0.3, -0.5, -1.0))
    return ClumpPairCase(clumps=((_sphere(a0, R), _sphere(a1, R)), (_sphere(b0, R), _sphere(b1, R))),
                         contact=(0, 0), young=E, poisson=0.5, label="two dumbbell clumps")


CASES = {
    "unequal clump pair": _unequal_pair(),
    "dumbbell clump pair": _dumbbell_pair(),
    "sphere cloud": CloudCase(n=30, fixed=2),
    "bonded sphere cloud": CloudCase(n=30, moment_law=True, seed=4),
    "clump cloud": CloudCase(n=20, clump_members=3, fixed=1, grow=1.3),
    "dumbbell cloud": CloudCase(n=20, clump_members=2, grow=1.7, r_fuzz=0.1, seed=5),
}
NO_MOMENT_LAW = CloudCase(n=30, moment_law=True, moment_rotation=False, seed=4)


@pytest.fixture(scope="module")
def yade() -> str:
    """YADE's executable (the test fails in CI without it)."""
    return require_engine("yade")


@pytest.fixture(scope="module")
def stepped(yade, tmp_path_factory):
    """Every scene exported, YADE's ``O.dt`` after one stepper step at each safety, dtcrit's audit."""
    from dtcrit.packing.audit.run import audit_snapshot

    tmp = tmp_path_factory.mktemp("yade_gsts")
    paths = [tmp / f"{k}.json" for k in range(len(CASES) + 1)]
    dts = stepper_dt([*CASES.values(), NO_MOMENT_LAW], paths, SAFETIES, yade=yade)
    out = {}
    for key, path, dt in zip([*CASES, "no moment law"], paths, dts):
        audit = audit_snapshot(path)
        out[key] = {"yade": dt, "audit": audit, "rows": {e.estimate.name: e for e in audit.estimators}, "path": path}
    return out


@pytest.mark.parametrize("key", list(CASES))
def test_audit_row_is_yade_stepper_dt(stepped, key):
    """``yade_gsts`` is YADE's ``O.dt`` at its default safety, ``yade_gsts_unscaled`` the same at 1."""
    c = stepped[key]
    row, unscaled = c["rows"]["yade_gsts"].estimate, c["rows"]["yade_gsts_unscaled"].estimate
    yade08 = c["yade"][0.8]
    print(f"{key}: YADE O.dt {yade08!r}, dtcrit row {row.dt!r}, row/YADE - 1 = {row.dt / yade08 - 1:.2e}, "
          f"YADE/dt_crit = {yade08 / c['audit'].dt_crit:.4f}")
    assert row.dt == pytest.approx(yade08, rel=1e-12, abs=0)
    assert unscaled.dt == pytest.approx(yade08 / 0.8, rel=1e-12, abs=0)


def test_cohfrictphys_without_its_moment_law_has_no_row(stepped):
    """CohFrictMat with ``momentRotationLaw`` off: YADE's stepper still adds CohFrictPhys's kr, ktw
    (its ``O.dt`` is below the step without them), which the export leaves out: no row, the reason named
    in the text and in the JSON (``dt``, ``ratio``, ``safe`` null).
    """
    import json

    import jsonschema

    from dtcrit.packing.bounds.yade_stepper import yade_stepper
    from dtcrit.packing.bounds.yade_stepper_export import from_export
    from dtcrit.packing.readers.yade_export import read_yade_audit

    c = stepped["no moment law"]
    row = c["rows"]["yade_gsts"].estimate
    assert row.dt is None and "kr, ktw" in row.detail
    doc = json.loads(c["path"].read_text())
    assert {it["phys"] for it in doc["interactions"]} == {"CohFrictPhys"}
    assert all(it["kr"] is None for it in doc["interactions"])
    text_row = next(line for line in c["audit"].to_text().splitlines() if line.startswith("yade_gsts "))
    assert "n/a" in text_row and "kr, ktw" in text_row
    jsonschema.validate(c["audit"].to_json(), json.loads((SRC / "dtcrit" / "schemas" / "dtcrit-audit-1.json").read_text()))
    for it in doc["interactions"]:
        it["phys"] = "FrictPhys"  # the same contacts without moment springs
    packing, _, _ = read_yade_audit(c["path"])
    without = yade_stepper(from_export(doc, packing)).dt
    assert c["yade"][0.8] < without * (1 - 1e-3)


@pytest.mark.parametrize("key", list(CASES))
def test_stepper_dt_at_another_safety(stepped, key):
    """The module at ``timestepSafetyCoefficient`` 0.5 is YADE's ``O.dt`` at 0.5."""
    import json

    from dtcrit.packing.bounds.yade_stepper import yade_stepper
    from dtcrit.packing.bounds.yade_stepper_export import from_export
    from dtcrit.packing.readers.yade_export import read_yade_audit

    path = stepped[key]["path"]
    packing, _, _ = read_yade_audit(path)
    step = yade_stepper(from_export(json.loads(path.read_text()), packing), 0.5)
    assert step.dt == pytest.approx(stepped[key]["yade"][0.5], rel=1e-12, abs=0)


def test_scenes_cover_translation_and_rotation(stepped):
    """The scenes exercise both terms: the bonded cloud's moment springs set a rotational step."""
    details = {k: c["rows"]["yade_gsts"].estimate.detail for k, c in stepped.items()}
    assert "rotation about body axis" in details["bonded sphere cloud"]
    assert any("translation" in d for d in details.values())


def test_unequal_clump_pair_yade_default_step_blows_up(stepped, yade):
    """YADE's own step (safety 0.8) on the unequal pair is above dtcrit's ``dt_crit``: the audit rates the
    row UNSAFE, and YADE grows at that step while it stays bounded at 0.99 ``dt_crit``.
    """
    c = stepped["unequal clump pair"]
    yade08, dt_crit = c["yade"][0.8], c["audit"].dt_crit
    assert yade08 / dt_crit > 1.1
    assert c["rows"]["yade_gsts"].unsafe is True
    at_gsts, below = run_batch([(CASES["unequal clump pair"], [Run(STEPS, dt=yade08), Run(STEPS, dt=0.99 * dt_crit)])],
                               yade=yade)[0]
    assert below.bounded, f"YADE grows at 0.99 dt_crit (growth {below.growth:.3g})"
    assert at_gsts.growing, f"YADE bounded at its stepper's {yade08:.6e} s (growth {at_gsts.growth:.3g})"


def test_clump_rows_need_the_export(stepped):
    """Called on the packing and contacts alone (no export), a clump scene has no row: the members'
    radii, the stepper's arms, are only in the export.
    """
    from dtcrit.packing.audit.snapshot import audit
    from dtcrit.packing.conventions.engines import ENGINES
    from dtcrit.packing.readers.yade_export import read_yade_audit

    packing, contacts, _ = read_yade_audit(stepped["clump cloud"]["path"])
    rows = {e.estimate.name: e for e in audit(packing, contacts, ENGINES["yade"], law="x", source="x").estimators}
    assert rows["yade_gsts"].estimate.dt is None and "member" in rows["yade_gsts"].estimate.detail
    assert math.isfinite(stepped["clump cloud"]["rows"]["yade_gsts"].estimate.dt)
