"""Scenes: the TOML description of a DEM simulation's contacts (``scene``, ``fields``, ``model``),
the ``dtcrit step`` API (``timestep``) and the estimates other DEM codes use (``code_estimates``; their
formulas and the contact physics are ``dtcrit.physics``); ``local_damping`` (the keys ``local_damping``,
``local_damping_law``: the step times ``1/sqrt(1 + alpha)``).
``collide``: the ``dtcrit collide`` report (the step that resolves each collision of a scene,
``dtcrit.collisions``).
``keys``: the scene-key registry (every key of every table, described; the reference pages are generated
from it).

Runtime only (NumPy; SciPy on first use for polyhedra): scenes import ``bodies`` and
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
