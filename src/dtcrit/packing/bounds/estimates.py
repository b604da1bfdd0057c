"""Cheap estimates and rigorous bounds on a packing's critical time step, side by side.

All act on the mass-scaled stiffness ``A = M^(-1/2) K M^(-1/2)`` (``omega^2`` are its eigenvalues)
and are stated for the undamped central-difference family, ``dt = 2 / omega``.

* ``gershgorin`` -- ``lambda_max(A) <= max_i sum_j |A_ij|`` (Gershgorin's circle theorem); the
  similar matrix ``M^-1 K`` gives a second valid row-sum bound and the smaller one is used.  A
  rigorous *lower* bound on the critical step.
* ``diagonal`` -- the per-body diagonal-stiffness estimate of YADE's GlobalStiffnessTimeStepper
  and PFC: every DOF alone on its summed contact stiffness ``K_dd``, ``dt = sqrt(2) sqrt(M_dd/K_dd)``
  minimised over DOFs (the ``sqrt(2)`` allows for neighbours moving in opposition), i.e.
  ``omega^2 = 2 max_d A_dd``.  No safety factor.  Not a bound either way.
* ``block_diagonal`` -- the same per-body idea made rigorous: each body's full 6 x 6 block
  ``A_pp`` (translation-rotation coupling and off-axis terms kept), ``omega^2 = 2 max_p
  lambda_max(A_pp)``.  Proof that it bounds ``omega_max^2`` from above: each contact's element
  ``A_e`` is positive semi-definite with body blocks ``[[X, Y], [Y^T, Z]]``; flipping the sign of
  one body's DOFs keeps it so, and adding the two gives ``A_e <= 2 diag(X, Z)``; summed over the
  contacts, ``A <= 2 blockdiag(A)``.  So ``dt = sqrt(2) min_p lambda_max(A_pp)^(-1/2)`` is a
  rigorous *lower* bound on the critical step (and exact for two equal spheres).
* ``two_particle_amax`` -- Peng et al. 2020, Eq. (48): ``dt = 2 / sqrt(k A_max)`` with ``A_max`` of
  Eq. (26) (``1/m_1 + 1/m_2 + a_1^2/I_xx1 + a_2^2/I_xx2``, ``a`` the largest half-length, ``I_xx`` the
  smallest principal moment) and ``k = max(k_n, k_s)``, minimised over the contacts.
* ``two_particle_exact`` -- each contact alone between its two free bodies with its real arms:
  ``omega_c^2 = lambda_max(K_c^(1/2) W K_c^(1/2))``, ``W = sum_p B_p M_p^-1 B_p^T`` (the contact
  compliance).  Adding the other contacts only stiffens the system (``K = K_c + K_rest``, both
  positive semi-definite), so the packing's critical step is never above this one: a rigorous
  *upper* bound on ``dt``.
* ``rayleigh`` -- ``w^T A w / w^T w <= lambda_max(A)`` for any trial vector ``w``: a rigorous *upper*
  bound on ``dt``.  Trials: all particles co-rotating about x, y or z; the single-contact modes of
  the stiffest contacts embedded in the packing (the best quotient over each contact's top
  eigenspace, Rayleigh-Ritz, so a degenerate pair does not depend on which eigenvector LAPACK
  returns); the single stiffest DOF.
"""
from __future__ import annotations

import numpy as np

from dtcrit.physics.estimate import Estimate

from dtcrit.packing.operators.assembly import contact_kinematics, contact_stiffness_tensor
from dtcrit.packing.operators.scattered_pass import top_eigenvalues
from dtcrit.packing.model import Contacts, Packing


def _abs_row_sums(a, weights=None, chunk: int = 1 << 18) -> np.ndarray:
    """``|A| w`` (``w`` = ones by default), block by block for a BSR matrix (no copy of ``|A|``)."""
    if hasattr(a, "abs_row_sums"):  # matrix-free operator (dtcrit.packing.operators.matrix_free)
        return a.abs_row_sums(weights)
    w = np.ones(a.shape[0]) if weights is None else np.asarray(weights, float)
    if not (hasattr(a, "blocksize") and a.blocksize == (6, 6)):
        return np.asarray(abs(a) @ w).reshape(-1)
    nb = a.indptr.size - 1
    block_rows = np.repeat(np.arange(nb), np.diff(a.indptr))
    w6 = w.reshape(-1, 6)
    out = np.zeros((nb, 6))
    for start in range(0, a.indices.size, chunk):
        sl = slice(start, start + chunk)
        part = np.einsum("bij,bj->bi", np.abs(a.data[sl]), w6[a.indices[sl]])
        for k in range(6):
            out[:, k] += np.bincount(block_rows[sl], weights=part[:, k], minlength=nb)
    return out.reshape(-1)


def gershgorin(a, mass_diag: np.ndarray) -> Estimate:
    """Gershgorin row-sum bound on ``omega_max^2``: a rigorous lower bound on the critical step.

    The smaller of ``max_i sum_j |A_ij|`` and the row sums of the similar ``M^-1 K`` (module docstring).

    Parameters
    ----------
    a : scipy.sparse matrix or LinearOperator
        Mass-scaled stiffness ``A = M^(-1/2) K M^(-1/2)`` [1/s^2].
    mass_diag : numpy.ndarray
        Diagonal of ``M`` (masses [kg] and principal inertias [kg m^2], 6 per particle).

    Returns
    -------
    Estimate
        ``omega2`` [1/s^2] and ``dt = 2/omega`` [s], with where it is attained.
    """
    sym = _abs_row_sums(a).max(initial=0.0)
    root = np.sqrt(mass_diag)
    unsym = (_abs_row_sums(a, root) / root).max(initial=0.0)  # rows of M^-1 K
    best = min(sym, unsym)
    which = "rows of M^-1/2 K M^-1/2" if sym <= unsym else "rows of M^-1 K"
    return Estimate.from_omega2("gershgorin", float(best), "lower bound on dt", which)


def _one_based(p: int) -> int:
    return int(p) + 1


def diagonal_stiffness(a, particle_id=_one_based) -> Estimate:
    """YADE / PFC per-body diagonal estimate ``omega^2 = 2 max_d A_dd`` (a heuristic, not a bound).

    YADE's GlobalStiffnessTimeStepper and PFC: ``dt = sqrt(2) sqrt(M_dd/K_dd)`` minimised over DOFs.

    Parameters
    ----------
    a : scipy.sparse matrix or LinearOperator
        Mass-scaled stiffness ``A = M^(-1/2) K M^(-1/2)`` [1/s^2].
    particle_id : callable
        Maps a 0-based particle index to the name used in ``detail`` (``Packing.particle_id``;
        default ``p + 1``).

    Returns
    -------
    Estimate
        ``omega2`` [1/s^2] and ``dt = 2/omega`` [s], with where it is attained.
    """
    d = np.asarray(a.diagonal())
    k = int(np.argmax(d))
    part = "rotation" if k % 6 >= 3 else "translation"
    return Estimate.from_omega2("diagonal", float(2.0 * d[k]), "heuristic",
                    f"sqrt(2) sqrt(M/K) on DOF {k % 6} ({part}) of particle {particle_id(k // 6)}")


def block_diagonal(a, particle_id=_one_based) -> Estimate:
    """Rigorous per-body bound ``omega_max^2 <= 2 max_p lambda_max(A_pp)`` (module docstring).

    Parameters
    ----------
    a : scipy.sparse matrix or LinearOperator
        Mass-scaled stiffness ``A = M^(-1/2) K M^(-1/2)`` [1/s^2].
    particle_id : callable
        Maps a 0-based particle index to the name used in ``detail`` (``Packing.particle_id``;
        default ``p + 1``).

    Returns
    -------
    Estimate
        ``omega2`` [1/s^2] and ``dt = 2/omega`` [s], with where it is attained.  A lower bound on ``dt``.
    """
    if hasattr(a, "block_summary"):  # matrix-free operator: the tops from its particle pass, no (N, 6, 6) array
        top = a.block_summary().top
    else:
        top = _block_tops(a)
    p = int(np.argmax(top))
    return Estimate.from_omega2("block_diagonal", float(2.0 * top[p]), "lower bound on dt",
                    f"sqrt(2) / sqrt(lambda_max of the 6x6 block) of particle {particle_id(p)}")


def _block_tops(a, chunk: int = 1 << 16) -> np.ndarray:
    """``lambda_max`` of each symmetrised 6 x 6 diagonal block of ``a`` (``diagonal_blocks`` of an
    operator that gives them, BSR blocks, or dense slices; ``scattered_pass.top_eigenvalues``).
    """
    n = a.shape[0] // 6
    if hasattr(a, "diagonal_blocks"):  # an operator that gives its blocks
        blocks = a.diagonal_blocks()
    elif hasattr(a, "blocksize") and a.blocksize == (6, 6):
        rows = np.repeat(np.arange(n), np.diff(a.indptr))
        on_diag = a.indices == rows
        blocks = np.zeros((n, 6, 6))
        blocks[rows[on_diag]] = a.data[on_diag]
    else:
        dense = a.toarray() if hasattr(a, "toarray") else np.asarray(a)
        blocks = np.stack([dense[6 * p:6 * p + 6, 6 * p:6 * p + 6] for p in range(n)])
    return top_eigenvalues(blocks, chunk)


def _compliance(packing: Packing, contacts: Contacts, sl) -> np.ndarray:
    """Contact compliance ``W`` (nc, 3, 3): relative contact acceleration per unit force."""
    bi, bj = contact_kinematics(packing, contacts, sl)
    inv = 1.0 / _mass_rows(packing)
    ci, cj = contacts.i[sl], contacts.j[sl]
    same = (ci == cj)[:, None, None]
    b_sum = bi + bj
    w_sep = (bi * inv[ci][:, None, :]) @ np.swapaxes(bi, 1, 2) + (bj * inv[cj][:, None, :]) @ np.swapaxes(bj, 1, 2)
    w_same = (b_sum * inv[ci][:, None, :]) @ np.swapaxes(b_sum, 1, 2)
    return np.where(same, w_same, w_sep)


def _mass_rows(packing: Packing) -> np.ndarray:
    return np.concatenate([np.repeat(packing.masses[:, None], 3, axis=1), packing.inertia], axis=1)


def _sqrt_contact_stiffness(contacts: Contacts, sl) -> np.ndarray:
    assert contacts.kn is not None and contacts.ks is not None  # contacts with their springs
    return contact_stiffness_tensor(contacts.normal[sl], np.sqrt(contacts.kn[sl]), np.sqrt(contacts.ks[sl]))


def single_contact_frequencies(packing: Packing, contacts: Contacts, chunk: int = 1 << 17,
                               compiled: bool | None = None) -> np.ndarray:
    """``omega_c^2`` of every contact alone between its two free bodies, with its real arms.

    ``omega_c^2 = lambda_max(K_c^(1/2) W K_c^(1/2))``, ``W`` the contact compliance (module docstring):
    the compiled loop of ``estimate_kernels`` when Numba is installed, else batched
    ``numpy.linalg.eigvalsh`` in chunks.

    Parameters
    ----------
    packing : Packing
        Particles (masses, principal inertias, orientations, radii or half-lengths).
    contacts : Contacts
        Contacts with their springs ``kn``, ``ks`` [N/m] and geometry.
    chunk : int
        Contacts per NumPy batch.
    compiled : bool or None
        Use the compiled loop (``None``: when available).

    Returns
    -------
    numpy.ndarray
        ``omega_c^2`` [1/s^2] per contact.
    """
    import dtcrit.packing.bounds.estimate_kernels as estimate_kernels

    if (estimate_kernels.available() if compiled is None else compiled) and contacts.count:
        return estimate_kernels.contact_frequencies(packing, contacts)
    out = np.empty(contacts.count)
    for start in range(0, contacts.count, chunk):
        sl = slice(start, min(start + chunk, contacts.count))
        root = _sqrt_contact_stiffness(contacts, sl)
        s = root @ _compliance(packing, contacts, sl) @ root
        out[sl] = np.linalg.eigvalsh(s)[:, -1]
    return out


def peng_a_max(packing: Packing, contacts: Contacts) -> np.ndarray:
    """Peng et al. 2020, Eq. (26) per contact: ``A_max = 1/m_i + 1/m_j + a_i^2/I_xx,i + a_j^2/I_xx,j``.

    ``a`` is the particle's largest half-length (``half_lengths``; the bounding radius when absent)
    and ``I_xx`` its smallest principal moment.  Two equal spheres of mass ``m`` give ``7/m``.

    Parameters
    ----------
    packing : Packing
        Particles (masses, principal inertias, orientations, radii or half-lengths).
    contacts : Contacts
        Contacts with their springs ``kn``, ``ks`` [N/m] and geometry.

    Returns
    -------
    numpy.ndarray
        ``A_max`` [1/kg] per contact.
    """
    a = packing.half_lengths.max(axis=1) if packing.half_lengths is not None else packing.radii
    per = 1.0 / packing.masses + a**2 / packing.inertia.min(axis=1)
    return per[contacts.i] + per[contacts.j]


def two_particle_amax(packing: Packing, contacts: Contacts) -> Estimate:
    """Peng et al. 2020, Eq. (48): ``omega^2 = k A_max`` with ``k = max(k_n, k_s)``, most demanding contact.

    A heuristic (``dt = 2/sqrt(k A_max)``); ``A_max`` from ``peng_a_max``.

    Parameters
    ----------
    packing : Packing
        Particles (masses, principal inertias, orientations, radii or half-lengths).
    contacts : Contacts
        Contacts with their springs ``kn``, ``ks`` [N/m] and geometry.

    Returns
    -------
    Estimate
        ``omega2`` [1/s^2] and ``dt = 2/omega`` [s], with where it is attained.
    """
    if contacts.count == 0:
        return Estimate.from_omega2("two_particle_amax", 0.0, "heuristic", "no contacts")
    assert contacts.kn is not None and contacts.ks is not None  # contacts with their springs
    w = np.maximum(contacts.kn, contacts.ks) * peng_a_max(packing, contacts)
    c = int(np.argmax(w))
    return Estimate.from_omega2("two_particle_amax", float(w[c]), "heuristic",
                    f"Eq. (48) at the contact of particles {packing.particle_id(contacts.i[c])} and "
                    f"{packing.particle_id(contacts.j[c])}")


def two_particle_exact(packing: Packing, contacts: Contacts, omega2_c: np.ndarray | None = None) -> Estimate:
    """Most demanding single contact with its real arms: an upper bound on the packing's ``dt``.

    Parameters
    ----------
    packing : Packing
        Particles (masses, principal inertias, orientations, radii or half-lengths).
    contacts : Contacts
        Contacts with their springs ``kn``, ``ks`` [N/m] and geometry.
    omega2_c : numpy.ndarray or None
        Precomputed ``single_contact_frequencies`` [1/s^2] (computed when ``None``).

    Returns
    -------
    Estimate
        ``omega2`` [1/s^2] and ``dt = 2/omega`` [s], with where it is attained.
    """
    if contacts.count == 0:
        return Estimate.from_omega2("two_particle_exact", 0.0, "upper bound on dt", "no contacts")
    w = single_contact_frequencies(packing, contacts) if omega2_c is None else omega2_c
    c = int(np.argmax(w))
    return Estimate.from_omega2("two_particle_exact", float(w[c]), "upper bound on dt",
                    f"the contact of particles {packing.particle_id(contacts.i[c])} and {packing.particle_id(contacts.j[c])} alone")
