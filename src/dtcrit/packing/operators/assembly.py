"""Global mass and stiffness matrices of a packing as ``scipy.sparse`` matrices.

Degrees of freedom, six per particle ``p``: ``q_p = (u_x, u_y, u_z, t_1, t_2, t_3)``, the
translation of the centre in the global frame and a small rotation about the particle's principal
axes (global rotation ``R_p t``), so that the mass matrix is ``diag(m, m, m, I_1, I_2, I_3)``
(Otsubo et al. 2017, Section 3).

A contact between ``i`` and ``j`` with contact point ``x_c``, arms ``a_i = x_c - x_i`` and
``a_j = x_c - x_j`` and unit normal ``n`` moves the two material points at ``x_c`` apart by

    delta = (u_j + theta_j x a_j) - (u_i + theta_i x a_i) = B_i q_i + B_j q_j,
    B_i = [-1, [a_i]_x R_i],   B_j = [1, -[a_j]_x R_j]

(``[a]_x`` the cross-product matrix; Peng et al. 2020, Eqs (1)-(2), (17)-(19) linearised).  Its
springs store ``1/2 delta^T K_c delta`` with ``K_c = k_n n n^T + k_s (1 - n n^T)``, so the contact
adds the 12 x 12 element ``[B_i B_j]^T K_c [B_i B_j]`` to the global stiffness.

Further per-contact terms, when the contacts carry them (``dtcrit.packing.model.Contacts``):

* rolling and twisting springs act on the relative rotation ``theta_j - theta_i = R_j t_j - R_i t_i``
  with ``K_r = k_tw n n^T + k_r (1 - n n^T)`` (YADE's CohFrictPhys moment law, LAMMPS ``granular``
  rolling/twisting springs, linearised);
* the initial-stress (geometric) stiffness of a contact pre-loaded by the compressive normal force
  ``F``: the force turns with the centre line, ``dF_i/du_i = -k_n n n^T + (F/r)(1 - n n^T)``, i.e.
  ``-(F/r)(1 - n n^T)`` on the relative displacement of the two centres (``r`` their distance).
  Otsubo et al. neglect it (relative order ``F/(k_n r)``, about the overlap strain); it is included
  when ``force_n`` is given (a bond in tension, ``F < 0``, stiffens);
* dashpots (``cn``, ``cs``; rolling and twisting ``cr``, ``ctw``) give the damping matrix ``C`` with the
  same kinematics as the springs, ``[B_i B_j]^T C_c [B_i B_j]``, ``C_c = c_n n n^T + c_s (1 - n n^T)``
  (``damping_matrix``).
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sps

from dtcrit.errors import InputError

from tqdm import tqdm

from dtcrit.packing.model import Contacts, Packing
from dtcrit.packing.operators.element_matrices import element_blocks, frame_tensor, slip_jacobians
from dtcrit.packing.uniform_values import held

LONG_WORK = 200_000  # contacts below which the assembly takes well under a second: no bar drawn


def contact_stiffness_tensor(normal: np.ndarray, kn: np.ndarray, ks: np.ndarray) -> np.ndarray:
    """``K_c = k_n n n^T + k_s (1 - n n^T)`` for each contact (``contact_element.frame_tensor``).

    Parameters
    ----------
    normal : numpy.ndarray
        Unit normals, shape (nc, 3).
    kn, ks : numpy.ndarray
        Coefficients along and across the normal, shape (nc,) (springs [N/m] or their square roots).

    Returns
    -------
    numpy.ndarray
        ``K_c``, shape (nc, 3, 3).
    """
    return frame_tensor(normal, kn, ks)


def _rotations(packing: Packing, contacts: Contacts, sl) -> tuple[np.ndarray | None, np.ndarray | None]:
    """The rotation matrices of the two bodies of each contact ``sl``, or ``(None, None)`` for spheres."""
    if packing.orientations is None:
        return None, None
    return packing.orientations[contacts.i[sl]], packing.orientations[contacts.j[sl]]


def contact_kinematics(packing: Packing, contacts: Contacts, sl=slice(None)) -> tuple[np.ndarray, np.ndarray]:
    """``(B_i, B_j)``, each (nc, 3, 6): relative contact displacement per body DOF
    (``contact_element.slip_jacobians``, module docstring).

    Parameters
    ----------
    packing : Packing
        The bodies (orientations give the principal axes of their rotation DOFs).
    contacts : Contacts
        The contacts (arms from the centres to the contact points).
    sl : slice
        The contacts to take.

    Returns
    -------
    tuple of numpy.ndarray
        ``B_i = [-1 | [a_i]_x R_i]`` and ``B_j = [1 | -[a_j]_x R_j]``.
    """
    return slip_jacobians(contacts.arm_i[sl], contacts.arm_j[sl], *_rotations(packing, contacts, sl))


def mass_diagonal(packing: Packing) -> np.ndarray:
    """Diagonal of the global mass matrix, ``(m, m, m, I_1, I_2, I_3)`` per particle, length 6N.

    Parameters
    ----------
    packing : Packing
        The bodies (masses [kg], principal moments of inertia [kg m^2]).

    Returns
    -------
    numpy.ndarray
        Length 6N [kg, kg m^2].
    """
    m = packing.masses[:, None]
    return np.concatenate([np.repeat(m, 3, axis=1), packing.inertia], axis=1).reshape(-1)


def mass_matrix(packing: Packing) -> sps.dia_matrix:
    """Global mass matrix ``M`` (6N x 6N, diagonal) as a sparse matrix.

    Parameters
    ----------
    packing : Packing
        The bodies.

    Returns
    -------
    scipy.sparse.dia_matrix
        ``diag(m, m, m, I_1, I_2, I_3)`` per body.
    """
    d = mass_diagonal(packing)
    return sps.dia_matrix((d[None, :], [0]), shape=(d.size, d.size))


def _require_stiffness(contacts: Contacts) -> None:
    if contacts.kn is None or contacts.ks is None:
        raise InputError("contacts", "no stiffness: apply a contact law first (model.apply_law)")


def _centre_distance(packing: Packing, contacts: Contacts, sl) -> np.ndarray:
    d = packing.positions[contacts.j[sl]] - packing.positions[contacts.i[sl]]
    if packing.box is not None:
        d = d + packing.box.shift(contacts.image[sl])
    return np.linalg.norm(d, axis=1)


def preload_coefficient(packing: Packing, contacts: Contacts, sl=slice(None)) -> np.ndarray | None:
    """``F/r`` of the pre-load term of each contact ``sl`` (module docstring), or ``None`` when no
    contact there carries a normal force.

    Parameters
    ----------
    packing : Packing
        The bodies (centres and periodic box give the centre distance ``r`` [m]).
    contacts : Contacts
        The contacts (``force_n``, compressive positive [N]).
    sl : slice
        The contacts to take.

    Returns
    -------
    numpy.ndarray or None
        ``F/r`` [N/m] per contact.
    """
    if contacts.force_n is None or not np.any(held(contacts.force_n[sl]) != 0):
        return None
    return contacts.force_n[sl] / _centre_distance(packing, contacts, sl)


def contact_blocks(packing: Packing, contacts: Contacts, sl, kind: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The 6 x 6 blocks ``(ii, jj, ij)`` of each contact's element of ``K`` (``kind="stiffness"``)
    or ``C`` (``kind="damping"``) for the contacts ``sl`` (``contact_element.element_blocks``).

    Parameters
    ----------
    packing : Packing
        The bodies.
    contacts : Contacts
        The contacts with their springs (``kn``, ``ks``, ``kr``, ``ktw``, ``force_n``) or dashpots
        (``cn``, ``cs``, ``cr``, ``ctw``); an absent dashpot counts as zero.
    sl : slice
        The contacts to take.
    kind : str
        ``"stiffness"`` or ``"damping"`` (no pre-load term).

    Returns
    -------
    tuple of numpy.ndarray
        ``ii``, ``jj``, ``ij``, each (nc, 6, 6).
    """
    zero = np.zeros(contacts.i[sl].shape)
    preload = None
    if kind == "stiffness":
        if contacts.kn is None or contacts.ks is None:
            raise InputError("contacts", "no stiffness: apply a contact law first (model.apply_law)")
        along, across = contacts.kn[sl], contacts.ks[sl]
        twist, roll = contacts.ktw, contacts.kr
        preload = preload_coefficient(packing, contacts, sl)
    else:
        along = zero if contacts.cn is None else contacts.cn[sl]
        across = zero if contacts.cs is None else contacts.cs[sl]
        twist, roll = contacts.ctw, contacts.cr
    rot_i, rot_j = _rotations(packing, contacts, sl)
    return element_blocks(contacts.normal[sl], contacts.arm_i[sl], contacts.arm_j[sl], along, across,
                          rot_i=rot_i, rot_j=rot_j, twist=None if twist is None else twist[sl],
                          roll=None if roll is None else roll[sl], preload=preload)


def stiffness_matrix(packing: Packing, contacts: Contacts, *, chunk: int = 1 << 17,
                     label: str = "assembly") -> sps.bsr_matrix:
    """Global stiffness matrix ``K`` (6N x 6N, symmetric, 6 x 6 blocks) as ``scipy.sparse.bsr_matrix``.

    Sums the element matrices of the module docstring.  A contact with one's own periodic image
    (``i == j``) adds ``(B_i + B_j)^T K_c (B_i + B_j)`` to the particle's diagonal block.  Built in
    chunks of ``chunk`` contacts (a progress bar shows when the assembly is long).

    Parameters
    ----------
    packing : Packing
        The bodies.
    contacts : Contacts
        The contacts with their springs (a contact law applied).
    chunk : int
        Contacts per vectorised chunk.
    label : str
        Description of the progress bar.

    Returns
    -------
    scipy.sparse.bsr_matrix
        ``K`` [N/m, N, N m], 6N x 6N in 6 x 6 blocks, symmetric.
    """
    _require_stiffness(contacts)
    return _assemble(packing, contacts, "stiffness", chunk, label)


def damping_matrix(packing: Packing, contacts: Contacts, *, chunk: int = 1 << 17,
                   label: str = "damping assembly") -> sps.bsr_matrix:
    """Global damping matrix ``C`` of the contact dashpots ``cn``, ``cs`` (module docstring).

    Parameters
    ----------
    packing : Packing
        The bodies.
    contacts : Contacts
        The contacts with their dashpots.
    chunk : int
        Contacts per vectorised chunk.
    label : str
        Description of the progress bar.

    Returns
    -------
    scipy.sparse.bsr_matrix
        ``C`` [N s/m, N s, N m s], 6N x 6N in 6 x 6 blocks, symmetric.
    """
    return _assemble(packing, contacts, "damping", chunk, label)


def _assemble(packing: Packing, contacts: Contacts, kind: str, chunk: int, label: str) -> sps.bsr_matrix:
    # a coefficient near the float limit overflows here to inf: scale_symmetric refuses it in one line
    with np.errstate(over="ignore", invalid="ignore"):
        return _assemble_blocks(packing, contacts, kind, chunk, label)


def _assemble_blocks(packing: Packing, contacts: Contacts, kind: str, chunk: int, label: str) -> sps.bsr_matrix:
    n = packing.n
    nc = contacts.count
    diag = np.zeros((n, 6, 6))
    upper = np.empty((nc, 6, 6))
    starts = range(0, nc, chunk)
    for start in tqdm(starts, desc=label, disable=None if nc >= LONG_WORK else True, leave=False):
        sl = slice(start, min(start + chunk, nc))
        k_ii, k_jj, k_ij = contact_blocks(packing, contacts, sl, kind)
        ci, cj = contacts.i[sl], contacts.j[sl]
        self_contact = ci == cj
        if self_contact.any():  # coupling blocks of a self-image contact land on the diagonal
            k_ii = k_ii.copy()
            k_ii[self_contact] += k_ij[self_contact] + np.swapaxes(k_ij[self_contact], 1, 2)
            k_ij[self_contact] = 0.0
        flat_ii = k_ii.reshape(-1, 36)
        flat_jj = k_jj.reshape(-1, 36)
        for e in range(36):
            diag.reshape(n, 36)[:, e] += np.bincount(ci, weights=flat_ii[:, e], minlength=n)
            diag.reshape(n, 36)[:, e] += np.bincount(cj, weights=flat_jj[:, e], minlength=n)
        upper[sl] = k_ij
    # off-diagonal blocks: orient each as (row < col), merge repeated pairs, then mirror
    off = contacts.i != contacts.j
    ci, cj = contacts.i[off], contacts.j[off]
    swap = ci > cj
    rows = np.where(swap, cj, ci).astype(np.int64)
    cols = np.where(swap, ci, cj).astype(np.int64)
    key = rows * n + cols
    order = np.argsort(key, kind="stable")
    key = key[order]
    blocks = upper[np.flatnonzero(off)[order]] if not off.all() else upper[order]
    del upper
    flip = swap[order]
    if flip.any():
        blocks[flip] = np.swapaxes(blocks[flip], 1, 2)
    if key.size and np.any(key[1:] == key[:-1]):
        first = np.concatenate([[True], key[1:] != key[:-1]])
        blocks = np.add.reduceat(blocks, np.flatnonzero(first), axis=0)
        key = key[first]
    rows, cols = key // n, key % n
    nb = key.size
    # place diagonal, upper and mirrored lower blocks straight into row-major (BSR) order
    all_rows = np.concatenate([np.arange(n), rows, cols])
    all_cols = np.concatenate([np.arange(n), cols, rows])
    dest = np.empty(n + 2 * nb, dtype=np.int64)
    dest[np.lexsort((all_cols, all_rows))] = np.arange(n + 2 * nb)
    data = np.empty((n + 2 * nb, 6, 6))
    data[dest[:n]] = diag
    del diag
    data[dest[n:n + nb]] = blocks
    data[dest[n + nb:]] = np.swapaxes(blocks, 1, 2)
    del blocks
    indices = np.empty(n + 2 * nb, dtype=np.int32 if n < 2**31 else np.int64)
    indices[dest] = all_cols
    indptr = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.bincount(all_rows, minlength=n), out=indptr[1:])
    return sps.bsr_matrix((data, indices, indptr), shape=(6 * n, 6 * n))


MAX_SCALED_ENTRY = 1e150
"""Largest entry of ``M^(-1/2) K M^(-1/2)`` (or ``C``) accepted: the eigen-solvers form squared norms
of its products, which overflow above about ``1e154`` (no physical packing comes near: ``omega`` would
exceed ``1e75`` rad/s)."""


def scale_symmetric(k: sps.bsr_matrix, mass_diag: np.ndarray, *, inplace: bool = False,
                    key: str = "stiffness") -> sps.bsr_matrix:
    """``A = M^(-1/2) K M^(-1/2)``: the symmetric standard form of ``K phi = omega^2 M phi``.
    InputError (``key``: ``"stiffness"``, or ``"damping"`` for ``C``) when an entry of ``A`` leaves
    the floating-point range (a huge stiffness over a tiny mass: ``omega^2`` would be inf).

    Parameters
    ----------
    k : scipy.sparse.bsr_matrix
        ``K`` (or ``C``) in 6 x 6 blocks.
    mass_diag : numpy.ndarray
        Diagonal of ``M`` (length 6N).
    inplace : bool
        Scale ``k``'s data in place instead of a copy.
    key : str
        Input key named in the error (``"stiffness"`` or ``"damping"``).

    Returns
    -------
    scipy.sparse.bsr_matrix
        ``M^(-1/2) K M^(-1/2)`` [1/s^2] (``1/s`` for ``C``).
    """
    s = 1.0 / np.sqrt(mass_diag)
    a = k if inplace else k.copy()
    nb = a.indptr.size - 1
    block_rows = np.repeat(np.arange(nb), np.diff(a.indptr))
    srow = s.reshape(-1, 6)[block_rows]
    scol = s.reshape(-1, 6)[a.indices]
    with np.errstate(over="ignore", invalid="ignore"):
        a.data *= srow[:, :, None]
        a.data *= scol[:, None, :]
    largest = float(np.max(np.abs(a.data), initial=0.0)) if a.data.size else 0.0
    if not (np.all(np.isfinite(a.data)) and largest <= MAX_SCALED_ENTRY):
        name = "C" if key == "damping" else "K"
        unit = "1/s" if name == "C" else "1/s^2"
        raise InputError(key, f"an entry of M^-1/2 {name} M^-1/2 is {largest:.3g} {unit}, above "
                              f"{MAX_SCALED_ENTRY:.0e}: the coefficient over the particle mass is out of the range "
                              "the eigen-solvers can square in floating point")
    return a
