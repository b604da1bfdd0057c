"""YADE (real engine) against dtcrit's critical step: lattices, a YADE-compressed packing, pairs.

Each case is predicted with dtcrit's own packing analysis (``dtcrit.packing``: the largest mode of
``K phi = omega^2 M phi`` for contacts with per-contact springs; leapfrog, undamped: 2/omega_max)
and run in YADE (``yade -n -x``, Debian 2023.02a) through ``support.engines.yade`` at 0.99x and 1.01x
of that step: bounded below, growing above.  The YADE cases of one kind share one YADE process.

The dtcrit contacts are built with YADE's conventions, read in its sources (pkg/dem/):

* contact point ``x1 + (R1 - delta/2) n`` (Ig2_Sphere_Sphere_ScGeom.cpp); Law2_ScGeom_FrictPhys_
  CundallStrack and Law2_ScGeom6D_CohFrictPhys_CohesionMoment apply the contact force there, so the
  torque arms are ``R_i - delta/2`` (ElasticContactLaw.cpp, CohesiveFrictionalContactLaw.cpp);
* the shear spring integrates the slip velocity ``alpha (v2 - v1) + R2 n x w2 + R1 n x w1``,
  ``alpha = (R1 + R2)/(R1 + R2 - delta)`` (``avoidGranularRatcheting``, on by default;
  ScGeom.cpp ``getIncidentVel``): the full radius on the velocity side.  Linearised, the tangential
  element is ``alpha k_s b_f b_v^T`` with force-side arms ``R_i - delta/2`` and velocity-side arms
  ``R_i/alpha``; dtcrit's contacts take the symmetric equivalent ``k_s -> alpha k_s`` and arms
  ``sqrt((R_i - delta/2) R_i/alpha)`` (exact for an isolated pair, whose tangential mode is rank one;
  for equal spheres the two arms coincide; otherwise they differ by ``delta (R_i - R_j)/(2(R_i+R_j))``);
* YADE's normal force ``kn delta`` turns with the centre line: the pre-loaded lattice and packing
  contacts carry the geometric stiffness of ``force_n`` (a pair's preload along the current centre
  line turns with it and cancels that term);
* Ip2_FrictMat_FrictMat_FrictPhys (FrictPhys.cpp): ``kn = 2 E1 R1 E2 R2/(E1 R1 + E2 R2)``,
  ``ks = 2 (E1 R1 nu1)(E2 R2 nu2)/(E1 R1 nu1 + E2 R2 nu2)`` (= nu kn for one material);
  Ip2_CohFrictMat_CohFrictMat_CohFrictPhys (CohesiveFrictionalContactLaw.cpp): the same kn, ks and
  ``kr = R1 R2 ks alphaKr``, ``ktw = R1 R2 ks alphaKtw`` (default alphas 2);
* NewtonIntegrator is leapfrog; spheres have I = 2/5 m R^2.

With a 10 % overlap these conventions put the pair's tangential step at
``2/sqrt(ks alpha (2/m + 2 (R - delta/2)^2/I))``: 2.6 % below dtcrit's default (arm R - delta/2,
no alpha), 1 % above the full-radius arm of LAMMPS; the pair test bisects YADE's threshold there.
"""
from __future__ import annotations

import copy
import json
import math
import stat
import subprocess
import sys

import numpy as np
import pytest

from support.engines import require_engine
from support.engines.yade import (ENGINE_SCRIPTS, LatticeCase, PairCase, Run, SceneCase, YadeError, bisect_thresholds,
                                 compress_packing, run_batch)

STEPS = 2000  # at 1.01x YADE halts after ~30-60 steps; bounded runs take ~0.3 s

R, RHO = 1.0e-3, 2500.0
MASS = 4.0 / 3.0 * math.pi * R**3 * RHO


@pytest.fixture(scope="module")
def yade() -> str:
    return require_engine("yade")


# ----------------------------------------------------------------------------- dtcrit's side


def yade_contacts(i, j, normal, overlap, r_i, r_j, kn, ks, *, image=None, kr=None, ktw=None, force_n=None,
                  ratcheting: bool = True):
    """dtcrit ``Contacts`` with YADE's arms and shear kinematics (module docstring)."""
    from dtcrit.packing import Contacts

    i, j = np.asarray(i, np.int64), np.asarray(j, np.int64)
    normal, overlap = np.asarray(normal, float), np.asarray(overlap, float)
    r_i, r_j = np.asarray(r_i, float), np.asarray(r_j, float)
    total = r_i + r_j
    alpha = total / (total - overlap) if ratcheting else np.ones_like(total)
    arm_i = np.sqrt((r_i - overlap / 2.0) * r_i / alpha)
    arm_j = np.sqrt((r_j - overlap / 2.0) * r_j / alpha)
    image = np.zeros((i.size, 3), np.int64) if image is None else np.asarray(image, np.int64)
    contacts = Contacts(i, j, normal, arm_i[:, None] * normal, -arm_j[:, None] * normal, overlap, image,
                        r_i * r_j / total)
    contacts = contacts.with_stiffness(kn, alpha * np.asarray(ks, float), kr=kr, ktw=ktw)
    return contacts if force_n is None else contacts.with_normal_force(force_n)


def _leapfrog_step(packing, contacts) -> float:
    from dtcrit.packing import analyse

    return analyse(packing, contacts=contacts, integrator="leapfrog", with_estimates=False).dt_integrator


def lattice_prediction(case: LatticeCase) -> float:
    """dtcrit's step for the YADE lattice: dtcrit's lattice geometry at the case's spacing."""
    from dtcrit.packing import Packing, find_sphere_contacts
    from dtcrit.packing.generators.lattices import lattice_positions

    delta = case.overlap * case.radius
    x, box = lattice_positions(case.lattice, case.cells, (2.0 * case.radius - delta) / 2.0)
    packing = Packing.spheres(x, case.radius, density=case.density, box=box)
    geo = find_sphere_contacts(packing)
    r = packing.radii
    contacts = yade_contacts(geo.i, geo.j, geo.normal, geo.overlap, r[geo.i], r[geo.j], case.kn, case.ks,
                             image=geo.image, force_n=case.kn * geo.overlap)
    return _leapfrog_step(packing, contacts)


def yade_pair_springs(case: PairCase) -> dict:
    """kn, ks (and kr, ktw when bonded with the moment law) as YADE's Ip2 functors make them."""
    e, nu, r = case.young, case.poisson, case.radius
    kn = 2.0 * (e * r) * (e * r) / (e * r + e * r)
    ks = 2.0 * (e * r * nu) ** 2 / (2.0 * e * r * nu)
    out = {"kn": kn, "ks": ks, "kr": None, "ktw": None}
    if case.bonded and case.moment_law:
        out["kr"], out["ktw"] = r * r * ks * case.alpha_kr, r * r * ks * case.alpha_ktw
    return out


def pair_prediction(case: PairCase) -> float:
    from dtcrit.packing import Packing

    n = np.asarray(case.direction, float) / np.linalg.norm(case.direction)
    delta = case.overlap * case.radius
    x = np.array([-0.5, 0.5])[:, None] * (2.0 * case.radius - delta) * n
    packing = Packing.spheres(x, case.radius, density=case.density)
    k = yade_pair_springs(case)
    contacts = yade_contacts([0], [1], n[None, :], [delta], [case.radius], [case.radius], k["kn"], k["ks"],
                             kr=k["kr"], ktw=k["ktw"])
    return _leapfrog_step(packing, contacts)


def packing_from_export(data: dict):
    """dtcrit ``Packing`` and YADE-convention ``Contacts`` from a ``dtcrit-yade-export/1`` file."""
    from dtcrit.packing import Box, Packing

    bodies = sorted(data["bodies"], key=lambda b: b["id"])
    assert [b["id"] for b in bodies] == list(range(len(bodies)))
    h = np.asarray(data["cell_hsize"], float)
    assert np.allclose(h, np.diag(np.diag(h)), rtol=0, atol=1e-15 * h.max()), "the cell stays orthogonal"
    lengths = np.diag(h)
    packing = Packing.spheres([b["pos"] for b in bodies], [b["radius"] for b in bodies],
                              masses=[b["mass"] for b in bodies], box=Box(np.zeros(3), lengths, (True,) * 3))
    rows = data["interactions"]
    col = lambda key: np.array([c[key] for c in rows], float)  # noqa: E731
    image = np.rint(np.array([c["shift2"] for c in rows]) / lengths).astype(np.int64)
    contacts = yade_contacts([c["id1"] for c in rows], [c["id2"] for c in rows], col("normal"),
                             col("penetration"), col("radius1"), col("radius2"), col("kn"), col("ks"),
                             image=image, force_n=np.maximum(col("fn"), 0.0),
                             ratcheting=bool(data["avoid_granular_ratcheting"]))
    return packing, contacts


# ----------------------------------------------------------------------------- lattices

KS_RATIOS = {"0": 0.0, "0.1": 0.1, "2/7": 2.0 / 7.0, "1": 1.0}
CELLS = {"sc": 4, "bcc": 2, "fcc": 2}  # SC needs 3+ cells: YADE keeps one interaction per body pair
LATTICES = {f"{name}-ks/kn={tag}": LatticeCase(name, cells, kn=1.0e5, ks=1.0e5 * ratio, radius=R, density=RHO)
            for name, cells in CELLS.items() for tag, ratio in KS_RATIOS.items()}


@pytest.fixture(scope="module")
def lattice_runs(yade):
    predicted = {key: lattice_prediction(case) for key, case in LATTICES.items()}
    jobs = [(case, [Run(STEPS, dt=0.99 * predicted[key]), Run(STEPS, dt=1.01 * predicted[key])])
            for key, case in LATTICES.items()]
    results = run_batch(jobs, yade=yade)
    return {key: (predicted[key], *res) for key, res in zip(LATTICES, results)}


@pytest.mark.parametrize("key", list(LATTICES))
def test_yade_lattice_bounded_below_and_growing_above_dtcrit(lattice_runs, key):
    dt, below, above = lattice_runs[key]
    assert below.bounded, f"{key}: YADE grows at 0.99x dtcrit's {dt:.6e} (growth {below.growth:.3g})"
    assert above.growing, f"{key}: YADE bounded at 1.01x dtcrit's {dt:.6e} (growth {above.growth:.3g})"


def test_lattice_steps_follow_the_tangential_stiffness():
    """The predictions differ across ks/kn (each ratio tests something): FCC at ks = kn has a 2.2x
    shorter step than at ks = 0 on the same normal springs (dtcrit's analysis, no engine)."""
    sc0, fcc0, fcc1 = (lattice_prediction(LATTICES[k]) for k in ("sc-ks/kn=0", "fcc-ks/kn=0", "fcc-ks/kn=1"))
    # SC with ks = 0: independent chains of springs kn, top mode 2 sqrt(kn/m)
    assert sc0 == pytest.approx(1.0 / math.sqrt(1.0e5 / MASS), rel=1e-5)
    assert fcc0 / fcc1 == pytest.approx(2.236, rel=1e-3)


# ----------------------------------------------------------------------------- a YADE packing

PACKING = dict(n=100, r_mean=R, r_fuzz=0.3, young=1.0e8, poisson=0.25, density=RHO, pressure_over_young=2.5e-4, seed=1)


@pytest.fixture(scope="module")
def yade_packing(yade, tmp_path_factory):
    info = compress_packing(tmp_path_factory.mktemp("yade_packing"), yade=yade, **PACKING)
    data = json.loads(open(info["export"]).read())
    packing, contacts = packing_from_export(data)
    dt = _leapfrog_step(packing, contacts)
    case = SceneCase(info["state"], label="YADE-compressed polydisperse packing")
    below, above = run_batch([(case, [Run(STEPS, dt=0.99 * dt), Run(STEPS, dt=1.01 * dt)])], yade=yade)[0]
    bracket = None
    if below.bounded and above.growing:
        (bracket,) = bisect_thresholds([case], 0.99 * dt, 1.01 * dt, steps=STEPS, rel_tol=1e-3, yade=yade)
    return {"info": info, "data": data, "packing": packing, "contacts": contacts, "dt": dt, "below": below,
            "above": above, "bracket": bracket}


def test_yade_packing_has_its_own_kn_per_contact(yade_packing):
    """YADE's default law as read in FrictPhys.cpp, on every exported contact of the packing."""
    data = yade_packing["data"]
    e, nu = PACKING["young"], PACKING["poisson"]
    rows = data["interactions"]
    assert len(rows) > 150 and data["schema"] == "dtcrit-yade-export/1" and data["periodic"]
    r1, r2 = (np.array([c[k] for c in rows]) for k in ("radius1", "radius2"))
    kn, ks = (np.array([c[k] for c in rows]) for k in ("kn", "ks"))
    assert kn == pytest.approx(2.0 * e * r1 * e * r2 / (e * r1 + e * r2), rel=1e-12)
    assert ks == pytest.approx(nu * kn, rel=1e-12)
    assert kn.max() / kn.min() > 1.3, "a polydisperse packing: each contact has its own kn"
    pen = np.array([c["penetration"] for c in rows])
    assert np.all(pen > 0) and 1e-4 < pen.mean() / PACKING["r_mean"] < 1e-2


def test_yade_packing_bounded_below_and_growing_above_dtcrit(yade_packing):
    dt, below, above = yade_packing["dt"], yade_packing["below"], yade_packing["above"]
    assert below.bounded, f"YADE grows at 0.99x dtcrit's {dt:.6e} (growth {below.growth:.3g})"
    assert above.growing, f"YADE bounded at 1.01x dtcrit's {dt:.6e} (growth {above.growth:.3g})"


def test_yade_export_as_a_script_on_the_saved_scene(yade, yade_packing, tmp_path):
    """``yade -n -x yade_export.py SCENE OUT`` on the saved packing writes what the in-scene export
    wrote (YADE does not save penetrationDepth: recomputed from the spheres, the positions after the
    last step), and refuses a wrong command line with a usage line."""
    out = tmp_path / "again.json"
    script = str(ENGINE_SCRIPTS / "yade_export.py")
    done = subprocess.run([yade, "-n", "-x", script, yade_packing["info"]["state"], str(out)], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    again, first = json.loads(out.read_text()), copy.deepcopy(yade_packing["data"])
    pen = [(a.pop("penetration"), b.pop("penetration")) for a, b in zip(again["interactions"], first["interactions"])]
    assert again == first
    assert np.allclose(*np.array(pen).T, rtol=1e-2, atol=0)
    bad = subprocess.run([yade, "-n", "-x", script], capture_output=True, text=True, timeout=120)
    assert bad.returncode != 0 and "usage: yade -n -x yade_export.py SCENE OUT.json" in bad.stderr


def test_dtcrit_audit_of_the_yade_export_within_its_bisected_threshold(yade_packing):
    """``dtcrit audit EXPORT --engine yade --json`` on the exported packing: its dt_crit lies within
    [0.998, 1] of YADE's threshold (bisected to 1e-3 here), dt_safe below it; dtcrit's packing
    analysis with YADE's exact arms lies in the bracket too."""
    assert yade_packing["bracket"] is not None, "YADE did not straddle dtcrit's step (see the test above)"
    lo, hi = yade_packing["bracket"]
    done = subprocess.run([sys.executable, "-m", "dtcrit", "audit", yade_packing["info"]["export"], "--engine", "yade",
                           "--json"], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    out = json.loads(done.stdout)
    assert 0.998 * lo <= out["dt_crit"] <= hi
    assert 0.0 < out["dt_safe"] <= out["dt_crit"]
    assert lo / 1.001 <= yade_packing["dt"] <= hi * 1.001


# ----------------------------------------------------------------------------- pairs

E_PAIR = 1.0e8  # kn = E R = 1e5 N/m
OVERLAP_PAIR = PairCase(young=E_PAIR, poisson=1.0, overlap=0.1, direction=(1.0, 0.3, -0.2), radius=R, density=RHO)


def test_yade_pair_threshold_confirms_its_arm_and_ratcheting_conventions(yade):
    """10 % overlap, ks = kn: the tangential mode governs and YADE's conventions move it by percents.

    YADE's bisected threshold lies within 1e-3 of dtcrit's step with YADE's conventions; dtcrit's
    default contact (arm R - delta/2, shear spring ks on the contact-point slip) would be 2.6 % above
    it, the full-radius arm 1 % below.
    """
    case = OVERLAP_PAIR
    dt = pair_prediction(case)
    k, d = yade_pair_springs(case), case.overlap * R
    alpha = 2.0 * R / (2.0 * R - d)
    assert dt == pytest.approx(2.0 / math.sqrt(alpha * k["ks"] * (2.0 + 5.0 * (1 - d / (2 * R)) ** 2) / MASS), rel=1e-9)
    (lo, hi), = bisect_thresholds([case], 0.99 * dt, 1.01 * dt, steps=STEPS, rel_tol=1e-3, yade=yade)
    assert lo / 1.001 <= dt <= hi * 1.001
    midpoint_arm = 2.0 / math.sqrt(k["ks"] * (2.0 + 5.0 * (1 - d / (2 * R)) ** 2) / MASS)
    assert midpoint_arm / hi > 1.02


BONDED = PairCase(young=E_PAIR, poisson=0.05, overlap=0.01, direction=(1.0, 1.0, 1.0), radius=R, density=RHO,
                  bonded=True, moment_law=True)


def gsts_dt(case: PairCase, safety: float) -> float:
    """YADE's GlobalStiffnessTimeStepper on the pair (GlobalStiffnessTimeStepper.cpp): per body the
    diagonal translational and rotational stiffnesses, 1.41044 sqrt(min(m/K_ii, I/K_rot_ii))."""
    k = yade_pair_springs(case)
    n = np.asarray(case.direction, float) / np.linalg.norm(case.direction)
    kr, ktw = k["kr"] or 0.0, k["ktw"] or 0.0
    trans = (k["kn"] - k["ks"]) * n**2 + k["ks"]
    rot = k["ks"] * (1.0 - n**2) * case.radius**2 + (ktw - kr) * n**2 + kr
    inertia = 0.4 * MASS * case.radius**2
    return 1.41044 * safety * math.sqrt(min(MASS / trans.max(), inertia / rot.max()))


@pytest.fixture(scope="module")
def bonded_runs(yade):
    dt = pair_prediction(BONDED)
    runs = [Run(STEPS, dt=0.99 * dt), Run(STEPS, dt=1.01 * dt), Run(STEPS, gsts_safety=1.0),
            Run(STEPS, gsts_safety=0.8)]
    return dt, run_batch([(BONDED, runs)], yade=yade)[0]


def test_bonded_pair_normal_mode_governs_as_dtcrit_step_says():
    """The bonded pair's step is its normal mode (kr, ktw and the shear modes are slower): the
    packing analysis with YADE's springs equals ``dtcrit step``'s isolated-contact step."""
    from dtcrit.scenes.scene import parse_scene
    from dtcrit.scenes.timestep import critical_step

    k = yade_pair_springs(BONDED)
    scene = (f'integrator = "leapfrog"\n[[particle]]\nshape = "sphere"\nradius = {R!r}\ndensity = {RHO!r}\n'
             f'[contact]\nmodel = "linear"\nkn = {k["kn"]!r}\nks = {k["ks"]!r}\n')
    step = critical_step(parse_scene(scene)).dt_isolated
    assert pair_prediction(BONDED) == pytest.approx(step, rel=1e-9)
    assert step == pytest.approx(2.0 / math.sqrt(2.0 * k["kn"] / MASS), rel=1e-12)


def test_bonded_pair_dtcrit_holds_where_gsts_blows_up(bonded_runs):
    """Bonded along (1,1,1): dtcrit's step is bounded at 0.99x and grows at 1.01x; YADE's
    GlobalStiffnessTimeStepper (diagonal stiffness: kn/3 + 2 ks/3 along each axis) picks a step
    1.65x (safety 1) and 1.32x (safety 0.8) too large, and the pair blows up at both."""
    dt, (below, above, gsts1, gsts08) = bonded_runs
    assert below.bounded and above.growing
    for safety, run in ((1.0, gsts1), (0.8, gsts08)):
        assert run.dt_max == pytest.approx(gsts_dt(BONDED, safety), rel=1e-6), "GSTS as read in its source"
        assert run.dt_max > 1.3 * dt if safety == 1.0 else run.dt_max > 1.25 * dt
        assert run.growing, f"GSTS at safety {safety} (dt {run.dt_max:.4e}) did not blow up"


# ----------------------------------------------------------------------------- the hook


def _fake_dtcrit(path, dt_crit: float, dt_safe: float, fail: bool = False) -> str:
    """A stand-in for the dtcrit command: checks the command line and the export it is given."""
    script = f"""#!{sys.executable}
import json, sys
args = sys.argv[1:]
assert args[0] == "audit" and args[2:5] == ["--engine", "yade", "--json"], args
data = json.load(open(args[1]))
assert data["schema"] == "dtcrit-yade-export/1" and len(data["interactions"]) == 1, data["schema"]
if {fail!r}:
    sys.stderr.write(args[1] + ": no contact law\\n")
    sys.exit(2)
print(json.dumps({{"dt_crit": {dt_crit!r}, "dt_safe": {dt_safe!r}}}))
"""
    path.write_text(script)
    path.chmod(path.stat().st_mode | stat.S_IXUSR)
    return str(path)


def test_yade_hook_with_dtcrit_audit_keeps_the_bonded_pair_stable(yade, bonded_runs):
    """The hook (``yade_hook.DtcritHook``) in place of GlobalStiffnessTimeStepper, started from the
    step GSTS chose at safety 0.8: every 1000 steps it exports the scene, runs ``dtcrit audit
    --engine yade --json`` on it and sets O.dt = 0.9 dt_safe; the pair stays bounded where GSTS at
    safety 1 and 0.8 blew it up, and each audit's dt_crit is the pair's step dtcrit predicts (for one
    contact dt_safe equals dt_crit: the hook's default safety 0.9 keeps the step off the boundary)."""
    dt, (_, _, gsts1, gsts08) = bonded_runs
    assert gsts1.growing and gsts08.growing
    hook = {"dtcrit": [sys.executable, "-m", "dtcrit"], "every": 1000}  # default safety 0.9
    run, = run_batch([(BONDED, [Run(STEPS, dt=gsts08.dt_max, hook=hook)])], yade=yade)[0]
    history = run.info["hook"]
    assert [h.get("error") for h in history] == [None] * len(history)
    iters = [h["iter"] for h in history]
    assert len(iters) == 2 and iters[0] == 1 and set(np.diff(iters)) == {1000}
    for h in history:
        assert h["dt_crit"] == pytest.approx(dt, rel=1e-6)
        assert 0.0 < h["dt_safe"] <= h["dt_crit"] and h["dt"] == 0.9 * h["dt_safe"]
    assert run.dt_first == history[0]["dt"] and run.dt_max <= dt
    assert run.bounded, f"the hooked run grows (growth {run.growth:.3g})"


def test_yade_hook_never_exceeds_dt_crit_and_stops_on_failure(yade, tmp_path):
    """Against stand-ins for dtcrit: a dt_safe above dt_crit is capped at dt_crit; a failing audit
    stops the simulation with dtcrit's message, or with ``on_error="keep"`` keeps the step."""
    dt = pair_prediction(BONDED)
    over = _fake_dtcrit(tmp_path / "over", dt_crit=dt, dt_safe=1.5 * dt)  # a broken bound: capped at dt_crit
    failing = _fake_dtcrit(tmp_path / "failing", dt_crit=dt, dt_safe=dt, fail=True)
    res = run_batch([(BONDED, [Run(200, dt=0.5 * dt, hook={"dtcrit": over, "every": 100, "safety": 1.0}),
                               Run(200, dt=0.5 * dt, hook={"dtcrit": failing, "every": 100, "on_error": "keep"})])],
                    yade=yade)[0]
    assert res[0].dt_last == dt
    kept = res[1].info["hook"]
    assert res[1].dt_last == 0.5 * dt and all("no contact law" in h["error"] for h in kept)
    with pytest.raises(YadeError, match="no contact law"):
        run_batch([(BONDED, [Run(200, dt=0.5 * dt, hook={"dtcrit": failing, "every": 100})])], yade=yade)
