"""Defaults of generated packings, one home for the library and the command line.

A module of constants only, so that building ``dtcrit``'s parsers (every command builds them all)
does not import the packing analysis.
"""

DEFAULT_DENSITY = 2650.0
"""Particle density of generated packings [kg/m^3] (quartz)."""
DEFAULT_RADIUS = 1.0e-3
"""Sphere (median) radius of generated packings [m]."""
