"""The matrix-free SLEPc route (``--backend slepc``, ``--slepc-matrix shell``, the default) under ``mpirun``.

On a random packing of 10^4 lognormal spheres with Hertz-Mindlin stiffness, one and two ranks give a
bracket ``[dt_safe, 2/sqrt(theta)]`` that holds the step of the top eigenvalue found independently
(ARPACK on ``A = M^-1/2 K M^-1/2`` assembled by ``scipy.sparse`` in this process) and the serial
matrix-free route's answer; ``dt_safe`` equals the serial route's bound, recomputed here from the
assembled matrix (Gershgorin rows of ``A`` and of ``M^-1 K``, the 6 x 6 diagonal blocks).

The runs use ``.venv-mpi`` (``python3 dev.py mpi-env``) with this checkout's ``src`` first on the
path; without it or ``mpirun`` they skip, except under ``CI=true``, where they fail.
"""
from __future__ import annotations

import json

import jsonschema
import numpy as np
import pytest
import scipy.sparse.linalg as spla

from dtcrit.packing.generators.random_packing import random_packing
from dtcrit.packing.model import HertzMindlinLaw, apply_law
from dtcrit.packing.detection.overlaps import find_sphere_contacts
from dtcrit.packing.operators.assembly import mass_diagonal, scale_symmetric, stiffness_matrix
from dtcrit.packing.readers.lammps_dump import read_dump, write_dump
from dtcrit.packing.step import packing_step
from support.paths import SRC

from support.mpi_runs import run_packing as _mpirun, run_ranks
SCHEMA = json.loads((SRC / "dtcrit" / "schemas" / "dtcrit-packing-slepc-1.json").read_text())
YOUNGS = 7e10
ROUNDING = 1e-12  # relative slack for the rounding of two computations of the same Rayleigh quotient


@pytest.fixture(scope="module")
def packing_file(tmp_path_factory):
    """10^4 lognormal spheres (``random_packing``, a short relaxation) as a dump: the MPI ranks and the
    references read the same 17-digit numbers.
    """
    path = tmp_path_factory.mktemp("shell") / "random_1e4.dump"
    write_dump(path, random_packing(10_000, cn=6.0, sizes="lognormal", spread=0.25, radius=1e-3, density=2650.0,
                                    seed=11, max_steps=20))
    return path


@pytest.fixture(scope="module")
def reference(packing_file):
    """``(lambda_max, dt_safe, contacts)`` from ``A`` assembled here: ARPACK to 1e-13 (its residual
    bounds its distance to an eigenvalue), and the larger of the Gershgorin step (the smaller of the
    largest absolute row sums of ``A`` and of ``M^-1 K``) and the block-diagonal step
    ``sqrt(2) / sqrt(max_p lambda_max(A_pp))``.
    """
    packing = read_dump(packing_file)
    contacts = apply_law(find_sphere_contacts(packing), HertzMindlinLaw(YOUNGS, 0.25))
    md = mass_diagonal(packing)
    a = scale_symmetric(stiffness_matrix(packing, contacts), md, inplace=True).tocsr()
    w, v = spla.eigsh(a, k=1, which="LA", tol=1e-13, v0=np.random.default_rng(1).standard_normal(a.shape[0]))
    assert np.linalg.norm(a @ v[:, 0] - w[0] * v[:, 0]) <= 1e-12 * w[0]
    root = np.sqrt(md)
    gershgorin = min(abs(a).sum(axis=1).max(), ((abs(a) @ root) / root).max())
    dense_blocks = a.tobsr(blocksize=(6, 6))
    rows = np.repeat(np.arange(packing.n), np.diff(dense_blocks.indptr))
    blocks = dense_blocks.data[dense_blocks.indices == rows]
    block_top = np.linalg.eigvalsh(0.5 * (blocks + np.swapaxes(blocks, 1, 2)))[:, -1].max()
    dt_safe = max(2.0 / np.sqrt(gershgorin), np.sqrt(2.0) / np.sqrt(block_top))
    return float(w[0]), float(dt_safe), contacts.count


@pytest.fixture(scope="module")
def runs(packing_file):
    """The JSON of ``mpirun -n 1`` and ``-n 2`` of the default (shell) route on the packing."""
    out = {}
    for ranks in (1, 2):
        proc = _mpirun(ranks, str(packing_file), "--youngs", str(YOUNGS), "--json")
        assert proc.returncode == 0, proc.stderr[-3000:]
        out[ranks] = json.loads(proc.stdout)
    return out


@pytest.mark.parametrize("ranks", [1, 2])
def test_the_bracket_holds_the_independent_step(runs, reference, ranks):
    """``[dt_safe, 2/sqrt(theta)]`` holds ARPACK's step, and ``dt_safe`` is the serial bound."""
    lam, dt_safe, count = reference
    doc = runs[ranks]
    jsonschema.validate(doc, SCHEMA)
    assert doc["ranks"] == ranks and doc["matrix"] == "shell" and doc["matrix_nonzeros"] == 0
    assert doc["n_contacts"] == count and min(r["contacts"] for r in doc["per_rank"]) > 0
    low, high = doc["dt_bracket"]["lower"], doc["dt_bracket"]["upper"]
    assert doc["dt_bracket"]["lower_from"] == "dt_safe" and low == doc["dt_safe"] and high == doc["dt_crit"]
    truth = 2.0 / np.sqrt(lam)
    assert low <= truth <= high * (1 + ROUNDING)
    assert doc["dt_safe"] == pytest.approx(dt_safe, rel=1e-12)
    # the serial route's relative residual, and a Ritz value within its residual of the top eigenvalue
    assert doc["tolerance"] == pytest.approx(1e-6) and doc["relative_residual"] <= 1e-6
    assert abs(doc["omega_max"] ** 2 - lam) <= doc["residual"]


def test_the_serial_route_answers_within_the_bracket(runs, packing_file):
    """The serial matrix-free route's step lies in the bracket, with the same ``dt_safe``."""
    serial = packing_step(packing_file, youngs=YOUNGS, route="matrix-free", certify="no")
    for doc in runs.values():
        low, high = doc["dt_bracket"]["lower"], doc["dt_bracket"]["upper"]
        # both upper ends are Rayleigh quotients' steps: they differ by the solvers' residuals at most
        assert low <= serial.dt_crit * (1 + ROUNDING) and serial.dt_crit <= high * (1 + 2e-6)
        assert serial.dt_safe == pytest.approx(doc["dt_safe"], rel=1e-12)


def test_one_and_two_ranks_agree_within_their_residuals(runs):
    """One and two ranks give Ritz values within the sum of their residuals, and, starting from one
    vector (``slepc_start.global_uniform``), take the same products within one restart of the basis."""
    one, two = (runs[r]["omega_max"] ** 2 for r in (1, 2))
    assert abs(one - two) <= runs[1]["residual"] + runs[2]["residual"]
    assert abs(runs[1]["matvecs"] - runs[2]["matvecs"]) <= runs[1]["ncv"]


def test_slepc_matrix_is_refused_without_the_slepc_backend(capsys):
    """``--slepc-matrix`` without ``--backend slepc``: one line naming both flags, exit 2."""
    from dtcrit.cli import main

    assert main(["packing", "--random", "50", "--kn", "1", "--slepc-matrix", "shell"]) == 2
    (line,) = capsys.readouterr().err.splitlines()
    assert "--slepc-matrix" in line and "--backend slepc" in line


SHELL_BOUNDS = """
import json, sys
from dtcrit.packing.model import HertzMindlinLaw
from dtcrit.packing.readers.lammps_dump import read_dump
from dtcrit.packing.distributed.slepc_backend import distribute
from dtcrit.packing.distributed.slepc_shell import ContactShell, local_layout, shell_bounds
share = distribute(read_dump(sys.argv[1]), HertzMindlinLaw(float(sys.argv[2]), 0.25))
layout = local_layout(share.glob, share.lo, share.hi, share.packing, share.contacts)
steps = [shell_bounds(ContactShell(layout, share.n, compiled=compiled)) for compiled in (True, False)]
if share.lo == 0:
    print(json.dumps(steps))
"""


def test_three_ranks_bounds_with_and_without_numba_are_the_serial_bound(packing_file, reference):
    """On three ranks every own particle's blocks and rows add parts from the others; the compiled
    particle pass and the NumPy path both give the bound of ``A`` assembled here."""
    proc = run_ranks(3, "-c", SHELL_BOUNDS, str(packing_file), str(YOUNGS))
    assert proc.returncode == 0, proc.stderr[-3000:]
    compiled, numpy_path = json.loads(proc.stdout)
    assert compiled == pytest.approx(reference[1], rel=1e-12)
    assert numpy_path == pytest.approx(reference[1], rel=1e-12)
