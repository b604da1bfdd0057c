"""The scene-key registry holds every key a scene file may carry, each described.

Independent of the registry's construction: the keys of every example scene (read with ``tomllib``) are
found in the registry under their table, and a key the registry does not list is refused by the parser.
"""
from __future__ import annotations

import json
import tomllib

import pytest
from support.paths import REPO_ROOT

from dtcrit.errors import InputError
from dtcrit.scenes import parse_scene
from dtcrit.scenes.keys import bodies_file_tables, scene_tables

TABLES = {t.anchor: {k.name for k in t.keys} for t in scene_tables()}
EXAMPLES = sorted((REPO_ROOT / "examples").glob("*.toml"))


def _used(doc: dict) -> list[tuple[str, str]]:
    used = [("top", k) for k in doc]
    for particle in doc.get("particle", []):
        used += [("particle", k) for k in particle]
        used += [("lognormal", k) for k in particle.get("lognormal", {})]
    used += [("contact", k) for k in doc.get("contact", {})]
    used += [("wall", k) for wall in doc.get("wall", []) for k in wall]
    used += [("collision", k) for k in doc.get("collision", {})]
    if isinstance(doc.get("integrator"), dict):
        used += [("integrator", k) for k in doc["integrator"]]
    return used


def test_the_examples_are_read():
    """An empty glob would pass the check below vacuously."""
    assert len(EXAMPLES) >= 10


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_every_key_of_an_example_scene_is_in_the_registry(path):
    """Each key the example uses, under its table, is one the registry lists."""
    doc = tomllib.loads(path.read_text())
    missing = [f"{table}.{key}" for table, key in _used(doc) if key not in TABLES[table]]
    assert not missing


def test_every_key_is_described():
    """No key of the registry has an empty description."""
    for table in scene_tables():
        for key in table.keys:
            assert len(key.description) > 10, f"{table.name} {key.name}"


def test_a_key_outside_the_registry_is_refused():
    """The parser refuses a key the registry does not list, naming it."""
    text = (REPO_ROOT / "examples" / "paper_ellipsoids.toml").read_text()
    assert "stiffness_factor_xyz" not in TABLES["contact"]
    with pytest.raises(InputError) as info:
        parse_scene(text.replace("[contact]", "[contact]\nstiffness_factor_xyz = 1.0"))
    assert "stiffness_factor_xyz" in str(info.value)


@pytest.mark.parametrize("path", sorted((REPO_ROOT / "examples" / "packings").glob("*.json")), ids=lambda p: p.stem)
def test_every_key_of_an_example_bodies_file_is_in_the_registry(path):
    """Each key of the example bodies file, under its table, is one the bodies-file registry lists."""
    doc = json.loads(path.read_text())
    tables = {t.name: {k.name for k in t.keys} for t in bodies_file_tables()}
    used = [("top level", k) for k in doc] + [("box", k) for k in (doc.get("box") or {})]
    used += [("bodies[]", k) for body in doc["bodies"] for k in body]
    used += [("bodies[].shape", k) for body in doc["bodies"] for k in body["shape"]]
    used += [("contacts[]", k) for contact in doc.get("contacts", []) for k in contact]
    assert len(used) > 10
    assert not [f"{table}: {key}" for table, key in used if key not in tables[table]]
