"""The text ``dtcrit packing`` prints for a packing report (``format_report``)."""
from __future__ import annotations

from dtcrit.packing.report import PackingReport


def format_report(r: PackingReport) -> str:
    """Human-readable text of a report (what ``dtcrit packing`` prints).

    Parameters
    ----------
    r : PackingReport
        The report.

    Returns
    -------
    str
        The text, one item a line.
    """
    lines = [
        f"packing: {r.label or '(unnamed)'}",
        f"contact law: {r.law}",
        f"particles {r.n_particles}, DOFs {r.dofs}, contacts {r.n_contacts}, "
        f"coordination mean {r.cn_mean:.4g} max {r.cn_max}",
        f"omega_max = {r.omega_max:.6g} rad/s  ({r.solver}, relative residual {r.relative_residual:.2g}"
        f"{f', {r.matvecs} matrix-vector products' if r.matvecs else ''})",
        f"dt_crit = 2/omega_max = {r.dt_crit:.7g} s   alpha = dt_crit / sqrt(m_min/K_max) = {r.alpha:.5g}"
        f"   (m_min {r.m_min:.4g} kg, K_max {r.k_max:.4g} N/m)",
        f"highest mode: {r.mode} ({100 * r.rotational_fraction:.1f} % of its kinetic energy in rotation)",
        f"{r.integrator}, modal damping ratio {r.damping_ratio:g}: dt = {r.dt_integrator:.7g} s"
        + ("  (no step is stable)" if r.dt_integrator == 0 else ""),
    ]
    b = r.bracket
    lines.append(f"bracket: {b.lower:.6g} s <= dt_crit <= {b.upper:.6g} s (lower end from {b.lower_from}; "
                 f"{r.route} route)")
    if r.certificate is not None:
        c = r.certificate
        lines.append(f"certificate: {'yes' if c.certified else 'no'}, sigma = {c.sigma:.9g} 1/s^2, {c.method}"
                     + (f"; {c.detail}" if c.detail else ""))
    if r.estimates:
        lines.append("")
        lines.append(f"{'estimate':<20}{'dt [s]':>14}{'dt / dt_crit':>14}  {'safe':<5} kind")
        for row in r.estimate_table():
            lines.append(f"{row['name']:<20}{row['dt']:>14.6g}{row['ratio']:>14.5f}  {'yes' if row['safe'] else 'NO':<5} "
                         f"{row['kind']}; {row['detail']}")
    return "\n".join(lines)
