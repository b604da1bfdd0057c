"""Helpers of the derivation scripts (``derivations/<topic>.py``), which are not scripts themselves.

``text``: the number, formula and verdict text every record prints; ``kinematics_symbolic``: the
symbolic sections of ``sec2_3_kinematics.md``; ``stability_tools``, ``stability_schemes`` and
``stability_tables``: the helpers and sections of ``sec4_stability.md``.
"""
