"""The ``dtcrit-spheres/1`` file: a conversion that fails leaves no file behind (nor a temporary one), and a
truncated or corrupted file is refused by ``open_spheres`` with one-line ``InputError`` naming it, never read
as garbage rows.
"""
from __future__ import annotations

import zipfile

import numpy as np
import pytest

from dtcrit.errors import InputError
from dtcrit.packing.generators.random_packing import random_packing
from dtcrit.packing.readers.lammps_dump import format_dump
from dtcrit.packing.readers.sphere_npz import SPHERE_DTYPE, convert_dump, open_spheres

N = 40
ROW_BYTES = 6 * 8  # id (int64), x, y, z, radius, mass (float64): the layout of the module docstring


def _dump_text():
    return format_dump(random_packing(N, cn=6.0, seed=3, density=1000.0), timestep=5)


def _bad_last_radius(text):
    """The dump with the radius column of its last row set to -1 (a row the serial reader refuses)."""
    lines = text.rstrip("\n").split("\n")
    cols = lines[-1].split()
    assert len(cols) == 7  # id type x y z radius mass
    cols[5] = "-1"
    return "\n".join(lines[:-1] + [" ".join(cols)]) + "\n"


def _one_line_naming(exc_info, path):
    message = str(exc_info.value)
    assert "\n" not in message and str(path) in message, message
    return message


def test_a_conversion_failing_on_the_last_row_leaves_no_file(tmp_path):
    """A dump whose last row has radius -1: refused, and neither the ``.npz`` nor a temporary file is left."""
    dump, out = tmp_path / "bad.dump", tmp_path / "bad.npz"
    dump.write_text(_bad_last_radius(_dump_text()))
    with pytest.raises(InputError):
        convert_dump(dump, out)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.dump"]  # neither the .npz nor a temporary file


def test_a_failed_conversion_keeps_the_file_it_would_have_replaced(tmp_path):
    """A failed conversion onto an existing sphere file leaves that file byte for byte."""
    good, bad, out = tmp_path / "good.dump", tmp_path / "bad.dump", tmp_path / "p.npz"
    good.write_text(_dump_text())
    bad.write_text(_bad_last_radius(_dump_text()))
    assert convert_dump(good, out) == N
    before = out.read_bytes()
    with pytest.raises(InputError):
        convert_dump(bad, out)
    assert out.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.dump", "good.dump", "p.npz"]
    assert len(open_spheres(out).rows) == N


@pytest.fixture
def npz(tmp_path):
    """A sphere file of ``N`` spheres converted from a dump."""
    dump, out = tmp_path / "p.dump", tmp_path / "p.npz"
    dump.write_text(_dump_text())
    assert convert_dump(dump, out) == N
    assert SPHERE_DTYPE.itemsize == ROW_BYTES
    return out


@pytest.mark.parametrize("rows", [N + 1, 99])
def test_a_header_announcing_more_rows_than_stored_is_refused(npz, rows):
    """The ``.npy`` header of spheres.npy patched to announce N + 1 rows (read past the member into the
    zip directory) or 99 rows (past the end of the file); the header keeps its length.
    """
    data = npz.read_bytes()
    old, new = f"'shape': ({N},)".encode(), f"'shape': ({rows},)".encode()
    assert data.count(old) == 1 and len(old) == len(new)
    npz.write_bytes(data.replace(old, new))
    with pytest.raises(InputError) as exc:
        open_spheres(npz)
    assert "spheres.npy" in _one_line_naming(exc, npz)


def test_a_member_shorter_than_its_header_is_refused(tmp_path):
    """A well-formed zip whose spheres.npy announces N rows but holds N - 2 (a writer that stopped early)."""
    path = tmp_path / "short.npz"
    with zipfile.ZipFile(path, "w", zipfile.ZIP_STORED) as archive:
        with archive.open("box.npy", "w") as member:
            box = np.zeros((), dtype=[("lo", "<f8", (3,)), ("hi", "<f8", (3,)), ("periodic", "?", (3,)),
                                      ("timestep", "<i8")])
            box["hi"] = 1.0
            np.lib.format.write_array(member, box, allow_pickle=False)
        with archive.open("spheres.npy", "w") as member:
            np.lib.format.write_array_header_2_0(member, {"descr": np.lib.format.dtype_to_descr(SPHERE_DTYPE),
                                                          "fortran_order": False, "shape": (N,)})
            member.write(np.ones(N - 2, dtype=SPHERE_DTYPE).tobytes())
    with pytest.raises(InputError) as exc:
        open_spheres(path)
    _one_line_naming(exc, path)


@pytest.mark.parametrize("keep", [0.5, 0.99])
def test_a_truncated_file_is_refused(npz, keep):
    """The file cut at half and at 99 % of its length."""
    data = npz.read_bytes()
    npz.write_bytes(data[:int(keep * len(data))])
    with pytest.raises(InputError) as exc:
        open_spheres(npz)
    _one_line_naming(exc, npz)


def test_an_intact_file_still_opens(npz):
    """The checks pass a file as ``convert_dump`` writes it."""
    spheres = open_spheres(npz)
    assert len(spheres.rows) == N and spheres.timestep == 5
    assert np.array_equal(np.sort(spheres.rows["id"]), np.arange(1, N + 1))
