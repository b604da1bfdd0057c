"""Every kind of bad input names where it lies: the source (file), the line and the key, held apart
in ``InputError.location`` while the one-line message stays as it was printed before.
"""
import json

import pytest

from dtcrit.errors import InputError, Location
from dtcrit.inputs.files import relocate

DUMP = """ITEM: TIMESTEP
0
ITEM: NUMBER OF ATOMS
2
ITEM: BOX BOUNDS ff ff ff
0.0 4.0
0.0 4.0
0.0 4.0
ITEM: ATOMS id type x y z radius mass
1 1 1.0 1.0 1.0 0.5 0.5
2 1 {x} 1.0 1.0 0.5 0.5
"""


def _raises(call) -> InputError:
    with pytest.raises(InputError) as caught:
        call()
    return caught.value


def test_a_scene_value_is_located_by_its_key():
    from dtcrit.scenes.scene import parse_scene

    text = ('integrator = "velocity-verlet"\n[[particle]]\nshape = "sphere"\nradius = 1e-3\ndensity = 2500\n'
            '[contact]\nmodel = "linear"\nkn = -1\nks = 0\n')
    exc = _raises(lambda: parse_scene(text, "s.toml"))
    assert exc.location == Location(None, None, "contact.kn")
    assert str(exc) == "contact.kn: must be positive (got -1)"


def test_a_scene_shape_table_is_located_by_its_key():
    from dtcrit.scenes.scene import parse_scene

    text = ('integrator = "velocity-verlet"\n[[particle]]\nshape = "ellipsoid"\nsemi_axes = [3, 2, "x"]\n'
            'density = 2500\n[contact]\nmodel = "linear"\nkn = 1\nks = 0\n')
    exc = _raises(lambda: parse_scene(text))
    assert exc.location.key == "particle[1].semi_axes[3]"
    assert exc.reason == "must be a number (got a string: 'x')"


def test_a_dump_row_is_located_by_file_and_line(tmp_path):
    from dtcrit.packing.readers.lammps_dump import read_dump

    path = tmp_path / "p.dump"
    path.write_text(DUMP.format(x="abc"))
    exc = _raises(lambda: read_dump(path))
    assert exc.location == Location(str(path), 11, None)
    assert str(exc) == f"{path}:11: 'abc' is not a number"


def test_a_dump_value_out_of_range_is_located_by_file_and_line(tmp_path):
    from dtcrit.packing.readers.lammps_dump import read_dump

    path = tmp_path / "p.dump"
    path.write_text(DUMP.format(x="1e150"))
    exc = _raises(lambda: read_dump(path))
    assert exc.location == Location(str(path), 11, None)
    assert exc.reason.startswith("a coordinate 1e+150 m is beyond")


def test_dump_text_without_a_file_is_located_by_line():
    from dtcrit.packing.readers.lammps_dump import read_snapshots

    exc = _raises(lambda: read_snapshots(DUMP.format(x="abc")))
    assert exc.location == Location(None, 11, None) and exc.key == "line 11"


def _bodies(tmp_path, shape, name="b.json"):
    doc = {"schema": "dtcrit-bodies/1", "box": None,
           "bodies": [{"id": 1, "shape": shape, "position": [0.0, 0.0, 0.0]}]}
    path = tmp_path / name
    path.write_text(json.dumps(doc))
    return path


def test_a_bodies_file_entry_is_located_by_file_and_key(tmp_path):
    from dtcrit.packing.readers.bodies_file import read_bodies_file

    path = _bodies(tmp_path, {"shape": "ellipsoid", "semi_axes": [3e-3, 2e-3, "x"], "density": 2500.0})
    exc = _raises(lambda: read_bodies_file(path))
    assert exc.location == Location(str(path), None, "bodies[0].shape.semi_axes[3]")
    assert str(exc) == f"{path}: bodies[0].shape.semi_axes[3]: must be a number (got a string: 'x')"


def test_a_bodies_shape_table_is_read_as_a_scene_particle_table(tmp_path):
    """The one shape parser: the same table gives the same message in a scene and a bodies file."""
    from dtcrit.packing.readers.bodies_file import read_bodies_file
    from dtcrit.scenes.scene import parse_scene

    scene = ('integrator = "velocity-verlet"\n[[particle]]\nshape = "box"\nhalf_lengths = [1e-3, 1e-3]\n'
             'density = 2500\n[contact]\nmodel = "linear"\nkn = 1\nks = 0\n')
    in_scene = _raises(lambda: parse_scene(scene))
    path = _bodies(tmp_path, {"shape": "box", "half_lengths": [1e-3, 1e-3], "density": 2500.0})
    in_file = _raises(lambda: read_bodies_file(path))
    assert in_scene.key == "particle[1].half_lengths" and in_file.location.key == "bodies[0].shape.half_lengths"
    assert in_scene.reason == in_file.reason == "must have 3 entries (got 2)"


def test_bad_json_is_located_by_file_and_line(tmp_path):
    from dtcrit.packing.readers.bodies_file import read_bodies_file

    path = tmp_path / "b.json"
    path.write_text('{"schema": "dtcrit-bodies/1",\n"box": null,\n"bodies": [}\n')
    exc = _raises(lambda: read_bodies_file(path))
    assert exc.location.source == str(path) and exc.location.line == 3 and exc.location.key is None


def test_a_yade_export_entry_is_located_by_file_and_key(tmp_path):
    from dtcrit.packing.readers.yade_export import read_yade_audit

    doc = {"schema": "dtcrit-yade-export/1", "interactions": [],
           "bodies": [{"id": 0, "pos": [0.0, 0.0, 0.0], "radius": 1.0, "mass": -2.0, "inertia": [1.0, 1.0, 1.0]}]}
    path = tmp_path / "e.json"
    path.write_text(json.dumps(doc))
    exc = _raises(lambda: read_yade_audit(path))
    assert exc.location == Location(str(path), None, "bodies[0].mass")
    assert exc.reason == "must be positive, found -2"


def test_a_contact_table_row_is_located_by_file_and_line(tmp_path):
    from dtcrit.packing.readers.contact_tables import read_contact_table
    from dtcrit.packing.readers.lammps_dump import read_dump

    dump = tmp_path / "p.dump"
    dump.write_text(DUMP.format(x="1.9"))
    table = tmp_path / "c.txt"
    table.write_text("id1 id2 kn ks\n1 2 1e5 nan\n")
    exc = _raises(lambda: read_contact_table(table, read_dump(dump)))
    assert exc.location == Location(str(table), 2, None)
    assert exc.reason == "ks must be a finite number >= 0, found nan"


def test_a_file_that_cannot_be_read_is_located_by_its_name(tmp_path):
    from dtcrit.inputs.files import text_lines

    missing = tmp_path / "missing.txt"
    exc = _raises(lambda: text_lines(missing))
    assert exc.location == Location(str(missing)) and exc.reason.startswith("cannot read: ")


@pytest.mark.parametrize("key, location", [
    ("f.json", Location("f.json")),
    ("f.json:12", Location("f.json", 12)),
    ("f.json: bodies[2].id", Location("f.json", None, "bodies[2].id")),
    ("--kn", Location(None, None, "--kn")),
    ("f.jsonx: a", Location(None, None, "f.jsonx: a")),
])
def test_relocate_splits_a_file_keyed_error(key, location):
    exc = relocate(InputError(key, "bad"), "f.json")
    assert exc.location == location and str(exc) == f"{key}: bad"
