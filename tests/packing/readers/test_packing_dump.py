"""LAMMPS / LIGGGHTS dump reading: content, periodicity, contacts, and one-line errors with line numbers."""
import json

import numpy as np
import pytest

from dtcrit.cli import main
from dtcrit.errors import InputError
from dtcrit.packing.detection.overlaps import find_sphere_contacts
from dtcrit.packing.readers.lammps_dump import format_dump, read_dump
from dtcrit.packing.generators.lattices import lattice
from dtcrit.packing.generators.random_packing import random_packing
from support.paths import EXAMPLES

EXAMPLE = EXAMPLES / "packings" / "random_lognormal_60.dump"

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
    (GOOD.replace("pp ff pp", "xy xz yz pp ff pp"), 6, "triclinic"),  # bounds lines without their tilt
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


# ---------------------------------------------------------------------------------------------
# LIGGGHTS's own layout, repeated columns, streaming
# ---------------------------------------------------------------------------------------------
LIGGGHTS_HEADER = "ITEM: ATOMS id type type x y z ix iy iz vx vy vz fx fy fz omegax omegay omegaz radius"
PAIR_STYLE = "gran/hooke/history 1e5 NULL 2e4 NULL 0.5 1"


def _example_rows():
    """``(head lines up to the BOX BOUNDS, rows id type x y z radius mass)`` of the example dump."""
    lines = EXAMPLE.read_text().splitlines()
    k = next(n for n, ln in enumerate(lines) if ln.startswith("ITEM: ATOMS"))
    assert lines[k].split()[2:] == ["id", "type", "x", "y", "z", "radius", "mass"]
    return lines[:k], [ln.split() for ln in lines[k + 1:] if ln.strip()]


def _liggghts_dump(tmp_path):
    """The example's particles written as LIGGGHTS's tutorials dump them (``type`` twice, image flags,
    velocities, forces and spins, no mass column), and the same particles as ``id type x y z radius``."""
    head, rows = _example_rows()
    spin = " 0 0 0 1.5 -2 0.25 3e-3 -1e-3 2e-3 10 -20 5"  # ix iy iz vx vy vz fx fy fz omegax omegay omegaz
    liggghts = head + [LIGGGHTS_HEADER] + [f"{r[0]} {r[1]} {r[1]} {r[2]} {r[3]} {r[4]}{spin} {r[5]}" for r in rows]
    plain = head + ["ITEM: ATOMS id type x y z radius"] + [" ".join(r[:6]) for r in rows]
    a, b = tmp_path / "liggghts.dump", tmp_path / "plain.dump"
    a.write_text("\n".join(liggghts) + "\n")
    b.write_text("\n".join(plain) + "\n")
    return a, b


def _audit_json(path, capsys, *extra):
    assert main(["audit", str(path), "--pair-style", PAIR_STYLE, "--density", "2650", "--json", *extra]) == 0
    return json.loads(capsys.readouterr().out)


def test_liggghts_layout_with_type_twice_gives_the_plain_layouts_answer(tmp_path, capsys):
    liggghts, plain = _liggghts_dump(tmp_path)
    assert LIGGGHTS_HEADER in liggghts.read_text()
    got, want = _audit_json(liggghts, capsys), _audit_json(plain, capsys)
    assert got["n_particles"] == want["n_particles"] == 60
    for key in ("dt_crit", "dt_safe", "dt_undamped", "n_contacts", "limiting"):
        assert got[key] == want[key], key


def test_a_repeated_column_that_is_read_is_refused_by_name_and_line(tmp_path, capsys):
    liggghts, _ = _liggghts_dump(tmp_path)
    for twice in ("x", "radius", "id"):
        text = liggghts.read_text().replace(LIGGGHTS_HEADER, LIGGGHTS_HEADER.replace(" omegaz ", f" {twice} "))
        path = _write(tmp_path, text, f"twice_{twice}.dump")
        assert main(["audit", str(path), "--pair-style", PAIR_STYLE, "--density", "2650"]) == 2
        err = capsys.readouterr().err
        assert err == (f"dtcrit: {path}:9: the ATOMS header names the column '{twice}' 2 times; dtcrit reads it, "
                       "so it must appear once\n")


def test_a_chosen_snapshot_is_read_without_the_rest_of_the_file(tmp_path):
    a = lattice("sc", 2, radius=0.5, density=1.0)
    path = tmp_path / "grows.dump"
    path.write_bytes(format_dump(a, timestep=7).encode() + b"ITEM: TIMESTEP\n\xff\xfe\x00garbage")
    got = read_dump(path, snapshot=0)
    assert got.n == a.n and got.label.endswith("timestep 7")
    with pytest.raises(InputError) as err:  # the last snapshot needs the garbage: one line naming it
        read_dump(path)
    assert err.value.key == f"{path}:{a.n + 11}" and "not UTF-8" in err.value.reason


def test_snapshot_index_out_of_range_and_from_the_end(tmp_path):
    a, b = lattice("sc", 2, radius=0.5, density=1.0), random_packing(20, cn=5, seed=2)
    path = _write(tmp_path, format_dump(a, timestep=1) + format_dump(b, timestep=2))
    assert read_dump(path, snapshot=-2).n == a.n and read_dump(path, snapshot=1).n == b.n
    for index in (2, -3):
        with pytest.raises(InputError) as err:
            read_dump(path, snapshot=index)
        assert err.value.key == "snapshot" and "2 snapshot(s)" in err.value.reason


def test_a_sphere_larger_than_the_periodic_box_is_refused_by_its_line(tmp_path):
    """Radius 1e23 m in a 4 m periodic box: its images overlap it ~1e23 deep (an endless image search)."""
    path = _write(tmp_path, GOOD.replace("2 2 1.0 1.0 1.95 0 0 0 0.5", "2 2 1.0 1.0 1.95 0 0 0 1e23"))
    with pytest.raises(InputError) as err:
        read_dump(path, density=1.0)
    assert err.value.key == f"{path}:12"
    assert err.value.reason.startswith("radius 1e+23 exceeds the periodic box length 4 along x")


@pytest.mark.parametrize("with_mass,density,words", [
    (False, None, "have no 'mass': give the particle density (--density)"),
    (True, 1.0, "include 'mass': do not give a density (--density) as well"),
])
def test_mass_or_density_is_asked_for_at_the_header_line(tmp_path, with_mass, density, words):
    text = GOOD.replace("vz radius", "radius mass").replace(" 0 0.5\n", " 0.5 2.0\n") if with_mass else GOOD
    path = _write(tmp_path, text)
    with pytest.raises(InputError) as err:
        read_dump(path, density=density)
    assert err.value.key == f"{path}:9" and words in err.value.reason
