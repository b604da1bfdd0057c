"""What a generated per-contact kernel has to cover, read off a scene.

The emitted function computes the critical step of *one contact* between two particles.  Its
shape depends only on the scene's structure, not on its numbers:

* ``identical``: one particle type, so one set of particle arguments serves both sides;
* ``sides``: per side ``"sphere"`` (the arm term r^2/I collapses to 5/(2 m), so A = 7/m for two
  identical spheres, Peng et al. 2020, Section 4.3) or ``"general"`` (mass, smallest principal
  moment, contact arm; plus all three principal moments when the rotation bound is emitted);
* ``damped_normal`` / ``damped_shear``: whether a viscous term exists in that direction;
* ``rotation``: whether the rotation-dominant bound (Eqs. (54), (56)) is emitted: ``omega_max``
  given and at least one side non-spherical (B_max = 0 for a sphere).
"""
from __future__ import annotations

from dataclasses import dataclass

from dtcrit.errors import InputError
from dtcrit.integrators.stability import check_integrator
from dtcrit.scenes.laws import resolve_pair

SIDE_KINDS = ("sphere", "general")


@dataclass(frozen=True)
class KernelStructure:
    """The structure of an emitted per-contact kernel: which arguments and terms it carries.

    Parameters
    ----------
    integrator : str
        Name of the integration scheme whose stability boundary the kernel evaluates.
    identical : bool
        Both particles of the contact are of one type (one set of particle arguments).
    sides : tuple of str
        Per side ``"sphere"`` or ``"general"`` (one entry when ``identical``, else two).
    damped_normal : bool
        The normal direction has a viscous term.
    damped_shear : bool
        The shear direction has a viscous term.
    rotation : bool
        The rotation-dominant bound (Peng et al. 2020, Eqs. (54), (56)) is emitted; needs a
        non-spherical side.

    Raises
    ------
    InputError
        When the integrator cannot be emitted, the sides do not match ``identical``, or ``rotation``
        is asked for spheres only.
    """

    integrator: str
    identical: bool
    sides: tuple[str, ...]  # one entry when identical, else two
    damped_normal: bool
    damped_shear: bool
    rotation: bool

    def __post_init__(self):
        check_integrator(self.integrator)
        from dtcrit.codegen.step import check_emittable

        check_emittable(self.integrator)  # a user-written scheme: refused in one line when it cannot be emitted
        if len(self.sides) != (1 if self.identical else 2) or any(s not in SIDE_KINDS for s in self.sides):
            raise InputError("sides", f"need {'one side' if self.identical else 'two sides'} from {SIDE_KINDS} (got {self.sides})")
        if self.rotation and "general" not in self.sides:  # B = 0 for spheres: no rotation bound to emit
            raise InputError("rotation", "the rotation-dominant bound needs a non-spherical side (B_max = 0 for a sphere)")

    @property
    def damped(self) -> bool:
        """Whether any direction has a viscous term."""
        return self.damped_normal or self.damped_shear

    def specialisations(self) -> list[str]:
        """What this structure leaves out compared with :func:`general_structure`.

        Returns
        -------
        list of str
            One sentence per specialisation, in the order the emitted header lists them.
        """
        out = []
        if self.identical:
            out.append("identical particles: one set of particle arguments")
        spheres = [n for n, s in enumerate(self.sides) if s == "sphere"]
        if spheres and len(spheres) == len(self.sides):
            out.append("spheres: exact modes A_n = 2/m, A_s = 7/m" if self.identical
                       else "spheres: exact modes A_n = 1/m1 + 1/m2, A_s = (7/2) (1/m1 + 1/m2)")
        elif spheres:
            out.append(f"particle {spheres[0] + 1} is a sphere: its arm term is 5/(2 m{spheres[0] + 1})")
        if not self.damped:
            out.append("undamped: no damping terms")
        elif not (self.damped_normal and self.damped_shear):
            out.append(f"no damping in the {'shear' if self.damped_normal else 'normal'} direction")
        if not self.rotation:
            out.append("no rotation-dominant bound (omega_max not given, or spheres only)")
        return out


def general_structure(integrator: str) -> KernelStructure:
    """Two different non-spherical particles, damped in both directions, with the rotation bound.

    Parameters
    ----------
    integrator : str
        Name of the integration scheme.

    Returns
    -------
    KernelStructure
        The structure with every argument and term, which covers any contact of that scheme.
    """
    return KernelStructure(integrator, False, ("general", "general"), True, True, True)


def structure_of_scene(scene) -> KernelStructure:
    """The structure a scene needs (``scene`` a :class:`dtcrit.scenes.model.Scene`).

    One kernel covers every particle-particle contact of the scene: all spheres (any number of
    types and sizes) give the exact sphere modes with two sides; otherwise at most two particle
    types.  Wall contacts are not emitted (the kernel is for a contact between two particles).

    Parameters
    ----------
    scene : dtcrit.scenes.model.Scene
        The parsed scene.

    Returns
    -------
    KernelStructure
        The smallest structure that serves every particle-particle contact of the scene.

    Raises
    ------
    InputError
        When the scene has more than two particle types, not all spheres.
    """
    kinds = ["sphere" if p.kind == "sphere" else "general" for p in scene.particles]
    sides: tuple[str, ...]
    if scene.identical:
        sides = (kinds[0],)
    elif all(k == "sphere" for k in kinds):
        sides = ("sphere", "sphere")
    elif len(kinds) > 2:
        raise InputError("particle", f"codegen emits the contact of one or two particle types, or of spheres of any "
                         f"number of types (this scene has {len(kinds)} types, not all spheres)")
    elif scene.pairs == "all" and kinds[0] != kinds[1]:
        # every pairing can occur: a sphere side cannot stand for the other type
        sides = ("general", "general")
    else:
        sides = tuple(kinds)
    contacts = [resolve_pair(scene, i, j) for i, j in scene.pair_numbers()]
    damped_n = any(c.cn > 0 for c in contacts)
    damped_s = any(c.cs > 0 for c in contacts)
    rotation = scene.omega_max is not None and any(s == "general" for s in sides)
    return KernelStructure(scene.integrator, len(sides) == 1, sides, damped_n, damped_s, rotation)
