"""The matrix-free PETSc operator of the distributed back-end: a shell matrix running the contact kernel.

``A = M^(-1/2) K M^(-1/2)`` is never stored (``--slepc-matrix shell``, the default).  Each rank keeps
its share of ``slepc_backend.distribute`` (its own particles ``lo..hi-1``, the partners of its
contacts, its contacts) and applies ``A`` with the serial route's operator
(``dtcrit.packing.operators.matrix_free.ContactOperator``: the compiled loop of
``matrix_free_kernels`` when Numba is installed, the vectorised NumPy path otherwise) to a local
vector of its own particles followed by its *ghosts*, the partners owned by other ranks:

1. ``local_layout`` renumbers the share once: own particles first (in PETSc's order), then the
   ghosts in ascending global index; the ghost list is built once and gives a PETSc ghosted vector
   (``VecCreateGhostBlock``, block size 6, one block per particle).
2. ``ContactShell.mult`` (``MatPython``): the input's own entries are copied into the ghosted
   vector and a forward scatter (``INSERT_VALUES``) fills its ghosts with the owners' values; the
   kernel writes ``A x`` over own and ghost rows of the local vector (a contact between an own
   particle and a ghost adds to both); a reverse scatter (``ADD_VALUES``) adds the ghost rows to
   their owners, which are then the output's entries.  Each contact lives on one rank, so every
   contribution is added once.  This is the assembled route's product without the matrix: the
   tests compare both with the serial operator's eigenvalue.
3. ``shell_bounds``: the serial route's rigorous lower bound on the step, ``dt_safe``, the larger
   of the Gershgorin (``estimates.gershgorin``: rows of ``M^-1/2 K M^-1/2`` and of ``M^-1 K``) and
   the block-diagonal (``estimates.block_diagonal``) steps.  Each rank's operator gives the scaled
   diagonal blocks and coupling row sums of its contacts; blocks and sums of ghost rows are added
   to their owners by the same reverse scatter, after which each rank holds complete rows for its
   own particles and calls the serial estimates on them (``OwnRows``); the bound is the largest
   over the ranks.

Memory per rank: the share (local packing and contacts) and the operator's arrays (the serial
route's, for ``C/P`` contacts), two ghosted vectors, and the eigen-solver's basis; no matrix.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from dtcrit.packing.model import Contacts, Packing
from dtcrit.packing.distributed.mpi_support import allgather, petsc, world

if TYPE_CHECKING:
    from dtcrit.packing.operators.matrix_free import ContactOperator

__all__ = ["LocalLayout", "local_layout", "ContactShell", "OwnRows", "shell_matrix", "shell_bounds"]


@dataclass(frozen=True)
class LocalLayout:
    """A rank's share renumbered for the ghosted vectors: own particles first, then the ghosts.

    Parameters
    ----------
    n_own : int
        Number of own particles (``hi - lo``).
    ghosts : numpy.ndarray
        Global indices of the ghost particles, ascending (PETSc's ghost block list).
    packing : Packing
        Local packing, own particles (in global order) then ghosts.
    contacts : Contacts
        The rank's contacts in this local numbering.
    """

    n_own: int
    ghosts: np.ndarray
    packing: Packing
    contacts: Contacts


def local_layout(glob: np.ndarray, lo: int, hi: int, packing: Packing, contacts: Contacts) -> LocalLayout:
    """Renumber a share (local particle ``k`` is global ``glob[k]``, ``glob`` ascending and holding
    ``lo..hi-1``) so that the own particles come first and the ghosts after them (module docstring, 1).

    Parameters
    ----------
    glob : numpy.ndarray
        Global index of each local particle, ascending.
    lo, hi : int
        The rank's own particles ``lo <= p < hi``.
    packing : Packing
        The share's local packing (in the order of ``glob``).
    contacts : Contacts
        The share's contacts (local indices into ``glob``).

    Returns
    -------
    LocalLayout
        The renumbered share and its ghost list.
    """
    glob = np.asarray(glob, dtype=np.int64)
    own = (glob >= lo) & (glob < hi)
    if int(own.sum()) != hi - lo:
        raise RuntimeError(f"the share holds {int(own.sum())} of its {hi - lo} own particles")
    order = np.concatenate([np.flatnonzero(own), np.flatnonzero(~own)])
    new_of_old = np.empty_like(order)
    new_of_old[order] = np.arange(order.size)

    def pick(values):
        return None if values is None else values[order]

    local = Packing(pick(packing.positions), pick(packing.masses), pick(packing.inertia), pick(packing.radii),
                    box=packing.box, orientations=pick(packing.orientations), label=packing.label)
    moved = replace(contacts, i=new_of_old[contacts.i], j=new_of_old[contacts.j])
    return LocalLayout(hi - lo, glob[~own], local, moved)


class ContactShell:
    """The ``MatPython`` context of ``A`` (module docstring, 2): ``mult`` exchanges the halo through a
    ghosted vector and runs the contact kernel on this rank's contacts.

    Parameters
    ----------
    layout : LocalLayout
        The renumbered share.
    n : int
        Number of particles of the whole packing.
    compiled : bool or None
        Use the compiled kernel (default: when Numba is installed).
    """

    def __init__(self, layout: LocalLayout, n: int, compiled: bool | None = None):
        from dtcrit.packing.operators.matrix_free import stiffness_operator

        PETSc, _ = petsc()
        comm, _, _ = world()
        self.layout, self.n = layout, int(n)
        # one thread per rank: the ranks are the parallelism (a rank per core)
        self.operator: ContactOperator | None = stiffness_operator(layout.packing, layout.contacts, compiled=compiled,
                                                                   threads=1)
        ghosts = np.ascontiguousarray(layout.ghosts, dtype=PETSc.IntType)
        size = (6 * layout.n_own, 6 * self.n)
        self.x_ghosted = PETSc.Vec().createGhost(ghosts, size, bsize=6, comm=comm)
        self.y_ghosted = PETSc.Vec().createGhost(ghosts, size, bsize=6, comm=comm)
        self.products = 0

    def mult(self, mat, x, y) -> None:
        """``y = A x`` (PETSc's ``MatMult`` of the shell matrix).

        Parameters
        ----------
        mat : petsc4py.PETSc.Mat
            The shell matrix (unused).
        x, y : petsc4py.PETSc.Vec
            Input and output, distributed as the matrix's rows.
        """
        PETSc, _ = petsc()
        xg, yg = self.x_ghosted, self.y_ghosted
        xg.getArray()[:] = x.getArray(readonly=True)
        xg.ghostUpdate(PETSc.InsertMode.INSERT_VALUES, PETSc.ScatterMode.FORWARD)
        with xg.localForm() as xl, yg.localForm() as yl:
            self.held().apply_into(xl.getArray(readonly=True), yl.getArray())
        yg.ghostUpdate(PETSc.InsertMode.ADD_VALUES, PETSc.ScatterMode.REVERSE)
        y.getArray()[:] = yg.getArray(readonly=True)
        self.products += 1

    def held(self) -> ContactOperator:
        """The operator (an error once ``shell_bounds`` dropped it).

        Returns
        -------
        ContactOperator
            This rank's contact operator over its local particles.
        """
        if self.operator is None:
            raise RuntimeError("the shell's operator was dropped after its bounds")
        return self.operator

    def reverse_sum(self, values: np.ndarray) -> np.ndarray:
        """Six numbers per local particle (own and ghost rows), summed onto their owners: the own rows'
        totals over all ranks (collective).

        Parameters
        ----------
        values : numpy.ndarray
            Shape (own + ghosts, 6).

        Returns
        -------
        numpy.ndarray
            Shape (own, 6): each own particle's sum over every rank's rows of it.
        """
        PETSc, _ = petsc()
        yg = self.y_ghosted
        with yg.localForm() as yl:
            yl.getArray()[:] = np.asarray(values).reshape(-1)
        yg.ghostUpdate(PETSc.InsertMode.ADD_VALUES, PETSc.ScatterMode.REVERSE)
        return yg.getArray(readonly=True).reshape(-1, 6).copy()

    def free(self) -> None:
        """Free the ghosted vectors (not ``destroy``: PETSc calls a context's ``destroy`` with the
        matrix, and the bounds need the vectors after the solve).
        """
        self.x_ghosted.destroy()
        self.y_ghosted.destroy()


class OwnRows:
    """A rank's complete rows of ``A`` as far as the serial bounds need them: the 6 x 6 diagonal blocks
    of its own particles and their absolute coupling row sums for the unit and the ``sqrt(mass)``
    weights (``estimates.gershgorin``, ``estimates.block_diagonal`` call ``abs_row_sums`` and
    ``diagonal_blocks`` on it as on a serial operator).

    Parameters
    ----------
    blocks : numpy.ndarray
        Scaled diagonal blocks ``A_pp``, (own, 6, 6).
    coupling_ones, coupling_root : numpy.ndarray
        ``sum_{q != p} |A_pq| w_q`` for ``w = 1`` and ``w = sqrt(m)``, (own, 6).
    root : numpy.ndarray
        ``sqrt`` of the own particles' mass diagonal, length 6 own.
    """

    def __init__(self, blocks: np.ndarray, coupling_ones: np.ndarray, coupling_root: np.ndarray, root: np.ndarray):
        self.blocks, self.root = blocks, root
        self.coupling = {"ones": coupling_ones, "root": coupling_root}
        self.shape = (6 * blocks.shape[0], 6 * blocks.shape[0])

    def diagonal_blocks(self) -> np.ndarray:
        """The own particles' diagonal blocks ``A_pp``.

        Returns
        -------
        numpy.ndarray
            (own, 6, 6).
        """
        return self.blocks

    def abs_row_sums(self, weights: np.ndarray | None = None) -> np.ndarray:
        """``sum_q |A_pq| w_q`` over the own rows, ``w`` the ones (``None``) or ``sqrt(m)``.

        Parameters
        ----------
        weights : numpy.ndarray or None
            ``None`` (ones) or the ``root`` given at construction.

        Returns
        -------
        numpy.ndarray
            Length 6 own.
        """
        if weights is None or np.all(np.asarray(weights) == 1.0):
            key, w = "ones", np.ones(self.shape[0])
        elif np.array_equal(np.asarray(weights).reshape(-1), self.root):
            key, w = "root", self.root
        else:
            raise ValueError("OwnRows has the row sums of the unit and sqrt(mass) weights only")
        diag = np.einsum("pab,pb->pa", np.abs(self.blocks), w.reshape(-1, 6))
        return (self.coupling[key] + diag).reshape(-1)


def _coupling_sums(op, chunk: int = 1 << 16) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(blocks, coupling_ones, coupling_root)`` of this rank's contacts over its local particles: the
    scaled diagonal blocks (N_loc, 6, 6) and ``|A| w`` less the blocks' part (N_loc, 6), for ``w = 1``
    and ``w = sqrt(m)`` (``ContactOperator.abs_row_sums`` counts the diagonal blocks in).
    """
    root = np.sqrt(op.mass_diag).reshape(-1, 6)
    blocks = op.diagonal_blocks()
    out = []
    for w in (None, root):
        sums = op.abs_row_sums(None if w is None else w.reshape(-1)).reshape(-1, 6).copy()
        for lo in range(0, len(sums), chunk):
            part = slice(lo, lo + chunk)
            diag = np.abs(blocks[part])
            sums[part] -= diag.sum(axis=2) if w is None else np.einsum("pab,pb->pa", diag, w[part])
        out.append(sums)
    return blocks, out[0], out[1]


def shell_bounds(shell: ContactShell) -> float:
    """The serial route's ``dt_safe`` (module docstring, 3), the same on every rank (collective).  The
    last use of the shell: its operator is dropped here, before the bounds' own arrays are made.

    Parameters
    ----------
    shell : ContactShell
        This rank's shell context.

    Returns
    -------
    float
        ``dt_safe`` [s]: the larger of the Gershgorin and block-diagonal steps (``inf`` without a
        stiff contact).
    """
    from dtcrit.packing.bounds import estimates as est
    from dtcrit.packing.operators.assembly import mass_diagonal

    n_own = shell.layout.n_own
    blocks, ones, root = _coupling_sums(shell.held())
    shell.operator = None  # with its cached blocks and row sums: only the local arrays are needed now
    own_blocks = np.empty((n_own, 6, 6))
    for b in range(6):
        own_blocks[:, :, b] = shell.reverse_sum(blocks[:, :, b])
    del blocks
    coupling = [shell.reverse_sum(values) for values in (ones, root)]
    del ones, root
    own_mass = mass_diagonal(shell.layout.packing)[:6 * n_own]
    rows = OwnRows(own_blocks, coupling[0], coupling[1], np.sqrt(own_mass))
    omega2 = [est.gershgorin(rows, own_mass).omega2 or 0.0, est.block_diagonal(rows).omega2 or 0.0] if n_own else [0.0, 0.0]
    top = allgather(omega2).max(axis=0)
    steps = [2.0 / math.sqrt(w2) for w2 in top if w2 > 0]
    return max(steps) if steps else math.inf


def shell_matrix(layout: LocalLayout, n: int, compiled: bool | None = None):
    """The shell matrix ``A`` and its context (collective).

    Parameters
    ----------
    layout : LocalLayout
        This rank's renumbered share.
    n : int
        Number of particles of the whole packing.
    compiled : bool or None
        Use the compiled kernel (default: when Numba is installed).

    Returns
    -------
    tuple
        ``(mat, shell)``: the ``petsc4py.PETSc.Mat`` of type ``python`` (symmetric) and its
        ``ContactShell``.
    """
    PETSc, _ = petsc()
    comm, _, _ = world()
    shell = ContactShell(layout, n, compiled)
    rows = 6 * layout.n_own
    mat = PETSc.Mat().createPython(((rows, 6 * n), (rows, 6 * n)), context=shell, comm=comm)
    mat.setOption(PETSc.Mat.Option.SYMMETRIC, True)
    mat.setUp()
    return mat, shell
