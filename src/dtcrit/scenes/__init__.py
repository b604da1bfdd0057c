"""Scenes: the TOML description of a DEM simulation's contacts (``scene``, ``fields``, ``model``;
``contact_table``: the ``[contact]`` table),
the ``dtcrit step`` API (``timestep``) and the estimates other DEM codes use (``code_estimates``; their
formulas and the contact physics are ``dtcrit.physics``); ``local_damping`` (the keys ``local_damping``,
``local_damping_law``: the step times ``1/sqrt(1 + alpha)``).
``collide``: the ``dtcrit collide`` report (the step that resolves each collision of a scene,
``dtcrit.collisions``); ``law_damping``: Hertz damping conventions that name one code's collision law
(LAMMPS ``granular``, YADE Mindlin, MercuryDPM), their keys and dashpots; ``collide_oblique``: its
oblique impacts (``[collision] angle_deg`` or ``tangential_ratio``).  ``dense_tables``: the dense-packing
bound's branch-and-bound values for known cases, shipped as generated data
(``_generated/dense_phi_nodes.json``).
``keys``: the scene-key registry (every key of every table, described; the reference pages are generated
from it).

Runtime only (NumPy; SciPy on first use for polyhedra of more than 40 corners): scenes import ``bodies`` and
``integrators``, never ``symbolic``.
"""
from dtcrit.physics.damping_conventions import damping_ratio_from_restitution
from dtcrit.physics.contact_laws import hertz_max_overlap
from dtcrit.scenes.model import ContactLaw, PairContact, Particle, Scene
from dtcrit.scenes.scene import load_scene, parse_scene, scene_from_dict

__all__ = [
    "Scene",
    "Particle",
    "ContactLaw",
    "PairContact",
    "load_scene",
    "parse_scene",
    "scene_from_dict",
    "damping_ratio_from_restitution",
    "hertz_max_overlap",
]
