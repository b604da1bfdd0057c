"""Parametric study: alpha = dt_crit / sqrt(m_min / K_max) against the maximum coordination number.

Otsubo, O'Sullivan & Shire (2017) report that the critical step depends on the particle mass, the
largest contact stiffness and the maximum coordination number ``CN_max``.  This module analyses a
fixed, seeded family of packings (the four lattices and random packings of three size
distributions over a range of mean coordination), fits ``alpha = p CN_max^(-q)`` by least squares
in log-log coordinates, and summarises how each cheap estimate compares with the exact step.

``python -m dtcrit.bench.packing_alpha_study [--plot FILE.png]`` prints the table (and draws the figure).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from dtcrit.packing.generators.lattices import lattice
from dtcrit.packing.model import LinearLaw
from dtcrit.packing.generators.random_packing import random_packing
from dtcrit.packing.report import PackingReport, analyse

ESTIMATES = ("gershgorin", "block_diagonal", "diagonal", "two_particle_amax", "two_particle_exact", "rayleigh")
RANDOM_CN = (3.0, 4.0, 5.0, 6.0, 8.0, 10.0)
RANDOM_SIZES = (("mono", 0.0), ("uniform", 0.3), ("lognormal", 0.3))
RANDOM_N = 200


@dataclass(frozen=True)
class StudyRow:
    """One packing of the alpha study and its analysis.

    Parameters
    ----------
    label : str
        Name of the packing.
    kind : str
        ``"lattice"``, ``"mono"``, ``"uniform"`` or ``"lognormal"``.
    report : PackingReport
        The packing's critical step and estimates.
    """

    label: str
    kind: str  # "lattice" | "mono" | "uniform" | "lognormal"
    report: PackingReport

    def ratio(self, name: str) -> float:
        """An estimate over the packing's critical step, ``dt_estimate / dt_crit``.

        Parameters
        ----------
        name : str
            Name of the estimate.

        Returns
        -------
        float
            The ratio (at most 1 for a safe estimate).
        """
        dt = self.report.estimates[name].dt
        assert dt is not None, f"estimate {name} has no step"
        return dt / self.report.dt_crit


def study_packings(n: int = RANDOM_N):
    """``(label, kind, packing)`` for the study (fixed seeds).

    Parameters
    ----------
    n : int
        Number of particles of the random packings.

    Yields
    ------
    tuple
        ``(label, kind, packing)``.
    """
    for name in ("sc", "bcc", "fcc", "hcp"):
        yield f"{name} lattice", "lattice", lattice(name, 2, radius=1.0, density=1.0)
    seed = 100
    for sizes, spread in RANDOM_SIZES:
        for cn in RANDOM_CN:
            seed += 1
            p = random_packing(n, cn=cn, sizes=sizes, spread=spread, seed=seed)
            yield f"random {sizes}, CN {cn:g}, seed {seed}", sizes, p


def run_study(ks_over_kn: float = 1.0, n: int = RANDOM_N) -> list[StudyRow]:
    """Analyse every packing of :func:`study_packings` with ``k_n = 1``, ``k_s = ks_over_kn``.

    Parameters
    ----------
    ks_over_kn : float
        Tangential over normal stiffness.
    n : int
        Number of particles of the random packings.

    Returns
    -------
    list of StudyRow
        One row per packing.
    """
    law = LinearLaw(1.0, ks_over_kn)
    return [StudyRow(label, kind, analyse(p, law, method="auto" if p.dofs <= 600 else "eigsh"))
            for label, kind, p in study_packings(n)]


@dataclass(frozen=True)
class PowerFit:
    """The power law ``alpha = p CN_max^-q`` fitted to the study; calling it evaluates the law.

    Parameters
    ----------
    p : float
        Prefactor.
    q : float
        Exponent.
    r2 : float
        Coefficient of determination of the log fit.
    count : int
        Number of packings fitted.
    """

    p: float
    q: float
    r2: float
    count: int

    def __call__(self, cn):
        """The law at ``cn``.

        Parameters
        ----------
        cn : array_like
            Largest coordination numbers.

        Returns
        -------
        numpy.ndarray
            ``p cn^-q``.
        """
        return self.p * np.asarray(cn, float) ** (-self.q)


def fit_alpha(rows) -> PowerFit:
    """Least-squares ``log alpha = log p - q log CN_max``; ``r2`` of the log fit.

    Parameters
    ----------
    rows : sequence of StudyRow
        The packings to fit.

    Returns
    -------
    PowerFit
        The fitted law.
    """
    cn = np.array([r.report.cn_max for r in rows], float)
    alpha = np.array([r.report.alpha for r in rows], float)
    x, y = np.log(cn), np.log(alpha)
    slope, intercept = np.polyfit(x, y, 1)
    resid = y - (intercept + slope * x)
    total = np.sum((y - y.mean()) ** 2)
    r2 = 1.0 - float(np.sum(resid**2) / total) if total > 0 else 1.0
    return PowerFit(float(math.exp(intercept)), float(-slope), r2, len(rows))


def ratio_summary(rows) -> dict[str, dict[str, float]]:
    """For each estimate: min / median / max of ``dt_estimate / dt_crit`` and how many are safe.

    Parameters
    ----------
    rows : sequence of StudyRow
        The packings.

    Returns
    -------
    dict
        Per estimate: ``min``, ``median``, ``max`` and the count of safe ratios.
    """
    out = {}
    for name in ESTIMATES:
        r = np.array([row.ratio(name) for row in rows])
        out[name] = {"min": float(r.min()), "median": float(np.median(r)), "max": float(r.max()),
                     "safe": int(np.sum(r <= 1.0 + 1e-9)), "count": int(r.size)}
    return out


def equal_sphere_rows(rows):
    """The rows of equal spheres (lattices and monodisperse random packings).

    Parameters
    ----------
    rows : sequence of StudyRow
        The packings.

    Returns
    -------
    list of StudyRow
        The equal-sphere rows.
    """
    return [r for r in rows if r.kind in ("lattice", "mono")]


def plot(rows, fit: PowerFit, path) -> None:
    """Plot alpha against CN_max, by packing family, with the equal-sphere power-law fit ``fit``, the
    lattice law and the two-sphere value (the legend outside the axes, clear of the points and fits).

    Parameters
    ----------
    rows : sequence of StudyRow
        The packings.
    fit : PowerFit
        The equal-sphere fit.
    path : str or pathlib.Path
        File to write (PNG).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8.4, 4.2))
    markers = {"lattice": "s", "mono": "o", "uniform": "^", "lognormal": "v"}
    for kind, marker in markers.items():
        sel = [r for r in rows if r.kind == kind]
        if sel:
            ax.plot([r.report.cn_max for r in sel], [r.report.alpha for r in sel], marker, label=kind, alpha=0.8)
    cn = np.linspace(2, max(r.report.cn_max for r in rows) + 1, 100)
    ax.plot(cn, fit(cn), "k-", lw=1, label=f"equal spheres: {fit.p:.3g} CN_max^({-fit.q:.3g})")
    ax.plot(cn, np.sqrt(1.2 / cn), "k:", lw=1, label="sqrt(1.2/CN) (lattice co-rotation)")
    ax.axhline(2 / math.sqrt(7), color="grey", ls="--", lw=1, label="two spheres, 2/sqrt(7)")
    ax.set_xlabel("maximum coordination number CN_max")
    ax.set_ylabel("alpha = dt_crit / sqrt(m_min / K_max)")
    ax.legend(fontsize=7.5, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0, frameon=False)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120, bbox_inches="tight", metadata={"Software": None})
    plt.close(fig)


def main(argv=None) -> int:
    """Command line: print the study's table and fits; ``--plot FILE`` also writes the figure.

    Parameters
    ----------
    argv : list of str, optional
        Arguments (``sys.argv[1:]`` when omitted).

    Returns
    -------
    int
        Exit status, 0.
    """
    import argparse

    parser = argparse.ArgumentParser(prog="python -m dtcrit.bench.packing_alpha_study")
    parser.add_argument("--plot", metavar="FILE", help="write the alpha-CN_max figure (PNG)")
    parser.add_argument("--ks-over-kn", type=float, default=1.0)
    args = parser.parse_args(argv)
    rows = run_study(args.ks_over_kn)
    fit = fit_alpha(rows)
    print(f"{'packing':<40}{'CN mean':>8}{'CN max':>7}{'alpha':>9}  mode")
    for r in rows:
        print(f"{r.label:<40}{r.report.cn_mean:>8.3g}{r.report.cn_max:>7d}{r.report.alpha:>9.4f}  {r.report.mode}")
    mono = fit_alpha(equal_sphere_rows(rows))
    for label, f in (("all packings", fit), ("equal spheres", mono)):
        print(f"fit, {label}: alpha = {f.p:.4g} CN_max^({-f.q:.4g})  (R^2 of log fit {f.r2:.3f}, {f.count} packings)")
    for name, s in ratio_summary(rows).items():
        print(f"{name:<20} dt/dt_crit min {s['min']:.3f} median {s['median']:.3f} max {s['max']:.3f}"
              f"  safe {s['safe']}/{s['count']}")
    if args.plot:
        plot(rows, mono, args.plot)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
