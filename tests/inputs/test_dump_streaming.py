"""A LAMMPS dump is streamed one snapshot at a time: ``iter_dump`` is a generator, ``read_dump`` picks
a snapshot from it without holding the others, and rows are parsed only for the snapshot read.
"""
import inspect
import tracemalloc

import numpy as np
import pytest

from dtcrit.errors import InputError, Location
from dtcrit.packing.readers.lammps_dump import iter_dump, read_dump

SNAPSHOTS, ATOMS = 1500, 20


def _snapshot(k: int) -> str:
    """Snapshot ``k``: timestep ``10 k``, atom ``a`` at x = a + k/10^4 (spheres of radius 0.1)."""
    rows = "".join(f"{a + 1} 1 {a + k * 1e-4!r} 0.5 0.5 0.1 1.0\n" for a in range(ATOMS))
    return (f"ITEM: TIMESTEP\n{10 * k}\nITEM: NUMBER OF ATOMS\n{ATOMS}\nITEM: BOX BOUNDS ff ff ff\n"
            f"-1.0 {ATOMS + 1.0}\n0.0 1.0\n0.0 1.0\nITEM: ATOMS id type x y z radius mass\n{rows}")


@pytest.fixture(scope="module")
def dump(tmp_path_factory):
    path = tmp_path_factory.mktemp("dumps") / "many.dump"
    path.write_text("".join(_snapshot(k) for k in range(SNAPSHOTS)))
    return path


def test_iter_dump_is_a_generator_over_every_snapshot(dump):
    stream = iter_dump(dump)
    assert inspect.isgenerator(stream)
    steps = [snap.timestep for snap in stream]
    assert steps == [10 * k for k in range(SNAPSHOTS)]


@pytest.mark.parametrize("index, k", [(0, 0), (7, 7), (-1, SNAPSHOTS - 1), (-3, SNAPSHOTS - 3), (-SNAPSHOTS, 0)])
def test_read_dump_picks_the_snapshot_by_python_index(dump, index, k):
    packing = read_dump(dump, snapshot=index)
    assert packing.label == f"many.dump, timestep {10 * k}"
    assert np.array_equal(packing.positions[:, 0], [a + k * 1e-4 for a in range(ATOMS)])


def test_an_index_beyond_the_file_names_the_count(dump):
    with pytest.raises(InputError) as caught:
        read_dump(dump, snapshot=SNAPSHOTS)
    assert caught.value.key == "snapshot" and caught.value.reason == (
        f"the file has {SNAPSHOTS} snapshot(s); index {SNAPSHOTS} is out of range")


def test_reading_the_last_snapshot_holds_one_snapshot_not_the_file(dump):
    size = dump.stat().st_size
    tracemalloc.start()
    try:
        read_dump(dump)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert size > 1_000_000
    assert peak < size / 20, f"peak {peak} bytes for a {size}-byte dump"


def test_the_stream_stops_at_the_snapshot_asked_for(tmp_path):
    """A broken header after snapshot 0 is never read when snapshot 0 is asked for."""
    path = tmp_path / "broken.dump"
    path.write_text(_snapshot(0) + "ITEM: TIMESTEP\nnot a number\n")
    assert read_dump(path, snapshot=0).n == ATOMS
    with pytest.raises(InputError) as caught:
        read_dump(path)
    start = _snapshot(0).count("\n")
    assert caught.value.location == Location(str(path), start + 2, None)


def test_rows_are_parsed_only_when_read(tmp_path):
    path = tmp_path / "bad_row.dump"
    path.write_text(_snapshot(0) + _snapshot(1).replace("0.5 0.5 0.1", "0.5 oops 0.1", 1))
    first, second = list(iter_dump(path))
    assert first.rows.shape == (ATOMS, 7)
    with pytest.raises(InputError) as caught:
        second.rows  # noqa: B018
    line = _snapshot(0).count("\n") + 10
    assert caught.value.location == Location(str(path), line, None)
    assert caught.value.reason == "'oops' is not a number"
    assert read_dump(path, snapshot=0).n == ATOMS
