"""LAMMPS / LIGGGHTS dump reading: content, periodicity, contacts, and one-line errors with line numbers."""
import json
from pathlib import Path

import numpy as np
import pytest

from dtcrit.cli import main
from dtcrit.errors import InputError
from dtcrit.packing.contacts import find_sphere_contacts
from dtcrit.packing.dump_io import format_dump, read_dump
from dtcrit.packing.lattices import lattice
from dtcrit.packing.random_packing import random_packing

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "packings" / "random_lognormal_60.dump"

GOOD = """ITEM: TIMESTEP
500
ITEM: NUMBER OF ATOMS
3
ITEM: BOX BOUNDS pp ff pp
0.0 4.0
-1.0 5.0
0.0 4.0
ITEM: ATOMS id type x y z vx vy vz radius
3 1 3.9 1.0 1.0 0 0 0 0.5
1 1 0.35 1.0 1.0 0 0 0 0.5
2 2 1.0 1.0 1.95 0 0 0 0.5
"""


def _write(tmp_path, text, name="p.dump"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_reads_columns_box_and_periodicity(tmp_path):
    p = read_dump(_write(tmp_path, GOOD), density=1000.0)
    assert p.n == 3
    assert p.box.periodic == (True, False, True)
    assert p.box.lo == pytest.approx([0, -1, 0])
    assert p.positions[0] == pytest.approx([0.35, 1.0, 1.0])  # sorted by id
    assert p.masses == pytest.approx(np.full(3, 4 / 3 * np.pi * 0.125 * 1000.0))
    c = find_sphere_contacts(p)
    # id 1 (x = 0.35) touches id 3 (x = 3.9) only through the periodic x boundary (distance 0.45)
    assert c.count == 1 and (c.i[0], c.j[0]) == (0, 2)
    assert list(c.image[0]) == [-1, 0, 0]
    assert c.normal[0] == pytest.approx([-1, 0, 0])
    assert c.overlap[0] == pytest.approx(1.0 - 0.45, abs=1e-12)


def test_scaled_coordinates_diameter_and_mass(tmp_path):
    text = GOOD.replace("x y z vx vy vz radius", "xs ys zs vx vy vz diameter mass")
    text = text.replace(" 0.5\n", " 1.0 2.5\n")
    p = read_dump(_write(tmp_path, text))
    assert p.radii == pytest.approx([0.5] * 3)
    assert p.masses == pytest.approx([2.5] * 3)
    assert p.positions[0] == pytest.approx([0.35 * 4.0, -1.0 + 1.0 * 6.0, 4.0])


def test_last_snapshot_by_default_and_round_trip(tmp_path):
    a = lattice("sc", 2, radius=0.5, density=1.0)
    b = random_packing(20, cn=5, seed=2)
    path = _write(tmp_path, format_dump(a, timestep=1) + format_dump(b, timestep=2))
    got = read_dump(path)
    assert got.n == b.n
    assert got.positions == pytest.approx(b.positions, rel=1e-15)
    assert got.radii == pytest.approx(b.radii, rel=1e-15)
    assert got.masses == pytest.approx(b.masses, rel=1e-15)
    assert read_dump(path, snapshot=0).n == a.n


def test_example_file_is_readable():
    p = read_dump(EXAMPLE)
    c = find_sphere_contacts(p)
    assert p.n == 60
    assert c.coordination(p.n).mean() == pytest.approx(6.0)


BAD = [
    (GOOD.replace("ITEM: TIMESTEP", "ITEM: TIME"), 1, "expected 'ITEM: TIMESTEP'"),
    (GOOD.replace("500", "five hundred"), 2, "timestep"),
    (GOOD.replace("NUMBER OF ATOMS\n3", "NUMBER OF ATOMS\n4"), 13, "unexpected end of file"),
    (GOOD.replace("-1.0 5.0", "5.0 -1.0"), 7, "must exceed"),
    (GOOD.replace("-1.0 5.0", "-1.0 5.0 0.3"), 7, "triclinic"),
    (GOOD.replace("pp ff pp", "xy xz yz pp ff pp"), 5, "triclinic"),
    (GOOD.replace("1 1 0.35 1.0 1.0 0 0 0 0.5", "1 1 0.35 1.0 0 0 0 0.5"), 11, "expected 9 values"),
    (GOOD.replace("2 2 1.0 1.0 1.95", "2 2 1.0 abc 1.95"), 12, "'abc' is not a number"),
    (GOOD.replace("2 2 1.0 1.0 1.95 0 0 0 0.5", "2 2 1.0 1.0 1.95 0 0 0 -0.5"), 12, "radius must be positive"),
    (GOOD.replace("2 2 1.0 1.0 1.95", "2 2 1.0 nan 1.95"), 12, "not finite"),
    (GOOD.replace("x y z vx", "q r s vx"), 9, "positions"),
    (GOOD.replace("3 1 3.9", "1 1 3.9"), 11, "appears twice"),
    (GOOD.replace("pp ff pp", "pf ff pp"), 5, "'pp'"),
]


@pytest.mark.parametrize("text,line,words", BAD)
def test_malformed_files_name_the_line(tmp_path, text, line, words):
    path = _write(tmp_path, text)
    with pytest.raises(InputError) as err:
        read_dump(path, density=1.0)
    assert err.value.key == f"{path}:{line}"
    assert words in err.value.reason


def test_missing_density_and_empty_file(tmp_path):
    with pytest.raises(InputError, match="density"):
        read_dump(_write(tmp_path, GOOD))
    with pytest.raises(InputError, match="empty"):
        read_dump(_write(tmp_path, "\n\n"))


def test_cli_one_line_error_with_file_and_line(tmp_path, capsys):
    path = _write(tmp_path, BAD[7][0])
    assert main(["packing", str(path), "--density", "1000", "--kn", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert err.startswith(f"dtcrit: {path}:12: ")
    assert "Traceback" not in err


def test_cli_reads_a_dump_and_prints_json(tmp_path, capsys):
    assert main(["packing", str(EXAMPLE), "--kn", "1e5", "--ks", "5e4", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("omega_max", "dt_crit", "alpha", "cn_mean", "cn_max", "n_particles", "dofs", "estimates"):
        assert key in out
    assert out["n_particles"] == 60 and out["dofs"] == 360
    assert out["dt_crit"] == pytest.approx(2.0 / out["omega_max"])
