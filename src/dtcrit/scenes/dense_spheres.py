"""Rigorous upper bound on omega_max^2 of ANY sphere packing with a given coordination cap.

    omega_max^2 = lambda_max(M^-1/2 K M^-1/2)  <=  dense_omega2_bound(...)
    dt_dense = 2 / sqrt(bound)  <=  dt_crit (central difference / leapfrog / velocity Verlet, undamped)

Proof: ``derivations/proofs/dense_packing_bound.md`` (Theorem 1; Lemmas 1-9 and Remark 3 are cited below by
number).  NumPy only.

Model (the hypotheses H1-H4 of ``derivations/proofs/dense_packing_bound.md``): spheres with 6 DOFs each (mass m, a rotational
inertia I, for a non-isotropic body its smallest principal moment), linear contact springs
``k_n, k_s`` (each contact's springs at most these), optional rolling ``k_r`` and twisting ``k_tw``
springs on the relative rotation, contact arms equal to the full radius (``a_i = R_i n``, the
LAMMPS / YADE convention; ``arms="overlap-midpoint"`` covers dtcrit's ``R - delta/2``, Remark 3),
every particle of species ``s`` with at most ``z[s]`` contacts,
contacts with ``d_ij <= (1 + contact_tolerance)(R_i + R_j)`` and every two distinct sphere images
with ``d >= (1 - overlap)(R_j + R_k)``.  Every particle must belong to one of the species given
(any species may touch any other).

The bound is ``min_p max_s Phi_s(p)`` where ``Phi_s`` is a rigorous upper bound (Lemmas 6-9) on
``sup lambda_max(sum_e Q_e)`` over all arrangements of at most ``z_s`` contact normals of a
particle of species ``s`` that are pairwise at least ``theta_s`` apart (Lemma 5), ``Q_e`` the
6 x 6 end matrix of Lemma 3 with the splitting weights of exponent ``p`` (Lemma 2).
"""
from __future__ import annotations
import math
from dataclasses import dataclass, field
import numpy as np
from dtcrit.scenes.dense_cells import _species_geometry, _trivial
from dtcrit.scenes.dense_tables import phi_upper


@dataclass
class DenseBound:
    """Result: ``omega2`` [1/s^2] (rigorous upper bound on omega_max^2), ``dt = 2/sqrt(omega2)`` (a
    rigorous lower bound on the undamped central-difference critical step), the weight exponent
    ``p`` used, the governing species and per-species details.

    Parameters
    ----------
    omega2 : float
        Rigorous upper bound on omega_max^2 [1/s^2].
    p : float
        The weight exponent of the splitting that gave it.
    governing : int
        Index of the species that attains the bound.
    species : list of dict
        Per species: mass, radius, inertia, effective coordination, smallest angle, bound, how.
    trivial_omega2 : float
        The bound without the angle argument (for comparison) [1/s^2].
    """

    omega2: float
    p: float
    governing: int
    species: list = field(default_factory=list)
    trivial_omega2: float = float("nan")

    @property
    def dt(self) -> float:
        """``2/sqrt(omega2)`` [s]: a lower bound on the undamped central-difference critical step."""
        return 2.0 / math.sqrt(self.omega2) if self.omega2 > 0 else math.inf


def _as_species(masses, radii, inertia, z):
    m = np.atleast_1d(np.asarray(masses, float))
    r = np.broadcast_to(np.atleast_1d(np.asarray(radii, float)), m.shape).astype(float)
    if inertia is None:
        i = 0.4 * m * r * r
    else:
        i = np.broadcast_to(np.atleast_1d(np.asarray(inertia, float)), m.shape).astype(float)
    zz = np.broadcast_to(np.atleast_1d(np.asarray(z)), m.shape).astype(int)
    for name, arr in (("masses", m), ("radii", r), ("inertia", i)):
        if not np.all(np.isfinite(arr)) or np.any(arr <= 0):
            raise ValueError(f"{name}: every value must be a positive finite number")
    if np.any(zz < 0):
        raise ValueError("z: must be >= 0")
    return m, r, i, zz


def _pars(kn, ks, kr, ktw, m, r, i, p, t0):
    """Per-species end parameters ``(alpha, beta, gamma, gamma_r, gamma_w, t0)`` with the splitting
    weights ``w = 1 + max_j (c_j / c_i)^p`` (Lemma 2) and the smallest arm ratio ``t0``.
    """
    cn, ct, cr = 1.0 / m, 1.0 / m + r * r / i, 1.0 / i
    wn = 1.0 + (cn.max() / cn) ** p
    wt = 1.0 + (ct.max() / ct) ** p
    wr = 1.0 + (cr.max() / cr) ** p
    return np.stack([wn * kn / m, wt * ks / m, wt * ks * r * r / i, wr * kr / i, wr * ktw / i, t0], 1)


def _domination(pars_i, pars_n):
    """Factor ``c`` with ``D(pars_i) <= c D_s D(pars_n) D_s`` (Loewner) for every arrangement, ``D_s``
    diagonal with ``max(D_s)^2 <= 1``-normalised scale folded into ``c`` (dense_packing_bound.md, Lemma 9, remark
    on species), so that ``Phi(pars_i) <= c Phi(pars_n)``; ``None`` when no such factor is found.
    """
    a, b, g, gr, gw, t0 = (float(t) for t in pars_i)
    an, bn, gn, grn, gwn, t0n = (float(t) for t in pars_n)
    if (bn == 0 and b > 0) or (gn == 0 and g > 0) or t0 < t0n:
        return None
    if bn > 0:
        s1 = b / bn
    else:
        s1 = a / an if an > 0 else 1.0
    if gn > 0:
        s2 = g / gn
    else:
        ratios = [c / d for c, d in ((gr, grn), (gw, gwn)) if d > 0]
        s2 = max(ratios) if ratios else 1.0
    delta = 1.0
    for comp, node, s in ((a, an, s1), (gr, grn, s2), (gw, gwn, s2)):
        if comp == 0:
            continue
        if node == 0 or s == 0:
            return None
        delta = max(delta, comp / (s * node))
    return delta * max(s1, s2) * (1.0 + 1e-12)


def dense_omega2_bound(kn, ks, masses, radii, inertia=None, z=12, *, kr: float = 0.0, ktw: float = 0.0,
                       overlap: float = 0.0, contact_tolerance: float = 1e-9, arms: str = "full",
                       p_grid=None, rtol: float = 2e-3, n_theta: int = 96) -> DenseBound:
    """Rigorous upper bound on ``omega_max^2`` of every packing of the given sphere species (dense_packing_bound.md, Theorem 1).

    ``kn, ks`` [N/m]: the largest normal / tangential contact stiffness (``ks = 0`` and ``ks > kn``
    allowed); ``kr, ktw`` [N m/rad]: rolling / twisting springs on the relative rotation (optional).
    ``masses, radii, inertia`` (arrays over species; ``inertia`` defaults to ``2/5 m R^2``, give the
    smallest principal moment for non-isotropic bodies); ``z`` the largest number of contacts of a
    particle (scalar or per species; 12 = kissing number of equal spheres); ``overlap`` the largest
    overlap as a fraction of ``R_i + R_j`` (``eps`` of H4); ``contact_tolerance`` how far beyond
    touching a contact may be (``d <= (1+tau)(R_i+R_j)``).  ``arms``: ``"full"`` (``a = R n``,
    LAMMPS / YADE; hypothesis H1) or ``"overlap-midpoint"`` (dtcrit's ``a = (R - delta/2) n``: every arm
    in ``[t0 R, R]`` with ``t0 = 1 - overlap (R_i + R_max) / (2 R_i)``, Remark 3).  ``p_grid`` the splitting exponents tried
    (each gives a valid bound, the smallest is returned; default ``(0, 0.5, 1)`` for several
    species).  ``rtol`` the branch-and-bound stopping tolerance and ``n_theta`` the sphere grid:
    they change only how tight the bound is, never its validity.

    Parameters
    ----------
    kn, ks : float
        Largest normal / tangential contact stiffness [N/m].
    masses : array_like
        Mass of each species [kg].
    radii : array_like
        Radius of each species [m].
    inertia : array_like, optional
        Smallest principal moment of each species [kg m^2]; ``2/5 m R^2`` when omitted.
    z : int or array_like
        Largest number of contacts of a particle (scalar or per species).
    kr, ktw : float
        Rolling / twisting springs [N m/rad].
    overlap : float
        Largest overlap as a fraction of ``R_i + R_j``.
    contact_tolerance : float
        How far beyond touching a contact may be, as a fraction of ``R_i + R_j``.
    arms : str
        ``"full"`` or ``"overlap-midpoint"``.
    p_grid : sequence of float, optional
        Splitting exponents tried.
    rtol : float
        Branch-and-bound stopping tolerance.
    n_theta : int
        Resolution of the sphere grid.

    Returns
    -------
    DenseBound
        The bound; ``.dt = 2/sqrt(omega2)`` is a lower bound on the true critical step of the
        undamped central-difference family for every such packing.
    """
    kn, ks, kr, ktw = (float(v) for v in (kn, ks, kr, ktw))
    if min(kn, ks, kr, ktw) < 0 or not all(math.isfinite(v) for v in (kn, ks, kr, ktw)):
        raise ValueError("stiffnesses must be finite and >= 0")
    if not 0.0 <= overlap < 1.0:
        raise ValueError("overlap must lie in [0, 1)")
    m, r, i, zz = _as_species(masses, radii, inertia, z)
    psi, z_eff = _species_geometry(r, zz, overlap, contact_tolerance)
    if arms == "full":
        t0 = np.ones_like(r)
    elif arms == "overlap-midpoint":
        t0 = np.clip(1.0 - overlap * (r + r.max()) / (2.0 * r), 0.0, 1.0)
    else:
        raise ValueError(f"arms must be 'full' or 'overlap-midpoint', got {arms!r}")
    if p_grid is None:
        p_grid = (0.0,) if len(m) == 1 or (np.ptp(m) == 0 and np.ptp(r) == 0 and np.ptp(i) == 0) else (0.0, 0.5, 1.0)
    nodes: list[tuple[np.ndarray, int, float, float]] = []  # (pars, z_eff, psi, rigorous Phi)

    def node_bound(pars_s, z_s, psi_s, exact=False):
        """Best rigorous bound from the computed nodes; with ``exact`` only nodes of the same
        ``(z_eff, psi)`` (then as good as the species' own branch and bound up to the scale).
        """
        ub = math.inf
        for pn, zn, psin, phin in nodes:
            if (z_s == zn and psi_s == psin) if exact else (z_s <= zn and psi_s >= psin):
                c = _domination(pars_s, pn)
                if c is not None:
                    ub = min(ub, c * phin)
        return ub

    best: DenseBound | None = None
    for p in p_grid:
        # a refined species at or above the best bound so far means this p cannot win: stop early
        abandon = best.omega2 if best is not None else math.inf
        pars = _pars(kn, ks, kr, ktw, m, r, i, p, t0)
        trivial = np.array([z_eff[s] * _trivial(pars[s]) for s in range(len(m))])
        active = (z_eff > 0) & (trivial > 0)
        if active.any() and len(m) > 1:
            # seed node: conservative for every species (largest z, smallest angle)
            seed = int(np.argmax(np.where(active, trivial, -1.0)))
            zs, ps = int(z_eff[active].max()), float(psi[active].min())
            if not np.isfinite(node_bound(pars[seed], zs, ps)):
                nodes.append((pars[seed].copy(), zs, ps, phi_upper(zs, ps, tuple(pars[seed]), rtol, n_theta, _domination)))
        ub = np.array([min(trivial[s], node_bound(pars[s], int(z_eff[s]), float(psi[s]))) if active[s] else 0.0
                       for s in range(len(m))])
        how = ["trivial (z lambda_max(Q))" if ub[s] == trivial[s] else "dominated by a computed node"
               for s in range(len(m))]
        refined = ~active.copy()
        # refine the species holding the current maximum until that maximum is its own branch-and-bound value
        while active.any():
            s = int(np.argmax(np.where(active, ub, -1.0)))
            if refined[s] or ub[s] >= abandon:
                break
            phi = node_bound(pars[s], int(z_eff[s]), float(psi[s]), exact=True)
            if not np.isfinite(phi):
                phi = phi_upper(int(z_eff[s]), float(psi[s]), tuple(pars[s]), rtol, n_theta, _domination)
                nodes.append((pars[s].copy(), int(z_eff[s]), float(psi[s]), phi))
            if phi < ub[s]:
                ub[s], how[s] = phi, "branch and bound"
            refined[s] = True
            for t in range(len(m)):
                if active[t] and not refined[t]:
                    nb = node_bound(pars[t], int(z_eff[t]), float(psi[t]))
                    if nb < ub[t]:
                        ub[t], how[t] = nb, "dominated by a computed node"
        running = float(ub.max(initial=0.0))
        gov = int(np.argmax(ub))
        if running >= abandon:
            continue
        details = [(float(ub[s]), how[s] if active[s] else "no contacts") for s in range(len(m))]
        cand = DenseBound(omega2=running, p=float(p), governing=gov, trivial_omega2=float(trivial.max()),
                          species=[{"mass": float(m[s]), "radius": float(r[s]), "inertia": float(i[s]),
                                    "z_eff": int(z_eff[s]), "theta_min_deg": math.degrees(2 * psi[s]),
                                    "omega2": details[s][0], "how": details[s][1]} for s in range(len(m))])
        if best is None or cand.omega2 < best.omega2:
            best = cand
    if best is None:
        raise ArithmeticError("no splitting exponent gave a finite bound")
    return best


def dense_dt_bound(*args, **kwargs) -> float:
    """``2 / sqrt(dense_omega2_bound(...).omega2)``: a rigorous lower bound on the critical step.

    Parameters
    ----------
    *args, **kwargs
        The arguments of :func:`dense_omega2_bound`.

    Returns
    -------
    float
        The step [s].
    """
    return dense_omega2_bound(*args, **kwargs).dt
