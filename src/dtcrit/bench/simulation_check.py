"""Stability by direct simulation on the extreme-case suite (section 3 of the benchmark).

For every suite case and integrator the contact system is stepped with the integrator's own
update rule (``dtcrit.integrators.simulate.run``, scaled units omega = 1, so inputs whose k A or c A would
overflow are simulated as well) at 0.99 and 1.01 times the exact critical step ``tau*`` (the
50-digit reference), and the outcome is recorded:

``agrees``             bounded at 0.99 tau* (late/early amplitude <= ``BOUNDED``) and growing at
                       1.01 tau* (>= ``GROWING``);
``disagrees``          anything else where growth was observable -- a bug to find;
``no-stable-step``     tau* = 0 (no step is stable) and the run grows at ``tau = TAU_PROBE``;
``unobservable``       the spectral radius at 1.01 tau* is so close to 1 that a growth factor of
                       ``GROWING`` needs more than the step budget (the row says how many steps);
(a damping ratio beyond float64 even in scaled units -- zeta ~ 5e444 -- is stepped in mpmath
with the same update rule; the row's note says so.)

Each run starts from (x, v) = (1, 0) and from (0, v0) and takes the larger growth (``_growth``).
The number of steps comes from the spectral radius at 1.01 tau* (``mpmath.eig`` of the matrix
built from the update rule, 30 or 80 digits): n = 2 ln(GROWING) / ln(rho) + 64, at least 256.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import mpmath as mp
import numpy as np

from dtcrit.bench.amplification import spectral_radius_mp
from dtcrit.integrators.schemes import INTEGRATORS, LinearForce
from dtcrit.integrators.simulate import run

BOUNDED = 2.0
GROWING = 100.0
TAU_PROBE = 0.1
MIN_STEPS = 256


@dataclass(frozen=True)
class SimulationRow:
    """One (case, integrator) row of the simulation check: the exact tau* against simulated growth.

    Parameters
    ----------
    case : str
        Suite case.
    integrator : str
        Name of the scheme.
    tau_crit : float
        The critical tau*.
    zeta : float
        Damping ratio.
    rho_above_minus_1 : float
        Spectral radius - 1 at 1.01 tau* (or at ``TAU_PROBE`` when tau* = 0).
    n_steps : int
        Steps simulated (or needed, when unobservable).
    growth_below : float
        Late/early amplitude at 0.99 tau* (NaN when not run).
    growth_above : float
        Late/early amplitude at 1.01 tau* (or at ``TAU_PROBE``).
    outcome : str
        Whether the simulation agrees with tau*.
    note : str
        Explanation of the outcome.
    """

    case: str
    integrator: str
    tau_crit: float
    zeta: float
    rho_above_minus_1: float  # spectral radius - 1 at 1.01 tau* (or at TAU_PROBE when tau* = 0)
    n_steps: int  # steps simulated (or needed, when unobservable)
    growth_below: float  # late/early amplitude at 0.99 tau* (nan when not run)
    growth_above: float  # late/early amplitude at 1.01 tau* (or at TAU_PROBE)
    outcome: str
    note: str = ""


def _steps_for(rho_minus_one: float) -> float:
    if not rho_minus_one > 0.0:
        return math.inf
    return 2.0 * math.log(GROWING) / math.log1p(rho_minus_one) + 64


def _growth(name: str, tau_below: np.ndarray, tau_above: np.ndarray, zeta: np.ndarray, n: int):
    """(growth at tau_below, growth at tau_above): the larger late/early amplitude over two
    initial states, (x, v) = (1, 0) and (0, v0), all four runs in one vectorised call.

    One initial state may leave a mode almost unexcited: with heavy damping the fast (unstable)
    mode is almost pure velocity, and (1, 0) excites it only by ~tau, which needs ~ln(1/tau)/ln(rho)
    steps to show.  Starting from both makes every mode visible within the step count.  v0 = 1
    for the two-variable schemes; for the schemes that store the acceleration a0 = -2 zeta v0,
    v0 = 1/max(1, 2 zeta) keeps |a0| <= 1 (the growth ratio does not depend on the scale, and the
    state norm must not overflow when zeta is ~1e290).
    """
    m = zeta.size
    v0 = np.ones(m) if len(INTEGRATORS[name].state) == 2 else 1.0 / np.maximum(1.0, 2.0 * zeta)
    tau = np.concatenate([tau_below, tau_below, tau_above, tau_above])
    z = np.tile(zeta, 4)
    x0 = np.tile(np.concatenate([np.ones(m), np.zeros(m)]), 2)
    v0 = np.tile(np.concatenate([np.zeros(m), v0]), 2)
    g = run(name, tau, z, n, x0=x0, v0=v0).growth.reshape(4, m)  # type: ignore[arg-type]  # run broadcasts array starts
    return np.maximum(g[0], g[1]), np.maximum(g[2], g[3])


def _rho_minus_one(name: str, tau: float, zeta) -> float:
    """The excess rho - 1 at 30 digits (at 80 when it is within 1e-25 of 0), rho the spectral radius."""
    for dps in (30, 80):
        with mp.workdps(dps):
            d = spectral_radius_mp(name, mp.mpf(tau), mp.mpf(zeta)) - 1
            if abs(d) > mp.mpf(10) ** -25 or dps == 80:
                return float(d)
    raise AssertionError("the 80-digit pass always returns")


def _growth_mp(name: str, tau, zeta, n: int, x0, v0):
    """Late/early amplitude of the update rule iterated in mpmath (30 digits): for damping ratios
    beyond float64 even in scaled units.  No renormalisation is needed (unbounded exponent).
    """
    integ = INTEGRATORS[name]
    with mp.workdps(30):
        f = LinearForce(mp.mpf(1), 2 * mp.mpf(zeta))
        x, v = mp.mpf(x0), mp.mpf(v0)
        state = (x, v) if len(integ.state) == 2 else (x, v, f(x, v))
        quarter = max(1, n // 4)
        early = late = mp.mpf(0)
        for i in range(n):
            state = integ.step(state, mp.mpf(tau), f)
            norm = mp.sqrt(sum(s * s for s in state))
            if i < quarter:
                early = max(early, norm)
            if i >= n - quarter:
                late = max(late, norm)
        return late / early


def _row_in_mpmath(case: str, name: str, tau_exact, zeta_exact, budget: int) -> SimulationRow:
    """The section-3 check for a damping ratio beyond float64: stepped in mpmath."""
    rho = _rho_minus_one(name, 1.01 * tau_exact, zeta_exact)
    need = _steps_for(rho)
    n = max(MIN_STEPS, int(min(need, budget, 4096)))
    v0 = 1 if len(INTEGRATORS[name].state) == 2 else 1 / max(mp.mpf(1), 2 * zeta_exact)
    with mp.workdps(30):
        gb = max(_growth_mp(name, 0.99 * tau_exact, zeta_exact, n, 1, 0), _growth_mp(name, 0.99 * tau_exact, zeta_exact, n, 0, v0))
        ga = max(_growth_mp(name, 1.01 * tau_exact, zeta_exact, n, 1, 0), _growth_mp(name, 1.01 * tau_exact, zeta_exact, n, 0, v0))
    gb, ga = float(gb), float(ga) if ga < mp.mpf(10) ** 300 else math.inf
    ok = gb <= BOUNDED and ga >= GROWING
    outcome = "agrees" if ok else ("unobservable" if need > n and gb <= BOUNDED else "disagrees")
    note = (f"zeta = {mp.nstr(zeta_exact, 3)} is beyond float64: stepped in mpmath (30 digits) for {n} steps; "
            f"growth {gb:.3g} at 0.99 tau*, {ga:.3g} at 1.01 tau*")
    if outcome == "unobservable":
        small = f"{rho:.2e}" if rho > 0 else "below 1e-80"
        note += f"; rho(1.01 tau*) - 1 = {small}: a growth of {GROWING:g} needs ~{need:.3g} steps"
    return SimulationRow(case, name, float(tau_exact), math.inf, rho, n, gb, ga, outcome, note)


def check(cases, integrators, tau_ref: dict, zeta_ref: dict, budget: int) -> list[SimulationRow]:
    """Rows for every (case, integrator).  ``tau_ref[(case, integrator)]`` is tau* (mpmath or float),
    ``zeta_ref[case]`` the exact damping ratio (mpmath).  ``budget``: most steps per run.

    Unobservable rows are still stepped for ``budget`` steps: the run at 0.99 tau* must stay
    bounded (else the row ``disagrees``), and both growth factors are recorded.

    Parameters
    ----------
    cases : sequence
        Suite cases.
    integrators : sequence of str
        Schemes.
    tau_ref : dict
        tau* per ``(case, integrator)``.
    zeta_ref : dict
        Exact damping ratio per case.
    budget : int
        Most steps per run.

    Returns
    -------
    list of SimulationRow
        One row per (case, integrator).
    """
    plan = []  # (case, name, tau*, zeta float, rho - 1, steps needed, steps run)
    rows: list[SimulationRow] = []
    for case in cases:
        z_exact = zeta_ref[case.name]
        z = float(z_exact)
        for name in integrators:
            t = float(tau_ref[(case.name, name)])
            if not math.isfinite(z):
                rows.append(_row_in_mpmath(case.name, name, tau_ref[(case.name, name)], z_exact, budget))
                continue
            rho = _rho_minus_one(name, 1.01 * t if t > 0 else TAU_PROBE, z)
            need = _steps_for(rho)
            plan.append((case.name, name, t, z, rho, need, max(MIN_STEPS, int(min(need, budget)))))
    # one vectorised run per integrator and step count (rounded up to a power of two, within budget)
    groups: dict[tuple[str, int], list[int]] = {}
    for i, p in enumerate(plan):
        n = p[6]
        groups.setdefault((p[1], min(budget, 1 << (n - 1).bit_length())), []).append(i)
    results: dict[int, tuple[float, float, int]] = {}
    for (name, n), idx in groups.items():
        taus = np.array([plan[i][2] for i in idx])
        zs = np.array([plan[i][3] for i in idx])
        positive = taus > 0
        g_below, g_above = _growth(name, 0.99 * taus, np.where(positive, 1.01 * taus, TAU_PROBE), zs, n)
        g_below[~positive] = np.nan
        for j, i in enumerate(idx):
            results[i] = (float(g_below[j]), float(g_above[j]), n)
    for i, (case, name, t, z, rho, need, _) in enumerate(plan):
        gb, ga, n = results[i]
        where = "1.01 tau*" if t > 0 else f"tau = {TAU_PROBE}"
        if need > budget and not (t > 0 and gb <= BOUNDED and ga >= GROWING):
            ok = not (t > 0) or gb <= BOUNDED
            outcome = "unobservable" if ok else "disagrees"
            small = f"{rho:.2e}" if rho > 0 else "below 1e-80"
            note = (f"rho({where}) - 1 = {small}: a growth of {GROWING:g} needs ~{need:.3g} steps (> budget {budget}); "
                    f"after {n} steps: growth {gb:.3g} at 0.99 tau*, {ga:.3g} at {where}")
        elif t > 0:
            ok = gb <= BOUNDED and ga >= GROWING
            outcome = "agrees" if ok else "disagrees"
            note = "" if ok else f"growth {gb:.3g} at 0.99 tau*, {ga:.3g} at 1.01 tau*"
        else:
            ok = ga >= GROWING
            outcome = "no-stable-step" if ok else "disagrees"
            note = f"tau* = 0; growth {ga:.3g} at tau = {TAU_PROBE}"
        rows.append(SimulationRow(case, name, t, z, rho, n, gb, ga, outcome, note))
    order = {(c.name, n): i for i, (c, n) in enumerate((c, n) for c in cases for n in integrators)}
    rows.sort(key=lambda r: order[(r.case, r.integrator)])
    return rows
