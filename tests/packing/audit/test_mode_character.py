"""The governing mode's character (``dtcrit.packing.audit.mode_character``) against answers known by
construction and against a direct ``numpy.linalg.eigh`` of dense ``K``, ``M`` assembled by hand
(``support.dense_packing``), through ``dtcrit audit --json`` and its text.
"""
from __future__ import annotations

import json
import math

import jsonschema
import numpy as np
import pytest

from dtcrit.cli import main
from support.dense_packing import DensePacking
from support.paths import REPO_ROOT as ROOT

SCHEMA = json.loads((ROOT / "src" / "dtcrit" / "schemas" / "dtcrit-audit-1.json").read_text())
SPRINGS = ("normal", "tangential", "rolling", "twisting")
R, RHO = 1e-3, 2500.0
MASS = 4.0 / 3.0 * math.pi * R**3 * RHO


def _audit(tmp_path, capsys, dense: DensePacking, *extra) -> tuple[dict, str]:
    dump, table = tmp_path / "p.dump", tmp_path / "contacts.txt"
    dump.write_text(dense.dump_text())
    table.write_text(dense.table_text())
    assert main(["audit", str(dump), "--contacts", str(table), "--json", *extra]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert main(["audit", str(dump), "--contacts", str(table), *extra]) == 0
    return doc, capsys.readouterr().out


def _pair(kn, ks, kr, ktw) -> DensePacking:
    x = np.array([[0.0, 0.0, 0.0], [2 * R - 2e-9, 0.0, 0.0]])
    return DensePacking([7, 9], x, np.array([R, R]), np.array([MASS, MASS]), [(0, 1, kn, ks, kr, ktw)])


def _cluster() -> DensePacking:
    """Four unequal spheres, five contacts of unequal springs: a top mode with no degeneracy."""
    radii = np.array([1.0e-3, 0.8e-3, 1.2e-3, 0.9e-3])
    x = np.zeros((4, 3))
    directions = [(1.0, 0.2, 0.0), (0.1, 1.0, 0.3), (-0.4, 0.3, 1.0)]
    for p, d in enumerate(directions, start=1):
        d = np.array(d) / np.linalg.norm(d)
        x[p] = x[0] + (radii[0] + radii[p] - 3e-9) * d
    masses = 4.0 / 3.0 * math.pi * radii**3 * RHO
    contacts = [(0, 1, 1.0e4, 7.0e3, 3e-3, 1e-3), (0, 2, 1.3e4, 9.0e3, 2e-3, 4e-3), (0, 3, 0.9e4, 5.0e3, 5e-3, 2e-3)]
    return DensePacking([1, 2, 3, 4], x, radii, masses, contacts)


def _top_mode(dense: DensePacking) -> tuple[np.ndarray, np.ndarray, dict]:
    """``eigh`` of ``M^-1/2 K M^-1/2``: the top eigenvalues and the top mode ``phi``, and the term matrices."""
    terms = dense.stiffness_terms()
    m = np.diag(dense.mass())
    s = 1 / np.sqrt(m)
    values, vectors = np.linalg.eigh(s[:, None] * sum(terms.values()) * s[None, :])
    return values[::-1], s * vectors[:, -1], terms


def test_a_pair_with_only_normal_springs_is_all_normal(tmp_path, capsys):
    """With ks = 0 the only straining mode stretches the normal spring, every particle alike, no rotation."""
    doc, text = _audit(tmp_path, capsys, _pair(1e4, 0.0, 0.0, 0.0))
    g = doc["governing_mode"]
    assert g["normal"] == pytest.approx(1.0, abs=1e-12)
    assert g["tangential"] == g["rolling"] == g["twisting"] == 0.0
    assert g["rotational_kinetic"] == pytest.approx(0.0, abs=1e-12)
    assert g["participation_ratio"] == pytest.approx(1.0, abs=1e-12)  # two equal spheres, equal energy
    jsonschema.validate(doc, SCHEMA)
    assert "100 % normal, 0 % tangential" in text


def test_a_twisting_spring_stiffer_than_the_rest_gives_a_rotational_mode(tmp_path, capsys):
    """The twist about the normal strains only the twisting spring (the arms lie along the normal), at
    omega^2 = 2 ktw / I; with ktw the stiffest term it is the top mode: all twisting, all rotation.  The
    dense eigh confirms it is the top mode and isolated.
    """
    dense = _pair(1e4, 5e3, 1e-3, 5e-2)
    values, phi, terms = _top_mode(dense)
    assert values[0] == pytest.approx(2 * 5e-2 / (0.4 * MASS * R**2), rel=1e-9) and values[1] < 0.9 * values[0]
    assert phi @ terms["twisting"] @ phi == pytest.approx(phi @ sum(terms.values()) @ phi, rel=1e-9)
    g = _audit(tmp_path, capsys, dense)[0]["governing_mode"]
    assert g["twisting"] == pytest.approx(1.0, abs=1e-9)
    assert g["rotational_kinetic"] == pytest.approx(1.0, abs=1e-9)


def test_the_shares_are_those_of_a_direct_eigen_solve(tmp_path, capsys):
    """On an unequal cluster the shares equal phi^T K_term phi / phi^T K phi of the top eigenvector of the
    hand-assembled dense matrices, the kinetic shares those of phi^T M phi, and they sum to 1.
    """
    dense = _cluster()
    values, phi, terms = _top_mode(dense)
    assert values[1] < (1 - 1e-3) * values[0]  # an isolated top mode: its vector is defined
    strain = {k: phi @ t @ phi for k, t in terms.items()}
    total = sum(strain.values())
    m = np.diag(dense.mass())
    kinetic = (m * phi**2).reshape(-1, 6)
    e_p = kinetic.sum(axis=1)
    doc, text = _audit(tmp_path, capsys, dense)
    g = doc["governing_mode"]
    for k in SPRINGS:
        assert g[k] == pytest.approx(strain[k] / total, abs=1e-7)
    assert sum(g[k] for k in SPRINGS) == pytest.approx(1.0, abs=1e-12)
    assert g["rotational_kinetic"] == pytest.approx(kinetic[:, 3:].sum() / kinetic.sum(), abs=1e-7)
    assert g["participation_ratio"] == pytest.approx(e_p.sum() ** 2 / (4 * np.sum(e_p**2)), rel=1e-7)
    assert g["participation_ratio"] == doc["limiting"]["participation_ratio"]  # one definition
    assert g["preload"] == 0.0
    jsonschema.validate(doc, SCHEMA)
    assert "governing mode: springs' strain energy" in text and "in rotation" in text


def test_the_example_packing_shares_sum_to_one_with_its_preload_apart(capsys):
    """The README example (Hertz, pre-loaded): four spring shares in [0, 1] summing to 1, the pre-load's
    signed fraction apart (negative: compressive forces soften).
    """
    assert main(["audit", str(ROOT / "examples/packings/random_lognormal_60.dump"), "--pair-style",
                 "gran/hertz/history 1e9 NULL 0 NULL 0.5 0", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    g = doc["governing_mode"]
    assert sum(g[k] for k in SPRINGS) == pytest.approx(1.0, abs=1e-12)
    assert all(0 <= g[k] <= 1 for k in SPRINGS) and g["preload"] < 0
    assert 0 < g["participation_ratio"] <= 1 and 0 <= g["rotational_kinetic"] <= 1
    jsonschema.validate(doc, SCHEMA)


def test_dt_crit_and_dt_safe_print_seven_significant_digits(tmp_path, capsys):
    """The text gives dt_crit and dt_safe to 7 significant digits (the JSON has them in full)."""
    doc, text = _audit(tmp_path, capsys, _cluster())
    lines = {line.split(" = ")[0]: line for line in text.splitlines() if line.startswith(("dt_crit =", "dt_safe ="))}
    assert lines["dt_crit"].startswith(f"dt_crit = {doc['dt_crit']:.7g} s")
    assert lines["dt_safe"].startswith(f"dt_safe = {doc['dt_safe']:.7g} s")


def test_the_terms_add_up_to_the_assembled_stiffness_on_oriented_bodies():
    """On turned ellipsoids in a periodic box (body-axis rotation DOFs, image contacts) with every spring
    and a pre-load, the contact terms of ``contact_energies`` add up to phi^T K phi of the assembled
    stiffness (built from the element's force law, ``contact_element.body_forces``) for random phi."""
    from dtcrit.packing.audit.mode_character import contact_energies
    from dtcrit.packing.operators.assembly import stiffness_matrix
    from dtcrit.packing.readers.bodies_file import read_bodies_file

    bodies = read_bodies_file(ROOT / "examples/packings/ellipsoids.json")
    rng = np.random.default_rng(7)
    nc = bodies.contacts.count
    contacts = bodies.contacts.with_stiffness(rng.uniform(1e4, 2e4, nc), rng.uniform(5e3, 1e4, nc),
                                              rng.uniform(1e-3, 2e-3, nc), rng.uniform(1e-3, 2e-3, nc))
    contacts = contacts.with_normal_force(rng.uniform(0.0, 1e-2, nc))
    k = stiffness_matrix(bodies.packing, contacts).toarray()
    for _ in range(3):
        phi = rng.normal(size=6 * bodies.packing.n)
        terms = contact_energies(bodies.packing, contacts, phi)
        assert sum(float(e.sum()) for e in terms.values()) == pytest.approx(phi @ k @ phi, rel=1e-10)
        assert all(np.all(terms[s] >= 0) for s in SPRINGS) and np.all(terms["preload"] <= 0)
