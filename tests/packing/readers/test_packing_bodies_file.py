"""``dtcrit packing BODIES.json``: packings of non-spherical bodies from a ``dtcrit-bodies/1`` file
(``dtcrit.packing.readers.bodies_file``), against eigen-solves assembled here and the Python route."""
from __future__ import annotations

import json
import math

import jsonschema
import numpy as np
import pytest
from scipy.linalg import eigh
from scipy.spatial.transform import Rotation

from dtcrit.cli import main
from support.paths import REPO_ROOT as ROOT

SCHEMA = json.loads((ROOT / "src" / "dtcrit" / "schemas" / "dtcrit-packing-1.json").read_text())
EXAMPLE = ROOT / "examples" / "packings" / "ellipsoids.json"
RHO = 2650.0


def _write(tmp_path, doc, name="bodies.json") -> str:
    path = tmp_path / name
    path.write_text(json.dumps(doc, indent=1))
    return str(path)


def _run(capsys, argv) -> dict:
    assert main(["packing", *argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def _cross(r) -> np.ndarray:
    return np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]], float)


def _pair_omega_max(m1, j1, r1, m2, j2, r2, n, kn, ks) -> float:
    """Largest omega of two rigid bodies joined by one spring at arms ``r1``, ``r2`` (world frame):
    DOFs (u1, theta1, u2, theta2); the contact points move by ``u + theta x r``; ``K = B^T C B``,
    ``C = kn n n^T + ks (1 - n n^T)``; ``M = diag(m1, J1, m2, J2)``; dense generalized eigen-solve."""
    b = np.hstack([-np.eye(3), _cross(r1), np.eye(3), -_cross(r2)])  # theta x r = -[r]x theta
    c = kn * np.outer(n, n) + ks * (np.eye(3) - np.outer(n, n))
    m = np.zeros((12, 12))
    m[0:3, 0:3], m[3:6, 3:6], m[6:9, 6:9], m[9:12, 9:12] = m1 * np.eye(3), j1, m2 * np.eye(3), j2
    return math.sqrt(eigh(b.T @ c @ b, m, eigvals_only=True).max())


def _ellipsoid_mass_inertia(a, b, c, rho):
    m = 4.0 / 3.0 * math.pi * a * b * c * rho
    return m, np.diag([m * (b * b + c * c) / 5, m * (a * a + c * c) / 5, m * (a * a + b * b) / 5])


def _quat(rotation: Rotation) -> list[float]:
    x, y, z, w = rotation.as_quat()  # SciPy is scalar-last; the file is [qw, qx, qy, qz]
    return [float(w), float(x), float(y), float(z)]


# ---------------------------------------------------------------- (a) tip-to-tip ellipsoid pair

def test_ellipsoid_pair_tip_to_tip_matches_a_dense_12_dof_solve(tmp_path, capsys):
    a1, b1, c1 = 3.0e-3, 2.0e-3, 1.0e-3
    a2, b2, c2 = 2.0e-3, 1.5e-3, 1.0e-3
    mass2, delta, kn, ks = 3.0e-5, 1.0e-5, 1.0e5, 7.0e4
    q1 = Rotation.from_euler("z", 180, degrees=True)  # long axis still along x
    q2 = Rotation.from_euler("x", 30, degrees=True)
    doc = {"schema": "dtcrit-bodies/1", "box": None, "bodies": [
        {"id": 7, "shape": {"shape": "ellipsoid", "semi_axes": [a1, b1, c1], "density": RHO},
         "position": [0.0, 0.0, 0.0], "orientation": _quat(q1)},
        {"id": 9, "shape": {"shape": "ellipsoid", "semi_axes": [a2, b2, c2], "mass": mass2},
         "position": [a1 + a2 - delta, 0.0, 0.0], "orientation": _quat(q2)}]}
    out = _run(capsys, [_write(tmp_path, doc), "--kn", str(kn), "--ks", str(ks)])
    m1, i1 = _ellipsoid_mass_inertia(a1, b1, c1, RHO)
    _, i2 = _ellipsoid_mass_inertia(a2, b2, c2, 1.0)
    i2 = i2 * mass2 / (4.0 / 3.0 * math.pi * a2 * b2 * c2)
    j1 = q1.as_matrix() @ i1 @ q1.as_matrix().T
    j2 = q2.as_matrix() @ i2 @ q2.as_matrix().T
    # the contact point sits halfway through the overlap on the x axis, at x = a1 - delta/2
    r1 = np.array([a1 - delta / 2, 0.0, 0.0])
    r2 = r1 - np.array([a1 + a2 - delta, 0.0, 0.0])
    expected = _pair_omega_max(m1, j1, r1, mass2, j2, r2, np.array([1.0, 0.0, 0.0]), kn, ks)
    assert out["n_contacts"] == 1 and out["n_particles"] == 2
    assert out["omega_max"] == pytest.approx(expected, rel=1e-9)


def test_clump_pair_from_a_file_matches_a_dense_12_dof_solve(tmp_path, capsys):
    """Two dumbbells of touching spheres (no overlap inside a clump: mass and inertia in closed
    form).  Clump 1 is given along y and turned onto x; clump 2's spheres sit off its frame origin."""
    r, delta, kn, ks = 1.0e-3, 2.0e-6, 2.0e5, 1.5e5
    m_s = 4.0 / 3.0 * math.pi * r**3 * RHO
    doc = {"schema": "dtcrit-bodies/1", "box": None, "bodies": [
        {"id": 1, "shape": {"shape": "clump", "spheres": [[0, -r, 0, r], [0, r, 0, r]], "density": RHO},
         "position": [0.0, 0.0, 0.0], "orientation": _quat(Rotation.from_euler("z", 90, degrees=True))},
        {"id": 2, "shape": {"shape": "clump", "spheres": [[r, 0, 0, r], [3 * r, 0, 0, r]], "density": RHO},
         "position": [2 * r - delta, 0.0, 0.0]}]}
    out = _run(capsys, [_write(tmp_path, doc), "--kn", str(kn), "--ks", str(ks)])
    m = 2 * m_s
    j = np.diag([2 * 0.4 * m_s * r**2] + [2 * (0.4 * m_s * r**2 + m_s * r**2)] * 2)  # axis along x
    r1 = np.array([2 * r - delta / 2, 0.0, 0.0])  # clump 2's centre is at 4 r - delta
    r2 = r1 - np.array([4 * r - delta, 0.0, 0.0])
    expected = _pair_omega_max(m, j, r1, m, j, r2, np.array([1.0, 0.0, 0.0]), kn, ks)
    assert out["n_contacts"] == 1
    assert out["omega_max"] == pytest.approx(expected, rel=1e-9)


# ---------------------------------------------------------------- (b) periodic lattice, file vs Python

def _lattice(rotation: Rotation, semi_axes, cells=2):
    """Identical rotated ellipsoids on a simple orthorhombic lattice, each axis spaced at 0.999 of
    twice the radial distance 2 rho(e) = 2 / |A^-1 R^T e| (translates of a centrally symmetric
    body overlap iff half the translation lies inside it): every axis neighbour overlaps."""
    rot = rotation.as_matrix()
    radial = np.array([1.0 / np.linalg.norm((rot.T @ e) / np.array(semi_axes)) for e in np.eye(3)])
    spacing = 0.999 * 2 * radial
    x = np.array([[i, j, k] for i in range(cells) for j in range(cells) for k in range(cells)], float) * spacing
    return x, spacing * cells


def test_periodic_lattice_file_equals_python_from_shapes(tmp_path, capsys):
    from dtcrit.bodies import Ellipsoid
    from dtcrit.packing.detection.overlaps import find_convex_contacts
    from dtcrit.packing.model import Box, LinearLaw, Packing
    from dtcrit.packing.report import analyse

    axes, kn, ks = (2.0e-3, 1.2e-3, 0.8e-3), 1.0e5, 6.0e4
    rotation = Rotation.from_rotvec([0.3, -0.5, 0.2])
    x, length = _lattice(rotation, axes)
    doc = {"schema": "dtcrit-bodies/1",
           "box": {"lo": [0.0, 0.0, 0.0], "hi": length.tolist(), "periodic": [True, True, True]},
           "bodies": [{"id": 100 + k, "shape": {"shape": "ellipsoid", "semi_axes": list(axes), "density": RHO},
                       "position": p.tolist(), "orientation": _quat(rotation)} for k, p in enumerate(x)]}
    out = _run(capsys, [_write(tmp_path, doc), "--kn", str(kn), "--ks", str(ks)])
    shape = Ellipsoid(*axes, density=RHO)
    packing = Packing.from_shapes([shape] * len(x), x, np.repeat(rotation.as_matrix()[None], len(x), 0),
                                  box=Box(np.zeros(3), length, (True, True, True)))
    contacts = find_convex_contacts(packing)
    ref = analyse(packing, LinearLaw(kn, ks), contacts)
    assert contacts.count >= 3 * len(x)  # both images along each axis of a 2-cell box, and some diagonals
    assert out["n_contacts"] == contacts.count and out["n_particles"] == 8
    # the penetration normal minimises a smooth overlap function, so it is found to ~sqrt(eps): SciPy's
    # rotation matrix and the file's quaternion formula differ in the last bit and move it by 1.2e-8
    assert out["omega_max"] == pytest.approx(ref.omega_max, rel=1e-7)
    assert out["cn_mean"] == pytest.approx(2 * contacts.count / 8)


def test_listed_contacts_replace_the_command_line_law(tmp_path, capsys):
    """Per-contact kn/ks from the file: equal springs everywhere reproduce the --kn/--ks run; a
    different spring on one contact changes the result; the Python reader agrees."""
    from dtcrit.packing.readers.bodies_file import read_bodies_file
    from dtcrit.packing.report import analyse

    doc = json.loads(EXAMPLE.read_text())
    base = _run(capsys, [str(EXAMPLE), "--kn", "1e5", "--ks", "8e4"])
    pairs = [(1, 2), (2, 3), (3, 4), (4, 1)]
    doc["contacts"] = [{"id1": a, "id2": b, "kn": 1e5, "ks": 8e4} for a, b in pairs]
    same = _run(capsys, [_write(tmp_path, doc)])
    assert same["omega_max"] == pytest.approx(base["omega_max"], rel=1e-12)
    doc["contacts"][2]["ks"] = 3.2e5  # the top mode is rotational: carried by the shear springs
    path = _write(tmp_path, doc, "stiffer.json")
    stiffer = _run(capsys, [path])
    assert stiffer["omega_max"] > base["omega_max"] * 1.01
    read = read_bodies_file(path)
    assert read.stiffness_given and read.kinds == {"ellipsoid": 4}
    assert analyse(read.packing, None, read.contacts).omega_max == pytest.approx(stiffer["omega_max"], rel=1e-12)


# ---------------------------------------------------------------- (c) bad input

def _good() -> dict:
    return json.loads(EXAMPLE.read_text())


def _edit(change):
    def make():
        doc = _good()
        change(doc)
        return doc
    return make


BAD = {
    "missing position": (_edit(lambda d: d["bodies"][1].pop("position")), "bodies[1].position", "missing"),
    "missing shape key": (_edit(lambda d: d["bodies"][2]["shape"].pop("semi_axes")), "bodies[2].shape.semi_axes", "missing"),
    "unknown shape": (_edit(lambda d: d["bodies"][0]["shape"].update(shape="ellipse")), "bodies[0].shape.shape", "ellipsoid"),
    "semi-axes length": (_edit(lambda d: d["bodies"][3]["shape"].update(semi_axes=[1e-3, 1e-3])), "bodies[3].shape.semi_axes",
                         "3 entries"),
    "two densities": (_edit(lambda d: d["bodies"][0]["shape"].update(mass=1.0)), "bodies[0].shape.mass", "not both"),
    "size distribution": (_edit(lambda d: d["bodies"][0].update(shape={"shape": "sphere", "radii": [1e-3, 2e-3],
                                                                       "density": 1.0})), "bodies[0].shape.radii", "one sphere"),
    "non-unit quaternion": (_edit(lambda d: d["bodies"][1].update(orientation=[1.0, 0.1, 0.0, 0.0])), "bodies[1].orientation",
                            "unit quaternion"),
    "duplicate id": (_edit(lambda d: d["bodies"][3].update(id=2)), "bodies[3].id", "already used by bodies[1]"),
    "unknown body key": (_edit(lambda d: d["bodies"][0].update(velocity=[0, 0, 0])), "bodies[0].velocity", "unknown key"),
    "wrong schema": (_edit(lambda d: d.update(schema="dtcrit-yade-export/1")), "schema", "dtcrit-bodies/1"),
    "box periodic": (_edit(lambda d: d["box"].update(periodic=[1, 0, 0])), "box.periodic", "three booleans"),
    "no bodies": (_edit(lambda d: d.update(bodies=[])), "bodies", "non-empty"),
    "contact id": (_edit(lambda d: d.update(contacts=[{"id1": 1, "id2": 17, "kn": 1.0, "ks": 1.0}])), "contacts[0].id2",
                   "no body has id 17"),
    "contact kn": (_edit(lambda d: d.update(contacts=[{"id1": 1, "id2": 2, "kn": -1.0, "ks": 1.0}])), "contacts[0].kn",
                   ">= 0"),
    "not touching": (_edit(lambda d: d.update(contacts=[{"id1": 1, "id2": 3, "kn": 1.0, "ks": 1.0}])), "contacts[0]",
                     "do not touch"),
    "touching, unlisted": (_edit(lambda d: d.update(contacts=[{"id1": 1, "id2": 2, "kn": 1.0, "ks": 1.0}])), "contacts",
                           "touch but are not listed"),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_input_is_one_line_naming_the_entry(name, tmp_path, capsys):
    make, key, words = BAD[name]
    path = _write(tmp_path, make())
    assert main(["packing", path, "--kn", "1e5"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert f"{path}: {key}:" in err and words in err


@pytest.mark.parametrize("argv,words", [
    (["--kn", "1e5", "--density", "1000"], "--density: not used with a bodies file"),
    ([], "kn: give the contact stiffness"),
    (["--youngs", "7e10"], "Hertz-Mindlin law needs sphere contacts"),
])
def test_bad_command_lines_with_a_bodies_file(argv, words, capsys):
    assert main(["packing", str(EXAMPLE), *argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and words in err


def test_file_stiffness_and_command_line_law_clash(tmp_path, capsys):
    doc = _good()
    doc["contacts"] = [{"id1": a, "id2": b, "kn": 1e5, "ks": 8e4} for a, b in ((1, 2), (2, 3), (3, 4), (4, 1))]
    assert main(["packing", _write(tmp_path, doc), "--kn", "1e5"]) == 2
    assert "lists each contact's kn and ks" in capsys.readouterr().err


def test_broken_json_names_the_line(tmp_path, capsys):
    path = tmp_path / "broken.json"
    path.write_text('{"schema": "dtcrit-bodies/1",\n "box": null,\n "bodies": [,]}\n')
    assert main(["packing", str(path), "--kn", "1"]) == 2
    err = capsys.readouterr().err
    assert f"{path}:3: not valid JSON" in err and err.count("\n") == 1


# ---------------------------------------------------------------- (d) schema

@pytest.mark.parametrize("argv", [[str(EXAMPLE), "--kn", "1e5", "--ks", "8e4"], [str(EXAMPLE), "--kn", "1e5", "--certify", "no"]])
def test_json_validates_against_the_packing_schema(argv, capsys):
    doc = _run(capsys, argv)
    jsonschema.validate(doc, SCHEMA)
    assert doc["schema"] == "dtcrit-packing/1" and doc["n_particles"] == 4 and doc["n_contacts"] == 4


def test_sphere_bodies_take_hertz_and_match_the_sphere_route(tmp_path, capsys):
    """Sphere bodies carry R* = R1 R2/(R1 + R2): --youngs works and equals the sphere packing's result."""
    from dtcrit.packing.model import HertzMindlinLaw, Packing
    from dtcrit.packing.report import analyse

    x = [[0.0, 0.0, 0.0], [1.998e-3, 0.0, 0.0], [1.998e-3, 1.4985e-3, 0.0]]
    radii = [1.0e-3, 1.0e-3, 0.5e-3]
    doc = {"schema": "dtcrit-bodies/1", "box": None, "bodies": [
        {"id": k + 1, "shape": {"shape": "sphere", "radius": r, "density": RHO}, "position": p}
        for k, (p, r) in enumerate(zip(x, radii))]}
    out = _run(capsys, [_write(tmp_path, doc), "--youngs", "7e10", "--poisson", "0.2"])
    ref = analyse(Packing.spheres(x, radii, density=RHO), HertzMindlinLaw(7e10, 0.2))
    assert out["n_contacts"] == 2
    assert out["omega_max"] == pytest.approx(ref.omega_max, rel=1e-7)


# ---------------------------------------------------------------- (e) small periodic boxes, many spheres

@pytest.mark.parametrize("length", [1e-3, 1e-6, 1e-12])
def test_periodic_box_shorter_than_a_body_is_refused_at_once(length, tmp_path, capsys):
    """One ellipsoid (a = 1.5 mm) in a periodic cube smaller than itself: it would overlap its own
    images several deep (1e-12 m: 1e9 images per axis to search); one line naming the box."""
    import time

    doc = {"schema": "dtcrit-bodies/1", "box": {"lo": [0, 0, 0], "hi": [length] * 3, "periodic": [True] * 3},
           "bodies": [{"id": 1, "shape": {"shape": "ellipsoid", "semi_axes": [1.5e-3, 1e-3, 0.75e-3], "density": RHO},
                       "position": [length / 2] * 3}]}
    path = _write(tmp_path, doc)
    start = time.perf_counter()
    assert main(["packing", path, "--kn", "1e5"]) == 2
    assert time.perf_counter() - start < 10.0
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"dtcrit: {path}: box.hi: the periodic length along x, {length:g} m")
    assert "bounding radius 0.0015 m of body 1" in err


def test_a_body_touching_its_own_first_image_is_still_answered(tmp_path, capsys):
    """A periodic chain of one ellipsoid per cell, long axis along x, cell 2a - delta: the body
    touches its two x images (one contact), the dense solve of one free body on two springs."""
    a, b, c, delta, kn, ks = 1.5e-3, 1e-3, 0.75e-3, 3e-6, 1e5, 8e4
    doc = {"schema": "dtcrit-bodies/1", "box": {"lo": [0, -5e-3, -5e-3], "hi": [2 * a - delta, 5e-3, 5e-3],
                                                 "periodic": [True, False, False]},
           "bodies": [{"id": 1, "shape": {"shape": "ellipsoid", "semi_axes": [a, b, c], "density": RHO},
                       "position": [0.0, 0.0, 0.0]}]}
    out = _run(capsys, [_write(tmp_path, doc), "--kn", str(kn), "--ks", str(ks)])
    # the spring joins the body to its own image: only the rotation about y and z strains it
    # (translations move both ends alike).  Arms +-(a - delta/2) e_x, shear ks: omega^2 = ks (2 r)^2 / I
    m, inertia = _ellipsoid_mass_inertia(a, b, c, RHO)
    r = a - delta / 2
    expected = math.sqrt(ks * (2 * r) ** 2 / min(inertia[1, 1], inertia[2, 2]))
    assert out["n_contacts"] == 1
    assert out["omega_max"] == pytest.approx(expected, rel=1e-7)


def _sphere_doc(n, seed, box=None, extra=()):
    """``n`` polydisperse spheres on a jittered cubic grid (neighbours overlap by up to a few %)."""
    rng = np.random.default_rng(seed)
    m = int(math.ceil(n ** (1 / 3)))
    x = np.array([[i, j, k] for i in range(m) for j in range(m) for k in range(m)][:n], float) * 1e-3
    x += rng.uniform(-2e-5, 2e-5, x.shape)
    radii = rng.uniform(0.49e-3, 0.52e-3, n)
    bodies = [{"id": 3 * k + 5, "shape": {"shape": "sphere", "radius": float(r), "density": RHO} if k % 2 else
               {"shape": "sphere", "radius": float(r), "mass": float(4 / 3 * math.pi * r**3 * RHO)},
               "position": p.tolist()} for k, (p, r) in enumerate(zip(x, radii))]
    return {"schema": "dtcrit-bodies/1", "box": box, "bodies": bodies + list(extra)}, x, radii


def test_sphere_bodies_are_the_sphere_packing_of_a_dump(tmp_path, capsys):
    """Spheres only: the same contacts and omega_max as the same spheres read from a LAMMPS dump."""
    from dtcrit.packing.readers.lammps_dump import format_dump
    from dtcrit.packing.model import Box, Packing

    length = 6e-3
    box = {"lo": [0.0] * 3, "hi": [length] * 3, "periodic": [True, True, False]}
    doc, x, radii = _sphere_doc(200, 3, box)
    spheres = Packing.spheres(x, radii, density=RHO, box=Box(np.zeros(3), np.full(3, length), (True, True, False)),
                              ids=[3 * k + 5 for k in range(200)])
    dump = tmp_path / "same.dump"
    dump.write_text(format_dump(spheres))
    by_file = _run(capsys, [_write(tmp_path, doc), "--kn", "1e5", "--ks", "8e4"])
    by_dump = _run(capsys, [str(dump), "--kn", "1e5", "--ks", "8e4"])
    assert by_file["n_contacts"] == by_dump["n_contacts"] > 300
    assert by_file["omega_max"] == pytest.approx(by_dump["omega_max"], rel=1e-12)


def test_spheres_beside_an_ellipsoid_meet_as_by_the_support_functions(tmp_path):
    """Mixed bodies: sphere pairs are found all at once, the pairs with the ellipsoid by penetration;
    both agree with ``find_convex_contacts`` (penetration for every pair) on the same shapes."""
    from dtcrit.bodies import Ellipsoid, Sphere
    from dtcrit.packing.readers.bodies_file import read_bodies_file
    from dtcrit.packing.detection.overlaps import find_convex_contacts
    from dtcrit.packing.model import Packing

    ell = {"id": 1, "shape": {"shape": "ellipsoid", "semi_axes": [1.2e-3, 0.6e-3, 0.5e-3], "density": RHO},
           "position": [1.0e-3, 1.0e-3, 2.55e-3]}
    doc, x, radii = _sphere_doc(27, 5, extra=[ell])
    read = read_bodies_file(_write(tmp_path, doc))
    shapes = [Sphere(float(r), density=RHO) for r in radii] + [Ellipsoid(1.2e-3, 0.6e-3, 0.5e-3, density=RHO)]
    ref = find_convex_contacts(Packing.from_shapes(shapes, np.vstack([x, ell["position"]])))
    got = read.contacts
    assert read.kinds == {"sphere": 27, "ellipsoid": 1}
    assert got.count == ref.count and np.any(got.j == 27) and np.any(got.j != 27)
    assert np.array_equal(got.i, ref.i) and np.array_equal(got.j, ref.j)
    for field in ("normal", "arm_i", "arm_j"):
        assert np.allclose(getattr(got, field), getattr(ref, field), rtol=0, atol=1e-7 * 1e-3), field
    assert np.allclose(got.overlap, ref.overlap, rtol=0, atol=1e-12)


def test_twenty_thousand_sphere_bodies_read_in_seconds(tmp_path):
    """One penetration per pair took ~4 ms a body (80 s here); the sphere route reads them at once."""
    import time

    from dtcrit.packing.readers.bodies_file import read_bodies_file

    doc, _, _ = _sphere_doc(20_000, 7)
    path = _write(tmp_path, doc)
    start = time.perf_counter()
    read = read_bodies_file(path)
    assert time.perf_counter() - start < 20.0
    assert read.packing.n == 20_000 and read.packing.is_spheres
    assert read.contacts.count > 20_000  # about half the 60,000 grid neighbours overlap


@pytest.mark.parametrize("extra", [[], ["--engine", "lammps"], ["--pair-style", "gran/hooke 1e5 NULL 0 NULL 0.5 0"]])
def test_audit_of_a_bodies_file_names_its_schema_not_a_yade_export(extra, capsys):
    assert main(["audit", str(EXAMPLE), *extra]) == 2
    err = capsys.readouterr().err
    assert err == (f"dtcrit: {EXAMPLE}: schema: expected 'dtcrit-yade-export/1' (written by yade_export.py), found "
                   "'dtcrit-bodies/1': a file of bodies, which dtcrit packing reads (dtcrit audit reads dumps and YADE "
                   "exports)\n")


def test_progress_shows_on_a_terminal_only_after_its_delay():
    import io

    from dtcrit.packing.detection.body_contacts import Progress

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    quiet, shown = io.StringIO(), Terminal()
    for stream, after in ((quiet, 0.0), (shown, 0.0)):
        progress = Progress("contacts", 10, after=after, stream=stream)
        progress.update(3)
        progress.close()
    assert quiet.getvalue() == ""
    assert shown.getvalue().startswith("\rcontacts: 3/10 (") and shown.getvalue().endswith(" s)\n")
    late = Terminal()
    progress = Progress("contacts", 10, after=3600.0, stream=late)
    progress.update(3)
    progress.close()
    assert late.getvalue() == ""
