"""What the PETSc/SLEPc back-end reports (``slepc_backend``): the result, its JSON units and its text."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

JSON_SCHEMA = "dtcrit-packing-slepc/1"
UNITS = {"omega_max": "rad/s", "dt_crit": "s", "dt_safe": "s", "dt_integrator": "s", "k_max": "N/m", "m_min": "kg",
         "residual": "1/s^2", "matvec_seconds": "s", "times.*": "s", "peak_rss_mib.*": "MiB", "per_rank.peak_rss_mib": "MiB",
         "dt_bracket.lower": "s", "dt_bracket.upper": "s"}
"""Units of the dimensional keys of ``dtcrit packing --backend slepc --json``; every other number is
dimensionless (counts, ratios, fractions)."""


@dataclass
class SlepcResult:
    """``omega_max`` [rad/s] and ``dt_crit = 2/omega_max`` [s] from SLEPc, with the solver's figures,
    sizes, stage times (slowest rank) [s] and peak memory per rank [MiB] (module docstring).

    Parameters
    ----------
    label, law : str
        The packing's label and the contact law's description.
    ranks, n_particles, dofs, n_contacts : int
        Processes, particles, degrees of freedom (6 per particle) and contacts.
    cn_mean : float
        Mean coordination number ``2 C / N``.
    k_max : float
        Largest contact stiffness ``max(k_n, k_s)`` [N/m].
    m_min : float
        Smallest mass of a particle touched by a stiff contact [kg].
    omega_max, dt_crit, dt_safe : float
        Top angular frequency [rad/s], ``2/omega_max`` [s] and the Gershgorin lower bound [s].
    alpha : float
        ``dt_crit / sqrt(m_min/k_max)``.
    rotational_fraction : float
        Share of the top mode's kinetic energy in rotation.
    solver : str
        Name of the eigen-solver.
    tolerance : float
        Relative residual tolerance used.
    ncv, iterations, matvecs : int
        Subspace size, restarts and matrix-vector products.
    residual, relative_residual : float
        ``|A v - theta v|`` [1/s^2] and that over ``theta``.
    matrix_mallocs, matrix_nonzeros : int
        PETSc's mallocs during assembly (0 when preallocated exactly) and stored entries.
    matvec_seconds : float
        Seconds per product (slowest rank).
    times : dict
        Stage times [s] (slowest rank).
    peak_rss_mib : dict
        Peak memory per stage [MiB] (largest rank).
    per_rank : list
        Rows, contacts and peak memory of each rank.
    matrix : str
        ``"shell"`` (matrix-free: the contact kernel under a PETSc shell matrix) or ``"assembled"``.
    dt_safe_from : str
        Which rigorous lower bound ``dt_safe`` is.
    dt_bracket : dict
        ``lower`` [s], ``upper`` [s], ``lower_from``: ``dtcrit.packing.solvers.certificate.bracket`` of
        the Ritz value and ``dt_safe``, ``lower <= dt_crit_true <= upper``.
    petsc_index_bits : int
        Width of the PETSc build's indices that ran, 32 or 64 (``petsc_build``: ``--petsc-indices``).
    """

    label: str
    law: str
    ranks: int
    n_particles: int
    dofs: int
    n_contacts: int
    cn_mean: float
    k_max: float
    m_min: float
    omega_max: float
    dt_crit: float
    dt_safe: float
    alpha: float
    rotational_fraction: float
    solver: str
    tolerance: float
    ncv: int
    iterations: int
    matvecs: int
    residual: float
    relative_residual: float
    matrix_mallocs: int
    matrix_nonzeros: int
    matvec_seconds: float
    times: dict
    peak_rss_mib: dict
    per_rank: list
    matrix: str = "assembled"
    dt_safe_from: str = "Gershgorin 2/sqrt(|A|_inf)"
    dt_bracket: dict = field(default_factory=dict)
    petsc_index_bits: int = 32

    def to_dict(self) -> dict:
        """The fields as a JSON-ready dict (a non-finite float becomes ``None``).

        Returns
        -------
        dict
            Field name to value.
        """
        def finite(v):
            if isinstance(v, dict):
                return {k: finite(x) for k, x in v.items()}
            return None if isinstance(v, float) and not math.isfinite(v) else v

        return {k: finite(v) for k, v in self.__dict__.items()}


def format_result(r: SlepcResult) -> str:
    """The text ``dtcrit packing --backend slepc`` prints (rank 0).

    Parameters
    ----------
    r : SlepcResult
        The result.

    Returns
    -------
    str
        The report, several lines.
    """
    t = r.times
    return "\n".join([
        f"packing: {r.label or '(unnamed)'}",
        f"contact law: {r.law}",
        f"particles {r.n_particles}, DOFs {r.dofs}, contacts {r.n_contacts}, coordination mean {r.cn_mean:.4g}",
        f"omega_max = {r.omega_max:.12g} rad/s  ({r.solver}, {r.matrix} matrix, {r.petsc_index_bits}-bit PETSc indices, on {r.ranks} rank{'s' if r.ranks > 1 else ''}, "
        f"{r.iterations} restarts, {r.matvecs} matrix-vector products, residual |Av - theta v| = {r.residual:.3g}, "
        f"relative {r.relative_residual:.2g})",
        f"dt_crit = 2/omega_max = {r.dt_crit:.12g} s   alpha = dt_crit / sqrt(m_min/K_max) = {r.alpha:.5g}",
        f"dt_safe = {r.dt_safe:.6g} s ({r.dt_safe_from}: a lower bound on the step)",
        *([f"dt_crit lies in [{b['lower']:.9g}, {b['upper']:.9g}] s (lower end: {b['lower_from']}; upper: 2/sqrt(theta), "
           "theta a Rayleigh quotient)"] if (b := r.dt_bracket) else []),
        f"highest mode: {100 * r.rotational_fraction:.1f} % of its kinetic energy in rotation",
        "time (slowest rank): " + ", ".join(f"{k} {v:.3g} s" for k, v in t.items())
        + f"; peak memory per rank {max(r.peak_rss_mib.values()):.0f} MiB",
    ])
