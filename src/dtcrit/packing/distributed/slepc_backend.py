"""The largest eigenvalue of a packing on many processes: PETSc matrix, SLEPc Krylov-Schur, under MPI.

``omega_max^2`` is the top eigenvalue of ``A = M^(-1/2) K M^(-1/2)`` (``dtcrit.packing.operators.assembly``;
Otsubo et al. 2017, Eq. (13)), and ``dt_crit = 2/omega_max`` for the central-difference family.  Run
as ``mpirun -n P dtcrit packing ... --backend slepc`` from the environment ``.venv-mpi`` (``python3
dev.py mpi-env``: Debian's petsc4py and slepc4py); petsc4py and slepc4py are imported inside the
functions, so this module imports without them.  A run with one process (no launcher) is a valid
one-rank run.

What each rank does (``distribute``, then ``slepc_analysis.analyse_share``):

1. Sphere packings are renumbered along a Morton curve (``slab_contacts.morton_order``; the
   eigenvalues do not depend on the numbering), so that a rank's particles are a compact piece of
   space.  Rank ``r`` owns the particles ``lo <= p < hi`` of PETSc's ownership split
   (``slab_contacts.split_rows``), i.e. the matrix rows ``6 lo .. 6 hi - 1`` in blocks of six DOFs.
2. It finds only its own particles' contacts (``slab_contacts.slab_sphere_contacts``: a k-d tree over
   its slab matched against its halo), each pair on one rank, and applies the contact law to those.
   A contact list every rank already holds (non-spherical bodies, a bodies file's ``contacts``) is
   cut into ``P`` contiguous parts instead (``slab_contacts.slab_of_list``).
3. It keeps a local packing of its own particles and their contact partners; the contacts' element
   blocks ``ii, jj, ij, ji`` (``assembly.contact_blocks``; a self-image contact puts all four on the
   particle's diagonal, as ``assembly.stiffness_matrix`` does), scaled by ``M^(-1/2)`` on both sides,
   go with ``ADD_VALUES`` into a PETSc ``MPISBAIJ`` matrix (block size 6, the upper block triangle:
   one block per contact), preallocated exactly from the block pattern of its rows; blocks of rows
   owned elsewhere travel through PETSc's stash, flushed every ``FLUSH`` chunks of ``CHUNK`` contacts.
   The local packing and contacts are dropped once the matrix holds them.
4. SLEPc's EPS: Krylov-Schur, Hermitian problem, ``LARGEST_REAL``, relative residual tolerance
   ``TOLERANCE`` (a Ritz value of a symmetric matrix lies within the residual norm of an
   eigenvalue, so the value is good to about that relative error), subspace ``NCV``;
   ``PETSC_OPTIONS="-eps_ncv 16 -eps_tol 1e-10"`` overrides them.  Reported: ``omega_max^2``, the
   residual norm ``|A v - theta v|`` of the unit pair, restarts and matrix-vector products (PETSc's
   ``MatMult`` event), the Gershgorin lower bound ``2/sqrt(|A|_inf)`` on the step, and the kinetic
   energy share of the rotational DOFs, reduced across ranks; the mode itself stays distributed
   (gathering ``6N`` numbers on rank 0 is not cheap at scale).

Memory per rank (measured on 10^4..10^6 spheres at 1 and 2 ranks; ``docs/howto/mpi.md``, sections
"Memory and time model" and "Measured").  Every rank reads or generates the whole input, O(N): a text
dump peaks at about 0.9 kB
per particle inside ``dump_io.read_dump``, a generated packing holds about 0.1 kB, and the search
adds wrapped and renumbered copies of all positions (about 0.13 kB per particle together).
Everything else is O(N/P + C/P) for C contacts: the search's temporaries (about 360 B per own
contact), the local contact list (144 B per contact), the matrix (292 B per stored 6 x 6 block, one
per contact and one per particle) and SLEPc's ``NCV + 1`` basis vectors with about eight work
vectors (48 B per particle each).  The solve's share, ``292 B (C + N)/P + 48 B (NCV + 9) N/P`` (on
several ranks ``NCV + 18`` vectors: the parallel product's own) over the ~100 MiB of the
interpreter, NumPy, SciPy and PETSc, is the peak unless the replicated input is larger.  Only rank
0 prints.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np

from dtcrit.errors import InputError

from dtcrit.packing.operators.assembly import contact_blocks, mass_diagonal
from dtcrit.packing.detection.overlaps import find_contacts, wrap_positions
from dtcrit.packing.model import Contacts, Packing, apply_law
from dtcrit.packing.distributed.mpi_support import agree, allgather, peak_mib, petsc, release_memory, world
from dtcrit.packing.distributed.petsc_build import check_dofs
from dtcrit.packing.distributed.slepc_result import JSON_SCHEMA, UNITS, SlepcResult, format_result
from dtcrit.packing.distributed.slab_contacts import SlabContacts, morton_order, slab_of_list, slab_sphere_contacts, split_rows

__all__ = ["TOLERANCE", "NCV", "CHUNK", "FLUSH", "SYMMETRIC", "JSON_SCHEMA", "UNITS", "RankShare", "SlepcResult",
           "distribute", "assemble", "solve", "format_result"]

TOLERANCE = 1e-12
"""EPS relative residual tolerance ``|A v - theta v| / theta``: the agreement with a serial solve
asked of this back-end is 1e-10 relative."""
NCV = 32
"""Krylov-Schur subspace size (SLEPc's default for one eigenvalue is 16).  Measured on 10^5 jittered
FCC spheres to 1e-12: 1176 products at 16, 744 at 24, 624 at 32, 600 at 48; 32 was the fastest, for
``NCV + 1`` basis vectors of the rank's rows."""
MAX_RESTARTS = 20_000
SYMMETRIC = True
"""Store ``A`` as ``MPISBAIJ`` (the upper block triangle: one 6 x 6 block per contact) rather than
``MPIBAIJ`` (two): half the matrix memory, the dominant term per contact."""
CHUNK = 1 << 13
"""Contacts per assembly chunk: the element blocks of one chunk and their temporaries (about 3 kB
per contact, 25 MiB a chunk) are bounded by it."""
FLUSH = 16
"""Chunks between two flushes of PETSc's stash (the blocks of rows owned elsewhere): a collective
step, so not after every chunk."""
@dataclass
class RankShare:
    """What one rank holds after ``distribute``: its rows ``lo..hi-1`` of ``n`` particles (in the
    solve's numbering: Morton order for sphere packings), a local packing of its own particles and
    their contact partners (local particle ``k`` is particle ``glob[k]`` of that numbering), its
    contacts in local numbering with their stiffness, the preallocation of its block rows (``d_nnz``,
    ``o_nnz``), and the stage times [s] and peak memory [MiB] so far.

    Parameters
    ----------
    n : int
        Number of particles of the whole packing.
    lo, hi : int
        This rank's rows (particles ``lo <= p < hi``).
    packing : Packing or None
        Local packing: own particles and their contact partners (``None`` once assembled).
    glob : numpy.ndarray
        Global index of each local particle.
    contacts : Contacts or None
        This rank's contacts in local numbering, with stiffness (``None`` once assembled).
    d_nnz, o_nnz : numpy.ndarray
        Blocks per own row in the diagonal and off-diagonal parts (PETSc preallocation).
    label : str
        The packing's label.
    law : str
        Description of the contact law.
    times : dict
        Stage times so far [s].
    peaks : dict
        Peak memory after each stage [MiB].
    """

    n: int
    lo: int
    hi: int
    packing: Packing | None
    glob: np.ndarray
    contacts: Contacts | None
    d_nnz: np.ndarray
    o_nnz: np.ndarray
    label: str
    law: str
    times: dict = field(default_factory=dict)
    peaks: dict = field(default_factory=dict)


def _local(packing: Packing, slab: SlabContacts, order) -> tuple[Packing, np.ndarray, Contacts]:
    c = slab.contacts
    glob = np.unique(np.concatenate([np.arange(slab.lo, slab.hi), c.i, c.j]))
    source = glob if order is None else order[glob]

    def pick(values: np.ndarray) -> np.ndarray:
        return values[source]

    local = Packing(pick(packing.positions), pick(packing.masses), pick(packing.inertia), pick(packing.radii),
                    box=packing.box, orientations=None if packing.orientations is None else pick(packing.orientations),
                    label=packing.label)
    return local, glob, replace(c, i=np.searchsorted(glob, c.i), j=np.searchsorted(glob, c.j))


def distribute(packing: Packing, law=None, contacts: Contacts | None = None, *, t_input: float = 0.0) -> RankShare:
    """The share of the problem on this rank (module docstring, steps 1-3 before the matrix).

    ``law`` sets each contact's stiffness unless ``contacts`` already carry one (as
    ``report.analyse``).  Collective: every rank of ``COMM_WORLD`` calls it with the same packing.

    Parameters
    ----------
    packing : Packing
        The whole packing (the same on every rank).
    law : object or None
        Contact law (``model.LinearLaw``, ``model.HertzMindlinLaw``); default linear unit springs.
    contacts : Contacts or None
        A contact list every rank holds (default: found here).
    t_input : float
        Seconds spent reading the input, recorded in the times.

    Returns
    -------
    RankShare
        This rank's share.
    """
    _, rank, size = world()
    start = time.perf_counter()
    peaks = {"input": peak_mib()}
    error, share = None, None
    try:
        if packing.n < size:
            raise InputError("packing", f"{packing.n} particles cannot be shared by {size} ranks (fewer ranks, please)")
        check_dofs(packing.n)
        lo, hi = split_rows(packing.n, size, rank)
        order = None
        sheared = packing.box is not None and packing.box.cell is not None  # searched whole, in periodic_cell
        if contacts is None and packing.is_spheres and not sheared:
            order = morton_order(wrap_positions(packing.positions, packing.box))
            slab = slab_sphere_contacts(packing, lo, hi, order=order)
        else:
            slab = slab_of_list(find_contacts(packing) if contacts is None else contacts, packing.n, lo, hi, rank, size)
        c = slab.contacts
        if c.kn is None or law is not None:
            from dtcrit.packing.model import LinearLaw

            law = LinearLaw(1.0, 1.0) if law is None else law
            c, law_text = apply_law(c, law), law.describe()
        else:
            law_text = "per-contact stiffness given"
        rows, cols = slab.pattern_rows, slab.pattern_cols
        if SYMMETRIC:  # SBAIJ stores the blocks right of the diagonal (and the diagonal blocks)
            rows, cols = rows[cols > rows], cols[cols > rows]
        own = (cols >= lo) & (cols < hi)
        d_nnz = 1 + np.bincount(rows[own] - lo, minlength=hi - lo)
        o_nnz = np.bincount(rows[~own] - lo, minlength=hi - lo)
        local, glob, local_contacts = _local(packing, SlabContacts(lo, hi, c, slab.pattern_rows, slab.pattern_cols),
                                             order)
        share = RankShare(packing.n, lo, hi, local, glob, local_contacts, d_nnz.astype(np.int32),
                          o_nnz.astype(np.int32), packing.label, law_text)
    except ValueError as exc:
        error = exc
    agree(error)
    if share is None:  # agree raised on every rank if any failed
        raise RuntimeError("distribute: no share although every rank succeeded")
    del slab, c, order  # (the caller holds the input packing)
    release_memory()
    share.times = {"input": t_input, "contacts": time.perf_counter() - start}
    share.peaks = dict(peaks, contacts=peak_mib())
    return share


def _held(share: RankShare) -> tuple[Packing, Contacts]:
    """The share's local packing and contacts (dropped once the matrix holds them)."""
    if share.packing is None or share.contacts is None:
        raise RuntimeError("this share's packing and contacts were dropped after its assembly")
    return share.packing, share.contacts


def assemble(share: RankShare):
    """The PETSc matrix ``A`` (``MPISBAIJ``, or ``MPIBAIJ`` without ``SYMMETRIC``; block size 6) from
    every rank's share (collective).

    Parameters
    ----------
    share : RankShare
        This rank's share (``distribute``).

    Returns
    -------
    petsc4py.PETSc.Mat
        ``A = M^(-1/2) K M^(-1/2)`` [1/s^2], distributed by block rows.
    """
    PETSc, _ = petsc()
    comm, _, _ = world()
    rows_local = 6 * (share.hi - share.lo)
    create = PETSc.Mat().createSBAIJ if SYMMETRIC else PETSc.Mat().createBAIJ
    mat = create(((rows_local, 6 * share.n), (rows_local, 6 * share.n)), 6, nnz=(share.d_nnz, share.o_nnz), comm=comm)
    mat.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, True)
    if SYMMETRIC:
        mat.setOption(PETSc.Mat.Option.IGNORE_LOWER_TRIANGULAR, True)
    if mat.getOwnershipRange() != (6 * share.lo, 6 * share.hi):
        raise RuntimeError(f"PETSc owns rows {mat.getOwnershipRange()}, expected {(6 * share.lo, 6 * share.hi)}")
    packing, c = _held(share)
    s = (1.0 / np.sqrt(mass_diagonal(packing))).reshape(-1, 6)
    chunks = int(allgather([math.ceil(c.count / CHUNK)]).max())
    add = PETSc.InsertMode.ADD_VALUES
    for k in range(chunks):
        sl = slice(k * CHUNK, min((k + 1) * CHUNK, c.count))
        if sl.start < c.count:
            k_ii, k_jj, k_ij = contact_blocks(packing, c, sl, "stiffness")
            si, sj = s[c.i[sl]], s[c.j[sl]]
            values = np.empty((len(si), 12, 12))
            values[:, :6, :6] = k_ii * si[:, :, None] * si[:, None, :]
            values[:, :6, 6:] = k_ij * si[:, :, None] * sj[:, None, :]
            values[:, 6:, :6] = np.swapaxes(k_ij, 1, 2) * sj[:, :, None] * si[:, None, :]
            values[:, 6:, 6:] = k_jj * sj[:, :, None] * sj[:, None, :]
            idx = np.ascontiguousarray(np.stack([share.glob[c.i[sl]], share.glob[c.j[sl]]], axis=1),
                                       dtype=PETSc.IntType)
            mat.setValuesBlockedRCV(idx, idx, values.reshape(len(si), 144), addv=add)
        if k % FLUSH == FLUSH - 1:
            mat.assemble(PETSc.Mat.AssemblyType.FLUSH_ASSEMBLY)
    mat.assemble()
    return mat


def solve(mat, tolerance: float = TOLERANCE, ncv: int = NCV, *, norm: bool = True, start=None) -> dict:
    """The top eigenpair of ``mat`` by Krylov-Schur (collective): ``theta``, ``residual``, ``iterations``
    (restarts), ``matvecs``, ``rotational_fraction``, ``norm_inf`` (``|A|_inf``), ``matvec_time`` (this
    rank's seconds in MatMult), and the ``tolerance`` and ``ncv`` used (PETSC_OPTIONS may set them).

    Parameters
    ----------
    mat : petsc4py.PETSc.Mat
        The symmetric matrix ``A``.
    tolerance : float
        Relative residual tolerance.
    ncv : int
        Krylov subspace size.
    norm : bool
        Compute ``|A|_inf`` (a stored matrix; a shell matrix has none: ``norm_inf`` is then ``nan``).
    start : callable or None
        ``start(mat)`` returns the initial vector (``slepc_start.chebyshev_start``; its products
        are counted); default SLEPc's random one.

    Returns
    -------
    dict
        The figures listed above.
    """
    PETSc, SLEPc = petsc()
    PETSc.Log.begin()
    matmult = PETSc.Log.Event("MatMult")
    before = matmult.getPerfInfo()
    initial = start(mat) if start is not None else None
    eps = SLEPc.EPS().create(comm=mat.getComm())
    eps.setOperators(mat)
    eps.setType(SLEPc.EPS.Type.KRYLOVSCHUR)
    eps.setProblemType(SLEPc.EPS.ProblemType.HEP)
    eps.setWhichEigenpairs(SLEPc.EPS.Which.LARGEST_REAL)
    eps.setDimensions(nev=1, ncv=min(ncv, mat.getSize()[0]))
    eps.setTolerances(tolerance, MAX_RESTARTS)
    eps.setFromOptions()  # PETSC_OPTIONS="-eps_ncv 24 -eps_tol 1e-11 ..." overrides these settings
    if initial is not None:
        eps.setInitialSpace([initial])
    eps.solve()
    after = matmult.getPerfInfo()
    tolerance, _ = eps.getTolerances()
    if eps.getConverged() < 1:
        raise InputError("slepc", f"Krylov-Schur did not converge to a relative residual {tolerance:g} in "
                                  f"{eps.getIterationNumber()} restarts")
    vec = mat.createVecRight()
    theta = eps.getEigenpair(0, vec).real
    vec.normalize()
    v2 = vec.getArray().reshape(-1, 6) ** 2
    energy = allgather([v2[:, 3:].sum(), v2.sum()]).sum(axis=0)
    out = {"theta": theta, "residual": eps.computeError(0, SLEPc.EPS.ErrorType.ABSOLUTE),
           "iterations": eps.getIterationNumber(), "matvecs": int(after["count"] - before["count"]),
           "rotational_fraction": energy[0] / energy[1] if energy[1] > 0 else 0.0,
           "norm_inf": mat.norm(PETSc.NormType.INFINITY) if norm else math.nan, "matvec_time": after["time"] - before["time"],
           "tolerance": tolerance, "ncv": eps.getDimensions()[1]}
    eps.destroy()
    vec.destroy()
    if initial is not None:
        initial.destroy()
    return out


def _local_figures(share: RankShare) -> tuple[int, float, float]:
    """``(contacts, K_max, m_min)`` of this rank: its contact count, largest ``max(k_n, k_s)``, and the
    smallest mass among the particles its contacts with a stiffness touch.
    """
    packing, c = _held(share)
    if c.kn is None or c.ks is None:
        raise InputError("contacts", "no stiffness: apply a contact law first (model.apply_law)")
    stiff = np.maximum(c.kn, c.ks)
    touched = np.unique(np.concatenate([c.i[stiff > 0], c.j[stiff > 0]]))
    return c.count, float(stiff.max(initial=0.0)), float(packing.masses[touched].min(initial=math.inf))
