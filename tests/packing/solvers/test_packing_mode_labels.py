"""The top-mode label of a degenerate eigenspace is the same whichever route computes it.

A simple-cubic lattice at ks = kn/3 has its top translational (zone-boundary) and rotational modes at
the same frequency when the cell count is even: the top eigenspace holds both kinds.  The dense
solver and ARPACK (which computes its largest Ritz pairs for this purpose), on the lattice and on
the same packing read back from a dump, must all say so; with an odd cell count there is no such
translational mode and all must say "rotational".  The reference is the full dense spectrum.
"""
from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

from dtcrit.packing.operators.assembly import mass_diagonal, scale_symmetric, stiffness_matrix
from dtcrit.packing.detection.overlaps import find_contacts
from dtcrit.packing.readers.lammps_dump import read_dump, write_dump
from dtcrit.packing.solvers.largest_mode import largest_mode
from dtcrit.packing.solvers.mode_kind import mode_character
from dtcrit.packing.generators.lattices import lattice
from dtcrit.packing.model import LinearLaw, apply_law


def _matrix(packing):
    c = apply_law(find_contacts(packing), LinearLaw(3.0, 1.0))
    return scale_symmetric(stiffness_matrix(packing, c), mass_diagonal(packing))


def _reference(a) -> str:
    """From the full spectrum: the range of the rotational energy share over the unit members of the
    top eigenspace is the range of the eigenvalues of V^T P_rot V (V its basis)."""
    w, v = sla.eigh(a.toarray())
    basis = v[:, w >= w[-1] * (1 - 1e-9)]
    rot_rows = np.zeros(a.shape[0], bool)
    rot_rows.reshape(-1, 6)[:, 3:] = True
    share = np.linalg.eigvalsh(basis[rot_rows].T @ basis[rot_rows])
    if share[0] < 0.5 < share[-1]:
        return "degenerate: translational and rotational"
    return "rotational" if share[0] >= 0.5 else "translational"


@pytest.mark.parametrize("cells", [4, 5, 6])
def test_dense_iterative_lattice_and_dump_agree(cells, tmp_path):
    p = lattice("sc", cells, radius=1.0, density=1.0)
    path = tmp_path / "sc.dump"
    write_dump(path, p)
    a_lattice, a_dump = _matrix(p), _matrix(read_dump(path))
    expected = _reference(a_lattice)
    assert expected == ("rotational" if cells % 2 else "degenerate: translational and rotational")
    for a in (a_lattice, a_dump):
        for method in ("dense", "eigsh"):
            top = largest_mode(a, method)
            assert mode_character(top.vector, top.space) == expected, (method, cells)
