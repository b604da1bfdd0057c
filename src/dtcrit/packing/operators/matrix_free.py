"""Matrix-free mass-scaled stiffness and damping operators: ``A v`` straight from the contact list.

``A = M^(-1/2) K M^(-1/2)`` (or ``M^(-1/2) C M^(-1/2)``) is applied without forming ``K``: for each
contact ``c`` between ``i`` and ``j`` (the element of ``dtcrit.packing.operators.contact_element``), with ``q = M^(-1/2) v`` split into translations ``u`` and body rotations ``t``
(global rotation ``theta = R t``),

    delta = u_j - u_i + a_i x theta_i - a_j x theta_j        (= B_i q_i + B_j q_j)
    f     = K_c delta = k_n (n . delta) n + k_s (delta - (n . delta) n)
    K q  += B_i^T f on i:  (-f, -R_i^T (a_i x f));   B_j^T f on j:  (f, R_j^T (a_j x f))

plus, when the contacts carry them, the rolling/twisting springs on ``w = theta_j - theta_i``
(moment ``m = k_tw (n . w) n + k_r (w - (n . w) n)``: ``-R_i^T m`` on i, ``R_j^T m`` on j) and the
pre-load geometric term on the centre displacement ``d = u_j - u_i`` (force
``p = -(F/r)(d - (n . d) n)``: ``-p`` on i, ``p`` on j).  A contact with its own periodic image
(``i == j``) scatters both sides onto the same particle, which is ``(B_i + B_j)^T K_c (B_i + B_j)``,
as assembled.  The dashpot operator ``C`` uses ``c_n, c_s`` (``c_r, c_tw``) in place of the springs
and has no pre-load term.

The product is one compiled loop over the contacts (``matrix_free_kernels``, Numba) or, without Numba,
vectorised NumPy in chunks scattered with ``numpy.add.at``; both evaluate ``contact_element.body_forces``.
Memory beyond the contact arrays is O(N) for the vectors plus one per-contact pre-load coefficient.

A second kind of pass (``particle_pass``, gathered by particle on Numba's threads) gives what the
rigorous bounds need without assembling: per particle the top eigenvalue of its 6 x 6 diagonal block
``A_pp``, the diagonal and the Gershgorin row sums ``sum_q |A_pq| w_q`` (``block_summary``, used by
``abs_row_sums`` and ``diagonal``: each contact's coupling block counted on its own, which equals the
assembled row sum unless two particles touch through several periodic images, where it is larger,
still a valid bound), and the blocks themselves of all or some particles (``diagonal_blocks``).
"""
from __future__ import annotations

import numpy as np
import scipy.sparse.linalg as spla

from dtcrit.errors import InputError
import dtcrit.packing.operators.matrix_free_kernels as kernels
import dtcrit.packing.operators.particle_pass as particle_pass
import dtcrit.packing.operators.scattered_pass as scattered_pass
from dtcrit.packing.operators.assembly import mass_diagonal, preload_coefficient
from dtcrit.packing.operators.combined import CombinedOperator
from dtcrit.packing.model import Contacts, Packing
from dtcrit.packing.normal_arms import lengths_along
from dtcrit.packing.uniform_values import held, held_bytes

CHUNK = 1 << 16  # contacts per vectorised chunk (measured: larger chunks gain nothing, cost memory)
KINDS = ("stiffness", "damping")
PARALLEL_MIN_CONTACTS = 1 << 20
"""Contacts from which the compiled product runs on blocks of contacts, one thread each
(``matrix_free_kernels.apply_blocks_*``, about 175,000 spheres): below it a product takes a few
milliseconds and is one block."""
PRODUCT_BLOCKS = 2
"""Blocks of a product by default, whatever the machine's cores, so that its bits are the same on
every machine (each block beyond the first holds one more (N, 6) vector)."""
SPHERE_LOOP_MAX_DOFS = 20_000_000
"""Above this the sphere loop (10 % less time a product at 1e6) runs only on contacts that hold their
arms as lengths (``normal_arms``); lengths projected from arm vectors would add 1 GB at 6e7 contacts."""


class ContactOperator(spla.LinearOperator):
    """``A = M^(-1/2) K M^(-1/2)`` (``kind="stiffness"``) or ``M^(-1/2) C M^(-1/2)`` (``"damping"``) of
    a packing as a symmetric ``scipy.sparse.linalg.LinearOperator`` (module docstring).

    ``mass_diag`` defaults to the packing's mass diagonal; ``ones`` gives ``K`` (``C``) itself.
    ``scale`` multiplies the operator (``damped`` combines two of them with ``combined``).
    ``applications`` counts the operator applications (one per vector).  ``compiled`` (default: when
    Numba is installed) runs the loops of ``operator_kernels``; ``False`` the vectorised NumPy path.

    Parameters
    ----------
    packing : Packing
        The bodies.
    contacts : Contacts
        The contacts with springs (``"stiffness"``) or dashpots (``"damping"``).
    kind : str
        ``"stiffness"`` or ``"damping"``.
    mass_diag : numpy.ndarray or None
        Diagonal of ``M`` (6N); default the packing's.
    chunk : int
        Contacts per chunk of the NumPy path and of the bounds' pass.
    compiled : bool or None
        Use the Numba loops (default: when Numba is installed).
    threads : int or None
        Blocks of contacts of the compiled product, one thread each (default ``PRODUCT_BLOCKS``; one
        below ``PARALLEL_MIN_CONTACTS`` contacts).  Each block is summed on its own and the blocks
        are added in order, so the product depends on this count only, not on the machine.
    """

    def __init__(self, packing: Packing, contacts: Contacts, kind: str = "stiffness", *,
                 mass_diag: np.ndarray | None = None, chunk: int = CHUNK, compiled: bool | None = None,
                 threads: int | None = None):
        if kind not in KINDS:
            raise InputError("kind", f"unknown operator kind {kind!r}; choose one of {', '.join(KINDS)}")
        if kind == "stiffness" and (contacts.kn is None or contacts.ks is None):
            raise InputError("contacts", "no stiffness: apply a contact law first (model.apply_law)")
        n = packing.n
        super().__init__(dtype=np.dtype(float), shape=(6 * n, 6 * n))
        self.packing, self.contacts, self.kind, self.chunk = packing, contacts, kind, int(chunk)
        md = mass_diagonal(packing) if mass_diag is None else np.asarray(mass_diag, float)
        self._given_mass = None if mass_diag is None else md  # the packing's own is not held (mass_diag)
        self.scale6 = (1.0 / np.sqrt(md)).reshape(n, 6)
        del md
        self.applications = 0
        if kind == "stiffness":
            self.along, self.across = contacts.kn, contacts.ks
            self.twist, self.roll = contacts.ktw, contacts.kr
        else:
            self.along, self.across = contacts.cn, contacts.cs
            self.twist, self.roll = contacts.ctw, contacts.cr
        self.translational = self.along is not None or self.across is not None
        self.rotational = self.twist is not None or self.roll is not None
        self.preload = None
        if kind == "stiffness":
            self.preload = preload_coefficient(packing, contacts)
        self.orientations = packing.orientations
        self.compiled = kernels.available() if compiled is None else bool(compiled)
        if self.compiled and not kernels.available():
            raise InputError("compiled", "the compiled operator needs Numba (pip install numba)")
        if self.compiled:
            self._kernel_args = self._pack_kernel_args()
            self._sphere_args = self._pack_sphere_args()
        wanted = PRODUCT_BLOCKS if threads is None else max(int(threads), 1)
        blocks = wanted if contacts.count >= PARALLEL_MIN_CONTACTS or threads is not None else 1
        self._bounds = kernels.block_bounds(contacts.count, blocks) if blocks > 1 else None
        self._halves = (kernels.halves_of(self._kernel_args[0], self._kernel_args[1])
                        if self.compiled and blocks == 2 else None)
        self._spare: np.ndarray | None = None

    @property
    def mass_diag(self) -> np.ndarray:
        """Diagonal of ``M`` (6N): the one given, else the packing's (``assembly.mass_diagonal``) computed
        on each call, so that the operator holds only its scale (one 6N vector less: 0.5 GB at 1e7
        particles, during the eigen-solve).

        Returns
        -------
        numpy.ndarray
            ``M_dd``, length 6N.
        """
        return self._given_mass if self._given_mass is not None else mass_diagonal(self.packing)

    def _pack_kernel_args(self):
        """Contiguous arrays for the compiled loops (no copy where the contacts already are)."""
        return kernels.loop_arguments(self.contacts, self.along, self.across, self.twist, self.roll, self.preload,
                                      self.orientations)

    def _pack_sphere_args(self):
        """Arguments of ``operator_kernels.apply_sphere_contacts`` when every contact is a sphere
        contact (arms along the normal: ``a_i = l_i n``, ``a_j = -l_j n`` to 4 ulps), with springs
        (and pre-load) only and no body rotations; otherwise ``None`` (the general loop).
        """
        c = self.contacts
        if (not self.translational or self.rotational or self.orientations is not None or c.count == 0
                or self.along is None or self.across is None
                or (self.shape[0] > SPHERE_LOOP_MAX_DOFS and lengths_along(c.arm_i, c.arm_j, c.normal) is None)):
            return None
        lengths = kernels.sphere_arm_lengths(c.normal, c.arm_i, c.arm_j, self.chunk)
        if lengths is None:
            return None
        li, lj = lengths
        pre = self.preload is not None
        c_args = self._kernel_args
        return (c_args[0], c_args[1], c_args[2], li, lj, c_args[5], c_args[6],
                c_args[9] if pre else np.zeros(0), pre)

    # -- the product -------------------------------------------------------------------------------
    def apply_into(self, x: np.ndarray, out: np.ndarray) -> np.ndarray:
        """``out = A x`` into a given (6N,) array, with no array allocated on the compiled path (at 1e6
        particles a fresh vector adds a sixth to the product's time: ``largest_mode`` calls this), nor
        held beyond ``out`` when the halves apply (the loop scales ``x`` as it reads it).

        Parameters
        ----------
        x : numpy.ndarray
            The vector, length 6N.
        out : numpy.ndarray
            Where to write ``A x``, length 6N, not overlapping ``x``.

        Returns
        -------
        numpy.ndarray
            ``out``.

        Raises
        ------
        ValueError
            When ``out`` overlaps ``x``.
        """
        if not self.compiled:
            out[:] = self._matvec(x)
            return out
        x = np.asarray(x, float)
        if np.may_share_memory(x, out):
            raise ValueError("apply_into: out must not overlap x (the loop reads x while it writes out)")
        self.applications += 1
        y = out.reshape(-1, 6)
        y[:] = 0.0
        self._compiled_product(x.reshape(-1, 6), y)  # the loop scales x as it reads it
        y *= self.scale6
        return out

    def _matvec(self, x):
        if self.compiled:
            return self.apply_into(x, np.empty(self.shape[0]))
        self.applications += 1
        q = np.asarray(x, float).reshape(-1, 6) * self.scale6
        y = np.zeros_like(q)
        nc = self.contacts.count
        for start in range(0, nc, self.chunk):
            sl = slice(start, min(start + self.chunk, nc))
            oi, oj = scattered_pass.chunk_forces(self, q, sl)
            scattered_pass.scatter_rows(y, self.contacts.i[sl], oi)
            scattered_pass.scatter_rows(y, self.contacts.j[sl], oj)
        y *= self.scale6
        return y.reshape(-1)

    def _compiled_product(self, x: np.ndarray, y: np.ndarray) -> None:
        """``y += K (s x)`` (``s`` the scale, unscaled out) by the compiled loop: the sphere loop when it
        applies; on two threads by the particles' halves (``kernels.halves_of``, no spare vector) or
        by blocks of contacts (one thread and one spare (N, 6) vector each beyond the first).
        """
        spheres = self._sphere_args is not None
        args = self._sphere_args if spheres else self._kernel_args
        s = self.scale6
        if self._bounds is None:
            (kernels.apply_spheres_span if spheres else kernels.apply_span)(x, s, y, 0, self.contacts.count,
                                                                            kernels.NO_LIMIT, *args)
        elif self._halves is not None:
            (kernels.apply_halves_spheres if spheres else kernels.apply_halves_general)(x, s, y, *self._halves, *args)
        else:
            if self._spare is None:
                self._spare = np.empty((len(self._bounds) - 2, *x.shape))
            (kernels.apply_blocks_spheres if spheres else kernels.apply_blocks_general)(x, s, y, self._spare,
                                                                                        self._bounds, *args)

    def _matmat(self, xs):
        xs = np.asarray(xs, float)
        return np.column_stack([self._matvec(xs[:, k]) for k in range(xs.shape[1])])

    def _adjoint(self):
        return self

    # -- what the bounds need (``particle_pass``) ---------------------------------------------------
    def block_summary(self) -> particle_pass.BlockSummary:
        """Per particle the top eigenvalue of ``A_pp``, the diagonal of ``A`` and ``|A| w`` for ``w = 1``
        and ``w = sqrt(m)`` (``particle_pass``, module docstring), computed once and kept (O(N) only).

        Returns
        -------
        particle_pass.BlockSummary
            ``top`` (N,), ``diagonal``, ``rows_ones``, ``rows_root`` (6N,).
        """
        if getattr(self, "_summary", None) is None:
            if self.compiled:
                self._summary = particle_pass.summary(self._kernel_args, self.scale6, self.mass_diag.reshape(-1, 6))
            else:
                blocks, (r1, r2) = scattered_pass.scattered_blocks(self, [np.ones(self.shape[0]),
                                                                         np.sqrt(self.mass_diag)])
                self._summary = particle_pass.BlockSummary(scattered_pass.top_eigenvalues(blocks),
                                                           np.einsum("nii->ni", blocks).reshape(-1), r1, r2)
        return self._summary

    def diagonal_blocks(self, particles: np.ndarray | None = None) -> np.ndarray:
        """The 6 x 6 diagonal blocks ``A_pp`` of the scaled operator (computed on each call, not kept).

        Parameters
        ----------
        particles : numpy.ndarray or None
            Distinct particle indices (the rows follow their order); ``None``: every particle.

        Returns
        -------
        numpy.ndarray
            ``A_pp`` per particle, (N, 6, 6) or (len(particles), 6, 6).
        """
        if self.compiled:
            return particle_pass.blocks(self._kernel_args, self.scale6, particles)
        blocks = scattered_pass.scattered_blocks(self, [])[0]
        return blocks if particles is None else blocks[np.asarray(particles, dtype=np.int64)]

    def abs_row_sums(self, weights: np.ndarray | None = None) -> np.ndarray:
        """``|A| w`` (``w`` = ones by default; rows of ``M^-1 K`` need ``w = sqrt(m)``, see
        ``estimates.gershgorin``): both from ``block_summary``, other weights by a pass of their own.

        Parameters
        ----------
        weights : numpy.ndarray or None
            ``w`` (length 6N); ``None``: ones.

        Returns
        -------
        numpy.ndarray
            ``sum_q |A_pq| w_q`` per row, length 6N.
        """
        w = None if weights is None else np.asarray(weights, float).reshape(-1)
        if w is not None and w.size != self.shape[0]:
            raise ValueError(f"abs_row_sums: {w.size} weights for an operator of {self.shape[0]} rows")
        if w is None or particle_pass.equals(w, np.ones_like):
            return self.block_summary().rows_ones
        if particle_pass.equals(w, np.sqrt, self.mass_diag):
            return self.block_summary().rows_root
        if self.compiled:
            return particle_pass.summary(self._kernel_args, self.scale6, w.reshape(-1, 6), root=False).rows_root
        return scattered_pass.scattered_blocks(self, [w])[1][0]

    def assembled(self):
        """The same operator assembled (``scipy.sparse`` BSR, ``dtcrit.packing.operators.assembly``): for the
        certificate's factorisation and for tests.

        Returns
        -------
        scipy.sparse.bsr_matrix
            ``M^(-1/2) K M^(-1/2)`` (or ``C``) assembled.
        """
        from dtcrit.packing.operators.assembly import damping_matrix, scale_symmetric, stiffness_matrix

        build = stiffness_matrix if self.kind == "stiffness" else damping_matrix
        return scale_symmetric(build(self.packing, self.contacts), self.mass_diag, inplace=True)

    def diagonal(self) -> np.ndarray:
        """The diagonal of ``A`` (the diagonal blocks' diagonals, ``block_summary``).

        Returns
        -------
        numpy.ndarray
            ``A_dd``, length 6N.
        """
        return self.block_summary().diagonal

    @property
    def is_zero(self) -> bool:
        """No contact carries a non-zero coefficient of this kind (a zero operator)."""
        coeffs = [a for a in (self.along, self.across, self.twist, self.roll, self.preload) if a is not None]
        return self.contacts.count == 0 or not any(np.any(held(a) != 0) for a in coeffs)

    def memory_bytes(self) -> int:
        """Bytes of the contact arrays one application reads (the bandwidth floor's pass).

        Returns
        -------
        int
            Bytes read per product from the contact arrays.
        """
        c = self.contacts
        arrays: list = [c.i, c.j, c.normal]  # (NormalArms count their lengths)
        if getattr(self, "_sphere_args", None) is not None:
            return int(sum(held_bytes(a) for a in arrays + list(self._sphere_args[3:8])))
        if self.translational:
            arrays += [c.arm_i, c.arm_j] + [a for a in (self.along, self.across) if a is not None]
        if self.rotational:
            arrays += [a for a in (self.twist, self.roll) if a is not None]
        if self.preload is not None:
            arrays.append(self.preload)
        return int(sum(held_bytes(a) for a in arrays))


def stiffness_operator(packing: Packing, contacts: Contacts, **kw) -> ContactOperator:
    """Matrix-free ``K~ = M^(-1/2) K M^(-1/2)``.

    Parameters
    ----------
    packing : Packing
        The bodies.
    contacts : Contacts
        The contacts.
    **kw
        Options of :class:`ContactOperator` (``mass_diag``, ``chunk``, ``compiled``).

    Returns
    -------
    ContactOperator
        ``M^(-1/2) K M^(-1/2)`` as a linear operator.
    """
    return ContactOperator(packing, contacts, "stiffness", **kw)


def damping_operator(packing: Packing, contacts: Contacts, **kw) -> ContactOperator:
    """Matrix-free ``C~ = M^(-1/2) C M^(-1/2)``.

    Parameters
    ----------
    packing : Packing
        The bodies.
    contacts : Contacts
        The contacts.
    **kw
        Options of :class:`ContactOperator` (``mass_diag``, ``chunk``, ``compiled``).

    Returns
    -------
    ContactOperator
        ``M^(-1/2) C M^(-1/2)`` as a linear operator.
    """
    return ContactOperator(packing, contacts, "damping", **kw)


__all__ = ["ContactOperator", "CombinedOperator", "stiffness_operator", "damping_operator", "CHUNK"]
