"""Shared helpers of the test suite, imported as ``support.*``.

``pythonpath = ["tests"]`` in the pytest configuration puts this package on the import path; test
modules are imported with ``--import-mode=importlib``, so two test files of the same name in two
folders of the mirrored tree do not clash.

Modules
-------
paths
    Repository root, ``examples/``, ``src/``, ``derivations/``.
ci
    Whether the run is under CI (a missing compiler or engine fails there instead of skipping).
precision
    Units in the last place against an mpmath (or exact) reference.
hypothesis_profiles
    The seeded hypothesis profiles (``ci``, ``dev``, ``thorough``).
amplification, multidof
    Direct amplification-matrix routes built numerically from the integrators' update rules.
codegen
    Compile and call emitted C, Fortran and NumPy kernels.
engines
    Run real DEM engines (LAMMPS, YADE) on small cases.
golden
    Compare command output with the golden files (numbers at a relative tolerance).
json_keys, packing_scene, records_compare, scenes
    Small helpers shared by two or more test modules.
"""
