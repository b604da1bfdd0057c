"""The particle block of a scene for the spheres of a packing (shared by the dense-bound tests)."""
import math

import numpy as np


def sphere_sizes_toml(packing) -> tuple[str, float]:
    """``(sizes, density)``: the scene lines of the packing's distinct radii (equal number fractions)
    and its density, from the first sphere's mass."""
    radii = np.unique(np.round(packing.radii, 15))
    density = float(packing.masses[0] / (4 / 3 * math.pi * packing.radii[0] ** 3))
    if radii.size == 1:
        return f"radius = {float(radii[0])!r}\n", density
    fr = np.full(radii.size, 1.0 / radii.size)
    fr[-1] = 1.0 - fr[:-1].sum()
    return f"radii = {[float(r) for r in radii]!r}\nfractions = {[float(f) for f in fr]!r}\n", density
