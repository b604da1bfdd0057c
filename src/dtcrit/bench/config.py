"""Sizes and repeats of a bench run (``dtcrit bench``): the quick configuration and the full one.

Used by :mod:`dtcrit.bench.runner`; ``--quick`` selects ``QUICK``, otherwise ``FULL_RUN``.
"""
from __future__ import annotations

from dataclasses import dataclass

from dtcrit.integrators.schemes import NAMES


@dataclass(frozen=True)
class BenchConfig:
    """Sizes and repeats of a bench run.

    Parameters
    ----------
    quick : bool
        The quick configuration.
    n_batch : int
        Scenes timed by the vectorised closed forms (and the floor kernel).
    n_eig : int
        Scenes timed by the per-scene and bisection routes.
    n_ref : int
        Reference sample: errors of every route but mpmath's.
    n_mp : int
        Scenes per integrator for the mpmath routes.
    mp_suite_cases : tuple of str or None
        Suite cases for the mpmath routes (None: all).
    mp_integrators : tuple of str or None
        Integrators for the mpmath routes (None: all).
    sim_budget : int
        Most steps of one simulation run.
    repeats : int
        Timing repeats (best is kept).
    startup_repeats : int
        Fresh-interpreter runs of ``dtcrit step`` per example scene.
    integrators : tuple of str
        Schemes benched.
    seed : int
        Seed of the random scenes.
    """

    quick: bool
    n_batch: int  # scenes timed by the vectorised closed forms (and the floor kernel)
    n_eig: int  # scenes timed by the per-scene and bisection routes
    n_ref: int  # reference sample: errors of every route but mpmath's
    n_mp: int  # scenes per integrator for the mpmath routes
    mp_suite_cases: tuple[str, ...] | None  # suite cases for the mpmath routes (None: all)
    mp_integrators: tuple[str, ...] | None  # integrators for the mpmath routes (None: all)
    sim_budget: int  # most steps of one simulation run
    repeats: int
    startup_repeats: int = 5  # fresh-interpreter runs of `dtcrit step` per example scene
    integrators: tuple[str, ...] = NAMES
    seed: int = 20200501


QUICK = BenchConfig(
    quick=True, n_batch=20_000, n_eig=200, n_ref=120, n_mp=1,
    mp_suite_cases=("steel-1mm", "critical-exact", "zeta-1e6", "kA-overflow"),
    mp_integrators=("velocity-verlet", "forward-euler"),
    sim_budget=8_192, repeats=3, startup_repeats=3,
)
FULL_RUN = BenchConfig(
    quick=False, n_batch=1_000_000, n_eig=20_000, n_ref=2_000, n_mp=4,
    mp_suite_cases=None, mp_integrators=None, sim_budget=400_000, repeats=5, startup_repeats=10,
)
