"""Readers of engine files: LAMMPS/LIGGGHTS dumps and local dumps, contact tables, ``dtcrit-bodies/1`` files, YADE exports.

Modules: ``lammps_dump`` (text dumps, read one snapshot at a time), ``contact_tables`` (``--contacts`` tables and
``--local`` dumps), ``bodies_file`` and ``bodies_values`` (``dtcrit-bodies/1``), ``yade_export`` and ``yade_clumps``
(``dtcrit-yade-export/1``), ``limits`` (the range of numbers a read packing may carry).
"""
