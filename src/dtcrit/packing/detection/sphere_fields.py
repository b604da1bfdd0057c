"""The contact fields of touching sphere pairs: normals, arms, overlaps, image shifts, ``R*``.

From candidate pairs ``(i, j)`` (sorted, each once: ``overlaps._sorted_pairs``) and their periodic
image, ``_filled`` writes every field of ``dtcrit.packing.contact_set.Contacts`` into arrays allocated
once at their final size, a chunk of pairs at a time.  The contact point is the middle of the overlap
along the centre line, ``x_c = x_i + (R_i - delta/2) n`` (Peng et al. 2020, Eqs (1)-(2)); the arms
are kept as their lengths ``R - delta/2`` along the normal (``dtcrit.packing.normal_arms``: 16 bytes a
contact instead of 48); the particle indices are int32 when ``6 N < 2^31`` (``contact_set.index_dtype``).
When every sphere has the same radius ``R`` (the same float), ``R*`` is the one value ``R R / (R + R)``,
held once (``equal_radius_eff``; the same arithmetic, so the same bits, as each contact's
``R_i R_j / (R_i + R_j)``).
"""
from __future__ import annotations

import numpy as np

from dtcrit.errors import InputError
from dtcrit.packing.contact_set import index_dtype
from dtcrit.packing.model import Box, Contacts, Packing
from dtcrit.packing.normal_arms import NormalArms
from dtcrit.packing.periodic_cell import own_images
from dtcrit.packing.uniform_values import uniform


def _image_of(sep: np.ndarray, box: Box | None) -> np.ndarray:
    """Integer periodic shift of ``j`` that brings it nearest to ``i`` (int8: |shift| <= 1 here)."""
    image = np.zeros((len(sep), 3), dtype=np.int8)
    if box is not None:
        periodic = np.array(box.periodic)
        image[:, periodic] = -np.rint(sep[:, periodic] / box.lengths[periodic]).astype(np.int8)
    return image


def _touching(packing: Packing, x, i, j, image, tolerance, moved=None):
    """The contacts among candidate pairs ``(i, j, image)``: field arrays of ``Contacts`` (the arms as
    their lengths ``length_i``, ``length_j``: ``_contacts``).
    """
    r = packing.radii
    box = packing.box
    sep = x[j] + (0.0 if box is None else box.shift(image)) - x[i]
    d = np.sqrt(np.einsum("ij,ij->i", sep, sep))
    touch = d <= (r[i] + r[j]) * (1.0 + tolerance)
    if not touch.all():
        i, j, image, sep, d = i[touch], j[touch], image[touch], sep[touch], d[touch]
    if np.any(d <= 0):
        k = int(np.argmax(d <= 0))
        raise InputError("positions", f"particles {packing.particle_id(i[k])} and {packing.particle_id(j[k])} "
                                      "have coincident centres")
    n = sep / d[:, None]
    overlap = np.maximum(r[i] + r[j] - d, 0.0)
    image = image if moved is None else narrowest_image(image + moved[j] - moved[i])
    return dict(i=i, j=j, normal=n, length_i=r[i] - 0.5 * overlap, length_j=r[j] - 0.5 * overlap,
                overlap=overlap, image=image, radius_eff=r[i] * r[j] / (r[i] + r[j]))


def equal_radius_eff(radii: np.ndarray, count: int) -> np.ndarray | None:
    """``R* = R R / (R + R)`` of ``count`` contacts held once (``uniform_values.uniform``) when every radius
    is the same float ``R``, else ``None`` (one ``R_i R_j / (R_i + R_j)`` per contact).

    Parameters
    ----------
    radii : numpy.ndarray
        (N,) sphere radii [m].
    count : int
        Contacts.

    Returns
    -------
    numpy.ndarray or None
        (count,) read-only view of the one ``R*`` [m], or ``None``.
    """
    if radii.size == 0 or radii.min() != radii.max():
        return None
    r = radii[0]
    return uniform(r * r / (r + r), count)


def _contacts(fields: dict, radii: np.ndarray) -> Contacts:
    """``Contacts`` of sphere fields: the arm lengths become ``NormalArms`` on the normals, ``R*`` of
    equal spheres one value (``equal_radius_eff``), the particle indices in ``contact_set.index_dtype``.
    """
    n = fields["normal"]
    same = equal_radius_eff(radii, n.shape[0])
    if same is not None:
        fields["radius_eff"] = same
    for key in ("i", "j"):  # int32 when 6 N < 2^31 (no copy when so already)
        fields[key] = fields[key].astype(index_dtype(radii.shape[0]), copy=False)
    return Contacts(arm_i=NormalArms(fields.pop("length_i"), n, 1.0), arm_j=NormalArms(fields.pop("length_j"), n, -1.0),
                    **fields)


def narrowest_image(image: np.ndarray) -> np.ndarray:
    """``image`` as int8 when its shifts fit (3 bytes per contact instead of 24), else unchanged.

    Parameters
    ----------
    image : numpy.ndarray
        (C, 3) integer periodic shifts.

    Returns
    -------
    numpy.ndarray
        The shifts, int8 when they fit.
    """
    fits = image.size == 0 or (int(image.min()) >= -128 and int(image.max()) <= 127)
    return image.astype(np.int8) if fits else image


def _joined(parts: list[dict], radii: np.ndarray) -> Contacts:
    """One ``Contacts`` from per-chunk field arrays, joined one field at a time (each field's
    pieces are released as it is joined, so the peak is the result plus one field).
    """
    if not parts:
        return Contacts.empty()
    fields = {}
    for name in list(parts[0]):
        fields[name] = np.concatenate([p.pop(name) for p in parts])
    return _contacts(fields, radii)


CONTACT_FIELDS = ("normal", "length_i", "length_j", "overlap", "image", "radius_eff")


def _filled(packing: Packing, x, pair_i, pair_j, frame_box, tolerance: float, chunk: int) -> Contacts:
    """``Contacts`` of the touching pairs among the sorted candidates, in two passes of ``chunk``
    pairs: which touch (a byte a pair), then each field written into its array, allocated once at
    its final size (no per-chunk pieces to join: the peak is the result plus one chunk's
    temporaries).  Image shifts are int8 when every one fits (``|shift| <= 1`` plus the centres'
    own wrapping ``moved_j - moved_i``); ``R*`` of equal spheres is not written per contact.
    """
    moved = own_images(packing, x)
    spans = [slice(lo, lo + chunk) for lo in range(0, len(pair_i), chunk)]
    touch = np.empty(len(pair_i), dtype=bool)
    for sl in spans:
        i, j = pair_i[sl], pair_j[sl]
        touch[sl] = _touch_mask(packing, x, i, j, _image_of(x[j] - x[i], frame_box), tolerance)
    if not touch.all():
        pair_i, pair_j = pair_i[touch], pair_j[touch]
    del touch
    count = len(pair_i)
    wide = moved is not None and int(np.abs(moved).max()) > 63
    equal = equal_radius_eff(packing.radii, 0) is not None  # R* then set once by _contacts
    fields = dict(normal=np.empty((count, 3)), length_i=np.empty(count), length_j=np.empty(count),
                  overlap=np.empty(count), image=np.empty((count, 3), dtype=np.int64 if wide else np.int8),
                  radius_eff=np.empty(0 if equal else count))
    names = [name for name in CONTACT_FIELDS if not (equal and name == "radius_eff")]
    for lo in range(0, count, chunk):
        sl = slice(lo, lo + chunk)
        i, j = pair_i[sl], pair_j[sl]
        part = _touching(packing, x, i, j, _image_of(x[j] - x[i], frame_box), tolerance, moved)
        for name in names:
            fields[name][sl] = part[name]
    return _contacts(dict(i=pair_i, j=pair_j, **fields), packing.radii)


def _touch_mask(packing: Packing, x, i, j, image, tolerance) -> np.ndarray:
    """Whether each candidate pair ``(i, j, image)`` touches: ``d <= (R_i + R_j) (1 + tolerance)``."""
    sep = x[j] + (0.0 if packing.box is None else packing.box.shift(image)) - x[i]
    return np.sqrt(np.einsum("ij,ij->i", sep, sep)) <= (packing.radii[i] + packing.radii[j]) * (1.0 + tolerance)


# --------------------------------------------------------------------------- convex shapes
