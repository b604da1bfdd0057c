"""The PETSc build of 32- or 64-bit indices (``dtcrit.packing.distributed.petsc_build``, ``--petsc-indices``).

The choice is a pure function of the particle count (tested at the counts either side of
``(2^31 - 1) / 6`` without making them); the partitioned route's count comes from the file's header
(``peek_count``, checked against the serial reader's counts, and shown to read only up to its snapshot);
a 64-bit default petsc4py (faked) serves 64 bits without recorded folders; under ``mpirun -n 2`` the
64-bit build gives the 32-bit build's ``omega_max`` on a 864-sphere FCC lattice and the JSON and text say
which build ran; a 64-bit run without the 64-bit build, and a process that already loaded the other
build, are refused in one line.  The MPI runs use ``.venv-mpi`` (``python3 dev.py mpi-env``, which
records the 64-bit build); without it, ``mpirun`` or (for the 64-bit runs) a recorded 64-bit build they
skip, except under ``CI=true``, where they fail.
"""
from __future__ import annotations

import dataclasses
import importlib.util
import io
import json
import os
import sys
import types

import jsonschema
import pytest

from dtcrit.errors import InputError
from dtcrit.packing.distributed import petsc_build as pb
from dtcrit.packing.distributed.slepc_result import SlepcResult, format_result
from dtcrit.packing.generators.lattices import lattice
from dtcrit.packing.readers import dump_ranges
from dtcrit.packing.readers.lammps_dump import format_dump, read_dump
from dtcrit.packing.readers.sphere_npz import convert_dump
from dtcrit.packing.step import packing_step
from support.ci import in_ci
from support.mpi_runs import MPI_PY, mpi_env, run_packing, run_ranks
from support.paths import REPO_ROOT, SRC

SCHEMA = json.loads((SRC / "dtcrit" / "schemas" / "dtcrit-packing-slepc-1.json").read_text())
FCC = ("--lattice", "fcc", "--cells", "6", "--kn", "1e5", "--json")
"""An 864-sphere FCC lattice (6 x 6 x 6 cells of 4), linear springs."""
LAST_32 = (2**31 - 1) // 6
"""The most particles whose ``6 N`` DOFs 32-bit indices number: 357,913,941."""


@pytest.mark.parametrize("n, wanted, bits", [(1, "auto", 32), (LAST_32, "auto", 32), (LAST_32 + 1, "auto", 64),
                                             (10**10, "auto", 64), (None, "auto", 32), (LAST_32, "32", 32),
                                             (1, "64", 64), (None, "64", 64), (LAST_32 + 1, "64", 64)])
def test_the_count_chooses_the_index_width(n, wanted, bits):
    """Auto: 64 bits from the first count whose ``6 N`` exceeds ``2^31 - 1``; 32 and 64 as asked."""
    assert 6 * LAST_32 <= 2**31 - 1 < 6 * (LAST_32 + 1)
    assert pb.index_bits(n, wanted) == bits


def test_32_bits_with_too_many_particles_and_unknown_widths_are_refused():
    """``--petsc-indices 32`` one particle beyond the limit: the line names the DOFs and the limit."""
    with pytest.raises(InputError) as info:
        pb.index_bits(LAST_32 + 1, "32")
    assert info.value.key == "petsc_indices"
    assert f"{6 * (LAST_32 + 1)} DOFs" in str(info.value) and "32-bit index limit 2^31 - 1 = 2147483647" in str(info.value)
    with pytest.raises(InputError, match="choose one of auto, 32, 64"):
        pb.index_bits(10, "48")
    assert "64-bit index limit 2^63 - 1" in str(pb.limit_error(2**62, 2**63 - 1))


def test_the_count_is_peeked_from_the_header(tmp_path, monkeypatch):
    """A sphere file's rows; a small dump's size bound (within 32 bits); the chosen snapshot's
    ``NUMBER OF ATOMS`` once the dump is large enough to matter (here: the threshold lowered to 0), equal
    to the serial reader's count for every index, with the scan blocks small enough to take several.
    """
    frames = [lattice(kind, cells, radius=1.0, density=1.0) for kind, cells in (("sc", 2), ("fcc", 2), ("bcc", 3))]
    dump = tmp_path / "three.dump"
    dump.write_text("".join(format_dump(p, timestep=10 * k) for k, p in enumerate(frames)))
    npz = tmp_path / "three.npz"
    convert_dump(dump, npz)
    assert pb.peek_count(npz) == frames[-1].n
    bound = pb.peek_count(dump)
    assert bound >= frames[-1].n and 6 * bound <= 2**31 - 1
    monkeypatch.setattr(pb, "UNREAD_BELOW", 0)
    for block in (pb.PEEK_BLOCK, 64, 7):
        monkeypatch.setattr(pb, "PEEK_BLOCK", block)
        for k in (-3, -2, -1, 0, 1, 2):
            assert pb.peek_count(dump, k) == read_dump(dump, snapshot=k).n, (block, k)
        assert pb.peek_count(dump, 3) is None and pb.peek_count(dump, -4) is None
    assert pb.peek_count(tmp_path / "missing.dump") is None and pb.peek_count(None) is None
    assert pb.peek_count(dump, "last") is None


def test_the_peek_reads_only_up_to_its_snapshot(tmp_path, monkeypatch):
    """Snapshot 0 of a ten-frame dump: the scan stops at its marker; snapshot -1: it reads backwards
    from the end, the last frame's bytes only (bytes counted through the reader's ``open``).
    """
    frames = [lattice("sc", 3, radius=1.0, density=1.0)] * 9 + [lattice("fcc", 2, radius=1.0, density=1.0)]
    dump = tmp_path / "ten.dump"
    dump.write_text("".join(format_dump(p, timestep=k) for k, p in enumerate(frames)))
    size, frame = dump.stat().st_size, len(format_dump(frames[0], timestep=0))
    read = []

    class Counted(io.BufferedReader):
        def read(self, n=-1):
            data = super().read(n)
            read.append(len(data))
            return data

    monkeypatch.setattr(dump_ranges, "open", lambda path, mode="rb": Counted(io.FileIO(path, "r")), raising=False)
    monkeypatch.setattr(pb, "UNREAD_BELOW", 0)
    monkeypatch.setattr(pb, "PEEK_BLOCK", 256)
    last = len(format_dump(frames[-1], timestep=9))
    for k, most in ((0, 256 + 64), (-1, 1.2 * last + 600), (4, 1.2 * 5 * frame + 600)):
        read.clear()
        assert pb.peek_count(dump, k) == frames[k].n
        assert sum(read) <= most < 0.7 * size, (k, sum(read), most, size)


def test_petsc_indices_is_refused_without_the_slepc_backend(capsys):
    """``--petsc-indices`` without ``--backend slepc``: one line naming both flags, exit 2."""
    from dtcrit.cli import main

    assert main(["packing", "--random", "50", "--kn", "1", "--petsc-indices", "64"]) == 2
    (line,) = capsys.readouterr().err.splitlines()
    assert "--petsc-indices" in line and "--backend slepc" in line


def test_a_64_bit_default_build_serves_64_bits(monkeypatch):
    """No 64-bit folders recorded: a default petsc4py of 64-bit indices (a cluster's own PETSc, faked
    here) is accepted and ``sys.path`` left alone; a 32-bit default, or none, is refused in one line.
    """
    monkeypatch.setenv(pb.DIRS_ENV, "")
    monkeypatch.setattr(pb, "loaded_bits", lambda: None)
    monkeypatch.setattr(pb, "default_bits", lambda: 64)
    path = list(sys.path)
    pb.select_build(64)
    assert sys.path == path
    for other in (32, None):
        monkeypatch.setattr(pb, "default_bits", lambda: other)
        with pytest.raises(InputError, match="64-bit PETSc indices need Debian's 64-bit build") as info:
            pb.select_build(64)
        assert info.value.key == "petsc_indices" and "\n" not in str(info.value)
    monkeypatch.setattr(pb, "default_bits", lambda: pytest.fail("32 bits need no import"))
    pb.select_build(32)


def petsc64_or_skip() -> None:
    """Skip (fail under ``CI=true``) when ``.venv-mpi`` records no 64-bit build (:data:`pb.DIRS_ENV` or
    its ``dtcrit-petsc64-dirs.txt``, empty or missing: installed as a user or with ``DTCRIT_NO_APT=1``).
    """
    given = os.environ.get(pb.DIRS_ENV)
    record = MPI_PY.parent.parent / pb.RECORD
    text = given if given is not None else (record.read_text() if record.is_file() else "")
    if not text.strip():
        message = f"PETSc's 64-bit-index build: none recorded in .venv-mpi/{pb.RECORD} (python3 dev.py mpi-env as root)"
        if in_ci():
            pytest.fail(message)
        pytest.skip(message)


@pytest.mark.parametrize("rank, lines", [(1, 0), (0, 1)])
def test_bad_input_after_mpi_started_is_printed_by_rank_0_only(monkeypatch, capsys, rank, lines):
    """No launcher variable set, MPI started (a fake ``petsc4py.PETSc`` of the given rank): the CLI takes
    the rank from MPI, so rank 1 exits 2 silently and rank 0 prints the one line.
    """
    from dtcrit.cli import main
    from dtcrit.cli import packing as cli_packing

    monkeypatch.setattr(cli_packing, "QUIET_EXIT_DELAY", 0.0)
    for key in cli_packing.LAUNCHER_RANK:
        monkeypatch.delenv(key, raising=False)
    world = types.SimpleNamespace(getRank=lambda: rank)
    monkeypatch.setitem(sys.modules, "petsc4py.PETSc", types.SimpleNamespace(COMM_WORLD=world))
    try:
        code = main(["packing", "--lattice", "sc", "--kn", "1", "--backend", "slepc", "--route", "assembled"])
    except SystemExit as exc:
        code = exc.code
    err = capsys.readouterr().err.splitlines()
    assert code == 2 and len(err) == lines, err
    assert all(line.startswith("dtcrit") and "--backend slepc" in line for line in err)


@pytest.fixture(scope="module")
def runs():
    # the FCC lattice is generated on every rank: no file to share
    """The JSON of ``mpirun -n 2`` on the FCC lattice: ``--petsc-indices auto`` (the default) and ``64``."""
    petsc64_or_skip()
    out = {}
    for wanted in ("auto", "64"):
        proc = run_packing(2, *FCC, "--petsc-indices", wanted)
        assert proc.returncode == 0, proc.stderr[-3000:]
        out[wanted] = json.loads(proc.stdout)
    return out


def test_64_bit_indices_give_the_32_bit_omega_max(runs):
    """Auto picks 32 bits for 864 spheres; 64 bits give its ``omega_max`` to 1e-10, and both lie within
    the Ritz residual of the serial route's ``omega_max`` (an independent solve in this process).
    """
    auto, wide = runs["auto"], runs["64"]
    for doc in (auto, wide):
        jsonschema.validate(doc, SCHEMA)
        assert doc["n_particles"] == 864 and doc["ranks"] == 2
    assert (auto["petsc_index_bits"], wide["petsc_index_bits"]) == (32, 64)
    for doc in (auto, wide):  # the text report names the loaded build's width as the JSON does
        result = SlepcResult(**{f.name: doc[f.name] for f in dataclasses.fields(SlepcResult)})
        assert f"{doc['petsc_index_bits']}-bit PETSc indices" in format_result(result)
    assert wide["omega_max"] == pytest.approx(auto["omega_max"], rel=1e-10, abs=0)
    serial = packing_step(lattice="fcc", cells=6, kn=1e5, certify="no").omega_max
    for doc in (auto, wide):  # |theta - lambda| <= |A v - theta v| for a unit Ritz pair of a symmetric A
        assert abs(doc["omega_max"] ** 2 - serial**2) <= doc["residual"] * (1 + 1e-9)


def test_64_bits_without_the_64_bit_build_is_one_line(tmp_path):
    """The build lookup pointed at an empty folder: exit 2, one line naming the packages and mpi-env."""
    env = mpi_env(**{pb.DIRS_ENV: str(tmp_path)})
    proc = run_packing(2, *FCC, "--petsc-indices", "64", env=env)
    assert proc.returncode == 2 and proc.stdout == ""
    lines = [line for line in proc.stderr.splitlines() if line.startswith("dtcrit")]
    assert len(lines) == 1 and lines[0].startswith("dtcrit: --petsc-indices: 64-bit PETSc indices need"), proc.stderr
    for needed in ("python3-petsc4py-64-real", "python3-slepc4py-64-real", "python3 dev.py mpi-env"):
        assert needed in lines[0]


def test_a_process_that_loaded_one_build_refuses_the_other():
    """One rank imports the 32-bit build, then asks for the 64-bit one: refused, not mixed."""
    code = ("from petsc4py import PETSc\n"
            "from dtcrit.errors import InputError\n"
            "from dtcrit.packing.distributed.petsc_build import select_build\n"
            "select_build(32)\n"
            "try:\n    select_build(64)\nexcept InputError as exc:\n    print(exc)\n")
    proc = run_ranks(1, "-c", code)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "already loaded the PETSc build of 32-bit indices; the 64-bit one needs a new process" in proc.stdout


def test_mpi_env_asks_apt_for_the_64_bit_build_once(tmp_path, monkeypatch):
    """``dev.py``'s ``ensure_mpi_env`` without the 64-bit packages (and no network, faked): an up-to-date
    ``.venv-mpi`` does not call ``apt-get``; a rebuild calls it once, and the next rebuild not again.
    """
    spec = importlib.util.spec_from_file_location("dev_tasks", REPO_ROOT / "dev.py")
    assert spec is not None and spec.loader is not None
    dev = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(dev)
    venv, asked = tmp_path / ".venv-mpi", []
    monkeypatch.setattr(dev, "MPI_VENV", venv)
    monkeypatch.setattr(dev, "MPI_PY", venv / "bin" / "python")
    monkeypatch.setattr(dev, "_found", lambda where: None if where in dev.MPI_APT_64.values() else tmp_path / "x" / "m")
    monkeypatch.setattr(dev, "_apt_install", lambda packages, why: bool(packages) and not asked.append(packages))
    monkeypatch.setattr(dev, "run", lambda *cmd, **kw: 1)  # creating the venv fails: the rebuild stops there
    dev.MPI_PY.parent.mkdir(parents=True)
    dev.MPI_PY.write_text("")
    (venv / ".dtcrit-installed").write_text(dev._mpi_digest([str(tmp_path / "x")] * 2, []))
    assert dev.ensure_mpi_env() is None and asked == []
    dev.MPI_PY.unlink()
    for _ in range(2):
        assert "could not create .venv-mpi" in dev.ensure_mpi_env()
    assert asked == [list(dev.MPI_APT_64)]
