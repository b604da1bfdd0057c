"""Every property of every JSON schema says what it means: the reference pages render these descriptions.

The walk visits every ``properties`` object anywhere in a schema (``$defs`` and combinators included).
"""
from __future__ import annotations

import json

import pytest
from support.paths import SRC

SCHEMAS = sorted((SRC / "dtcrit" / "schemas").glob("*.json"))


def _undescribed(node, path: str = "") -> list[str]:
    missing = []
    if isinstance(node, dict):
        for key, child in node.get("properties", {}).items():
            if not (isinstance(child, dict) and str(child.get("description", "")).strip()):
                missing.append(f"{path}/properties/{key}")
        for key, child in node.items():
            missing += _undescribed(child, f"{path}/{key}")
    elif isinstance(node, list):
        for i, child in enumerate(node):
            missing += _undescribed(child, f"{path}/{i}")
    return missing


def test_the_schemas_are_found():
    """An empty glob would pass the check below vacuously."""
    assert len(SCHEMAS) >= 9


@pytest.mark.parametrize("schema", SCHEMAS, ids=lambda p: p.stem)
def test_every_property_has_a_description(schema):
    """No property of the schema lacks a ``description``."""
    missing = _undescribed(json.loads(schema.read_text()))
    assert not missing, f"{schema.name}: properties without a description: {missing}"
