"""Contacts of a packing of convex bodies and clumps (``dtcrit.packing.readers.bodies_file``).

A clump is its member spheres: members of different bodies meet like convex bodies, the arms are
measured from the clump's centre of mass, and members of one clump never touch each other.  Two
spheres (free spheres or clump members) meet along their centre line, ``delta = R_1 + R_2 - d``,
contact point ``x_1 + (R_1 - delta/2) n`` (``dtcrit.packing.detection.overlaps``), computed for all such
pairs at once; any other pair by the support-function penetration
(``dtcrit.packing.detection.overlaps.convex_penetration``: normal along the minimum-translation direction,
contact point halfway between the two deepest support points), which for two spheres gives the
same point.  A packing of spheres only is a sphere packing and goes to ``find_sphere_contacts``.

Candidates come from the parts' bounding spheres; periodic axes use the box's images as for
spheres (sheared cells included: ``dtcrit.packing.periodic_cell``).  The one-pair-at-a-time penetration reports its progress on standard error (when that is
a terminal) once it has run for ``PROGRESS_AFTER`` seconds.
"""
from __future__ import annotations

import math
import sys
import time

import numpy as np

from dtcrit.errors import InputError
from dtcrit.packing.detection.overlaps import _candidate_pairs, convex_penetration, find_sphere_contacts, wrap_positions
from dtcrit.packing.model import Contacts, Packing
from dtcrit.packing.periodic_cell import image_of, own_images

PROGRESS_AFTER = 2.0
"""Seconds of pair-by-pair penetration after which progress is shown (then every as many)."""


class Progress:
    """``done/total`` of a long loop on standard error, rewritten in place.

    Drawn only when the stream is a terminal and the loop has run for ``after`` seconds (then every
    ``after`` seconds); :meth:`close` ends the line.

    Parameters
    ----------
    what : str
        Name of the loop, printed before the count.
    total : int
        Number of items the loop runs over.
    after : float
        Seconds before the first and between later updates (``PROGRESS_AFTER``).
    stream : file-like or None
        Where to write (``None``: ``sys.stderr``).
    """

    def __init__(self, what: str, total: int, after: float = PROGRESS_AFTER, stream=None):
        self.what, self.total, self.after = what, total, after
        self.stream = sys.stderr if stream is None else stream
        self.start = self.last = time.monotonic()
        self.shown = False
        try:
            self.live = self.stream.isatty()
        except (AttributeError, ValueError):
            self.live = False

    def update(self, done: int) -> None:
        """Show ``done/total`` and the elapsed seconds if ``after`` seconds passed since the last update.

        Parameters
        ----------
        done : int
            Items finished so far.
        """
        if not self.live:
            return
        now = time.monotonic()
        if now - self.last >= self.after:
            self.last, self.shown = now, True
            self.stream.write(f"\r{self.what}: {done}/{self.total} ({now - self.start:.0f} s)")
            self.stream.flush()

    def close(self) -> None:
        """End the progress line (a newline) if anything was drawn."""
        if self.shown:
            self.stream.write("\n")
            self.stream.flush()


def _parts(packing: Packing):
    """Convex parts: a convex body is one part, a clump one sphere per member (module docstring).
    Returns ``(owner, offset, shapes, radius)``: ``offset`` the part's centre from its body's (world
    frame), ``radius`` the sphere radius of a sphere part, NaN for other shapes.
    """
    from dtcrit.bodies import Clump, Sphere

    owner: list[int] = []
    offset: list[np.ndarray] = []
    parts: list[object] = []
    radius: list[float] = []
    assert packing.shapes is not None  # only called for packings of shaped bodies
    for b, shape in enumerate(packing.shapes):
        if isinstance(shape, Clump):
            assert packing.orientations is not None  # a clump packing carries orientations
            for cx, cy, cz, r in shape.spheres:
                owner.append(b)
                offset.append(packing.orientations[b] @ np.array([cx, cy, cz]))
                parts.append(None)
                radius.append(float(r))
        else:
            owner.append(b)
            offset.append(np.zeros(3))
            parts.append(shape)
            radius.append(float(shape.radius) if isinstance(shape, Sphere) else math.nan)
    return np.array(owner, dtype=np.int64), np.array(offset), parts, np.array(radius)


def _sphere_pairs(a, b, sep, ra, rb, tolerance):
    """Rows ``(keep, normal, arm_a, arm_b, overlap)`` of sphere-sphere candidate pairs."""
    d = np.sqrt(np.einsum("ij,ij->i", sep, sep))
    keep = d <= (ra + rb) * (1.0 + tolerance)
    n = sep / np.where(d > 0, d, 1.0)[:, None]
    overlap = np.maximum(ra + rb - d, 0.0)
    arm_a = (ra - 0.5 * overlap)[:, None] * n
    return keep, n, arm_a, arm_a - sep, overlap


def _convex_pairs(parts, radius, rot, a, b, sep, bound, tolerance):
    """Rows of the other candidate pairs, one penetration at a time (with progress); a clump member
    meeting a non-spherical body becomes a ``Sphere`` here.
    """
    from dtcrit.bodies import Sphere

    for k in np.unique(np.concatenate([a, b])):
        if parts[k] is None:
            parts[k] = Sphere(float(radius[k]), mass=1.0)
    rows = np.zeros(len(a), bool), np.zeros((len(a), 3)), np.zeros((len(a), 3)), np.zeros((len(a), 3)), np.zeros(len(a))
    keep, normal, arm_a, arm_b, overlap = rows
    progress = Progress("contacts between non-spherical bodies", len(a))
    for c in range(len(a)):
        progress.update(c)
        if np.linalg.norm(sep[c]) > bound[c] * (1.0 + tolerance):
            continue
        with np.errstate(under="ignore"):
            apart = np.linalg.norm(sep[c]) > 0
        start = None if apart else np.array([1.0, 0.0, 0.0])  # centres that coincide in double precision
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            depth, n, pa, pb = convex_penetration(parts[a[c]], rot[a[c]], parts[b[c]], rot[b[c]], sep[c], start)
        if not (np.isfinite(depth) and np.all(np.isfinite(n))):
            raise InputError("position", f"the penetration search found no contact normal between two bodies "
                                         f"(parts {a[c]} and {b[c]} counted from 0)")
        if depth < -tolerance * bound[c]:
            continue
        point = 0.5 * (pa + (sep[c] + pb))  # relative to part a's centre
        keep[c], normal[c], arm_a[c], arm_b[c], overlap[c] = True, n, point, point - sep[c], max(depth, 0.0)
    progress.close()
    return rows


def find_body_contacts(packing: Packing, tolerance: float = 1e-9) -> Contacts:
    """Contacts of a packing of convex bodies and clumps (module docstring).

    Arms point from each body's centre of mass to the contact point; a packing of spheres only goes
    to ``find_sphere_contacts``.

    Parameters
    ----------
    packing : Packing
        Convex bodies and clumps (shapes, orientations, centres of mass).
    tolerance : float
        Relative gap (a fraction of the summed bounding radii) up to which a pair still counts.

    Returns
    -------
    Contacts
        The contacts; ``radius_eff = R_1 R_2 / (R_1 + R_2)`` [m] where two spheres (or clump
        members) meet, NaN otherwise.
    """
    if packing.is_spheres:
        return find_sphere_contacts(packing, tolerance)
    owner, offset, parts, radius = _parts(packing)
    box = packing.box
    rot = packing.orientations if packing.orientations is not None else np.repeat(np.eye(3)[None], packing.n, 0)
    xb = wrap_positions(packing.positions, box)
    x = wrap_positions(xb[owner] + offset, box)
    bound = np.where(np.isnan(radius), packing.radii[owner], radius)  # bounding radius of each part
    i, j, image = _candidate_pairs(x, 2.0 * bound.max() * (1.0 + tolerance), box)
    keep = (owner[i] != owner[j]) | np.any(image != 0, axis=1)  # members of one clump are one rigid body
    i, j, image = i[keep], j[keep], image[keep]
    sep = x[j] + (0.0 if box is None else box.shift(image)) - x[i]
    spheres = ~np.isnan(radius[i]) & ~np.isnan(radius[j])
    found = [np.zeros(len(i), bool), np.zeros((len(i), 3)), np.zeros((len(i), 3)), np.zeros((len(i), 3)),
             np.zeros(len(i))]
    s, o = np.flatnonzero(spheres), np.flatnonzero(~spheres)
    for where, rows in ((s, _sphere_pairs(i[s], j[s], sep[s], radius[i[s]], radius[j[s]], tolerance)),
                        (o, _convex_pairs(parts, radius, rot[owner], i[o], j[o], sep[o], bound[i[o]] + bound[j[o]], tolerance))):
        for field, value in zip(found, rows):
            field[where] = value
    touch, normal, arm_a, arm_b, overlap = found
    same = touch & spheres & ~np.any(sep != 0, axis=1)
    if same.any():
        k = int(np.argmax(same))
        raise InputError("position", f"bodies {packing.particle_id(owner[i[k]])} and {packing.particle_id(owner[j[k]])} "
                                     "hold spheres with coincident centres: no contact normal")
    i, j, image, normal, arm_a, arm_b, overlap = (v[touch] for v in (i, j, image, normal, arm_a, arm_b, overlap))
    bi, bj = owner[i], owner[j]
    # body j's image: x_j + H S = x_i + offset_a + sep - offset_b
    sep = x[j] + (0.0 if box is None else box.shift(image)) - x[i]
    body_image = np.zeros((len(i), 3)) if box is None else image_of(box, xb[bi] - xb[bj] + offset[i] - offset[j] + sep)
    moved = own_images(packing, xb)  # images of the packing's own centres, not of the wrapped ones
    body_image = body_image if moved is None else body_image + moved[bj] - moved[bi]
    ra, rb = radius[i], radius[j]
    return Contacts(i=bi, j=bj, normal=normal, arm_i=offset[i] + arm_a, arm_j=offset[j] + arm_b, overlap=overlap,
                    image=body_image.astype(np.int64), radius_eff=ra * rb / (ra + rb))
