"""Sheared (triclinic) periodic cells: contact search against an O(N^2) search over all images, nearest
images, the FCC lattice sheared by one of its own translations, LAMMPS's triclinic dump bounds and YADE's
sheared ``hSize`` with its ``shift2``.

The references are independent of the code under test: the brute-force search tries every image
``H n`` within a range it derives itself (``|n_k| <= max |f_k(x_j - x_i)| + r / w_k``, ``f`` the cell
coordinates and ``w_k`` the face spacings, from ``numpy.linalg.inv``), on the raw (unwrapped) positions,
and compares separation vectors, which do not depend on how either side wraps the particles; the
sheared FCC's step is the unsheared FCC's (a tilt by a lattice translation leaves the crystal as it is);
the dump bounds are LAMMPS's Howto-triclinic formulas evaluated by hand.
"""
from __future__ import annotations

import itertools
import json

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from dtcrit.cli import main
from dtcrit.errors import InputError
from dtcrit.packing import Box, LinearLaw, Packing, analyse, lattice
from dtcrit.packing.detection.overlaps import find_sphere_contacts
from dtcrit.packing.periodic_cell import nearest_image
from dtcrit.packing.readers.lammps_dump import format_dump, read_dump
from dtcrit.packing.readers.yade_export import read_yade_audit


def _cell(lengths, tilts, angle=0.0):
    """Upper-triangular LAMMPS cell with tilts (xy, xz, yz), optionally turned by ``angle`` about (1, 1, 1)
    (a general YADE hSize).
    """
    h = np.diag(np.asarray(lengths, float))
    h[0, 1], h[0, 2], h[1, 2] = tilts
    if angle:
        k = np.ones(3) / np.sqrt(3.0)
        kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
        h = (np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * kx @ kx) @ h
    return h


def _box(h, periodic=(True, True, True)):
    return Box(np.zeros(3), np.diag(h).copy(), periodic, cell=h)


def _brute_pairs(x, r, h, periodic, tolerance=1e-9):
    """Every (i, j, separation) within (R_i + R_j)(1 + tol) over all images, i < j or i == j with the
    separation lexicographically positive: O(N^2) per image.
    """
    ginv = np.linalg.inv(h)
    w = 1.0 / np.linalg.norm(ginv, axis=1)
    rc = 2.0 * r.max() * (1 + tolerance)
    f = (x[None, :, :] - x[:, None, :]) @ ginv.T
    reach = [int(np.ceil(np.abs(f[..., k]).max() + rc / w[k])) + 1 if periodic[k] else 0 for k in range(3)]
    out = []
    for n in itertools.product(*(range(-m, m + 1) for m in reach)):
        sep = x[None, :, :] + h @ np.array(n, float) - x[:, None, :]
        d = np.linalg.norm(sep, axis=2)
        for i, j in zip(*np.nonzero(d <= (r[:, None] + r[None, :]) * (1 + tolerance))):
            s = sep[i, j]
            if i < j or (i == j and tuple(np.sign(s[np.flatnonzero(s)[:1]])) == (1.0,)):
                out.append((int(i), int(j), s))
    return out


def _same_pairs(found, reference, scale):
    key = lambda rows: sorted((i, j, *np.round(s / scale, 6)) for i, j, s in rows)  # noqa: E731
    assert key(found) == key(reference)


TILT = st.tuples(st.sampled_from([-1.0, 1.0]), st.floats(-4.0, np.log10(2.0)))


@settings(max_examples=40, deadline=None)
@given(n=st.integers(2, 24), tilts=st.tuples(TILT, TILT, TILT), angle=st.sampled_from([0.0, 0.2, -0.35]),
       periodic=st.sampled_from([(True, True, True), (True, True, False), (True, False, True)]),
       seed=st.integers(0, 2**16))
def test_contacts_of_a_sheared_cell_are_every_image_in_range(n, tilts, angle, periodic, seed):
    """Tilts over several decades, up to twice the edge (LAMMPS's ``box tilt large``, any YADE cell)."""
    rng = np.random.default_rng(seed)
    lengths = rng.uniform(2.0, 4.0, 3)
    t = [sign * 10.0**u * lengths[a] for (sign, u), a in zip(tilts, (0, 0, 1))]
    if not periodic[1]:
        t[0] = 0.0  # an xy tilt needs y periodic (LAMMPS)
    if not periodic[2]:
        t[1] = t[2] = 0.0
    h = _cell(lengths, t, angle)
    assume(np.all(np.diag(h) > 0))
    box = _box(h, periodic)
    x = rng.uniform(-0.5, 1.5, (n, 3)) @ h.T
    r = rng.uniform(0.3, 0.9, n)
    assume(min(1.0 / np.linalg.norm(np.linalg.inv(h), axis=1)[list(np.flatnonzero(periodic))]) > 0.2)
    packing = Packing.spheres(x, r, density=1.0, box=box)
    try:
        c = find_sphere_contacts(packing)
    except InputError as exc:  # a sphere wider than the shortest periodic translation
        assume("own periodic image" not in exc.reason)
        raise
    x = packing.positions  # images are of the packing's own (unwrapped) positions
    found = [(i, j, x[j] + h @ s - x[i]) for i, j, s in zip(c.i, c.j, c.image)]
    reference = _brute_pairs(packing.positions, r, h, periodic)
    _same_pairs(found, reference, r.max())
    d = np.array([np.linalg.norm(s) for _, _, s in found]).reshape(-1)
    if len(found):
        seps = np.array([s for _, _, s in found])
        assert np.allclose(c.normal, seps / d[:, None], atol=1e-12)
        assert np.allclose(c.overlap, np.maximum(r[c.i] + r[c.j] - d, 0.0), atol=1e-12)


@settings(max_examples=30, deadline=None)
@given(tilts=st.tuples(TILT, TILT, TILT), angle=st.sampled_from([0.0, 0.3]), seed=st.integers(0, 2**16))
def test_nearest_image_is_the_shortest_of_all_images(tilts, angle, seed):
    """Against the shortest of all images with |n_k| <= 12, for separations up to three cells."""
    rng = np.random.default_rng(seed)
    lengths = rng.uniform(1.0, 3.0, 3)
    h = _cell(lengths, [s * 10.0**u * lengths[a] for (s, u), a in zip(tilts, (0, 0, 1))], angle)
    assume(np.all(np.diag(h) > 0))
    sep = rng.uniform(-3.0, 3.0, (20, 3)) @ h.T
    image = nearest_image(_box(h), sep)
    images = np.array(list(itertools.product(range(-12, 13), repeat=3)), float)
    best = np.linalg.norm(sep[:, None, :] + images @ h.T, axis=2).min(axis=1)
    assert np.allclose(np.linalg.norm(sep + image @ h.T, axis=1), best, rtol=1e-12)


FCC_TILTS = {"xy = a": (1, 0, 0), "xz = yz = a/2": (0, 0.5, 0.5), "xy = L": (2, 0, 0), "xy 3a, xz a, yz 2a": (3, 1, 2)}


@pytest.mark.parametrize("ratio", [0.1, 1.0])
@pytest.mark.parametrize("name", sorted(FCC_TILTS))
def test_fcc_sheared_by_a_lattice_translation_keeps_its_step(name, ratio):
    """The crystal is the same set of spheres, so the same contacts (12 each) and the same step."""
    plain = lattice("fcc", 2, radius=1e-3, density=2500.0)
    a = plain.box.lengths[0] / 2
    h = _cell(plain.box.lengths, a * np.array(FCC_TILTS[name], float))
    sheared = Packing.spheres(plain.positions, 1e-3, masses=plain.masses, box=_box(h))
    law = LinearLaw(1e5, ratio * 1e5)
    assert find_sphere_contacts(sheared).count == 6 * plain.n
    assert analyse(sheared, law).dt_crit == pytest.approx(analyse(plain, law).dt_crit, rel=1e-12)


def test_lammps_triclinic_bounds_are_converted_as_the_manual_says(tmp_path):
    """xlo_bound = xlo + min(0, xy, xz, xy + xz) etc. (Howto triclinic), here by hand for xy = 2,
    xz = -1, yz = 3 on [0, 10] x [1, 9] x [-2, 4].
    """
    text = ("ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS xy xz yz pp pp pp\n"
            "-1 12 2\n1 12 -1\n-2 4 3\nITEM: ATOMS id x y z radius mass\n1 1 2 0 0.5 1\n")
    (tmp_path / "t.dump").write_text(text)
    box = read_dump(tmp_path / "t.dump").box
    assert box.lo.tolist() == [0, 1, -2] and box.hi.tolist() == [10, 9, 4]
    assert box.cell.tolist() == [[10, 2, -1], [0, 8, 3], [0, 0, 6]]
    xs = text.replace("id x y z", "id xs ys zs").replace("1 1 2 0 0.5 1", "1 0.5 0.5 0.5 0.5 1")
    (tmp_path / "s.dump").write_text(xs)
    assert read_dump(tmp_path / "s.dump").positions[0].tolist() == [0 + 5 + 1 - 0.5, 1 + 4 + 1.5, -2 + 3]


@pytest.mark.parametrize("angle", [0.0, 0.25])
def test_sheared_dump_round_trip_and_cli_step(tmp_path, capsys, angle):
    """``xy xz yz`` (upper-triangular) and ``abc origin`` (general) dumps read back to the same step."""
    plain = lattice("fcc", 2, radius=1e-3, density=2500.0)
    a = plain.box.lengths[0] / 2
    h = _cell(plain.box.lengths, (a, 0.0, 0.0), angle)
    turn = h @ np.linalg.inv(_cell(plain.box.lengths, (a, 0.0, 0.0)))  # the rotation of a general cell
    x = plain.positions @ turn.T  # the same crystal, turned with its cell
    sheared = Packing.spheres(x, 1e-3, masses=plain.masses, box=_box(h))
    path = tmp_path / "sheared.dump"
    path.write_text(format_dump(sheared))
    assert ("abc origin" in path.read_text()) == bool(angle)
    assert main(["packing", str(path), "--kn", "1e5", "--ks", "1e5", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    expected = analyse(plain, LinearLaw(1e5, 1e5)).dt_crit
    assert out["dt_crit"] == pytest.approx(expected, rel=1e-9)


def _yade_export(h, bodies, inters):
    return {"schema": "dtcrit-yade-export/1", "dt": 1e-7, "iter": 1, "periodic": True,
            "cell_hsize": np.asarray(h).tolist(), "avoid_granular_ratcheting": True, "bodies": bodies,
            "interactions": inters}


def _sphere(bid, pos, r=1e-3):
    m = 4.0 / 3.0 * np.pi * r**3 * 2500.0
    return {"id": bid, "pos": list(pos), "radius": r, "mass": m, "inertia": [0.4 * m * r * r] * 3, "clump_id": None,
            "is_clump": False, "fixed": False}


def test_yade_sheared_cell_and_shift2(tmp_path):
    """Two spheres touching across the sheared face: body 2 seen through ``shift2 = hSize cellDist``."""
    h = _cell([0.01, 0.01, 0.01], (0.004, 0.0, 0.0))
    shift = h @ np.array([0.0, -1.0, 0.0])
    x1 = np.array([0.005, 0.0005, 0.005])
    x2 = x1 - shift + np.array([0.0, -0.0019, 0.0])  # x2 + shift2 - x1 = (0, -1.9e-3, 0)
    inter = {"id1": 0, "id2": 1, "kn": 1e5, "ks": 3e4, "fn": 0.0, "shift2": shift.tolist()}
    path = tmp_path / "e.json"
    path.write_text(json.dumps(_yade_export(h, [_sphere(0, x1), _sphere(1, x2)], [inter])))
    packing, contacts, _ = read_yade_audit(path)
    sep = packing.positions[1] + packing.box.shift(contacts.image[0]) - packing.positions[0]
    assert sep == pytest.approx([0.0, -0.0019, 0.0], abs=1e-15)
    assert contacts.normal[0] == pytest.approx([0.0, -1.0, 0.0])
    inter["shift2"] = (shift + [0.003, 0, 0]).tolist()  # not a whole cell translation
    path.write_text(json.dumps(_yade_export(h, [_sphere(0, x1), _sphere(1, x2)], [inter])))
    with pytest.raises(InputError, match="not a whole number of cell vectors"):
        read_yade_audit(path)


@pytest.mark.parametrize("route", ["assembled", "matrix-free"])
def test_a_cell_and_its_relabelled_lattice_basis_give_one_step(route):
    """``H`` and ``H U`` (``U`` unimodular: ``b + 2a``, ``c - b``) are one periodic system, so one step, with
    the pre-load's geometric stiffness (centre distances through the images) on every contact.
    """
    plain = lattice("fcc", 2, radius=1e-3, density=2500.0)
    lengths = plain.box.lengths
    rng = np.random.default_rng(3)
    x = plain.positions * 0.999 + rng.normal(size=plain.positions.shape) * 1e-5
    h = _cell(lengths, (0.37 * lengths[1], 0.0, -0.21 * lengths[2]))
    steps = []
    for cell in (h, h @ np.array([[1, 2, 0], [0, 1, -1], [0, 0, 1]], float)):
        packing = Packing.spheres(x, 1e-3, masses=plain.masses, box=_box(cell))
        contacts = find_sphere_contacts(packing)
        contacts = contacts.with_stiffness(np.full(contacts.count, 1e5), np.full(contacts.count, 3e4))
        steps.append(analyse(packing, None, contacts.with_normal_force(1e5 * contacts.overlap), route=route).dt_crit)
    assert steps[0] == pytest.approx(steps[1], rel=1e-10)


def test_clumps_and_convex_bodies_find_the_sphere_contacts_of_a_sheared_cell():
    """The same spheres as one-member clumps (``find_body_contacts``) and as convex shapes
    (``find_convex_contacts``, support-function penetration) touch as the spheres do, through the same
    images of the packing's own (unwrapped) centres.
    """
    from dtcrit.bodies import Clump, Sphere
    from dtcrit.packing.detection.body_contacts import find_body_contacts
    from dtcrit.packing.detection.overlaps import find_convex_contacts

    rng = np.random.default_rng(11)
    h = _cell([3.0, 2.5, 2.8], (1.9, -0.7, 0.8), 0.2)
    x = rng.uniform(-0.5, 1.5, (14, 3)) @ h.T
    r = rng.uniform(0.4, 0.8, 14)
    spheres = find_sphere_contacts(Packing.spheres(x, r, density=1.0, box=_box(h)))
    assert spheres.count > 5 and np.any(spheres.image)
    clumps = Packing.from_shapes([Clump([(0.0, 0.0, 0.0, rk)], density=1.0) for rk in r], x,
                                 np.repeat(np.eye(3)[None], 14, 0), box=_box(h))
    convex = Packing.from_shapes([Sphere(rk, density=1.0) for rk in r], x, box=_box(h))
    for found in (find_body_contacts(clumps), find_convex_contacts(convex)):
        key = lambda c: sorted(zip(c.i.tolist(), c.j.tolist(), map(tuple, c.image.tolist())))  # noqa: E731
        assert key(found) == key(spheres)
        order = np.lexsort((found.j, found.i)), np.lexsort((spheres.j, spheres.i))
        assert np.allclose(found.normal[order[0]], spheres.normal[order[1]], atol=1e-7)
