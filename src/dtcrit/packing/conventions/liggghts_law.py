"""LIGGGHTS's granular contact law per contact, from each pair's atom types (``dtcrit audit --liggghts-input``).

The input is read by :mod:`dtcrit.packing.conventions.liggghts_input`; the formulas are LIGGGHTS-PUBLIC
``src/`` (``global_properties.cpp`` for the mixing, the ``*_model_*.h`` files for the forces).  For the
types ``i``, ``j`` of a contact, ``R* = R_i R_j/(R_i + R_j)``, ``m* = m_i m_j/(m_i + m_j)``,
``a = sqrt(R* delta)``:

* mixing: ``Y* = 1/((1 - nu_i^2)/Y_i + (1 - nu_j^2)/Y_j)``, ``G* = 1/(2 (2 - nu_i)(1 + nu_i)/Y_i +
  2 (2 - nu_j)(1 + nu_j)/Y_j)`` (Mindlin's ``G*``), ``beta = ln e_ij/sqrt(ln^2 e_ij + pi^2)``;
* ``model hertz`` (``normal_model_hertz.h``): force ``k_n delta`` with ``k_n = 4/3 Y* a``, tangent
  stiffness ``S_n = 2 Y* a``; ``k_t = S_t = 8 G* a``; dashpots ``gamma_n = -2 sqrt(5/6) beta sqrt(S_n m*)``,
  ``gamma_t = -2 sqrt(5/6) beta sqrt(S_t m*)`` (0 with ``tangential_damping off``);
* ``model hooke`` (``normal_model_hooke.h``): ``k_n = 16/15 sqrt(R*) Y* (15 m* v^2/(16 sqrt(R*) Y*))^(1/5)``
  with ``v`` the ``characteristicVelocity``, ``k_t = k_n`` (``0.285714286 k_n`` with ``ktToKnUser on``),
  ``gamma_n = sqrt(4 m* k_n ln^2 e/(ln^2 e + pi^2))``, ``gamma_t = gamma_n``;
* ``tangential history`` (``tangential_model_history.h``): spring ``k_t`` and dashpot ``gamma_t`` on the
  slip; ``no_history`` (``tangential_model_no_history.h``): the dashpot only; ``coefficientFriction``
  0 removes the tangential force (the Coulomb cap ``mu |F_n|`` is zero);
* ``rolling_friction epsd`` (``rolling_model_epsd.h``): spring ``k_r = 2.25 k_n mu_r^2 R*^2`` on the relative
  rotation, with LIGGGHTS's ``k_n`` (the secant ``4/3 Y* a`` for Hertz), dashpot ``eta_r 2 sqrt(I_r k_r)``,
  ``I_r = 1.4 m_i R_i^2 m_j R_j^2/(m_i R_i^2 + m_j R_j^2)``; ``epsd2`` (``rolling_model_epsd2.h``):
  ``k_r = k_t R*^2``, no dashpot; ``epsd3`` (``rolling_model_epsd3.h``): ``k_r = f k_n mu_r^2 R*^2`` with
  ``f`` the ``rollingStiffness``, dashpot as epsd; ``mu_r = 0`` removes the moment.  ``torsionTorque on``
  puts the same spring and dashpot about the normal.  ``cdt`` (``rolling_model_cdt.h``) is a moment of
  constant size ``mu_r k_n delta R*`` against the relative rotation, like a sliding friction: no spring or
  dashpot, so it adds nothing to the linear analysis (said in the law's description).

Kinematics (``surface_model_default.h``): the slip velocity and the torque both use the arm
``R - delta/2`` (``cri = radi - 0.5 deltan``): dtcrit's ``mid-overlap`` arms.  The friction limits are
taken as not reached (sticking contacts), as for every law of the audit.
"""
from __future__ import annotations

from contextlib import closing
from dataclasses import dataclass

import numpy as np

from dtcrit.errors import InputError
from dtcrit.physics import contact_laws as cl
from dtcrit.physics import damping_conventions as dc
from dtcrit.physics.rotational_springs import epsd2_rolling_stiffness, epsd_rolling_dashpot, epsd_rolling_stiffness

from dtcrit.packing.conventions.law_terms import ContactTerms
from dtcrit.packing.conventions.liggghts_input import LiggghtsInput
from dtcrit.packing.model import Contacts, Packing
from dtcrit.packing.uniform_values import uniform

KT_TO_KN_USER = 0.285714286  # normal_model_hooke.h: "kt *= 0.285714286; //2//7"


@dataclass(frozen=True)
class LiggghtsLaw:
    """A LIGGGHTS input's contact law bound to the atom types of a dump's particles (module docstring).

    Parameters
    ----------
    spec : LiggghtsInput
        The parsed ``pair_style gran`` and materials.
    types : numpy.ndarray
        Each particle's atom type (1-based), in the packing's order.
    """

    spec: LiggghtsInput
    types: np.ndarray
    arm = "mid-overlap"  # surface_model_default.h: R - delta/2 for the slip velocity and the torque

    def describe(self) -> str:
        """The law in words, for reports.

        Returns
        -------
        str
            The description (with the note on ``cdt``).
        """
        text = f"LIGGGHTS {self.spec.pair_style} (materials per atom type, {self.spec.where})"
        if self.spec.rolling == "cdt":
            text += "; rolling_friction cdt: a constant-size moment, no spring or dashpot"
        return text

    def material(self) -> None:
        """None: the materials differ per atom type (see :meth:`describe`).

        Returns
        -------
        None
            Always.
        """
        return None

    def terms(self, packing: Packing, contacts: Contacts) -> ContactTerms:
        """Every contact's springs, dashpots and normal force (module docstring).

        Parameters
        ----------
        packing : Packing
            The particles (masses, radii), in the order of ``types``.
        contacts : Contacts
            The sphere contacts (overlaps, effective radii).

        Returns
        -------
        ContactTerms
            The per-contact terms.
        """
        s = self.spec
        ti, tj = self.types[contacts.i] - 1, self.types[contacts.j] - 1
        m_eff = cl.reduced(packing.masses[contacts.i], packing.masses[contacts.j])
        r_star, delta = contacts.radius_eff, contacts.overlap
        youngs, poisson = s.value("youngsModulus"), s.value("poissonsRatio")
        y_star = cl.effective_youngs_modulus(youngs[ti], poisson[ti], youngs[tj], poisson[tj])
        beta = np.vectorize(dc.liggghts_beta, otypes=[float])(s.value("coefficientRestitution"))[ti, tj]
        if s.normal == "hertz":
            a = np.sqrt(r_star * delta)
            g_star = cl.effective_shear_modulus(youngs[ti], poisson[ti], youngs[tj], poisson[tj])
            kn_secant, kn = 4.0 / 3.0 * y_star * a, cl.hertz_normal_stiffness(y_star, a)
            kt = cl.mindlin_tangent_stiffness(g_star, a)
            cn, ct = dc.liggghts_hertz_dashpot(beta, kn, m_eff), dc.liggghts_hertz_dashpot(beta, kt, m_eff)
        else:
            kn_secant = kn = cl.liggghts_hooke_stiffness(y_star, r_star, m_eff, float(s.value("characteristicVelocity")))
            kt = kn * KT_TO_KN_USER if s.settings["ktToKnUser"] else kn
            cn = ct = dc.liggghts_hooke_dashpot(beta, kn, m_eff)
        ct = ct if s.settings["tangential_damping"] else 0.0 * ct
        sticking = (s.value("coefficientFriction")[ti, tj] > 0) if s.tangential != "off" else np.zeros(len(ti), bool)
        ks = np.where(sticking & (s.tangential == "history"), kt, 0.0)
        cs = np.where(sticking, ct, 0.0)
        kr, cr = self._rolling(packing, contacts, kn_secant, kt, ti, tj)
        twist = s.settings["torsionTorque"] and kr is not None
        return ContactTerms(kn, ks, cn, cs, kn_secant * delta, kr=kr, cr=cr,
                            ktw=kr if twist else None, ctw=cr if twist else None)

    def _rolling(self, packing: Packing, contacts: Contacts, kn_secant, kt, ti, tj):
        """``(k_r, c_r)`` of the rolling model (``None, None`` for ``off`` and ``cdt``)."""
        s = self.spec
        if s.rolling in ("off", "cdt"):
            return None, None
        mu_r = s.value("coefficientRollingFriction")[ti, tj]
        r_star = contacts.radius_eff
        if s.rolling == "epsd2":
            return np.where(mu_r > 0, epsd2_rolling_stiffness(kt, r_star), 0.0), uniform(0.0, contacts.count)
        factor = 2.25 if s.rolling == "epsd" else float(s.value("rollingStiffness"))
        kr = epsd_rolling_stiffness(factor, kn_secant, mu_r, r_star)
        eta = s.value("coefficientRollingViscousDamping")[ti, tj]
        m, r = packing.masses, packing.radii
        cr = np.array([epsd_rolling_dashpot(float(e), float(k), float(m[i]), float(r[i]), float(m[j]), float(r[j]))
                       for e, k, i, j in zip(eta, kr, contacts.i, contacts.j)])
        return kr, cr.reshape(kr.shape)


def dump_types(path, snapshot_index: int, packing: Packing) -> np.ndarray:
    """The atom type of each particle of a dump snapshot, in the order of its packing (sorted by id).

    Parameters
    ----------
    path : str or os.PathLike
        The dump.
    snapshot_index : int
        The snapshot (Python style, -1 the last).
    packing : Packing
        The packing read from that snapshot (its particle count is checked).

    Returns
    -------
    numpy.ndarray
        The types (int, >= 1).

    Raises
    ------
    InputError
        ``PATH:type`` when the dump has no ``type`` column or a type is not a positive whole number.
    """
    from dtcrit.packing.readers.dump_stream import _chosen, iter_dump

    with closing(iter_dump(path)) as snapshots:
        snap = _chosen(snapshots, snapshot_index)
    if "type" not in snap.columns:
        raise InputError(f"{path}:type", "--liggghts-input takes each contact's materials from its atom types: "
                                         "the dump needs a 'type' column")
    rows = snap.rows
    types = rows[:, snap.columns.index("type")]
    if "id" in snap.columns:
        types = types[np.argsort(rows[:, snap.columns.index("id")], kind="stable")]
    if len(types) != packing.n or not np.all((types >= 1) & (types == np.rint(types))):
        raise InputError(f"{path}:type", "atom types must be whole numbers >= 1, one per atom")
    return types.astype(np.int64)


def bind_types(spec: LiggghtsInput, types: np.ndarray) -> LiggghtsLaw:
    """The law of ``spec`` for particles of the given types, refusing a type without materials.

    Parameters
    ----------
    spec : LiggghtsInput
        The parsed input.
    types : numpy.ndarray
        Each particle's atom type (1-based).

    Returns
    -------
    LiggghtsLaw
        The law, ready for ``terms``.

    Raises
    ------
    InputError
        ``FILE:LINE`` of the first property that gives fewer types than the dump's largest.
    """
    top = int(types.max()) if len(types) else 0
    for prop in spec.properties.values():
        if prop.values.ndim and prop.values.shape[0] < top:
            raise InputError(prop.where, f"atom type {top} of the dump has no {prop.name}: it gives "
                                         f"{prop.values.shape[0]} type(s)")
    return LiggghtsLaw(spec, types)


def read_liggghts_law(input_path, dump_path, snapshot_index: int, packing: Packing) -> LiggghtsLaw:
    """The contact law of a LIGGGHTS input file for the particles of a dump snapshot.

    Parameters
    ----------
    input_path : str or os.PathLike
        The LIGGGHTS input (``dtcrit.packing.conventions.liggghts_input.read_liggghts_input``).
    dump_path : str or os.PathLike
        The dump (its ``type`` column).
    snapshot_index : int
        The snapshot read.
    packing : Packing
        The packing read from it.

    Returns
    -------
    LiggghtsLaw
        The law with each particle's type.
    """
    from dtcrit.packing.conventions.liggghts_input import read_liggghts_input

    return bind_types(read_liggghts_input(input_path), dump_types(dump_path, snapshot_index, packing))
