"""Readers of engine files: LAMMPS/LIGGGHTS dumps and local dumps, contact tables, ``dtcrit-bodies/1`` files, YADE exports.

Modules: ``lammps_dump`` (text dumps: a snapshot as a packing, writing dumps) and ``dump_stream`` (a dump
streamed one snapshot at a time, ``iter_dump``), ``dump_ranges`` (a dump read by byte ranges, for the partitioned
input), ``sphere_npz`` (the ``dtcrit-spheres/1`` binary sphere file, read by row slices), ``contact_tables`` (``--contacts`` tables and ``--local``
dumps), ``bodies_file``, ``bodies_array`` (its bodies as a packing) and ``bodies_values`` (``dtcrit-bodies/1``;
shapes by ``dtcrit.bodies.spec``),
``yade_export``, ``yade_clumps``, ``yade_walls`` (``dtcrit-yade-export/1``; its Wall and Facet bodies) and ``yade_terms`` (what the audit does with
each export field: modelled or refused), ``limits`` (the range of numbers a read
packing may carry).  Values are checked by ``dtcrit.inputs``; errors carry their location (source, line, key).
"""
