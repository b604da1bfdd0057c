"""Scene files as users write them: byte-order marks, top-level keys after a table, runaway titles,
files that are not scenes at all, and `dtcrit --version`.  Each problem is one line and exit 2."""
from __future__ import annotations

import pytest

from dtcrit import __version__
from dtcrit.cli import main

BODY = ('integrator = "velocity-verlet"\n[[particle]]\nshape = "sphere"\nradius = 0.001\ndensity = 2500.0\n'
        '[contact]\nmodel = "linear"\nkn = 1e5\nks = 1e5\n')


def _run(tmp_path, data: bytes, *extra):
    path = tmp_path / "scene.toml"
    path.write_bytes(data)
    return main(["step", str(path), *extra]), path


def test_utf8_byte_order_mark_is_accepted(tmp_path, capsys):
    rc, _ = _run(tmp_path, b"\xef\xbb\xbf" + BODY.encode())
    assert rc == 0 and "dt_crit" in capsys.readouterr().out


@pytest.mark.parametrize("data,key,reason", [
    ((BODY + "safety = 0.5\n").encode(), "contact.safety", "top-level key"),
    (('title = "' + "x" * 5000 + '"\n' + BODY).encode(), "title", "at most 200"),
    (b"\x00" * (9 << 20), "file", "larger than a scene file"),
])
def test_bad_files_are_one_line(tmp_path, capsys, data, key, reason):
    rc, path = _run(tmp_path, data)
    out, err = capsys.readouterr()
    assert rc == 2 and out == "" and len(err.splitlines()) == 1
    assert err.startswith(f"{path}:{key}: ") and reason in err, err


def test_version(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0 and capsys.readouterr().out.strip() == f"dtcrit {__version__}"


def test_cube_from_corners_with_duplicates(tmp_path, capsys):
    """A cube given by its 8 corners plus 2 repeats: 8 vertices are reported, and its moments, equal up to
    rounding, give B_max = 0 (no rotation limit) instead of a 1e13 s step from B ~ 3e-16."""
    corners = [[x, y, z] for x in (1, -1) for y in (1, -1) for z in (1, -1)]
    text = ('integrator = "velocity-verlet"\nomega_max = 10.0\n[[particle]]\nshape = "polyhedron"\n'
            f'vertices = {corners + corners[:2]!r}\ndensity = 1000.0\n[contact]\nmodel = "linear"\nkn = 1e5\nks = 1e5\n')
    rc, _ = _run(tmp_path, text.encode())
    out = capsys.readouterr().out
    assert rc == 0 and "8 vertices (10 points given)" in out and "B_max = 0 for every pair" in out


def test_friction_is_accepted_with_a_note(tmp_path, capsys):
    rc, path = _run(tmp_path, (BODY + "friction = 0.5\n").encode())
    out, err = capsys.readouterr()
    assert rc == 0 and "dt_crit" in out
    assert err.startswith(f"{path}:contact.friction: note: accepted, not used") and len(err.splitlines()) == 1
