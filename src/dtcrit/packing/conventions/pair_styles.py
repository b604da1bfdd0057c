"""LAMMPS / LIGGGHTS granular pair styles as the per-contact springs and dashpots they apply.

The user gives the style exactly as in the input script, e.g.
``--pair-style 'gran/hooke/history 1e4 1e4 0 0 1e4 0'``.  ``pair_style gran/*`` (LAMMPS docs
``pair_gran``; sources ``src/GRANULAR/pair_gran_hooke.cpp``, ``pair_gran_hooke_history.cpp``,
``pair_gran_hertz_history.cpp``) takes ``Kn Kt gamma_n gamma_t xmu dampflag [limit_damping]``:

* ``Kt`` ``NULL`` -> ``2/7 Kn``; ``gamma_t`` ``NULL`` -> ``gamma_n / 2``; ``dampflag 0`` -> no tangential
  dashpot; ``xmu = 0`` -> no tangential force at all (the Coulomb cap ``xmu |F_n|`` is zero);
* normal force ``Kn delta - m_eff gamma_n v_n`` with ``m_eff = m_i m_j / (m_i + m_j)``: ``k_n = Kn``,
  ``c_n = m_eff gamma_n``;
* ``gran/hooke`` has no shear history: the tangential force is the dashpot ``-m_eff gamma_t v_t``
  only (``k_s = 0``); ``gran/hooke/history`` adds the spring ``-Kt xi`` (``k_s = Kt``);
* ``gran/hertz/history`` multiplies every term by ``sqrt(delta R*)``, ``R* = R_i R_j/(R_i + R_j)``:
  the force ``Kn delta sqrt(R* delta)`` has the tangent stiffness ``k_n = 3/2 Kn sqrt(R* delta)``;
  ``k_s = Kt sqrt(R* delta)``, ``c_n = m_eff gamma_n sqrt(R* delta)``, ``c_s = m_eff gamma_t sqrt(R* delta)``.

The friction limit is taken as not reached (sticking contacts): the linear analysis of the step.
``limit_damping`` (``if (limit_damping && ccel < 0.0) ccel = 0.0``: the normal force is clamped at zero
when the dashpot would make it attractive) is refused when ``gamma_n > 0``, where it can act; the linear
analysis does not model the clamp.  :data:`GRAN_TERMS` lists every argument and keyword with what the
audit does with it.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dtcrit.errors import InputError
from dtcrit.physics.contact_laws import lammps_hertz_tangent_stiffness, reduced
from dtcrit.physics.damping_conventions import lammps_gran_defaults

from dtcrit.packing.conventions.granular_style import parse_granular
from dtcrit.packing.conventions.law_terms import FLAG, ContactTerms, number
from dtcrit.packing.model import Contacts, Packing
from dtcrit.packing.uniform_values import entries

GRAN_STYLES = ("gran/hooke", "gran/hooke/history", "gran/hertz/history")

#: every argument and keyword of ``pair_style gran/*`` (LAMMPS pair_gran docs): what the audit does with it
GRAN_TERMS = {
    "Kn": "modelled: normal spring (Hertz: times sqrt(R* delta), tangent 3/2)",
    "Kt": "modelled: shear spring (gran/hooke has no shear history: no spring)",
    "gamma_n": "modelled: normal dashpot m_eff gamma_n",
    "gamma_t": "modelled: shear dashpot m_eff gamma_t",
    "xmu": "modelled: 0 removes the tangential force; else contacts taken as sticking",
    "dampflag": "modelled: 0 removes the shear dashpot",
    "limit_damping": "refused when gamma_n > 0 (the clamp of the normal force at zero is not modelled)",
}


@dataclass(frozen=True)
class GranPairStyle:
    """A parsed ``pair_style gran/*`` line (module docstring).

    Parameters
    ----------
    style : str
        ``gran/hooke``, ``gran/hooke/history`` or ``gran/hertz/history`` (``/omp``, ``/kk`` stripped).
    kn : float
        ``Kn``: [N/m] for Hooke; [N/m^2] for Hertz (multiplied by ``sqrt(R* delta)``).
    kt : float
        ``Kt`` in the units of ``kn`` (``NULL`` -> ``2/7 Kn``).
    gamma_n : float
        Normal damping ``gamma_n`` [1/s] (times ``m_eff``; for Hertz also ``sqrt(R* delta)`` [1/(s m)]).
    gamma_t : float
        Tangential damping ``gamma_t`` in the units of ``gamma_n`` (``NULL`` -> ``gamma_n / 2``).
    xmu : float
        Friction coefficient; 0 means no tangential force at all.
    dampflag : int
        0: no tangential dashpot; 1: tangential dashpot on.
    text : str
        The style line as given.
    """

    style: str
    kn: float
    kt: float
    gamma_n: float
    gamma_t: float
    xmu: float
    dampflag: int
    text: str

    arm = "radius"  # slip velocity and torque with the full radius (module docstring)

    def material(self) -> None:
        """None: the ``gran/*`` styles take spring constants, not a material.

        Returns
        -------
        None
            Always.
        """
        return None  # the gran/* styles take spring constants, not a material

    def describe(self) -> str:
        """The style in words, for reports.

        Returns
        -------
        str
            The description.
        """
        return f"LAMMPS pair_style {self.text}"

    def terms(self, packing: Packing, contacts: Contacts) -> ContactTerms:
        """Every contact's springs, dashpots and normal force under this style (module docstring).

        Parameters
        ----------
        packing : Packing
            The particles (masses).
        contacts : Contacts
            The sphere contacts (overlaps, effective radii).

        Returns
        -------
        ContactTerms
            The per-contact terms.
        """
        m = packing.masses
        m_eff = reduced(m[contacts.i], m[contacts.j])
        delta = contacts.overlap
        hertz = self.style == "gran/hertz/history"
        scale = np.sqrt(delta * contacts.radius_eff) if hertz else 1.0  # Hooke: springs of one value, held once
        kn = lammps_hertz_tangent_stiffness(self.kn, scale) if hertz else self.kn * scale
        force = self.kn * delta * scale
        tangential = self.xmu > 0
        ks = (self.kt * scale if self.style != "gran/hooke" else 0.0) * tangential
        cs = m_eff * self.gamma_t * scale * (tangential and self.dampflag == 1)
        count = contacts.count
        return ContactTerms(entries(kn, count), entries(ks, count), m_eff * self.gamma_n * scale, cs, force)


def parse_pair_style(text: str):
    """The contact law of a ``pair_style`` line, as given in the input script.

    Parameters
    ----------
    text : str
        The line (a leading ``pair_style`` is dropped), e.g. ``gran/hooke/history 1e4 NULL 0 NULL 0.5 0``;
        for ``granular`` the ``pair_coeff`` words follow the style name.

    Returns
    -------
    GranPairStyle or GranularStyle
        A ``GranPairStyle`` for ``gran/*``, a
        ``dtcrit.packing.conventions.granular_style.GranularStyle`` for ``granular``.

    Raises
    ------
    InputError
        For an empty line, an unknown style or malformed arguments.
    """
    words = str(text).split()
    if words and words[0] == "pair_style":
        words = words[1:]
    if not words:
        raise InputError(FLAG, "empty: give the style and its arguments, e.g. 'gran/hooke/history 1e4 NULL 0 NULL 0.5 0'")
    style, args = words[0], words[1:]
    if style == "granular":
        return parse_granular(args)
    if style.endswith("/omp") or style.endswith("/kk"):
        style = style.rsplit("/", 1)[0]
    if style not in GRAN_STYLES:
        raise InputError(FLAG, f"unknown or unsupported pair style {style!r}; supported: {', '.join(GRAN_STYLES)}, granular")
    limit_damping = bool(args) and args[-1] == "limit_damping"
    if limit_damping:
        args = args[:-1]
    if len(args) != 6:
        raise InputError(FLAG, f"{style} takes 6 arguments (Kn Kt gamma_n gamma_t xmu dampflag), found {len(args)}")
    kn = number(args[0], "Kn")
    kt = number(args[1], "Kt", allow_null=True)
    gamma_n = number(args[2], "gamma_n")
    gamma_t = number(args[3], "gamma_t", allow_null=True)
    xmu = number(args[4], "xmu")
    assert kn is not None and gamma_n is not None and xmu is not None  # NULL is refused for these
    if xmu > 1e4:
        raise InputError(FLAG, f"xmu must lie in [0, 1e4] (LAMMPS's own limit), found {args[4]!r}")
    if args[5] not in ("0", "1"):
        raise InputError(FLAG, f"dampflag must be 0 or 1, found {args[5]!r}")
    if kn == 0:
        raise InputError(FLAG, "Kn must be positive")
    if limit_damping and gamma_n > 0:
        raise InputError(FLAG, f"limit_damping with gamma_n = {args[2]} clamps the normal force at zero, which the "
                               "audit does not model (it is a no-op only with gamma_n = 0)")
    kt, gamma_t = lammps_gran_defaults(kn, kt, gamma_n, gamma_t)
    return GranPairStyle(style, kn, kt, gamma_n, gamma_t, xmu, int(args[5]), " ".join([words[0], *args]))


def apply_terms(contacts: Contacts, terms: ContactTerms, *, preload: bool) -> Contacts:
    """Contacts carrying a law's springs, dashpots and (with ``preload``) normal force.

    Parameters
    ----------
    contacts : Contacts
        The sphere contacts.
    terms : ContactTerms
        Per-contact springs [N/m, N m/rad], dashpots [N s/m, N m s/rad] and normal force [N].
    preload : bool
        Whether to attach the normal force (its geometric stiffness enters ``K``).

    Returns
    -------
    Contacts
        Copy with the stiffness, damping and, if ``preload``, the normal force set.
    """
    out = contacts.with_stiffness(terms.kn, terms.ks, terms.kr, terms.ktw)
    out = out.with_damping(terms.cn, terms.cs, terms.cr, terms.ctw)
    return out.with_normal_force(terms.force_n) if preload else out
