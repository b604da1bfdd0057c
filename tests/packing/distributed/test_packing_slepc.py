"""``dtcrit packing --backend slepc --slepc-matrix assembled`` under ``mpirun``: PETSc/SLEPc on one and
two ranks give the top eigenvalue of a 10^4-sphere packing to 1e-10 relative of an independent serial solve (ARPACK to 1e-13
on the matrix assembled by ``scipy.sparse`` in this process), with exact preallocation; each rank's
slab of contacts, concatenated, is the serial contact list; bad input is one line and exit 2.

The MPI runs use ``.venv-mpi`` (``python3 dev.py mpi-env``; ``python3 dev.py test`` builds it).  Without
it or ``mpirun`` these tests skip, except under ``CI=true``, where they fail.
"""
from __future__ import annotations

import importlib.util
import json
import subprocess
import sys

import jsonschema
import numpy as np
import pytest
import scipy.sparse.linalg as spla

from dtcrit.packing.operators.assembly import mass_diagonal, scale_symmetric, stiffness_matrix
from dtcrit.packing.detection.overlaps import find_sphere_contacts, wrap_positions
from dtcrit.packing.readers.lammps_dump import read_dump, write_dump
from dtcrit.packing.generators.lattices import lattice
from dtcrit.packing.model import Box, HertzMindlinLaw, Packing, apply_law
from dtcrit.packing.generators.random_packing import random_packing
from dtcrit.bench.packing_scaling import jittered_fcc
from dtcrit.packing.distributed.slab_contacts import morton_order, slab_sphere_contacts, split_rows
from support.paths import REPO_ROOT as ROOT

from support.mpi_runs import MPI_PY, mpi_env as _mpi_env, mpirun_or_skip as _mpi_or_skip, run_packing as _mpirun
SCHEMA = json.loads((ROOT / "src" / "dtcrit" / "schemas" / "dtcrit-packing-slepc-1.json").read_text())
YOUNGS = 7e10  # Hertz-Mindlin: every contact's stiffness follows its own overlap


@pytest.fixture(scope="module")
def packing_file(tmp_path_factory):
    """A relaxed random packing of 10^4 lognormal spheres (mean coordination 6) as a dump: the MPI runs
    and the reference read the same 17-digit numbers."""
    path = tmp_path_factory.mktemp("slepc") / "random_1e4.dump"
    write_dump(path, random_packing(10_000, cn=6.0, sizes="lognormal", spread=0.25, radius=1e-3, density=2650.0,
                                    seed=7))
    return path


@pytest.fixture(scope="module")
def reference(packing_file):
    """``(omega_max^2, contacts, |A|_inf)``: ARPACK (tol 1e-13) on ``A = M^-1/2 K M^-1/2`` assembled here
    (its own residual bounds its distance to an eigenvalue) and the largest absolute row sum."""
    packing = read_dump(packing_file)
    contacts = apply_law(find_sphere_contacts(packing), HertzMindlinLaw(YOUNGS, 0.25))
    a = scale_symmetric(stiffness_matrix(packing, contacts), mass_diagonal(packing), inplace=True).tocsr()
    w, v = spla.eigsh(a, k=1, which="LA", tol=1e-13, v0=np.random.default_rng(1).standard_normal(a.shape[0]))
    assert np.linalg.norm(a @ v[:, 0] - w[0] * v[:, 0]) <= 1e-12 * w[0]
    return float(w[0]), contacts.count, float(abs(a).sum(axis=1).max())


@pytest.fixture(scope="module")
def runs(request):
    _mpi_or_skip()  # before the packing is made
    packing_file = request.getfixturevalue("packing_file")
    out = {}
    for ranks in (1, 2):
        proc = _mpirun(ranks, str(packing_file), "--youngs", str(YOUNGS), "--json", "--slepc-matrix", "assembled")
        assert proc.returncode == 0, proc.stderr[-3000:]
        out[ranks] = json.loads(proc.stdout)
    return out


def test_two_ranks_give_the_serial_top_eigenvalue(runs, reference):
    omega2, count, row_sum = reference
    doc = runs[2]
    jsonschema.validate(doc, SCHEMA)
    assert doc["ranks"] == 2 and doc["n_particles"] == 10_000 and doc["n_contacts"] == count
    assert sum(r["contacts"] for r in doc["per_rank"]) == count and min(r["contacts"] for r in doc["per_rank"]) > 0
    assert doc["matrix_mallocs"] == 0  # the preallocation from the slabs' block patterns was exact
    assert abs(doc["omega_max"] ** 2 - omega2) <= 1e-10 * omega2
    assert doc["relative_residual"] <= 1e-11
    assert doc["dt_safe"] == pytest.approx(2.0 / np.sqrt(row_sum), rel=1e-12)  # Gershgorin, from the upper triangle
    assert doc["dt_safe"] < doc["dt_crit"]


def test_one_and_two_ranks_agree(runs, reference):
    one, two = runs[1]["omega_max"] ** 2, runs[2]["omega_max"] ** 2
    jsonschema.validate(runs[1], SCHEMA)
    assert runs[1]["ranks"] == 1 and abs(one - two) <= 1e-10 * one
    assert abs(one - reference[0]) <= 1e-10 * reference[0]


def test_the_schema_refuses_broken_documents(runs):
    for broken in ({k: v for k, v in runs[2].items() if k != "omega_max"}, dict(runs[2], ranks=0),
                   dict(runs[2], schema="dtcrit-packing/1")):
        with pytest.raises(jsonschema.ValidationError):
            jsonschema.validate(broken, SCHEMA)


def test_a_slab_error_is_one_line_from_its_rank(tmp_path):
    """Coincident centres that only rank 1's slab holds (in the Morton numbering the back-end uses):
    rank 1 reports them, one line, exit 2."""
    base = lattice("sc", 3, radius=1.0, density=1.0)
    for a in range(base.n - 1, 0, -1):
        x = base.positions.copy()
        x[a] = x[a - 1]
        where = np.argsort(morton_order(wrap_positions(x, base.box)))  # particle -> its number
        if min(where[a], where[a - 1]) >= split_rows(base.n, 2, 1)[0]:
            break
    path = tmp_path / "coincident.dump"
    write_dump(path, Packing.spheres(x, base.radii, density=1.0, box=base.box))
    proc = _mpirun(2, str(path), "--kn", "1")
    assert proc.returncode != 0
    lines = [line for line in proc.stderr.splitlines() if "coincident" in line]
    assert lines == [f"{path}:positions: particles {a} and {a + 1} have coincident centres"], proc.stderr


def test_the_scale_benchmark_runs_on_two_ranks():
    """``python -m dtcrit.bench.slepc_scaling`` (the README's measured table): one JSON line whose
    ranks' contacts add up to the serial count."""
    cmd = [_mpi_or_skip(), "-n", "2", str(MPI_PY), "-m", "dtcrit.bench.slepc_scaling", "500", "fcc", "assembled"]
    proc = subprocess.run(cmd, capture_output=True, text=True, env=_mpi_env(), cwd=ROOT, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    doc = json.loads(proc.stdout)
    serial = find_sphere_contacts(jittered_fcc(500)).count
    assert doc["ranks"] == 2 and doc["n_contacts"] == serial == sum(r["contacts"] for r in doc["per_rank"])
    assert doc["matvecs"] > 0 and all(r["rss_solve"] >= r["rss_base"] for r in doc["per_rank"])


@pytest.mark.skipif(importlib.util.find_spec("petsc4py") is not None, reason="petsc4py is importable here")
def test_without_petsc_one_line_says_what_to_install():
    proc = subprocess.run([sys.executable, "-m", "dtcrit", "packing", "--random", "100", "--kn", "1", "--backend", "slepc"],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2 and proc.stdout == ""
    (line,) = proc.stderr.splitlines()
    for needed in ("apt-get install python3-slepc4py-real python3-petsc4py-real openmpi-bin", "python3 dev.py mpi-env",
                   "mpirun -n P .venv-mpi/bin/dtcrit packing"):
        assert needed in line


def _shuffled_box(periodic) -> Packing:
    rng = np.random.default_rng(3)
    x = rng.uniform(0.0, 10.0, (500, 3))
    box = None if periodic is None else Box(np.zeros(3), np.full(3, 10.0), periodic)
    return Packing.spheres(x, rng.uniform(0.3, 0.7, 500), density=1.0, box=box)


SLAB_CASES = {
    "fcc 1 cell (self images)": lambda: lattice("fcc", 1, radius=1.0, density=1.0),
    "bcc 3 cells": lambda: lattice("bcc", 3, radius=1.0, density=1.0),
    "random lognormal": lambda: random_packing(300, cn=6.0, sizes="lognormal", spread=0.3, seed=1),
    "open box": lambda: _shuffled_box(None),
    "periodic x and z": lambda: _shuffled_box((True, False, True)),
    "periodic, no spatial order": lambda: _shuffled_box((True, True, True)),
}


@pytest.mark.parametrize("ranks", [1, 2, 3, 7])
@pytest.mark.parametrize("case", sorted(SLAB_CASES))
def test_slabs_concatenate_to_the_serial_contact_list(case, ranks):
    packing = SLAB_CASES[case]()
    serial = find_sphere_contacts(packing)
    slabs = [slab_sphere_contacts(packing, *split_rows(packing.n, ranks, r)) for r in range(ranks)]
    for key in ("i", "j", "image", "normal", "arm_i", "arm_j", "overlap", "radius_eff"):
        assert np.array_equal(np.concatenate([getattr(s.contacts, key) for s in slabs]), getattr(serial, key)), key
    rows, cols = np.concatenate([serial.i, serial.j]), np.concatenate([serial.j, serial.i])
    off = rows != cols
    wanted = set(zip(rows[off].tolist(), cols[off].tolist()))
    got = [set(zip(s.pattern_rows.tolist(), s.pattern_cols.tolist())) for s in slabs]
    assert set().union(*got) == wanted  # every block of every row, no more
    for s, pattern in zip(slabs, got):
        assert all(s.lo <= p < s.hi for p, _ in pattern)



@pytest.mark.parametrize("case", sorted(SLAB_CASES))
def test_slabs_in_morton_numbering_hold_the_serial_contacts(case):
    """Renumbered along the Morton curve and split over 3 ranks, the contacts are the serial ones."""
    packing = SLAB_CASES[case]()
    serial = find_sphere_contacts(packing)
    order = morton_order(wrap_positions(packing.positions, packing.box))
    slabs = [slab_sphere_contacts(packing, *split_rows(packing.n, 3, r), order=order) for r in range(3)]

    def canonical(i, j, image, normal):
        swap = i > j  # the same contact seen from j: image and normal change sign
        sign = np.where(swap, -1, 1)[:, None]
        return sorted(zip(np.minimum(i, j).tolist(), np.maximum(i, j).tolist(), map(tuple, (sign * image).tolist()),
                          map(tuple, np.round(sign * normal, 12).tolist())))

    got = [canonical(order[s.contacts.i], order[s.contacts.j], s.contacts.image, s.contacts.normal) for s in slabs]
    assert sorted(sum(got, [])) == canonical(serial.i, serial.j, serial.image, serial.normal)
