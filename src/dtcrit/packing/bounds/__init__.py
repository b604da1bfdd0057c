"""Cheap estimates and rigorous bounds on the critical step of a packing, rated against the exact step.

Modules: ``estimates`` (Gershgorin, block and diagonal bounds, Rayleigh trials, the two-particle bound),
``rayleigh_trials`` (Rayleigh-quotient trials: a lower bound on the top eigenvalue), ``estimate_kernels`` (compiled single-contact frequencies),
``yade_stepper`` (YADE's GlobalStiffnessTimeStepper as it runs, clumps included), ``yade_stepper_export`` (its
input read from a YADE export).
"""
