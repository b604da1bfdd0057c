"""Engine conventions: how each DEM code turns a pair style or its contact model into per-contact springs and dashpots.

Modules: ``engines`` (contact arms and pre-load per engine), ``pair_styles`` (LAMMPS/LIGGGHTS ``gran/*``),
``granular_style`` (LAMMPS ``pair_style granular``), ``law_terms`` (the per-contact terms a law gives),
``liggghts_input`` (a LIGGGHTS input's ``pair_style gran`` and ``fix property/global`` materials),
``liggghts_law`` (LIGGGHTS's law per contact, from the atom types),
``lammps_walls`` (LAMMPS ``fix wall/gran`` lines as wall contacts).
"""
