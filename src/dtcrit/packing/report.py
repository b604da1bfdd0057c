"""One report per packing: the exact ``omega_max``-based step and the cheap estimates side by side.

``dt_crit = 2 / omega_max`` (Otsubo et al. 2017, Eq. (13)) is the undamped critical step of the
central-difference family (leapfrog, velocity Verlet).  ``alpha = dt_crit / sqrt(m_min / K_max)``
with ``m_min`` the smallest mass among particles that have a contact (rattlers do not vibrate)
and ``K_max`` the largest contact stiffness ``max(k_n, k_s)``.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

import dtcrit.packing.bounds.estimates as est
import dtcrit.packing.bounds.rayleigh_trials as trials
import dtcrit.packing.operators.matrix_free_kernels as operator_kernels
from dtcrit.packing.operators.assembly import mass_diagonal, scale_symmetric, stiffness_matrix
from dtcrit.packing.solvers.certificate import SPARSE_DOFS, Certificate, bracket, certify, factor_bytes, factor_seconds
from dtcrit.packing.detection.overlaps import find_contacts
from dtcrit.packing.solvers.integrator_step import DEFAULT_INTEGRATOR, integrator_dt
from dtcrit.packing.solvers.largest_mode import DEFAULT_TOL, TopMode, largest_mode
from dtcrit.packing.solvers.mode_kind import mode_character, rotational_fraction
from dtcrit.errors import InputError, NotConvergedError
from dtcrit.packing.model import Contacts, HertzMindlinLaw, LinearLaw, Packing, apply_law
from dtcrit.packing.operators.matrix_free import stiffness_operator
from dtcrit.physics.estimate import Estimate, RatedEstimate
from dtcrit.physics.json_numbers import json_safe

OPERATOR_DOFS = 200_000
"""Above this many DOFs ``analyse`` applies ``K`` matrix-free (``dtcrit.packing.operators.matrix_free``) when the
compiled loops are available; at and below it the assembled route (and ``eigsh``'s 12 Ritz pairs for
the degenerate-eigenspace label, ``eigen.ITERATIVE_SPACE_LIMIT``) is kept.  Measured on the jittered
FCC benchmark at 585k DOFs: one compiled product 8.7 ms against 16 ms assembled, no 2.5 s assembly,
0.13 s for the bounds' pass."""
NUMPY_OPERATOR_DOFS = 6_000_000
"""Without Numba the vectorised product is 4x slower than the assembled one: the matrix-free route
is then taken only where the assembled matrix would not fit (about 7 GiB at 6e6 DOFs)."""
CERTIFY_AUTO_DOFS = 25_000
"""``certify="auto"`` never factorises above this many DOFs; ``certify=True`` goes up to
``certificate.SPARSE_DOFS``."""
CERTIFY_BUDGET = 4.0
CERTIFY_FLOOR_SECONDS = 2.0
"""``certify="auto"`` certifies when the factorisation is estimated (``certificate.factor_seconds``)
to take at most ``CERTIFY_BUDGET`` times the eigen-solve just measured, or ``CERTIFY_FLOOR_SECONDS``,
and its factor fits in half the available memory: the default's cost stays a few eigen-solves
(before: FCC at 24k DOFs took 107 s and 3.4 GiB certified, 1.8 s and 0.2 GiB without)."""


def auto_certifies(dofs: int, coordination: float, eigen_seconds: float) -> bool:
    """Whether ``certify="auto"`` factorises (``CERTIFY_BUDGET``, ``CERTIFY_FLOOR_SECONDS``).

    True when ``dofs <= CERTIFY_AUTO_DOFS``, the factor fits in half the available memory and its
    estimated time is at most ``max(CERTIFY_BUDGET * eigen_seconds, CERTIFY_FLOOR_SECONDS)``.

    Parameters
    ----------
    dofs : int
        Degrees of freedom of the packing.
    coordination : float
        Mean contacts per particle (scales the factor's fill).
    eigen_seconds : float
        Measured time of the eigen-solve [s].

    Returns
    -------
    bool
        Whether the certificate is computed.
    """
    from dtcrit.packing.solvers.memory import available_bytes

    if dofs > CERTIFY_AUTO_DOFS:
        return False
    have = available_bytes()
    if have is not None and factor_bytes(dofs, coordination) > 0.5 * have:
        return False
    return factor_seconds(dofs, coordination) <= max(CERTIFY_BUDGET * eigen_seconds, CERTIFY_FLOOR_SECONDS)
ROUTES = ("auto", "assembled", "matrix-free")


JSON_SCHEMA = "dtcrit-packing/1"
UNITS = {"omega_max": "rad/s", "dt_crit": "s", "dt_integrator": "s", "m_min": "kg", "k_max": "N/m",
         "dt_safe": "s", "dt_bracket.lower": "s", "dt_bracket.upper": "s", "certificate.sigma": "1/s^2",
         "certificate.dt_lower": "s",
         "estimates.*.dt": "s", "estimates.*.omega": "rad/s"}
"""Units of the dimensional keys of ``dtcrit packing --json`` (schema ``dtcrit-packing/1``); every other
number is dimensionless (counts, coordination, ``alpha``, ratios, residuals, fractions)."""


@dataclass
class PackingReport:
    """Everything ``dtcrit packing`` prints (schema ``dtcrit-packing/1``).

    Parameters
    ----------
    label : str
        Name of the packing.
    law : str
        The contact law in words.
    n_particles : int
        Number of particles.
    dofs : int
        Degrees of freedom (6 per particle).
    n_contacts : int
        Number of contacts.
    cn_mean : float
        Mean coordination number ``2 n_contacts / n_particles``.
    cn_max : int
        Largest number of contacts on one particle.
    m_min : float
        Smallest mass among particles that have a contact [kg].
    k_max : float
        Largest contact stiffness ``max(k_n, k_s)`` [N/m].
    omega_max : float
        Largest angular eigenfrequency of ``K phi = omega^2 M phi`` [rad/s].
    dt_crit : float
        ``2/omega_max`` [s] (Otsubo et al. 2017, Eq. (13)).
    alpha : float
        ``dt_crit / sqrt(m_min / k_max)`` (dimensionless).
    integrator : str
        The integrator whose step ``dt_integrator`` is.
    damping_ratio : float
        Modal damping ratio of the top mode.
    dt_integrator : float
        Critical step [s] of ``integrator`` on the top mode with ``damping_ratio``.
    integrator_formula : str
        How ``dt_integrator`` was obtained.
    mode : str
        Character of the top mode (``mode_character``).
    rotational_fraction : float
        Share of the top mode's kinetic energy in rotation.
    solver : str
        Eigen-solver used.
    matvecs : int
        Matrix-vector products spent.
    relative_residual : float
        ``|A v - theta v| / theta``.
    estimates : dict of str to Estimate
        The cheap estimates and bounds keyed by name (``dtcrit.packing.bounds.estimates``).
    route : str
        ``"assembled"`` or ``"matrix-free"``.
    dt_safe : float
        Larger of the Gershgorin and block-diagonal lower bounds [s] (NaN without estimates).
    certificate : Certificate or None
        The inertia certificate, when computed.
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
    estimates: dict[str, Estimate] = field(default_factory=dict)
    route: str = "assembled"
    dt_safe: float = math.nan
    certificate: Certificate | None = None

    @property
    def bracket(self):
        """``lower <= dt_crit_true <= upper`` (``certificate.bracket``)."""
        theta = self.omega_max ** 2
        return bracket(theta, self.dt_safe if math.isfinite(self.dt_safe) else 0.0, self.certificate)

    def estimate_table(self) -> list[dict]:
        """The estimates rated against ``dt_crit``, one row each in schema ``dtcrit-packing/1``'s form.

        Returns
        -------
        list of dict
            ``name``, ``dt`` [s], ``omega`` [rad/s], ``ratio``, ``safe``, ``kind``, ``detail``.
        """
        return [_estimate_row(RatedEstimate(e, self.dt_crit)) for e in self.estimates.values()]

    def to_dict(self) -> dict:
        """The report as schema ``dtcrit-packing/1``'s body (non-finite numbers as null).

        Returns
        -------
        dict
            The keys of the report, ``estimates``, ``certificate`` and ``dt_bracket``.
        """
        out = {k: getattr(self, k) for k in (
            "label", "law", "n_particles", "dofs", "n_contacts", "cn_mean", "cn_max", "m_min", "k_max",
            "omega_max", "dt_crit", "alpha", "integrator", "damping_ratio", "dt_integrator",
            "integrator_formula", "mode", "rotational_fraction", "solver", "matvecs", "relative_residual",
            "route", "dt_safe")}
        out["estimates"] = {row.pop("name"): row for row in self.estimate_table()}
        cert = self.certificate or Certificate(False, "none: not requested", self.omega_max ** 2 * (1 + 1e-6))
        out["certificate"] = cert.to_dict()
        out["dt_bracket"] = self.bracket.to_dict()
        return json_safe(out)


def _estimate_row(rated: RatedEstimate) -> dict:
    """Schema ``dtcrit-packing/1``'s row of a rated estimate: the common shape plus ``omega = sqrt(omega2)``."""
    common = rated.to_json()
    omega2 = rated.estimate.omega2 or 0.0
    return {"name": common["name"], "dt": common["dt"], "omega": math.sqrt(omega2) if omega2 > 0 else 0.0,
            "ratio": common["ratio"], "safe": common["safe"], "kind": common["kind"], "detail": common["detail"]}


def analyse(packing: Packing, law=None, contacts: Contacts | None = None, *, integrator: str = DEFAULT_INTEGRATOR,
            damping_ratio: float = 0.0, method: str = "auto", tolerance: float = DEFAULT_TOL,
            with_estimates: bool = True, route: str = "auto", certify_step="auto") -> PackingReport:
    """Global eigenmode analysis of a packing: ``dt_crit = 2/omega_max`` and the cheap estimates.

    Parameters
    ----------
    packing : Packing
        The particles.
    law : LinearLaw or HertzMindlinLaw or None
        Sets each contact's stiffness unless ``contacts`` already carry one (default linear
        ``k_n = k_s = 1`` N/m).
    contacts : Contacts or None
        The contacts; found by overlap (``find_contacts``) when ``None``.
    integrator : str
        Integrator of ``dt_integrator``.
    damping_ratio : float
        Modal damping ratio of the top mode (``integrator_dt``).
    method : str
        Eigen-solver of ``largest_mode``.
    tolerance : float
        Eigen-solver tolerance.
    with_estimates : bool
        Whether to compute the estimates and bounds (and so ``dt_safe``).
    route : str
        ``"assembled"`` (sparse ``K``), ``"matrix-free"`` (``dtcrit.packing.operators.matrix_free``)
        or ``"auto"`` (matrix-free above ``OPERATOR_DOFS``, or ``NUMPY_OPERATOR_DOFS`` without Numba).
    certify_step : bool or str
        ``True`` / ``False`` / ``"auto"`` (up to ``CERTIFY_AUTO_DOFS``, ``auto_certifies``) for the
        certificate that no mode lies above ``omega_max^2 (1 + 1e-6)``
        (``dtcrit.packing.solvers.certificate``).

    Returns
    -------
    PackingReport
        The report.

    Raises
    ------
    InputError
        For an unknown route, a Hertz law on zero overlaps (``check_hertz_overlaps``) or bad inputs
        found by the callees.
    NotConvergedError
        When the eigen-solver stops early, with its bracket on ``dt_crit`` (``dt_bracket_error``).
    """
    if contacts is None:
        contacts = find_contacts(packing)
    if contacts.kn is None or law is not None:
        law = law if law is not None else LinearLaw(1.0, 1.0)
        if isinstance(law, HertzMindlinLaw):
            check_hertz_overlaps(packing, contacts)
        contacts = apply_law(contacts, law)
        law_text = law.describe()
    else:
        law_text = "per-contact stiffness given"
    if route not in ROUTES:
        raise InputError("route", f"unknown route {route!r}; choose one of {', '.join(ROUTES)}")
    if route == "auto":
        limit = OPERATOR_DOFS if operator_kernels.available() else NUMPY_OPERATOR_DOFS
        route = "matrix-free" if packing.dofs > limit else "assembled"
    if route == "matrix-free":  # the operator holds its scale, not M: no mass diagonal held through the solve
        a = stiffness_operator(packing, contacts)
    else:
        a = scale_symmetric(stiffness_matrix(packing, contacts), mass_diagonal(packing), inplace=True)
    def hint():  # all particles co-rotating: built inside the solver, released after its start
        return trials.co_rotation(packing, 0) + trials.co_rotation(packing, 1) + trials.co_rotation(packing, 2)

    clock = time.perf_counter()
    try:
        top: TopMode = largest_mode(a, method, tol=tolerance, hint=hint)
    except NotConvergedError as exc:
        raise dt_bracket_error(exc, a, mass_diagonal(packing), packing) from None
    eigen_seconds = time.perf_counter() - clock
    omega = top.omega
    dt = 2.0 / omega if omega > 0 else math.inf
    cn = contacts.coordination(packing.n)
    assert contacts.kn is not None and contacts.ks is not None  # set by the law above
    stiff = np.maximum(contacts.kn, contacts.ks)
    active = stiff > 0
    k_max = float(stiff.max(initial=0.0))
    touched = np.zeros(packing.n, bool)
    touched[contacts.i[active]] = True
    touched[contacts.j[active]] = True
    m_min = float(packing.masses[touched].min()) if touched.any() else float(packing.masses.min())
    alpha = dt / math.sqrt(m_min / k_max) if k_max > 0 and math.isfinite(dt) else math.inf
    dt_int, formula = integrator_dt(omega, integrator, damping_ratio)
    estimates: dict[str, Estimate] = {}
    if with_estimates:
        w_c = est.single_contact_frequencies(packing, contacts) if contacts.count else None
        for e in (est.gershgorin(a, mass_diagonal(packing)), est.block_diagonal(a, packing.particle_id),
                  est.diagonal_stiffness(a, packing.particle_id),
                  est.two_particle_amax(packing, contacts),
                  est.two_particle_exact(packing, contacts, w_c), trials.rayleigh(a, packing, contacts, w_c)):
            estimates[e.name] = e
    bounds = [estimates[k] for k in ("gershgorin", "block_diagonal") if k in estimates]
    dt_safe = max((e.dt for e in bounds if e.dt is not None), default=math.nan)
    coordination = float(cn.mean()) if packing.n else 0.0
    wanted = (auto_certifies(packing.dofs, coordination, eigen_seconds) if certify_step == "auto"
              else bool(certify_step))
    cert = certify(a, top.value, sparse_dofs=SPARSE_DOFS) if wanted and top.value > 0 else None
    if cert is None and certify_step == "auto" and top.value > 0:
        cert = Certificate(False, "none: too costly", top.value * (1 + 1e-6), None,
                           f"the factorisation of {packing.dofs} DOFs would take about "
                           f"{factor_seconds(packing.dofs, coordination):.3g} s and "
                           f"{factor_bytes(packing.dofs, coordination) / 2**30:.3g} GiB, over {CERTIFY_BUDGET:g}x the "
                           f"eigen-solve's {eigen_seconds:.2g} s (--certify yes factorises up to {SPARSE_DOFS} DOFs); "
                           "the bracket's lower end is dt_safe")
    return PackingReport(
        label=packing.label, law=law_text, n_particles=packing.n, dofs=packing.dofs, n_contacts=contacts.count,
        cn_mean=float(cn.mean()), cn_max=int(cn.max(initial=0)), m_min=m_min, k_max=k_max, omega_max=omega,
        dt_crit=dt, alpha=alpha, integrator=integrator, damping_ratio=float(damping_ratio), dt_integrator=dt_int,
        integrator_formula=formula, mode=mode_character(top.vector, top.space), rotational_fraction=rotational_fraction(top.vector),
        solver=top.method, matvecs=top.matvecs,
        relative_residual=top.residual / top.value if top.value > 0 else 0.0, estimates=estimates,
        route=route, dt_safe=dt_safe, certificate=cert,
    )


ROUNDING_OVERLAP = 64 * np.finfo(float).eps
"""Overlaps at most this times the largest coordinate are rounding noise of the positions (a lattice's
spheres that only touch): a Hertz stiffness ``2 E* sqrt(R* delta)`` computed from them means nothing."""


def check_hertz_overlaps(packing: Packing, contacts: Contacts) -> None:
    """Refuse a Hertz law on contacts whose overlaps are all zero or at rounding level.

    The Hertz tangent stiffness ``2 E* sqrt(R* delta)`` vanishes at zero overlap (no vibrating mode)
    and is noise when ``delta`` is at the rounding level of the coordinates (``ROUNDING_OVERLAP``).

    Parameters
    ----------
    packing : Packing
        The particles (positions and box give the coordinate scale).
    contacts : Contacts
        The contacts (overlaps [m]).

    Raises
    ------
    InputError
        With key ``youngs`` when the largest overlap is at or below the rounding level.
    """
    if not contacts.count:
        return
    scale = float(np.max(np.abs(packing.positions), initial=0.0))
    if packing.box is not None:
        scale = max(scale, float(np.max(np.abs(packing.box.hi))), float(np.max(np.abs(packing.box.lo))))
    largest = float(np.max(contacts.overlap, initial=0.0))
    if largest <= ROUNDING_OVERLAP * scale:
        raise InputError("youngs", "the Hertz stiffness 2 E* sqrt(R* delta) vanishes at zero overlap, and these "
                                   f"spheres only touch (largest overlap {largest:.3g} m, rounding noise of coordinates "
                                   f"up to {ROUNDING_OVERLAP * scale:.3g} m): no mode vibrates; give linear springs (--kn [--ks]) or a "
                                   "packing whose spheres overlap")


def dt_bracket_error(exc: NotConvergedError, a, md, packing: Packing) -> NotConvergedError:
    """The eigen-solver's bracket on ``omega_max^2`` as one on ``dt_crit = 2/omega_max``.

    The lower end is raised to ``dt_safe`` (the Gershgorin and block-diagonal bounds) when larger.

    Parameters
    ----------
    exc : NotConvergedError
        The solver's error, bracketing ``omega_max^2`` [1/s^2].
    a : scipy.sparse matrix or LinearOperator
        ``A = M^(-1/2) K M^(-1/2)`` [1/s^2].
    md : numpy.ndarray
        Diagonal of ``M`` (masses [kg], inertias [kg m^2]).
    packing : Packing
        The particles (names in the bounds' detail).

    Returns
    -------
    NotConvergedError
        The bracket on ``dt_crit [s]``.
    """
    bounds = [est.gershgorin(a, md).dt, est.block_diagonal(a, packing.particle_id).dt]
    lower = max([b for b in bounds if b is not None and math.isfinite(b)] + [2.0 / math.sqrt(exc.upper) if exc.upper > 0 else 0.0])
    upper = 2.0 / math.sqrt(exc.lower) if exc.lower > 0 else math.inf
    return NotConvergedError("dt_crit [s]", lower, upper, exc.solver, exc.reason)
