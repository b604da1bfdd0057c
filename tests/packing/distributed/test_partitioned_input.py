"""The partitioned input of the distributed route: a dump read in byte-range pieces and a
``dtcrit-spheres/1`` file read in row slices give, under ``mpirun -n 2``, the serial reader's contact
list (``read_dump`` + ``find_sphere_contacts``: the same ``(id_i, id_j)`` pairs and overlaps) while no
rank holds every row; the PETSc/SLEPc step from a ``.npz`` file equals ARPACK on the matrix assembled
here; the pieces of a dump hold every row once with the serial reader's line numbers in errors.

The MPI runs use ``.venv-mpi`` (``python3 dev.py mpi-env``); without it or ``mpirun`` they skip, except
under ``CI=true``, where they fail.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest
import scipy.sparse.linalg as spla

from dtcrit.bench.packing_scaling import jittered_fcc
from dtcrit.errors import InputError
from dtcrit.packing.detection.overlaps import find_sphere_contacts
from dtcrit.packing.distributed.petsc_build import LIMITS
from dtcrit.packing.generators.random_packing import random_packing
from dtcrit.packing.model import Box, LinearLaw, Packing, apply_law
from dtcrit.packing.operators.assembly import mass_diagonal, scale_symmetric, stiffness_matrix
from dtcrit.packing.readers.dump_ranges import header_at, piece_packing, rows_in_range, scan_markers
from dtcrit.packing.readers.lammps_dump import format_dump, read_dump, write_dump
from dtcrit.packing.readers.sphere_npz import convert_dump, open_spheres
from support.paths import REPO_ROOT as ROOT
from support.paths import SRC

from support.mpi_runs import mpi_env, run_ranks
PROBE = ROOT / "tests" / "support" / "partitioned_probe.py"
KN = 1e5


def _run(*args: str) -> subprocess.CompletedProcess:
    """``mpirun -n 2 .venv-mpi/bin/python ARGS`` on this source tree, the tests' helpers on the path."""
    return run_ranks(2, *args, env=mpi_env(str(SRC) + os.pathsep + str(ROOT / "tests")))


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """A periodic jittered FCC packing of 4000 spheres of varied radii, some centres a box length outside
    the box, as a dump (after a snapshot of another packing, rows in shuffled id order) and as a sphere
    file; and a dump whose header announces more spheres than 32-bit PETSc indexes.
    """
    folder = tmp_path_factory.mktemp("partitioned")
    fcc = jittered_fcc(4000)
    rng = np.random.default_rng(5)
    order = rng.permutation(fcc.n)
    x = fcc.positions[order] + np.where(rng.random((fcc.n, 1)) < 0.1, fcc.box.lengths, 0.0)
    shuffled = Packing.spheres(x, rng.uniform(1.0005, 1.0035, fcc.n), density=1.0, box=fcc.box, ids=order + 1)
    text = format_dump(shuffled, timestep=7)
    dump = folder / "random.dump"
    dump.write_text(format_dump(jittered_fcc(500, seed=9), timestep=3) + text)  # the last snapshot is read
    npz = folder / "random.npz"
    convert_dump(dump, npz)
    huge = folder / "huge.dump"
    huge.write_text(text.replace("ITEM: NUMBER OF ATOMS\n4000", f"ITEM: NUMBER OF ATOMS\n{LIMITS[32] // 6 + 1}"))
    half_open = folder / "half_open.dump"  # walls (no wall contacts) on x and y: no images there
    write_dump(half_open, Packing.spheres(fcc.positions[order], shuffled.radii, density=1.0, ids=shuffled.ids,
                                          box=Box(fcc.box.lo, fcc.box.hi, (False, False, True))))
    return dump, npz, huge, half_open


@pytest.fixture(scope="module")
def probed(files, tmp_path_factory):
    out = tmp_path_factory.mktemp("probe") / "out.json"
    proc = _run(str(PROBE), str(out), *map(str, files))
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(out.read_text())


def _serial_pairs(path):
    packing = read_dump(path)
    c = find_sphere_contacts(packing)
    i, j = packing.ids[c.i], packing.ids[c.j]
    pairs = np.stack([np.minimum(i, j), np.maximum(i, j)], axis=1)
    k = np.lexsort((pairs[:, 1], pairs[:, 0]))
    return pairs[k], c.overlap[k], (packing.radii[c.i] + packing.radii[c.j])[k], packing.n


@pytest.mark.parametrize("which", [0, 1, 3], ids=["text dump", "npz sphere file", "half-open box"])
def test_two_ranks_read_the_serial_contact_list(files, probed, which):
    pairs, overlap, reach, n = _serial_pairs(files[3 if which == 3 else 0])
    doc = probed[str(files[which])]
    i, j = np.array(doc["i"]), np.array(doc["j"])
    got = np.stack([np.minimum(i, j), np.maximum(i, j)], axis=1)
    k = np.lexsort((got[:, 1], got[:, 0]))
    assert doc["n"] == n and np.array_equal(got[k], pairs)
    # overlap = R_i + R_j - |d|, |d| from the separation taken from either end: a few ulps of R_i + R_j
    assert np.all(np.abs(np.array(doc["overlap"])[k] - overlap) <= 8 * np.finfo(float).eps * reach)
    assert doc["own"] == [n // 2, n - n // 2]
    assert max(doc["rows_held"]) < n  # no rank ever held the whole packing


def test_a_count_beyond_32_bit_indices_is_refused_from_the_header(files, probed):
    (line,) = probed[str(files[2])]["error"]
    assert "32-bit index limit 2^31 - 1" in line and str(LIMITS[32]) in line


def test_the_npz_route_gives_the_top_eigenvalue(tmp_path):
    """``dtcrit packing FILE.npz --backend slepc`` (partitioned by its suffix) on two ranks: the
    top eigenvalue of ARPACK (tol 1e-13) on ``M^-1/2 K M^-1/2`` assembled here from the dump lies in the
    reported bracket, and the Ritz value is within the route's residual tolerance of it.
    """
    fcc = jittered_fcc(500, seed=2)
    radii = np.random.default_rng(6).uniform(1.0005, 1.0035, fcc.n)
    dump, npz = tmp_path / "small.dump", tmp_path / "small.npz"
    write_dump(dump, Packing.spheres(fcc.positions, radii, density=1.0, box=fcc.box))
    convert_dump(dump, npz)
    proc = _run("-m", "dtcrit", "packing", str(npz), "--kn", str(KN), "--backend", "slepc", "--json")
    assert proc.returncode == 0, proc.stderr[-3000:]
    doc = json.loads(proc.stdout)
    packing = read_dump(dump)
    contacts = apply_law(find_sphere_contacts(packing), LinearLaw(KN, KN))
    a = scale_symmetric(stiffness_matrix(packing, contacts), mass_diagonal(packing), inplace=True).tocsr()
    w, _ = spla.eigsh(a, k=1, which="LA", tol=1e-13, v0=np.random.default_rng(1).standard_normal(a.shape[0]))
    assert doc["ranks"] == 2 and doc["n_contacts"] == contacts.count
    # the default matrix-free route stops at a relative residual of 1e-6 and brackets the true step
    bracket = doc["dt_bracket"]
    assert bracket["lower"] <= 2.0 / np.sqrt(w[0]) <= bracket["upper"]
    assert abs(doc["omega_max"] ** 2 - w[0]) <= 1e-5 * w[0]


@pytest.mark.parametrize("pieces", [1, 2, 3, 7, 50])
def test_pieces_hold_every_row_once(tmp_path, pieces):
    """A two-snapshot dump with CRLF line ends: the second snapshot's rows split into ``pieces`` byte
    ranges are its rows, each once, in order.
    """
    packing = random_packing(60, cn=6.0, seed=2)
    text = format_dump(packing, timestep=1) + format_dump(packing, timestep=2)
    path = tmp_path / "two.dump"
    path.write_bytes(text.replace("\n", "\r\n").encode())
    size = path.stat().st_size
    markers = scan_markers(path, 0, size)
    assert len(markers.offsets) == 2 and markers.newlines == text.count("\n")
    assert markers.newlines_before[1] == format_dump(packing, timestep=1).count("\n")
    header = header_at(path, markers.offsets[1], markers.newlines_before[1] + 1)
    assert header.timestep == 2 and header.count == 60
    rows = []
    for k in range(pieces):
        a = header.rows_start + (size - header.rows_start) * k // pieces
        b = header.rows_start + (size - header.rows_start) * (k + 1) // pieces
        rows += rows_in_range(path, header.rows_start, size, a, b, header.first_line)
    assert rows == text.split("\n")[header.first_line - 1:header.first_line - 1 + 60]


def test_a_bad_row_is_named_by_its_line_as_the_serial_reader_names_it(tmp_path):
    packing = random_packing(40, cn=6.0, seed=2)
    lines = format_dump(packing).split("\n")
    lines[30] = lines[30].rsplit(" ", 2)[0] + " -1 1"  # radius -1 on line 31
    path = tmp_path / "bad.dump"
    path.write_text("\n".join(lines))
    with pytest.raises(InputError) as serial:
        read_dump(path)
    header = header_at(path, 0, 1)
    start = len("\n".join(lines[:25])) + 1  # a piece from line 26
    rows = rows_in_range(path, header.rows_start, path.stat().st_size, start, path.stat().st_size, 26)
    with pytest.raises(InputError) as piece:
        piece_packing(header, rows, 26, None)
    assert str(piece.value) == str(serial.value) and serial.value.location.line == 31


def test_the_sphere_file_holds_the_dump(tmp_path):
    packing = random_packing(200, cn=6.0, seed=4, density=1000.0)
    box = Box(packing.box.lo, packing.box.hi, (True, False, True))
    dump = tmp_path / "p.dump"
    write_dump(dump, Packing.spheres(packing.positions, packing.radii, masses=packing.masses, box=box),
               with_mass=False)
    npz = tmp_path / "p.npz"
    assert convert_dump(dump, npz, density=1000.0) == 200
    spheres, serial = open_spheres(npz), read_dump(dump, density=1000.0)
    rows = np.array(spheres.rows)[np.argsort(spheres.rows["id"])]
    assert spheres.box.periodic == (True, False, True) and np.array_equal(spheres.box.hi, box.hi)
    assert np.array_equal(np.stack([rows["x"], rows["y"], rows["z"]], 1), serial.positions)
    assert np.array_equal(rows["mass"], serial.masses) and np.array_equal(rows["id"], serial.ids)


def test_a_byte_that_is_not_utf8_is_named_in_a_piece(tmp_path):
    text = format_dump(random_packing(20, cn=6.0, seed=2))
    path = tmp_path / "latin1.dump"
    path.write_bytes(text.encode().replace(b"\n3 1 ", b"\n3 1 \xe9", 1))
    header = header_at(path, 0, 1)
    with pytest.raises(InputError) as piece:
        rows_in_range(path, header.rows_start, path.stat().st_size, header.rows_start, path.stat().st_size,
                      header.first_line)
    assert piece.value.location.line == header.first_line + 2 and "not UTF-8" in str(piece.value)


def test_partitioned_read_needs_the_slepc_backend():
    proc = subprocess.run([sys.executable, "-m", "dtcrit", "packing", "--random", "20", "--kn", "1",
                           "--partitioned-read"], capture_output=True, text=True, timeout=300,
                          env={**os.environ, "PYTHONPATH": str(SRC)})
    assert proc.returncode == 2 and proc.stdout == ""
    (line,) = proc.stderr.splitlines()
    assert "partitioned-read" in line and "--backend slepc" in line


def test_the_converter_command(tmp_path):
    dump, out = tmp_path / "p.dump", tmp_path / "p.npz"
    write_dump(dump, random_packing(30, cn=6.0, seed=2), with_mass=False)
    cmd = [sys.executable, "-m", "dtcrit.packing.readers.sphere_npz", str(dump), str(out)]
    env = {**os.environ, "PYTHONPATH": str(SRC)}
    bad = subprocess.run(cmd, capture_output=True, text=True, timeout=300, env=env)
    assert bad.returncode == 2 and len(bad.stderr.splitlines()) == 1 and "--density" in bad.stderr
    good = subprocess.run([*cmd, "--density", "2500"], capture_output=True, text=True, timeout=300, env=env)
    assert good.returncode == 0 and "30 spheres" in good.stdout
    assert len(open_spheres(out).rows) == 30
