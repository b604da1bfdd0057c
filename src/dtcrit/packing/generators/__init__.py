"""Packings made in Python: regular lattices and random packings.

Modules: ``lattices`` (simple cubic, BCC, FCC, HCP), ``random_packing`` (a size distribution and a coordination).
"""
