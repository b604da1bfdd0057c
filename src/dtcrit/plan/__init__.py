"""``dtcrit plan``: what a simulation costs, and the least intrusive way to a larger step.

Density scaling with per-body mass and inertia factors whose critical step the exact eigen-solve of
the scaled packing (its contacts re-derived at the scaled masses) confirms at least the target
(starting from factors the Gershgorin and block-diagonal bounds prove give a critical step >= target), compared with YADE's ``densityScaling`` rule and a uniform factor; the
stiffness reduction that reaches the same step; the cost before and after.

Runtime layer (NumPy/SciPy): imports ``packing`` (the audit's snapshot reader and eigen-solve),
``physics`` and ``collisions``, never SymPy.

Modules: ``bounds`` (sufficient per-body factors), ``exact`` (the scaled packing's exact step and its
certified stability), ``density`` (:func:`plan_density_scaling`), ``stiffness`` (the stiffness
reduction), ``physics`` (size classes, inertial number, contact durations), ``report``
(:func:`dtcrit.plan.report.plan_snapshot`, the whole plan), ``output`` (text and JSON), ``dump``
(``--write-dump``), ``rederive`` (the contacts at the scaled masses, by the engine's law), ``resolution``
(the normal law and collision-damping model of a snapshot's contacts).
"""
from dtcrit.plan.density import DensityPlan, plan_density_scaling

__all__ = ["DensityPlan", "plan_density_scaling"]
