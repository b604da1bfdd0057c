"""YADE (real engine) against dtcrit's step for clumps, rolling and twisting springs and bonds.

Each case runs in YADE (``yade -n -x``, Debian 2023.02a; ``support.engines.yade_bodies``) at 0.99x and
1.01x of dtcrit's step -- bounded below, growing above -- and YADE's threshold is then bisected to
2e-3 around it:

* a clump pair: two dumbbell clumps (overlapping members, YADE's own mass and principal inertia),
  touching member to member with arms far off the normal, a preload along the current centre line
  of the touching members;
* a clump packing: 24 dumbbells compressed periodically by YADE;
* two bonded pairs with CohFrictPhys's moment law (``kr = alphaKr ks R1 R2``, ``ktw = alphaKtw ks R1
  R2``), one where rolling governs and one where twisting does;
* a bonded zig-zag chain (CohFrictPhys bonds, unloaded) whose bending and twisting springs govern.

dtcrit's predictions: for the clump cases and the chain, ``read_yade_audit`` of YADE's own export
(``yade_export.py``) and ``dtcrit.packing.audit.snapshot.audit`` with the ``yade`` conventions (what
``dtcrit audit EXPORT`` computes; ``dtcrit.packing.readers.yade_clumps`` gives the clump kinematics); for the
pairs, ``dtcrit step`` on a scene with ``model = "yade"`` and ``rolling_model = "yade"``.  The
reader's own checks that need no engine are at the end.
"""
from __future__ import annotations

import json
import math
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest

from support.engines import require_engine
from support.engines.yade import PairCase, Run, SceneCase
from support.engines.yade_bodies import ChainCase, ClumpPairCase, bisect_thresholds, compress_clumps, export_cases, run_batch

STEPS = 2000
R, RHO, E = 1.0e-3, 2500.0, 1.0e8
MASS = 4.0 / 3.0 * math.pi * R**3 * RHO


def _unit(v) -> np.ndarray:
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def _clump_pair() -> ClumpPairCase:
    delta = 0.01 * R
    a0, b0 = np.zeros(3), np.array([2.0 * R - delta, 0.0, 0.0])
    a1 = a0 + 1.5 * R * _unit((-0.3, 1.0, 0.2))  # members 1.5 R apart: overlapping spheres
    b1 = b0 + 1.5 * R * _unit((0.3, -0.5, -1.0))
    member = lambda p: (*map(float, p), R)  # noqa: E731
    return ClumpPairCase(clumps=((member(a0), member(a1)), (member(b0), member(b1))), contact=(0, 0), young=E,
                         poisson=0.5, density=RHO, label="two dumbbell clumps")


def _chain() -> ChainCase:
    bond = 2.0 * R - 0.01 * R
    pts = [np.zeros(3)]
    for k in range(5):  # 120-degree zig-zag: only neighbours touch
        ang = math.radians(30.0 if k % 2 == 0 else -30.0)
        pts.append(pts[-1] + bond * np.array([math.cos(ang), math.sin(ang), 0.0]))
    return ChainCase(positions=tuple(tuple(map(float, p)) for p in pts), radius=R, young=E, poisson=0.3, density=RHO,
                     alpha_kr=2.0, alpha_ktw=2.0, label="bonded zig-zag chain of 6")


def _moment_pair(alpha_kr: float, alpha_ktw: float) -> PairCase:
    return PairCase(young=E, poisson=0.5, radius=R, density=RHO, direction=(1.0, 0.3, -0.2), overlap=0.01,
                    bonded=True, moment_law=True, alpha_kr=alpha_kr, alpha_ktw=alpha_ktw)


CLUMP_PAIR, CHAIN = _clump_pair(), _chain()
PAIRS = {"rolling pair": (_moment_pair(4.0, 1.0), "rolling"), "twisting pair": (_moment_pair(1.0, 4.0), "twisting")}


# ----------------------------------------------------------------------------- dtcrit's side

def audit_step(path) -> tuple[float, object, object]:
    """dtcrit's ``dt_crit`` of a YADE export as ``dtcrit audit`` computes it, with the packing, contacts."""
    from dtcrit.packing.audit.snapshot import audit
    from dtcrit.packing.conventions.engines import ENGINES
    from dtcrit.packing.readers.yade_export import read_yade_audit

    packing, contacts, _ = read_yade_audit(path)
    report = audit(packing, contacts, ENGINES["yade"], law="YADE's per-contact terms (export)", source=str(path))
    return report.dt_crit, packing, contacts


def scene_step(case: PairCase, tmp_path) -> dict:
    """``dtcrit step --json`` on the scene of the pair: YADE's law with its moment springs."""
    scene = tmp_path / f"pair_{case.alpha_kr}_{case.alpha_ktw}.toml"
    scene.write_text(f'integrator = "leapfrog"\n[[particle]]\nshape = "sphere"\nradius = {case.radius!r}\n'
                     f'density = {case.density!r}\n[contact]\nmodel = "yade"\nyoungs_modulus = {case.young!r}\n'
                     f'ks_ratio = {case.poisson!r}\nrolling_model = "yade"\nalpha_kr = {case.alpha_kr!r}\n'
                     f'alpha_ktw = {case.alpha_ktw!r}\n')
    done = subprocess.run([sys.executable, "-m", "dtcrit", "step", str(scene), "--json"], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


@pytest.fixture(scope="module")
def yade() -> str:
    return require_engine("yade")


@pytest.fixture(scope="module")
def engine(yade, tmp_path_factory):
    """Every case predicted, run at 0.99x and 1.01x in one YADE process, then bisected together."""
    tmp = tmp_path_factory.mktemp("yade_clumps_springs_bonds")
    packing_info = compress_clumps(tmp / "clumps", n=24, radius=R, spacing=1.0, young=E, poisson=0.25, density=RHO,
                                   pressure_over_young=2.5e-4, yade=yade)
    pair_path, chain_path = export_cases([CLUMP_PAIR, CHAIN], [tmp / "clump_pair.json", tmp / "chain.json"], yade=yade)
    cases = {}
    for key, case, path in (("clump pair", CLUMP_PAIR, pair_path),
                            ("clump packing", SceneCase(packing_info["state"]), packing_info["export"]),
                            ("bonded chain", CHAIN, chain_path)):
        dt, packing, contacts = audit_step(path)
        cases[key] = {"case": case, "dt": dt, "export": path, "packing": packing, "contacts": contacts}
    for key, (case, _) in PAIRS.items():
        step = scene_step(case, tmp)
        cases[key] = {"case": case, "dt": step["dt_isolated"], "step": step}
    keys = list(cases)
    runs = run_batch([(cases[k]["case"], [Run(STEPS, dt=0.99 * cases[k]["dt"]), Run(STEPS, dt=1.01 * cases[k]["dt"])])
                      for k in keys], yade=yade)
    for k, (below, above) in zip(keys, runs):
        cases[k].update(below=below, above=above, bracket=None)
    straddle = [k for k in keys if cases[k]["below"].bounded and cases[k]["above"].growing]
    brackets = bisect_thresholds([cases[k]["case"] for k in straddle], [0.99 * cases[k]["dt"] for k in straddle],
                                 [1.01 * cases[k]["dt"] for k in straddle], steps=STEPS, rel_tol=2e-3, yade=yade,
                                 known_ends=True)
    for k, bracket in zip(straddle, brackets):
        cases[k]["bracket"] = bracket
    cases["clump packing"]["info"] = packing_info
    return cases


KEYS = ["clump pair", "clump packing", "rolling pair", "twisting pair", "bonded chain"]


@pytest.mark.parametrize("key", KEYS)
def test_yade_bounded_below_and_growing_above_dtcrit(engine, key):
    c = engine[key]
    assert c["below"].bounded, f"{key}: YADE grows at 0.99x dtcrit's {c['dt']:.6e} (growth {c['below'].growth:.3g})"
    assert c["above"].growing, f"{key}: YADE bounded at 1.01x dtcrit's {c['dt']:.6e} (growth {c['above'].growth:.3g})"


@pytest.mark.parametrize("key", KEYS)
def test_yade_threshold_bisected_around_dtcrit(engine, key):
    """YADE's threshold, bisected to 2e-3, contains dtcrit's step (1e-3 slack for the classification)."""
    c = engine[key]
    assert c["bracket"] is not None, f"{key}: YADE did not straddle dtcrit's step"
    lo, hi = c["bracket"]
    ratio = c["dt"] / math.sqrt(lo * hi)
    print(f"{key}: dtcrit {c['dt']:.6e} s, YADE threshold in [{lo:.6e}, {hi:.6e}] s, dtcrit/YADE = {ratio:.5f}")
    assert lo / 1.001 <= c["dt"] <= hi * 1.001, f"{key}: dtcrit/YADE = {ratio:.5f}"


def test_clump_pair_arms_reach_yade_contact_point_from_the_clump_centres(engine):
    """Equal members: YADE's force and velocity arms coincide (``dtcrit.packing.readers.yade_clumps``), so the
    contact's arms are exactly YADE's exported contact point minus each clump's centre of mass; they
    lie far off the normal (the lever of the clump), and the clumps carry YADE's own mass and inertia."""
    c = engine["clump pair"]
    doc = json.loads(open(c["export"]).read())
    clumps = {b["id"]: b for b in doc["bodies"] if b["is_clump"]}
    (it,) = doc["interactions"]
    members = {b["id"]: b for b in doc["bodies"]}
    centre = lambda mid: np.array(clumps[members[mid]["clump_id"]]["pos"])  # noqa: E731
    contacts, packing = c["contacts"], c["packing"]
    point = np.array(it["point"])
    assert contacts.arm_i[0] == pytest.approx(point - centre(it["id1"]), abs=1e-15)
    assert contacts.arm_j[0] == pytest.approx(point - centre(it["id2"]), abs=1e-15)
    off_normal = np.linalg.norm(np.cross(contacts.arm_i[0], contacts.normal[0])) / np.linalg.norm(contacts.arm_i[0])
    assert off_normal > 0.3
    assert packing.n == 2 and sorted(packing.masses) == pytest.approx(sorted(b["mass"] for b in clumps.values()))
    assert packing.masses[0] == pytest.approx(2.0 * MASS, rel=1e-12), "YADE sums the members' volumes"


def test_clump_packing_is_a_packing_of_clumps(engine):
    c = engine["clump packing"]
    packing, contacts = c["packing"], c["contacts"]
    assert packing.n == 24 and packing.orientations is not None
    assert contacts.count > 40 and contacts.coordination(packing.n).mean() > 3.5
    assert 1e-4 < contacts.overlap.mean() / R < 3e-3
    assert np.all(contacts.force_n == 0.0), "clump contacts enter without pre-load (yade_clumps docstring)"


@pytest.mark.parametrize("key", list(PAIRS))
def test_moment_pairs_rotational_mode_governs(engine, key):
    """``dtcrit step`` names the rotational mode and its step is the closed form 2/sqrt(2 k/I) with
    YADE's ``k = alpha ks R^2`` (``ks = poisson kn``, ``kn = E R``)."""
    case, direction = PAIRS[key]
    step = engine[key]["step"]["contact_rotation"]
    assert step["direction"] == direction
    alpha = case.alpha_kr if direction == "rolling" else case.alpha_ktw
    k = alpha * case.poisson * E * R * R**2
    assert engine[key]["dt"] == pytest.approx(2.0 / math.sqrt(2.0 * k / (0.4 * MASS * R**2)), rel=1e-9)


def test_bonded_chain_bending_and_twisting_govern(engine):
    """Without its kr, ktw the chain's step would be 23 % longer: the bending springs set it."""
    from dtcrit.packing import analyse

    c = engine["bonded chain"]
    contacts = c["contacts"]
    assert contacts.kr == pytest.approx(2.0 * 0.3 * E * R * R**2, rel=1e-9) and contacts.ktw == pytest.approx(contacts.kr)
    free = analyse(c["packing"], contacts=replace(contacts, kr=None, ktw=None), integrator="leapfrog",
                   with_estimates=False).dt_integrator
    assert free / c["dt"] > 1.15


# ----------------------------------------------------------------------------- the reader, no engine

def _export(bodies, interactions, **top):
    return {"schema": "dtcrit-yade-export/1", "dt": 1e-7, "iter": 3, "periodic": False, "cell_hsize": None,
            "avoid_granular_ratcheting": True, "bodies": bodies, "interactions": interactions, **top}


def _sphere(bid, pos, r=R, **kw):
    m = 4.0 / 3.0 * math.pi * r**3 * RHO
    return {"id": bid, "pos": list(pos), "radius": r, "mass": m, "inertia": [0.4 * m * r * r] * 3, "clump_id": None,
            "is_clump": False, "fixed": False, "ori": [1, 0, 0, 0], **kw}


def _inter(a, b, **kw):
    return {"id1": a, "id2": b, "kn": 1e5, "ks": 3e4, "kr": None, "ktw": None, "cn": None, "cs": None, "fn": 2.0, **kw}


def test_sphere_export_read_both_ways_gives_the_same_contacts(tmp_path):
    """On spheres, ``read_yade_audit`` gives what ``with_arms(read_yade_export(...), "yade")`` gives
    (the route ``dtcrit audit`` takes for sphere exports today)."""
    from dtcrit.packing.conventions.engines import with_arms
    from dtcrit.packing.readers.yade_export import read_yade_audit, read_yade_export

    rng = np.random.default_rng(4)
    r = R * (1.0 + 0.3 * rng.random(3))
    x = np.array([[0, 0, 0], [r[0] + r[1] - 2e-5, 0, 0], [0, r[0] + r[2] - 1e-5, 1e-5]])
    path = tmp_path / "spheres.json"
    path.write_text(json.dumps(_export([_sphere(k, x[k], r[k]) for k in range(3)],
                                       [_inter(0, 1), _inter(0, 2, kr=1e-3, ktw=2e-3, cn=0.1, cs=0.05)])))
    p1, c1, _ = read_yade_export(path)
    c1 = with_arms(p1, c1, "yade")
    p2, c2, meta = read_yade_audit(path)
    assert meta["clumps"] == 0 and p2.orientations is None
    for key in ("i", "j", "normal", "arm_i", "arm_j", "overlap", "kn", "ks", "kr", "ktw", "cn", "cs", "force_n"):
        assert np.allclose(getattr(c1, key), getattr(c2, key), rtol=1e-13, atol=0), key


def test_clump_export_members_folded_into_rigid_bodies(tmp_path):
    """A clump of two members and a sphere: one contact member-sphere (arm from the clump's centre,
    orientation from ``ori``), the interaction inside the clump dropped, bounding radius of the clump."""
    from dtcrit.packing.readers.yade_export import read_yade_audit

    q = [math.cos(0.3), 0.0, 0.0, math.sin(0.3)]  # 0.6 rad about z
    m = 2.0 * MASS
    clump = {"id": 2, "pos": [0.0, 0.0, 0.0], "radius": None, "mass": m, "inertia": [1e-11, 2e-11, 3e-11],
             "clump_id": None, "is_clump": True, "fixed": False, "ori": q}
    members = [_sphere(0, (-0.75 * R, 0, 0), clump_id=2), _sphere(1, (0.75 * R, 0, 0), clump_id=2)]
    free = _sphere(3, (0.75 * R + 2.0 * R - 1e-5, 0, 0))
    path = tmp_path / "clump.json"
    path.write_text(json.dumps(_export([*members, clump, free], [_inter(0, 1), _inter(1, 3)])))
    packing, contacts, meta = read_yade_audit(path)
    assert meta["clumps"] == 1 and list(packing.ids) == [2, 3] and contacts.count == 1
    assert packing.radii[0] == pytest.approx(1.75 * R) and packing.masses[0] == m
    assert packing.orientations[0] == pytest.approx(
        np.array([[math.cos(0.6), -math.sin(0.6), 0], [math.sin(0.6), math.cos(0.6), 0], [0, 0, 1]]), abs=1e-15)
    delta = 1e-5
    assert contacts.arm_i[0] == pytest.approx([0.75 * R + R - delta / 2, 0, 0], rel=1e-12)
    assert contacts.arm_j[0] == pytest.approx([-(R - delta / 2), 0, 0], rel=1e-12)
    assert contacts.ks[0] == pytest.approx(3e4 * 2 * R / (2 * R - delta), rel=1e-12)
    assert contacts.force_n[0] == 0.0


@pytest.mark.parametrize("change, key", [
    (lambda d: d["bodies"].__setitem__(2, {**d["bodies"][2], "ori": [0, 0, 0, 0]}), "bodies[2].ori"),
    (lambda d: d["bodies"].__setitem__(0, {**d["bodies"][0], "clump_id": 9}), "bodies[0].clump_id"),
    (lambda d: d["bodies"].__setitem__(0, {**d["bodies"][0], "radius": -1.0}), "bodies[0].radius"),
    (lambda d: d.__setitem__("bodies", [d["bodies"][2], d["bodies"][3]]), "bodies"),
    (lambda d: d["interactions"].__setitem__(0, {**d["interactions"][0], "id2": 2}), "interactions[0]"),
])
def test_bad_clump_exports_are_one_line_errors(tmp_path, change, key):
    """Broken clump exports fail with the key and the reason (``dtcrit.errors.InputError``)."""
    from dtcrit.errors import InputError
    from dtcrit.packing.readers.yade_export import read_yade_audit

    clump = {"id": 2, "pos": [0.0, 0.0, 0.0], "radius": None, "mass": 2 * MASS, "inertia": [1e-11, 2e-11, 3e-11],
             "clump_id": None, "is_clump": True, "fixed": False, "ori": [1, 0, 0, 0]}
    doc = _export([_sphere(0, (-0.75 * R, 0, 0), clump_id=2), _sphere(1, (0.75 * R, 0, 0), clump_id=2), clump,
                   _sphere(3, (2.74 * R, 0, 0))], [_inter(1, 3)])
    change(doc)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(doc))
    with pytest.raises(InputError) as err:
        read_yade_audit(path)
    assert err.value.key.endswith(key) and "\n" not in str(err.value)
