"""Record: a critical step that holds for any packing with at most z contacts per particle.

Writes ``records/dense_bound.md``: the proof behind ``dtcrit.scenes.dense`` (block bound, then the
Rayleigh-quotient argument for damping), the symbolic checks of which integrators it covers, and
the ratio of the dense step to the exact global step of lattices and random packings
(``dtcrit.packing``, an independent route).  Deterministic: fixed seeds, four significant digits.
"""
from __future__ import annotations

import math

import numpy as np
import sympy as sp
from _shared.text import num

from dtcrit.integrators.schemes import NAMES
from dtcrit.packing import LinearLaw, analyse, find_sphere_contacts, lattice, random_packing
from dtcrit.scenes.dense import DENSE_SCHEMES
from dtcrit.scenes.scene import parse_scene
from dtcrit.scenes.timestep import critical_step
from dtcrit.symbolic.integrators import C, K, characteristic_polynomial, h, lam

RECORD = "dense_bound.md"
KS_RATIOS = (0.0, 0.1, 2 / 7, 1.0, 2.0)


def affine_in_k_and_c(name: str) -> bool:
    """The characteristic polynomial has no K^2, C^2 or K C terms: m p(z) + h c q(z) + h^2 k r(z)."""
    p = sp.expand(characteristic_polynomial(name, dimensionless=False).as_expr())
    return all(sp.simplify(sp.diff(p, a, b)) == 0 for a, b in ((K, K), (C, C), (K, C)))


def stable_region(name: str) -> str:
    """The one-mode stable set in (k~, c~) = (h^2 K, h C) from the polynomial at z = -1 and z = 1."""
    p = sp.expand(characteristic_polynomial(name, dimensionless=False).as_expr())
    kt, ct = sp.symbols("k~ c~", nonnegative=True)
    at = {K: kt / h**2, C: ct / h}
    return f"P(-1) = {sp.factor(sp.simplify(p.subs(lam, -1).subs(at)))}"


def _scene(radius: float, density: float, kn: float, ks: float, z: int) -> str:
    return (f'integrator = "velocity-verlet"\ncoordination_max = {z}\n[[particle]]\nshape = "sphere"\n'
            f'radius = {radius!r}\ndensity = {density!r}\n[contact]\nmodel = "linear"\nkn = {kn!r}\nks = {ks!r}\n')


def _poly_scene(packing, kn, ks, z):
    radii = np.unique(np.round(packing.radii, 15))
    density = float(packing.masses[0] / (4 / 3 * math.pi * packing.radii[0] ** 3))
    fr = np.full(radii.size, 1.0 / radii.size)
    fr[-1] = 1.0 - fr[:-1].sum()
    c = find_sphere_contacts(packing)
    overlap = float(np.max(c.overlap / (packing.radii[c.i] + packing.radii[c.j]))) * (1 + 1e-9) + 1e-15
    return (f'integrator = "velocity-verlet"\ncoordination_max = {z}\noverlap_max = {overlap!r}\n'
            f'[[particle]]\nshape = "sphere"\nradii = {[float(r) for r in radii]!r}\nfractions = {[float(f) for f in fr]!r}\ndensity = {density!r}\n'
            f'[contact]\nmodel = "linear"\nkn = {kn!r}\nks = {ks!r}\n')


def ratio_rows() -> list[tuple[str, float, float, float]]:
    packings = [("sc 2^3", lattice("sc", 2)), ("bcc 2^3", lattice("bcc", 2)), ("fcc 2^3", lattice("fcc", 2)),
                ("fcc 3^3", lattice("fcc", 3)), ("random mono, 64, CN 5", random_packing(64, cn=5.0, seed=3)),
                ("random uniform +-30 %, 64, CN 5", random_packing(64, cn=5.0, sizes="uniform", spread=0.3, seed=4))]
    rows = []
    kn = 1.0e4
    for label, packing in packings:
        for ratio in KS_RATIOS:
            rep = analyse(packing, LinearLaw(kn, ratio * kn), integrator="velocity-verlet", with_estimates=False)
            z = int(rep.cn_max)
            res = critical_step(parse_scene(_poly_scene(packing, kn, ratio * kn, z)))
            how = "sphere" if "sphere-packing" in res.dense.reason else "block"
            rows.append((f"{label}, ks/kn = {num(ratio, 3)}, z = {z}", res.dt_dense / rep.dt_crit,
                         res.dt_isolated / rep.dt_crit, how))
    return rows


def build() -> str:
    out = [
        "# A step for any packing with at most z contacts per particle (`coordination_max`)",
        "",
        "Source: Otsubo, O'Sullivan & Shire 2017 (the two-particle step is an upper bound on a packing's step, "
        "unsafe in dense packings); the bound and its proof are dtcrit's.  Built by `derivations/dense_bound.py`; "
        "regenerate with `python3 dev.py generate`.",
        "",
        "## The bound",
        "",
        "Packing: particles with 6 DOFs (mass `m_i`, inertia `I_i`), linear contacts `K = sum_c K_c`, "
        "`C = sum_c C_c`, each element positive semi-definite; every particle has at most `z` contacts "
        "(particle-particle or wall).  `M` is the mass matrix.",
        "",
        "**Step 0 (spheres: the geometry of contact normals).**  For spheres the proof in "
        "`derivations/proofs/dense_packing_bound.md` (`dtcrit.scenes.dense_spheres`) sharpens step 1: the contact "
        "normals of a sphere are at least the law-of-cosines angle apart (60 degrees for equal spheres without overlap; "
        "the scene's `overlap_max`, default 0.05 of `R_i + R_j`, narrows it), at most as many fit as the Tammes "
        "problem allows, and the sum over normals is bounded by an integral over disjoint caps, evaluated with "
        "certified error control.  It bounds any assembly of such contact elements, springs and dashpots alike.",
        "",
        "**Step 1 (block bound).**  A particle-particle element couples the blocks of particles i and j: "
        "with `G = [G_i, G_j]`, `(G_i a + G_j b)^T K_c (G_i a + G_j b) <= 2 a^T G_i^T K_c G_i a + 2 b^T G_j^T K_c G_j b`, so "
        "`K_c <= 2 blockdiag`; a wall element has one block only.  Summing, "
        "`M^-1/2 K M^-1/2 <= blockdiag_i (sum_(c at i) w_c D_ic)` with `w_c = 2` or `1` and "
        "`D_ic = M_i^-1/2 G_ic^T K_c G_ic M_i^-1/2`, whose largest eigenvalue is that of "
        "`K_c^1/2 A_ic K_c^1/2`, `A_ic = G_ic M_i^-1 G_ic^T = 1/m_i + [p]x^T I_i^-1 [p]x` (the particle's part of "
        "the contact coefficient matrix, Peng et al. 2020 Section 3).  For a sphere with arm `R n`, "
        "`A_ic = (1/m) n n^T + (1/m + R^2/I)(1 - n n^T)` commutes with `K_c`: `lambda = max(kn/m, ks (1/m + R^2/I))`; "
        "for another shape `lambda <= max(kn, ks)(1/m + S)` with the arm supremum `S`.  Hence "
        "`lambda_K := lambda_max(M^-1/2 K M^-1/2) <= z max_(i, c) w_c lambda_ic`, and the same with the dashpots "
        "for `lambda_C`.",
        "",
        "**Step 2 (damping, any C).**  Each scheme evaluates the force once per step, at fixed scalar combinations "
        "of its stored state (`dtcrit.integrators.schemes`), so eliminating the state from an eigenvector of the "
        "whole packing's update gives `P(z) u = 0` with `P(z) = M p(z) + h C q(z) + h^2 K r(z)`, `p, q, r` the "
        "scalar coefficients of the one-mode characteristic polynomial (which is therefore affine in K and C).  "
        "Then `u* P(z) u = m p(z) + h c q(z) + h^2 k r(z) = 0` with `(m, c, k) = (u*Mu, u*Cu, u*Ku)`: every "
        "eigenvalue of the packing is an eigenvalue of one mode with `c/m <= lambda_C`, `k/m <= lambda_K`.  If "
        "that mode's stable set in `(c/m, k/m)` is closed downwards, the one-mode step at `(lambda_C, lambda_K)` "
        "is stable for the packing: proportional damping or not.",
        "",
        "## Which integrators (symbolic, from the update rules)",
        "",
        "| integrator | polynomial affine in K and C | P(-1) in (k~, c~) = (h^2 K, h C) | covered |",
        "| --- | --- | --- | --- |",
    ]
    for name in NAMES:
        affine = affine_in_k_and_c(name)
        out.append(f"| `{name}` | {'yes' if affine else 'no'} | {stable_region(name)} | "
                   f"{'yes' if name in DENSE_SCHEMES else 'no'} |")
    out += [
        "",
        "The stable set is bounded by the root at -1 (the exact boundaries of `sec4_stability.md`): "
        "`k~ + 2 c~ <= 4` for symplectic Euler, leapfrog and velocity Verlet, `k~ + 4 c~ <= 4` for velocity "
        "Verlet with a predicted velocity, `k~ <= 4` for centred damping: all closed downwards.  Forward Euler "
        "and the paper's Eq. (40) scheme are unstable undamped (their stable sets do not contain `c~ = 0`): no "
        "bound for them.  `tests/test_step_dense.py` checks every covered scheme on a damped, non-proportional "
        "packing against the spectral radius of the whole packing's update-rule matrix.",
        "",
        "## Against the exact global step (velocity Verlet, undamped)",
        "",
        "`dtcrit.packing` assembles the packing's 6-DOF `K` and `M` and solves for the largest eigenvalue "
        "(an independent route); the scene gives the packing's sizes and `coordination_max` = its largest "
        "coordination.  `tests/test_step_dense.py` checks `dense <= exact` on these and more packings, and the "
        "damped, non-proportional case against the spectral radius of the whole packing's update-rule matrix.",
        "",
        "| packing | bound | dt_dense / dt_exact | dt_isolated / dt_exact |",
        "| --- | --- | --- | --- |",
    ]
    rows = ratio_rows()
    for label, dense, iso, how in rows:
        out.append(f"| {label} | {how} | {num(dense, 4)} | {num(iso, 4)} |")
    dense = sorted(r[1] for r in rows)
    iso = sorted(r[2] for r in rows)
    out += [
        "",
        f"dt_dense / dt_exact over {len(rows)} cases: min {num(dense[0], 4)}, median {num(dense[len(dense) // 2], 4)}, "
        f"max {num(dense[-1], 4)} (never above 1).  The isolated-contact step is above the exact one in every case: "
        f"min {num(iso[0], 4)}, median {num(iso[len(iso) // 2], 4)}, max {num(iso[-1], 4)}.",
        "",
        "`sphere`: the geometric sphere-packing bound (step 0), used for sphere-only scenes without walls with at "
        "most six sizes; `block`: step 1 alone (here the polydisperse packings, whose 64 sizes are each a species).  "
        "What remains of the gap is the price of a bound that holds for every arrangement of z contacts: the worst "
        "arrangement is not the lattice (the proof's section 7 gives the sharpness of each piece).",
        "",
        "",
    ]
    return "\n".join(out)


if __name__ == "__main__":
    print(build())
