"""What a plan reports about the physics, against closed forms: YADE's unbalanced force ratio of a chain of
three spheres, the Love-Weber pressure of a pressed pair, and the size classes' masses.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from dtcrit.packing.audit.run import read_snapshot
from dtcrit.plan.physics import mean_pressure, size_classes, unbalanced_force_ratio

R, RHO, KN, GAP = 1e-3, 2500.0, 1e5, -2e-6  # overlap 2e-6 m per contact
MASS = 4.0 / 3.0 * math.pi * R**3 * RHO
BOX = 0.1


def _chain(tmp_path, count):
    rows = [f"{k + 1} 1 {0.05 + k * (2 * R + GAP)!r} 0.05 0.05 {R!r} {MASS!r}" for k in range(count)]
    text = "\n".join(["ITEM: TIMESTEP", "0", "ITEM: NUMBER OF ATOMS", str(count), "ITEM: BOX BOUNDS pp pp pp",
                      *[f"0.0 {BOX!r}"] * 3, "ITEM: ATOMS id type x y z radius mass", *rows]) + "\n"
    path = tmp_path / "chain.dump"
    path.write_text(text)
    return read_snapshot(path, pair_style=f"gran/hooke/history {KN!r} NULL 0 NULL 0.5 0")


def test_unbalanced_force_ratio_of_a_chain(tmp_path):
    """Three spheres in a row: the ends feel F, the middle 0, each contact carries F: ratio (F + 0 + F)/3 / F."""
    snap = _chain(tmp_path, 3)
    ratio = unbalanced_force_ratio(snap.packing, snap.contacts, False, np.ones(3, bool))
    assert ratio == pytest.approx(2.0 / 3.0, rel=1e-9)


def test_love_weber_pressure_of_a_pair(tmp_path):
    """One contact of force kn delta and branch length 2R - delta: p = F l / (3 V)."""
    snap = _chain(tmp_path, 2)
    delta = -GAP
    expected = KN * delta * (2 * R - delta) / (3.0 * BOX**3)
    assert mean_pressure(snap.packing, snap.contacts, False, np.ones(2, bool)) == pytest.approx(expected, rel=1e-6)


def test_size_classes_add_up():
    """The bins hold every free body once; their added masses sum to the total."""
    rng = np.random.default_rng(4)
    radii = rng.uniform(0.5, 1.5, 40)
    masses = radii**3
    factors = 1.0 + rng.uniform(0, 3, 40) * (radii < 1.0)
    free = np.ones(40, bool)
    classes = size_classes(radii, masses, factors, free, None, bins=4)
    assert sum(c["count"] for c in classes) == 40
    assert sum(c["added_mass"] for c in classes) == pytest.approx(float(np.sum(masses * (factors - 1))), rel=1e-12)
    assert classes[-1]["added_mass"] == 0.0  # the largest spheres were not scaled
