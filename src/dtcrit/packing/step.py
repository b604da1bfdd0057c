"""The critical step of a whole packing: read or generate it, pick its contact law, analyse it.

``packing_step`` is the API behind ``dtcrit packing`` (serial back-end): the packing comes from a
LAMMPS/LIGGGHTS dump, a ``dtcrit-bodies/1`` file, a periodic lattice or a random packing; the contact
law is linear springs (``kn``, ``ks``) or the Hertz-Mindlin tangent stiffness at each contact's overlap
(``youngs``, ``poisson``); the global eigenmode analysis (Otsubo et al. 2017, ``dt_crit = 2/omega_max``,
Eq. (13)) runs in :func:`dtcrit.packing.report.analyse`.  The result is a frozen :class:`PackingStep`
whose ``to_json()`` is the document ``dtcrit packing --json`` prints (schema ``dtcrit-packing/1``).

Bad input raises :class:`dtcrit.errors.InputError` whose ``key`` names the parameter (``kn``,
``damping_ratio``, ``random``, ...; ``packing`` for the packing as a whole); the reasons name the
command line's flags, which the command line prints unchanged.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass, field, fields
from typing import TYPE_CHECKING

from dtcrit.errors import InputError
from dtcrit.packing.step_input import DEFAULT_DENSITY, DEFAULT_RADIUS, RANDOM_SECONDS_LIMIT, PackingInput, packing_input

if TYPE_CHECKING:
    from dtcrit.packing.bounds.estimates import Estimate
    from dtcrit.packing.model import Packing
    from dtcrit.packing.report import PackingReport
    from dtcrit.packing.solvers.certificate import Certificate

__all__ = ["DEFAULT_DENSITY", "DEFAULT_RADIUS", "PackingInput", "PackingStep", "RANDOM_SECONDS_LIMIT",
           "packing_input", "packing_step"]

CERTIFY = {"auto": "auto", "yes": True, "no": False}
"""``certify`` words and what :func:`dtcrit.packing.report.analyse` receives for them."""


@dataclass(frozen=True)
class PackingStep:
    """The critical step of a packing from its largest eigenfrequency, with the cheap estimates beside it.

    The fields are those ``dtcrit packing`` prints (:class:`dtcrit.packing.report.PackingReport`).

    Parameters
    ----------
    label, law : str
        The packing's label and the contact law in words.
    n_particles, dofs, n_contacts : int
        Particles, degrees of freedom (6 per particle) and contacts.
    cn_mean : float
        Mean coordination number.
    cn_max : int
        Largest coordination number.
    m_min : float
        Smallest mass of a particle that has a contact [kg].
    k_max : float
        Largest contact stiffness ``max(kn, ks)`` [N/m].
    omega_max : float
        Largest eigenfrequency of ``M^-1/2 K M^-1/2`` [rad/s].
    dt_crit : float
        ``2 / omega_max`` [s], the undamped step of the central-difference family (Otsubo et al. 2017, Eq. (13)).
    alpha : float
        ``dt_crit / sqrt(m_min / k_max)``.
    integrator : str
        The integrator of the damped bound.
    damping_ratio : float
        Modal damping ratio of the highest mode.
    dt_integrator : float
        The integrator's step at that damping ratio [s].
    integrator_formula : str
        The formula of ``dt_integrator``.
    mode : str
        Character of the highest mode (translation, rotation, mixed; degenerate).
    rotational_fraction : float
        Share of the highest mode's kinetic energy in rotation.
    solver : str
        The eigen-solver used.
    matvecs : int
        Matrix-vector products the solver took.
    relative_residual : float
        Its residual relative to ``omega_max^2``.
    estimates : tuple of Estimate
        The cheap estimates (Gershgorin, block-diagonal, two-particle, Rayleigh, ...).
    route : str
        ``assembled`` or ``matrix-free``.
    dt_safe : float
        The larger of the Gershgorin and block-diagonal lower bounds [s].
    certificate : Certificate or None
        The inertia-count certificate that no mode lies above ``omega_max^2 (1 + 1e-6)``.
    packing : Packing
        The packing analysed (not part of the JSON form).

    Examples
    --------
    >>> from dtcrit import packing_step
    >>> step = packing_step(lattice="bcc", cells=2, kn=1e5)
    >>> step.to_json()["schema"], round(step.omega_max * step.dt_crit, 12)
    ('dtcrit-packing/1', 2.0)
    """

    label: str
    law: str
    n_particles: int
    dofs: int
    n_contacts: int
    cn_mean: float
    cn_max: int
    m_min: float
    k_max: float
    omega_max: float
    dt_crit: float
    alpha: float
    integrator: str
    damping_ratio: float
    dt_integrator: float
    integrator_formula: str
    mode: str
    rotational_fraction: float
    solver: str
    matvecs: int
    relative_residual: float
    estimates: tuple[Estimate, ...]
    route: str
    dt_safe: float
    certificate: Certificate | None
    packing: Packing = field(repr=False, compare=False)

    @classmethod
    def from_report(cls, report: PackingReport, packing: Packing) -> PackingStep:
        """The frozen form of a :class:`dtcrit.packing.report.PackingReport`.

        Parameters
        ----------
        report : PackingReport
            The report of :func:`dtcrit.packing.report.analyse`.
        packing : Packing
            The packing it analysed.

        Returns
        -------
        PackingStep
            The same numbers, frozen.
        """
        values = {f.name: getattr(report, f.name) for f in fields(report)}
        values["estimates"] = tuple(report.estimates.values())
        return cls(packing=packing, **values)

    def report(self) -> PackingReport:
        """The mutable :class:`dtcrit.packing.report.PackingReport` of the same numbers.

        Returns
        -------
        PackingReport
            A new report (changing it leaves this result as it is).
        """
        from dtcrit.packing.report import PackingReport

        values = {f.name: getattr(self, f.name) for f in fields(PackingReport)}
        values["estimates"] = {e.name: e for e in self.estimates}
        return PackingReport(**values)

    def to_json(self) -> dict:
        """The JSON document ``dtcrit packing --json`` prints (schema ``dtcrit-packing/1``).

        Returns
        -------
        dict
            The envelope (schema, version, units) and the report; non-finite numbers are ``None``.
        """
        from dtcrit.json_meta import envelope
        from dtcrit.packing.report import JSON_SCHEMA, UNITS

        doc = envelope(JSON_SCHEMA, UNITS)
        doc.update(self.report().to_dict())
        return doc

    def to_text(self) -> str:
        """The text ``dtcrit packing`` prints.

        Returns
        -------
        str
            The report without a final newline.
        """
        from dtcrit.packing.report_text import format_report

        return format_report(self.report())


def packing_step(source: str | os.PathLike | None = None, *, lattice: str | None = None, cells: int = 2,
                 random: int | None = None, cn: float = 6.0, sizes: str = "mono", spread: float = 0.0,
                 seed: int = 0, radius: float = DEFAULT_RADIUS, density: float | None = None,
                 kn: float | None = None, ks: float | None = None, youngs: float | None = None,
                 poisson: float = 0.25, snapshot: int = -1, integrator: str = "velocity-verlet",
                 damping_ratio: float = 0.0, solver: str = "auto", route: str = "auto", certify: str = "auto",
                 write_dump: str | os.PathLike | None = None) -> PackingStep:
    """The critical time step of a packing from its largest eigenfrequency (Otsubo et al. 2017).

    Exactly one of ``source``, ``lattice`` and ``random`` gives the packing; ``kn`` (and ``ks``) or
    ``youngs`` (and ``poisson``) the contact law, unless a bodies file lists each contact's stiffness.

    Parameters
    ----------
    source : str or os.PathLike, optional
        A LAMMPS/LIGGGHTS text dump (``ITEM: ATOMS id type x y z radius [mass]``) or a
        ``dtcrit-bodies/1`` JSON file of non-spherical bodies.
    lattice : {'sc', 'bcc', 'fcc', 'hcp'}, optional
        A periodic lattice of touching spheres.
    cells : int
        Lattice cells along each axis.
    random : int, optional
        A random packing of this many spheres (FIRE relaxation).
    cn : float
        Target mean coordination of the random packing.
    sizes : {'mono', 'uniform', 'lognormal'}
        Size distribution of the random packing.
    spread : float
        Uniform: half-width / radius; lognormal: sigma of ``ln R``.
    seed : int
        Seed of the random packing.
    radius : float
        Sphere (median) radius of a generated packing [m].
    density : float, optional
        Particle density [kg/m^3]: ``DEFAULT_DENSITY`` for generated packings; required for a dump
        without a mass column; refused with a bodies file.
    kn, ks : float, optional
        Linear normal and tangential spring stiffness [N/m] (``ks`` defaults to ``kn``).
    youngs : float, optional
        Young's modulus [Pa]: the Hertz-Mindlin tangent stiffness ``2 E* sqrt(R* delta)`` at each overlap.
    poisson : float
        Poisson's ratio with ``youngs``.
    snapshot : int
        Snapshot index in the dump (-1: the last).
    integrator : str
        Integrator of the damped bound (a name of ``dtcrit.INTEGRATORS``).
    damping_ratio : float
        Modal damping ratio of the highest mode (finite, at least 0).
    solver : {'auto', 'dense', 'eigsh', 'lobpcg'}
        The eigen-solver.
    route : {'auto', 'assembled', 'matrix-free'}
        Assembled sparse ``K``, or ``K`` applied from the contact list (auto: by size).
    certify : {'auto', 'yes', 'no'}
        Certify by an ``LDL^T`` inertia count that no mode lies above ``omega_max^2 (1 + 1e-6)``.
    write_dump : str or os.PathLike, optional
        Also write the analysed sphere packing as a LAMMPS dump file there.

    Returns
    -------
    PackingStep
        ``omega_max``, ``dt_crit = 2/omega_max``, ``dt_safe``, the integrator's step, the estimates.

    Raises
    ------
    InputError
        Bad input (``key`` names the parameter) or a packing without a vibrating mode.
    NotConvergedError
        The eigen-solver stopped early (its bracket on ``dt_crit``).

    Examples
    --------
    >>> from dtcrit import packing_step
    >>> step = packing_step(lattice="sc", cells=2, kn=1e6)
    >>> step.n_particles, step.dofs, step.n_contacts
    (8, 48, 24)
    >>> round(step.dt_safe / step.dt_crit, 9)  # the lower bounds are sharp on a lattice
    1.0
    """
    if not math.isfinite(damping_ratio) or damping_ratio < 0:
        raise InputError("damping_ratio", f"must be a finite number >= 0, got {damping_ratio}")
    if certify not in CERTIFY:
        raise InputError("certify", f"unknown {certify!r}; choose one of {', '.join(CERTIFY)}")
    given = packing_input(source, lattice=lattice, cells=cells, random=random, cn=cn, sizes=sizes, spread=spread,
                          seed=seed, radius=radius, density=density, kn=kn, ks=ks, youngs=youngs, poisson=poisson,
                          snapshot=snapshot, route=route, certify=certify, write_dump=write_dump)
    from dtcrit.packing import report as packing_report

    report = packing_report.analyse(given.packing, given.law, given.contacts, integrator=integrator,
                                    damping_ratio=damping_ratio, method=solver, route=route,
                                    certify_step=CERTIFY[certify])
    if report.n_contacts == 0:
        raise InputError("packing", "no two particles touch: no contact limits the step (nothing to analyse)")
    if not report.omega_max > 0:
        why = (" (Hertz stiffness 2 E* sqrt(R* delta) vanishes at zero overlap: the spheres only touch)"
               if "hertz" in report.law.lower() else "")
        raise InputError("packing", f"every contact has zero stiffness{why}: no vibrating mode, no critical step")
    if write_dump:
        from dtcrit.packing.readers.lammps_dump import write_dump as write

        write(write_dump, given.packing)
    return PackingStep.from_report(report, given.packing)
