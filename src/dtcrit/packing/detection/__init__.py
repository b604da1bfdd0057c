"""Contact detection: spheres by overlap (``scipy.spatial.cKDTree``), convex bodies and clumps.

Modules: ``overlaps`` (spheres and convex shapes), ``sphere_fields`` (the fields of touching sphere pairs),
``body_contacts`` (bodies and clumps of a ``dtcrit-bodies/1`` file),
``walls`` (the particles touching a LAMMPS ``fix wall/gran`` plane or cylinder).
"""
