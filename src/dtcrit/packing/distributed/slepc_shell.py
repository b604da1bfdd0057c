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
   the block-diagonal (``estimates.block_diagonal``) steps.  Each rank sums its own particles'
   diagonal blocks and coupling row sums in the serial route's compiled particle pass
   (``particle_pass.summary``), adding the parts that other ranks' contacts give them: those ranks
   compute them for their ghost rows (``particle_pass.partial_rows``) and the reverse scatter adds
   them to their owners (nothing is exchanged on one rank).  It then calls the serial estimates on
   its complete own rows (``OwnRows``); the bound is the largest over the ranks.

The compiled loops of a rank run on its share of its node's cores (``mpi_support.rank_threads``:
one rank alone uses every core it may run on, as the serial route does).

Memory per rank: the share (local packing and contacts) and the operator's arrays (the serial
route's, for ``C/P`` contacts), two ghosted vectors, and the eigen-solver's basis; no matrix.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from dtcrit.packing.model import Contacts, Packing
from dtcrit.packing.distributed.mpi_support import allgather, petsc, rank_threads, world

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
        from dtcrit.packing.operators import matrix_free_kernels as kernels
        from dtcrit.packing.operators.matrix_free import stiffness_operator

        PETSc, _ = petsc()
        comm, _, _ = world()
        self.layout, self.n = layout, int(n)
        # the rank's share of its node's cores (rank_threads): one rank alone uses the machine
        self.threads = kernels.use_threads(rank_threads())
        self.operator: ContactOperator | None = stiffness_operator(layout.packing, layout.contacts, compiled=compiled,
                                                                   threads=self.threads)
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
    """A rank's complete rows of ``A`` as far as the serial bounds need them: the ``BlockSummary`` of its
    own particles (top eigenvalue of each 6 x 6 diagonal block, absolute row sums for the unit and the
    ``sqrt(mass)`` weights); ``estimates.gershgorin`` and ``estimates.block_diagonal`` call
    ``abs_row_sums`` and ``block_summary`` on it as on the serial operator.

    Parameters
    ----------
    summary : dtcrit.packing.operators.particle_pass.BlockSummary
        The own particles' blocks and rows, every rank's contacts summed.
    root : numpy.ndarray
        ``sqrt`` of the own particles' mass diagonal, length 6 own.
    """

    def __init__(self, summary, root: np.ndarray):
        self.summary, self.root = summary, root
        self.shape = (root.size, root.size)

    def block_summary(self):
        """The own particles' ``BlockSummary``.

        Returns
        -------
        dtcrit.packing.operators.particle_pass.BlockSummary
            ``top``, ``diagonal``, ``rows_ones``, ``rows_root``.
        """
        return self.summary

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
            return self.summary.rows_ones
        if np.array_equal(np.asarray(weights).reshape(-1), self.root):
            return self.summary.rows_root
        raise ValueError("OwnRows has the row sums of the unit and sqrt(mass) weights only")


def _numpy_rows(op) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(blocks, r1, r2)`` of every local particle without Numba: the scaled diagonal blocks and the
    coupling sums ``|A| w`` less the blocks' part, ``w = 1`` and ``w = sqrt(m)``
    (``scattered_pass.scattered_blocks`` counts the diagonal blocks in).
    """
    from dtcrit.packing.operators import scattered_pass

    root = np.sqrt(op.mass_diag)
    blocks, (r1, r2) = scattered_pass.scattered_blocks(op, [np.ones_like(root), root])
    magnitude = np.abs(blocks)
    return (blocks, r1.reshape(-1, 6) - magnitude.sum(axis=2),
            r2.reshape(-1, 6) - np.einsum("pab,pb->pa", magnitude, root.reshape(-1, 6)))


def _ghost_parts(shell: ContactShell, op) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``summary``'s ``extras`` of the own particles: the parts of their blocks and coupling sums that
    other ranks' contacts give (those ranks' ghost rows, added to their owners by the reverse scatter).
    """
    from dtcrit.packing.operators import particle_pass

    n_own, n_local = shell.layout.n_own, shell.layout.packing.n
    nothing = (np.full(n_own, -1, np.int64), np.zeros((0, 6, 6)), np.zeros((0, 6)), np.zeros((0, 6)))
    if allgather([n_local - n_own]).max() == 0:  # no rank has ghosts (one rank): nothing to exchange
        return nothing
    if op.compiled:
        parts = particle_pass.partial_rows(op._kernel_args, op.scale6, op.mass_diag.reshape(-1, 6),
                                           np.arange(n_own, n_local))
    else:
        blocks, r1, r2 = _numpy_rows(op)
        parts = blocks[n_own:], r1[n_own:], r2[n_own:]

    def summed(values: np.ndarray) -> np.ndarray:  # ghost rows (G, 6) -> their owners' totals (own, 6)
        rows = np.zeros((n_local, 6))
        rows[n_own:] = values
        return shell.reverse_sum(rows)

    hit = np.flatnonzero(summed(np.ones((n_local - n_own, 6)))[:, 0] > 0)
    at = nothing[0]
    at[hit] = np.arange(hit.size)
    received = np.empty((hit.size, 6, 6))
    for b in range(6):
        received[:, :, b] = summed(parts[0][:, :, b])[hit]
    return at, received, summed(parts[1])[hit], summed(parts[2])[hit]


def _own_summary(op, n_own: int, extras: tuple):
    """The own particles' ``BlockSummary`` (``particle_pass.summary`` with ``extras``; without Numba the
    same sums from ``_numpy_rows``).
    """
    from dtcrit.packing.operators import particle_pass, scattered_pass

    weight = op.mass_diag.reshape(-1, 6)
    if op.compiled:
        return particle_pass.summary(op._kernel_args, op.scale6, weight, rows=n_own, extras=extras)
    blocks, r1, r2 = (values[:n_own] for values in _numpy_rows(op))
    at, more, more_r1, more_r2 = extras
    hit = np.flatnonzero(at >= 0)
    blocks[hit] += more[at[hit]]
    r1[hit] += more_r1[at[hit]]
    r2[hit] += more_r2[at[hit]]
    magnitude = np.abs(blocks)
    return particle_pass.BlockSummary(scattered_pass.top_eigenvalues(blocks), np.einsum("nii->ni", blocks).reshape(-1),
                                      (r1 + magnitude.sum(axis=2)).reshape(-1),
                                      (r2 + np.einsum("pab,pb->pa", magnitude, np.sqrt(weight[:n_own]))).reshape(-1))


def shell_bounds(shell: ContactShell) -> float:
    """The serial route's ``dt_safe`` (module docstring, 3), the same on every rank (collective).  The
    last use of the shell: its operator is dropped here.

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

    n_own = shell.layout.n_own
    op = shell.held()
    summary = _own_summary(op, n_own, _ghost_parts(shell, op))
    own_mass = op.mass_diag[:6 * n_own]
    shell.operator = None
    rows = OwnRows(summary, np.sqrt(own_mass))
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
