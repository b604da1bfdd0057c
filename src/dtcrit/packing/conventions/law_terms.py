"""What a contact law gives each contact (``ContactTerms``) and the number parsing the LAMMPS pair-style
readers share (``dtcrit.packing.conventions.pair_styles``, ``dtcrit.packing.conventions.granular_style``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from dtcrit.errors import InputError

FLAG = "--pair-style"


@dataclass(frozen=True)
class ContactTerms:
    """Per-contact springs, dashpots and normal force of a contact law, one entry per contact.

    Parameters
    ----------
    kn : numpy.ndarray
        Normal tangent stiffness [N/m].
    ks : numpy.ndarray
        Tangential stiffness [N/m].
    cn : numpy.ndarray
        Normal dashpot [N s/m].
    cs : numpy.ndarray
        Tangential dashpot [N s/m].
    force_n : numpy.ndarray
        Normal force [N], compressive positive (gives the geometric stiffness with a pre-load).
    kr : numpy.ndarray or None
        Rolling spring [N m/rad], when the law has one.
    ktw : numpy.ndarray or None
        Twisting spring [N m/rad], when the law has one.
    cr : numpy.ndarray or None
        Rolling dashpot [N m s/rad], when the law has one.
    ctw : numpy.ndarray or None
        Twisting dashpot [N m s/rad], when the law has one.
    """

    kn: np.ndarray
    ks: np.ndarray
    cn: np.ndarray
    cs: np.ndarray
    force_n: np.ndarray
    kr: np.ndarray | None = None
    ktw: np.ndarray | None = None
    cr: np.ndarray | None = None
    ctw: np.ndarray | None = None


def number(text: str, what: str, *, allow_null: bool = False) -> float | None:
    """A pair-style coefficient: a finite number >= 0 (or ``NULL`` when allowed).

    Parameters
    ----------
    text : str
        The word of the pair style.
    what : str
        Its name in the error message.
    allow_null : bool
        Whether ``NULL`` (None) is accepted.

    Returns
    -------
    float or None
        The value.
    """
    if allow_null and text == "NULL":
        return None
    try:
        value = float(text)
    except ValueError:
        raise InputError(FLAG, f"{what} must be a number{' or NULL' if allow_null else ''}, found {text!r}") from None
    if not math.isfinite(value) or value < 0:
        raise InputError(FLAG, f"{what} must be a finite number >= 0, found {text!r}")
    return value
