"""Rayleigh-quotient trials on a packing: a lower bound on its largest eigenvalue, so an upper bound on dt_crit.

Trial vectors are the modes of the stiffest contacts (``contact_mode``, ``contact_modes``, ranked by
``_stiffest`` on rounded frequencies so that the choice does not depend on the last bits), the
co-rotation of the whole packing (``co_rotation``); ``rayleigh`` takes the best quotient over their span.
"""
from __future__ import annotations

import numpy as np
from dtcrit.physics.estimate import Estimate
from dtcrit.packing.operators.assembly import contact_blocks, contact_kinematics
from dtcrit.packing.model import Contacts, Packing
from dtcrit.packing.bounds.estimates import _compliance, _mass_rows, _sqrt_contact_stiffness, single_contact_frequencies


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
    if w.size <= k:
        return np.argsort(-_rounded(w), kind="stable")
    # in chunks (at 6e7 contacts each whole-array temporary is 480 MB): every member of the top k
    # is among its chunk's top k, and the candidates stay in index order for the stable sort
    picks = []
    for lo in range(0, w.size, STIFFEST_CHUNK):
        key = _rounded(w[lo:lo + STIFFEST_CHUNK])
        if key.size <= k:
            picks.append(np.arange(lo, lo + key.size))
            continue
        cut = np.partition(key, key.size - k)[key.size - k]
        above = np.flatnonzero(key > cut)  # and the first of those equal to the cut: at most k kept
        tied = np.flatnonzero(key == cut)[:k - above.size]
        picks.append(np.sort(np.concatenate([above, tied])) + lo)
    pick = np.concatenate(picks)
    return pick[np.argsort(-_rounded(w[pick]), kind="stable")][:k]


STIFFEST_CHUNK = 1 << 22


def _rounded(w: np.ndarray) -> np.ndarray:
    """``w`` rounded to 30 significant bits (``_stiffest``'s ranking key)."""
    mant, expo = np.frexp(w)
    return np.ldexp(np.round(np.ldexp(mant, 30)), expo - 30)


def principal_submatrix(a, particles: np.ndarray) -> np.ndarray:
    """The dense rows and columns of a matrix-free ``A`` for the six DOFs of each of ``particles``.

    ``A_SS`` from the diagonal blocks of these particles only (``diagonal_blocks(particles=...)``) and
    the scaled coupling blocks ``s_i K_ij s_j`` (``assembly.contact_blocks``) of the contacts joining two of the particles (every
    periodic image; a contact with its own image is in its diagonal block).  For vectors ``u``, ``v``
    zero outside those DOFs, ``u^T A v = u_S^T A_SS v_S``: a local trial's quotient without a product
    over all contacts.

    Parameters
    ----------
    a : dtcrit.packing.operators.matrix_free.ContactOperator
        The operator (``diagonal_blocks``, ``scale6``, ``contacts``, ``packing``, ``kind``).
    particles : numpy.ndarray
        Distinct particle indices; the rows follow their order, six per particle.

    Returns
    -------
    numpy.ndarray
        ``A_SS``, (6m, 6m) for m particles.
    """
    p = np.asarray(particles, dtype=np.int64)
    where = {int(q): k for k, q in enumerate(p)}
    out = np.zeros((6 * len(p), 6 * len(p)))
    blocks = a.diagonal_blocks(particles=p)  # only these particles' blocks
    for k in range(len(p)):
        out[6 * k:6 * k + 6, 6 * k:6 * k + 6] = blocks[k]
    c = a.contacts
    member = np.zeros(a.shape[0] // 6, dtype=bool)
    member[p] = True
    pick = np.flatnonzero(member[c.i] & member[c.j] & (c.i != c.j))
    if pick.size:
        k_ij = contact_blocks(a.packing, c, pick, a.kind)[2]
        for blk, ci, cj in zip(k_ij, c.i[pick], c.j[pick]):
            r, t = 6 * where[int(ci)], 6 * where[int(cj)]
            scaled = a.scale6[ci][:, None] * blk * a.scale6[cj][None, :]
            out[r:r + 6, t:t + 6] += scaled
            out[t:t + 6, r:r + 6] += scaled.T
    return out


def _sparse(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(indices, values)`` of the non-zero entries of ``v``."""
    nz = np.flatnonzero(v)
    return nz, v[nz]


def _local_quotients(a, trials: list[tuple[str, list[tuple[np.ndarray, np.ndarray]]]]) -> list[tuple[str, float]]:
    """Each local trial's best quotient over its span (vectors as ``_sparse`` pairs), from one
    ``principal_submatrix`` of every particle the trials touch.
    """
    support = np.unique(np.concatenate([nz // 6 for _, vs in trials for nz, _ in vs] + [np.zeros(0, np.int64)]))
    if support.size == 0:
        return [(label, 0.0) for label, _ in trials]
    sub = principal_submatrix(a, support)
    row = np.full(a.shape[0] // 6, -1, dtype=np.int64)
    row[support] = np.arange(support.size)
    quotients = []
    for label, vs in trials:
        local = []
        for nz, values in vs:
            v = np.zeros(sub.shape[0])
            v[6 * row[nz // 6] + nz % 6] = values
            local.append(v)
        quotients.append((label, _span_quotient(sub, local)))
    return quotients


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
    def local_trials():  # each vector is zero away from one or two particles
        if contacts.count:
            w = single_contact_frequencies(packing, contacts) if omega2_c is None else omega2_c
            for c in _stiffest(w, n_contacts):
                yield (f"mode of the contact of particles {packing.particle_id(contacts.i[c])} and "
                       f"{packing.particle_id(contacts.j[c])} alone", contact_modes(packing, contacts, int(c)))
        d = np.asarray(a.diagonal())
        k = int(_stiffest(d, 1)[0])
        unit = np.zeros(a.shape[0])
        unit[k] = 1.0
        yield f"DOF {k % 6} of particle {packing.particle_id(k // 6)} alone", [unit]

    # the co-rotations one at a time (at 1e7 particles each is 480 MB), one product each
    quotients = [(f"co-rotation about {'xyz'[k]}", _span_quotient(a, [co_rotation(packing, k)])) for k in range(3)]
    if hasattr(a, "diagonal_blocks") and hasattr(a, "contacts"):  # matrix-free: no product for local trials
        quotients += _local_quotients(a, [(label, [_sparse(v) for v in vs]) for label, vs in local_trials()])
    else:
        quotients += [(label, _span_quotient(a, vs)) for label, vs in local_trials()]
    best, name = 0.0, "none"
    for label, q in quotients:
        if q > best * (1 + 1e-9):  # a rounding-level tie keeps the earlier trial's name
            name = label
        best = max(best, q)
    return Estimate.from_omega2("rayleigh", best, "upper bound on dt", name)
