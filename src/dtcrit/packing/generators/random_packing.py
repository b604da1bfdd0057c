"""Random sphere packings with a chosen size distribution and mean coordination number.

Algorithm (all steps vectorised; neighbour search with ``scipy.spatial.cKDTree``):

1. **Sizes.**  ``n`` radii drawn from the distribution: ``"mono"`` (all ``radius``), ``"uniform"``
   (``radius * U(1 - spread, 1 + spread)``) or ``"lognormal"`` (``ln R ~ N(ln radius, spread^2)``,
   truncated to ``radius * exp(+-3 spread)``).
2. **Random placement.**  Centres uniform in a periodic cube sized so that the spheres' volume
   fraction is ``fraction`` (default 0.66, a little above random close packing): random sequential
   addition without rejection, so the spheres overlap heavily at first.
3. **Overlap relaxation.**  The harmonic overlap energy ``sum 1/2 (R_i + R_j - d_ij)^2`` is
   minimised with FIRE (the fast inertial relaxation engine: damped dynamics that mixes the velocity
   toward the force and restarts when the power turns negative) on a Verlet neighbour list with
   a skin, until the largest residual force is below ``force_tol * radius`` or ``max_steps``.
   Because the fraction exceeds jamming, the result is a mechanically stable, disordered packing
   with small overlaps (a few per cent of a radius).
4. **Coordination control.**  With the centres fixed, every radius is scaled by one factor ``s``.
   The number of contacts after scaling is the number of pairs with ``d_ij / (R_i + R_j) < s``, so
   ``s`` is put midway between the ``t``-th and ``(t+1)``-th smallest ratio, with
   ``t = round(cn * n / 2)``: the mean coordination number ``2 t / n`` matches the target to within
   ``1/n``.  Masses follow from the scaled radii and the density.

Rattlers (spheres without contacts) can remain; they only add zero eigenvalues.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dtcrit.errors import InputError

from dtcrit.packing.detection.overlaps import _candidate_pairs, wrap_positions
from dtcrit.packing.model import Box, Packing

DISTRIBUTIONS = ("mono", "uniform", "lognormal")
SECONDS_PER_SPHERE_STEP = 4.5e-6
"""Measured cost of one FIRE step per sphere (100,000 mono spheres: 250 steps in 112 s on the 2-core
development machine, shared): ``generation_seconds`` scales it."""
PROGRESS_SPHERES = 20_000  # from this size on, the relaxation draws a tqdm bar on a terminal


def generation_seconds(n: int, max_steps: int = 250) -> float:
    """Estimated wall time [s] of ``random_packing(n)``: the FIRE relaxation dominates (at most
    ``max_steps`` steps, each linear in ``n``).
    """
    return SECONDS_PER_SPHERE_STEP * float(n) * float(max_steps)


def spatial_order(x: np.ndarray, cell: float) -> np.ndarray:
    """Rows of ``x`` sorted along a space-filling order of cells of side ``cell`` (cache locality:
    neighbours end up close in memory, which makes the gathers of large packings several times
    faster).
    """
    c = np.floor((x - x.min(axis=0)) / cell).astype(np.int64)
    # snake (boustrophedon) order over z, y, x keeps consecutive cells adjacent
    cy = np.where(c[:, 2] % 2 == 1, c[:, 1].max() - c[:, 1], c[:, 1])
    cx = np.where((c[:, 2] * (c[:, 1].max() + 1) + cy) % 2 == 1, c[:, 0].max() - c[:, 0], c[:, 0])
    return x[np.lexsort((cx, cy, c[:, 2]))]


def sample_radii(n: int, distribution: str, radius: float, spread: float, rng) -> np.ndarray:
    """``n`` radii from the named distribution (module docstring, step 1)."""
    if distribution == "mono":
        return np.full(n, radius)
    if distribution == "uniform":
        if not 0.0 <= spread < 1.0:
            raise InputError("spread", f"uniform sizes need 0 <= spread < 1, got {spread}")
        return radius * rng.uniform(1.0 - spread, 1.0 + spread, n)
    if distribution == "lognormal":
        if not 0.0 <= spread <= 1.5:
            raise InputError("spread", f"lognormal sizes need 0 <= spread <= 1.5 (sigma of ln R), got {spread}")
        z = rng.standard_normal(n)
        bad = np.abs(z) > 3.0
        while bad.any():  # truncate at three standard deviations by redrawing
            z[bad] = rng.standard_normal(int(bad.sum()))
            bad = np.abs(z) > 3.0
        return radius * np.exp(spread * z)
    raise InputError("sizes", f"unknown size distribution {distribution!r}; choose one of {', '.join(DISTRIBUTIONS)}")


@dataclass
class RelaxationStats:
    """How the overlap relaxation of a random packing ended.

    Attributes
    ----------
    steps : int
        Relaxation steps taken.
    max_force : float
        Largest overlap force on a particle at the end (relaxation units).
    max_overlap : float
        Largest remaining overlap at the end (length units of the packing).
    """

    steps: int
    max_force: float
    max_overlap: float


def _overlap_forces(xt, i, j, offset, sum_r):
    """Overlap forces, coordinates stored as rows ``xt`` (3, n): per-axis gathers are the fast
    memory pattern for large packings.
    """
    sep = [xt[a][j] - xt[a][i] + offset[a] for a in range(3)]
    d = np.sqrt(sep[0] * sep[0] + sep[1] * sep[1] + sep[2] * sep[2])
    over = sum_r - d
    on = np.flatnonzero(over > 0)
    n = xt.shape[1]
    force = np.zeros_like(xt)
    if on.size == 0:
        return force, 0.0
    over_on = over[on]
    scale = over_on / np.maximum(d[on], 1e-12 * sum_r[on])
    ii, jj = i[on], j[on]
    for a in range(3):
        f = sep[a][on] * scale  # pushes j away from i along the centre line
        force[a] = np.bincount(jj, weights=f, minlength=n) - np.bincount(ii, weights=f, minlength=n)
    return force, float(over_on.max())


def relax_overlaps(x, r, box: Box, *, force_tol: float = 1e-3, max_steps: int = 250) -> tuple[np.ndarray, RelaxationStats]:
    """FIRE minimisation of the harmonic overlap energy (module docstring, step 3)."""
    x = wrap_positions(x, box)
    lengths = box.lengths
    scale = float(np.mean(r))
    skin = 0.6 * scale
    max_move = 0.1 * scale  # cap on any sphere's move in one step (keeps the early steps tame)
    cutoff = 2.0 * float(r.max()) + skin

    def neighbours(xt):
        x = wrap_positions(xt.T, box)
        i, j, image = _candidate_pairs(x, cutoff, box)
        sep = x[j] + image * lengths - x[i]
        near = np.einsum("ij,ij->i", sep, sep) < (r[i] + r[j] + skin) ** 2
        i, j, image = i[near], j[near], image[near]
        return np.ascontiguousarray(x.T), i, j, np.ascontiguousarray((image * lengths).T), r[i] + r[j]

    from tqdm import tqdm

    dt, dt_max, alpha = 0.05, 0.25, 0.1
    xt, i, j, offset, sum_r = neighbours(np.ascontiguousarray(x.T))
    v = np.zeros_like(xt)
    ref = xt.copy()
    positive = 0
    max_over = np.inf
    fmax = np.inf
    step = 0
    # tqdm draws only on a terminal (disable=None), and only for large packings
    steps = tqdm(range(1, max_steps + 1), desc="random packing: relaxation", unit=" steps", leave=False,
                 disable=None if x.shape[0] >= PROGRESS_SPHERES else True)
    for step in steps:
        if np.max(np.abs(xt - ref)) > 0.5 * skin:
            xt, i, j, offset, sum_r = neighbours(xt)
            ref = xt.copy()
        force, max_over = _overlap_forces(xt, i, j, offset, sum_r)
        fmax = float(np.sqrt((force * force).sum(axis=0).max()))
        if fmax < force_tol * scale:
            break
        power = float(np.vdot(force, v))
        if power > 0:
            vnorm = np.sqrt(np.vdot(v, v))
            fnorm = np.sqrt(np.vdot(force, force))
            v *= 1.0 - alpha
            v += (alpha * vnorm / fnorm) * force
            positive += 1
            if positive > 5:
                dt = min(dt * 1.1, dt_max)
                alpha *= 0.99
        else:
            v[:] = 0.0
            dt *= 0.5
            alpha = 0.1
            positive = 0
        v += force * dt
        move = v * dt
        biggest = float(np.abs(move).max())
        if biggest > max_move:
            move *= max_move / biggest
        xt += move
    steps.close()
    return wrap_positions(xt.T, box), RelaxationStats(step, fmax, max_over)


def scale_to_coordination(x, r, box: Box, cn: float) -> tuple[float, int]:
    """Radius factor ``s`` giving mean coordination ``cn`` and the resulting contact count."""
    n = x.shape[0]
    target = int(round(cn * n / 2.0))
    if target < 0:
        raise InputError("cn", f"must be >= 0, got {cn}")
    if target == 0:
        return 0.5 * _smallest_ratio(x, r, box), 0
    factor = 1.25
    while True:
        i, j, image = _candidate_pairs(x, 2.0 * float(r.max()) * factor, box)
        sep = x[j] + image * box.lengths - x[i]
        ratio = np.sqrt(np.einsum("ij,ij->i", sep, sep)) / (r[i] + r[j])
        ratio = np.sort(ratio[ratio < factor])
        if ratio.size > target:
            return 0.5 * (ratio[target - 1] + ratio[target]), target
        if factor > 2.0:
            raise InputError("cn", f"mean coordination {cn} is out of reach for this packing")
        factor *= 1.25


def _smallest_ratio(x, r, box) -> float:
    i, j, image = _candidate_pairs(x, 4.0 * float(r.max()), box)
    sep = x[j] + image * box.lengths - x[i]
    return float((np.sqrt(np.einsum("ij,ij->i", sep, sep)) / (r[i] + r[j])).min())


def random_packing(n: int, *, cn: float = 6.0, sizes: str = "mono", radius: float = 1.0, spread: float = 0.0,
                   density: float = 1.0, fraction: float = 0.66, seed: int = 0, force_tol: float = 1e-3,
                   max_steps: int = 250) -> Packing:
    """A random periodic sphere packing with mean coordination ``cn`` (module docstring)."""
    n = int(n)
    if n < 2:
        raise InputError("n", f"a random packing needs at least 2 spheres, got {n}")
    for key, value in (("radius", radius), ("density", density), ("fraction", fraction)):
        if not np.isfinite(value) or value <= 0:
            raise InputError(key, f"must be a positive finite number, got {value}")
    if fraction >= 0.74:
        raise InputError("fraction", f"must be below 0.74, got {fraction}")
    if not np.isfinite(cn) or cn < 0 or cn > 14:
        raise InputError("cn", f"mean coordination number must lie in [0, 14], got {cn}")
    if not np.isfinite(spread) or spread < 0:
        raise InputError("spread", f"must be a finite number >= 0, got {spread}")
    if isinstance(seed, (bool, float)) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError("seed", f"must be a whole number >= 0, got {seed!r}")
    rng = np.random.default_rng(seed)
    r = sample_radii(n, sizes, float(radius), float(spread), rng)
    with np.errstate(over="ignore", under="ignore"):
        length = float(np.cbrt((4.0 / 3.0) * np.pi * np.sum(r**3) / fraction))
        mass = float(density * (4.0 / 3.0) * np.pi * np.min(r) ** 3)
    if not (np.isfinite(length) and length > 0 and np.isfinite(mass) and mass > 0):
        raise InputError("radius", f"{radius:g} m spheres: the box or the masses (4/3 pi R^3 rho) leave the "
                                   "floating-point range")
    box = Box.cube(length)
    x = spatial_order(rng.uniform(0.0, length, (n, 3)), length / max(1, int(np.cbrt(n))))
    x, stats = relax_overlaps(x, r, box, force_tol=force_tol, max_steps=max_steps)
    s, _ = scale_to_coordination(x, r, box, cn)
    r = r * s
    label = f"random {sizes} packing, n = {n}, mean CN target {cn:g}, seed {seed}"
    packing = Packing.spheres(x, r, density=density, box=box, label=label)
    return packing
