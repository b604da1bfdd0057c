"""Checks of single scene values under the names the scene parsers use (``_number``, ``_vector``,
``_check_keys``, ...): each is the one check of :mod:`dtcrit.inputs`, so that a bad value gives the
same message in a scene, a bodies file and the shape tables of :mod:`dtcrit.bodies.spec`.  Each
problem is one :class:`dtcrit.errors.InputError` whose key is the path of the value
(``contact.kn``, ``particle[2].semi_axes``); unknown keys name the nearest valid key.
"""
from __future__ import annotations

from dtcrit.bodies.spec import TOP_LEVEL_KEYS, check_table_keys as _check_keys
from dtcrit.inputs.arrays import clump_spheres as _clump_spheres
from dtcrit.inputs.arrays import finite_row as _finite_row
from dtcrit.inputs.arrays import vector as _vector
from dtcrit.inputs.arrays import vertices as _vertices
from dtcrit.inputs.keys import required as _required
from dtcrit.inputs.text import key_text as _key_text
from dtcrit.inputs.text import short as _short
from dtcrit.inputs.text import type_name as _type_name
from dtcrit.inputs.values import choice as _choice
from dtcrit.inputs.values import number as _number
from dtcrit.inputs.values import string as _string

__all__ = ["TOP_LEVEL_KEYS", "_check_keys", "_choice", "_clump_spheres", "_finite_row", "_key_text", "_number",
           "_required", "_short", "_string", "_type_name", "_vector", "_vertices"]
