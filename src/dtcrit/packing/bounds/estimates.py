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
    n = a.shape[0] // 6
    if hasattr(a, "diagonal_blocks"):  # matrix-free operator (dtcrit.packing.operators.matrix_free)
        blocks = a.diagonal_blocks()
    elif hasattr(a, "blocksize") and a.blocksize == (6, 6):
        rows = np.repeat(np.arange(n), np.diff(a.indptr))
        on_diag = a.indices == rows
        blocks = np.zeros((n, 6, 6))
        blocks[rows[on_diag]] = a.data[on_diag]
    else:
        dense = a.toarray() if hasattr(a, "toarray") else np.asarray(a)
        blocks = np.stack([dense[6 * p:6 * p + 6, 6 * p:6 * p + 6] for p in range(n)])
    top = np.empty(n)
    for lo in range(0, n, 1 << 16):  # in chunks: the (N, 6, 6) blocks are 2.9 GB at 1e7 particles
        part = blocks[lo:lo + (1 << 16)]
        top[lo:lo + (1 << 16)] = np.linalg.eigvalsh(0.5 * (part + np.swapaxes(part, 1, 2)))[:, -1]
    p = int(np.argmax(top))
    return Estimate.from_omega2("block_diagonal", float(2.0 * top[p]), "lower bound on dt",
                    f"sqrt(2) / sqrt(lambda_max of the 6x6 block) of particle {particle_id(p)}")


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


def contact_mode(packing: Packing, contacts: Contacts, c: int) -> np.ndarray:
    """Mass-scaled global vector of contact ``c``'s own highest mode (zero away from its pair).

    Parameters
    ----------
    packing : Packing
        Particles (masses, principal inertias, orientations, radii or half-lengths).
    contacts : Contacts
        Contacts with their springs ``kn``, ``ks`` [N/m] and geometry.
    c : int
        Index of the contact.

    Returns
    -------
    numpy.ndarray
        The vector, 6 entries per particle of the packing.
    """
    return contact_modes(packing, contacts, c, rtol=0.0)[0]


def contact_modes(packing: Packing, contacts: Contacts, c: int, rtol: float = 1e-8) -> list[np.ndarray]:
    """Mass-scaled global vectors of contact ``c``'s top eigenspace (zero away from its pair).

    Every eigenvector of ``K_c^(1/2) W K_c^(1/2)`` whose eigenvalue is within the relative ``rtol``
    of the largest, embedded as in :func:`contact_mode`.  Two spheres' tangential pair is exactly
    degenerate, and which member of that plane LAPACK returns depends on the last bits of the
    input; the *span* does not, so :func:`rayleigh` uses the best quotient over the span.

    Parameters
    ----------
    packing : Packing
        Particles (masses, principal inertias, orientations, radii or half-lengths).
    contacts : Contacts
        Contacts with their springs ``kn``, ``ks`` [N/m] and geometry.
    c : int
        Index of the contact.
    rtol : float
        Relative distance from the largest eigenvalue within which eigenvectors are kept.

    Returns
    -------
    list of numpy.ndarray
        The vectors, 6 entries per particle of the packing, largest eigenvalue first.
    """
    sl = slice(c, c + 1)
    root = _sqrt_contact_stiffness(contacts, sl)[0]
    w = _compliance(packing, contacts, sl)[0]
    vals, vecs = np.linalg.eigh(root @ w @ root)
    bi, bj = contact_kinematics(packing, contacts, sl)
    rows = _mass_rows(packing)
    i, j = int(contacts.i[c]), int(contacts.j[c])
    out = []
    for k in range(2, -1, -1):
        if k < 2 and vals[k] < vals[2] - rtol * abs(vals[2]):
            break
        force = root @ vecs[:, k]
        vec = np.zeros(packing.dofs)
        # velocity pattern q = M^-1 B^T f, mass-scaled w = M^(1/2) q = M^(-1/2) B^T f
        vec[6 * i:6 * i + 6] += (bi[0].T @ force) / np.sqrt(rows[i])
        vec[6 * j:6 * j + 6] += (bj[0].T @ force) / np.sqrt(rows[j])
        out.append(vec)
    return out


def _span_quotient(a, vectors: list[np.ndarray]) -> float:
    """Largest Rayleigh quotient of ``a`` over the span of ``vectors`` (Rayleigh-Ritz: the top
    eigenvalue of ``Q^T A Q`` for an orthonormal basis ``Q`` of the span; never above
    ``lambda_max(A)``, and independent of which basis of the span is given).  One product with
    ``a`` per vector; only the small Gram matrices are kept.
    """
    if len(vectors) == 1:
        v = vectors[0]
        norm = float(v @ v)
        return float(v @ (a @ v)) / norm if norm > 0 else 0.0
    gram = np.array([[float(u @ v) for v in vectors] for u in vectors])
    proj = np.empty_like(gram)
    for k, v in enumerate(vectors):
        av = a @ v
        proj[:, k] = [float(u @ av) for u in vectors]
    proj = 0.5 * (proj + proj.T)
    s, u = np.linalg.eigh(gram)
    keep = s > 1e-12 * max(float(s[-1]), 0.0)
    if not np.any(keep):
        return 0.0
    basis = u[:, keep] / np.sqrt(s[keep])  # coefficients of an orthonormal basis of the span
    return float(np.linalg.eigvalsh(basis.T @ proj @ basis)[-1])


def co_rotation(packing: Packing, axis: int) -> np.ndarray:
    """Mass-scaled vector of every particle rotating by the same small angle about a global axis.

    The rotation entries are ``M^(1/2)`` times the axis in each body frame (``R^T e``).

    Parameters
    ----------
    packing : Packing
        Particles (principal inertias and orientations).
    axis : int
        Global axis: 0, 1 or 2 for x, y, z.

    Returns
    -------
    numpy.ndarray
        The trial vector, 6 entries per particle.
    """
    e = np.zeros(3)
    e[axis] = 1.0
    body = np.repeat(e[None, :], packing.n, axis=0)
    if packing.orientations is not None:
        body = np.einsum("nji,j->ni", packing.orientations, e)  # R^T e
    vec = np.zeros((packing.n, 6))
    vec[:, 3:] = body * np.sqrt(packing.inertia)
    return vec.reshape(-1)


def _stiffest(w: np.ndarray, k: int) -> np.ndarray:
    """Indices of the ``k`` largest ``w``, largest first.

    Ranked on ``w`` rounded to 30 significant bits (a relative 1e-9), ties to the lower index: many
    contacts of a packing have the same frequency up to rounding, and which of them the last bits
    favour must not change the trials (NumPy's SIMD loops differ between processors).
    """
    w = np.asarray(w, dtype=float)
    mant, expo = np.frexp(w)
    key = np.ldexp(np.round(np.ldexp(mant, 30)), expo - 30)
    if w.size <= k:
        return np.argsort(-key, kind="stable")
    cut = np.partition(key, w.size - k)[w.size - k]
    pick = np.flatnonzero(key >= cut)
    return pick[np.argsort(-key[pick], kind="stable")][:k]


def rayleigh(a, packing: Packing, contacts: Contacts, omega2_c: np.ndarray | None = None,
             n_contacts: int = 8) -> Estimate:
    """Best Rayleigh quotient over the trial modes of the module docstring: an upper bound on ``dt``.

    Parameters
    ----------
    a : scipy.sparse matrix or LinearOperator
        Mass-scaled stiffness ``A = M^(-1/2) K M^(-1/2)`` [1/s^2].
    packing : Packing
        Particles (masses, principal inertias, orientations, radii or half-lengths).
    contacts : Contacts
        Contacts with their springs ``kn``, ``ks`` [N/m] and geometry.
    omega2_c : numpy.ndarray or None
        Precomputed ``single_contact_frequencies`` [1/s^2] (computed when ``None``).
    n_contacts : int
        Number of stiffest contacts whose modes are tried.

    Returns
    -------
    Estimate
        ``omega2`` [1/s^2] and ``dt = 2/omega`` [s], with where it is attained.  ``detail`` names the best trial.
    """
    def trials():  # one at a time: at 1e7 particles each trial vector is 480 MB
        for k in range(3):
            yield f"co-rotation about {'xyz'[k]}", co_rotation(packing, k)
        if contacts.count:
            w = single_contact_frequencies(packing, contacts) if omega2_c is None else omega2_c
            for c in _stiffest(w, n_contacts):
                yield (f"mode of the contact of particles {packing.particle_id(contacts.i[c])} and "
                       f"{packing.particle_id(contacts.j[c])} alone", contact_modes(packing, contacts, int(c)))
        d = np.asarray(a.diagonal())
        k = int(_stiffest(d, 1)[0])
        unit = np.zeros(a.shape[0])
        unit[k] = 1.0
        yield f"DOF {k % 6} of particle {packing.particle_id(k // 6)} alone", unit

    best, name = 0.0, "none"
    for label, v in trials():
        q = _span_quotient(a, v if isinstance(v, list) else [v])
        if q > best * (1 + 1e-9):  # a rounding-level tie keeps the earlier trial's name
            name = label
        best = max(best, q)
    return Estimate.from_omega2("rayleigh", best, "upper bound on dt", name)
