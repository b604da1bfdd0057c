"""Run LAMMPS (the `lmp` binary, GRANULAR package) on periodic lattices of equal spheres.

Geometry (``LatticeCase``): ``cells`` x ``cells`` x ``cells`` cubic cells of a simple cubic
(SC), body-centred cubic (BCC) or face-centred cubic (FCC) lattice of equal spheres of radius R
in a fully periodic box (``boundary p p p``).  Nearest neighbours sit at the centre distance
``2R - delta0``, a uniform overlap ``delta0 = overlap * R`` (default 1e-6 R), so every sphere has
6, 8 or 12 contacts.  By symmetry the lattice is in equilibrium without any preload (each
sphere's contact forces cancel in opposite pairs), yet every contact carries the normal force
``kn * delta0``.  Cubic cell edges: ``d`` (SC), ``2 d / sqrt(3)`` (BCC), ``sqrt(2) d`` (FCC), d the
neighbour distance.

The box must be wider than twice the neighbour cutoff (``2R`` plus the skin, 0.1 R) so every
contact partner of a sphere is a distinct atom: LAMMPS carries the shear history over a
re-neighbouring by the partner's atom ID (fix NEIGH_HISTORY, ``partner[i][m] == tag[j]``), so two
contacts of one pair through different periodic images would share it.  SC therefore needs
``cells >= 3`` (4 keeps the zone-boundary modes of an even period).

What LAMMPS computes for these contacts (29Sep2021 sources, src/GRANULAR/pair_gran_hooke_history.cpp
and src/fix_nve_sphere.cpp; the same as for the pair cases of ``support.engines.lammps``):
  * normal force ``kn (R_i + R_j - r) - meff gamman v_n`` along the *current* centre line,
    ``meff = m_i m_j / (m_i + m_j)``;
  * shear displacement accumulated as ``vtr dt`` from the half-step velocities, with slip velocity
    ``v_t + n x (R_i w_i + R_j w_j)`` (the code divides ``R_i w_i + R_j w_j`` by r and crosses it
    with the centre vector of length r: the arm is the full radius), then projected on the
    current tangent plane; tangential force ``-(kt * shear + meff gammat vtr)``, capped at
    ``xmu |F_n|`` (xmu = 1e4, the largest value accepted, so no contact slides here);
  * torques ``-R_i n x F_t``: full radius arm, no overlap correction;
  * fix nve/sphere: velocity Verlet (half kick of v and omega, drift, forces at x_{n+1} with the
    half-step v and omega, half kick), ``I = 0.4 m R^2``.

Geometric stiffness.  Because the normal force turns with the centre line, a pre-loaded contact
adds ``-(F/r)(1 - n n^T)`` (F = kn delta0) to the stiffness of the relative displacement of the
two centres: a softening of relative size ``delta0 / (2R - delta0)`` against kn, about 5e-7 at
the default overlap (measured on BCC at kt = 0.1 kn: it lengthens the step by 0.42 % at overlap
1e-2, so by about 4e-7 at 1e-6), well below what the 0.99x / 1.01x checks resolve.  The
tangential history's projection and the normal's rotation of the shear are second order in the
motion.  The arm is R in LAMMPS; the lattice a predictor builds at zero overlap has arm R as well.
One consequence is not small: SC and BCC with kt = 0 are mechanisms (floppy modes of zero
stiffness), which the softening makes unstable whatever the step, growing as ``exp(lambda t)``
with ``lambda = 2 sqrt(overlap kn / m)`` (measured: an e-folding of 500-600 steps at the critical
step and overlap 1e-6); runs of those cases must stay well short of that many e-foldings.

Kick (``_kick``): random displacements of about ``a = kick * delta0`` (default kick 1e-5: 1e-11 R,
some 5e3 ulps of the coordinates, far from opening a contact), velocities of about
``a sqrt(kn/m)`` and spins of about that over R; a fixed seed makes runs reproducible.

Classification (``run_case``): every ``thermo_every`` steps LAMMPS reports the largest net force
|f_i| and |torque_i|/R_i over the atoms (both zero at equilibrium, so they measure the motion),
the kinetic energy (translational + rotational) and the smallest and largest number of contacts
per atom (compute contact/atom).  The growth figure is the larger of the force deviation over
``kn * a`` and the square root of the kinetic-energy ratio to its initial value.  Forces as well as
the energy, because at the boundary velocity Verlet's critical mode has zero full-step velocity.
Away from the boundary the growth figure stays about 5-15; near it the critical mode's response to
the kick grows like ``1.3 / sqrt(1 - dt/dt_c)`` (measured), hence the high ``GROWTH_LIMIT`` (a limit of
300 would call runs within 2e-5 of the threshold growing).
A run is bounded when it was not halted, its growth figure stays below ``GROWTH_LIMIT``, the
envelope of its last quarter is below ``WINDOW_LIMIT`` times that of its second quarter, and no
contact opened or closed.  ``fix halt`` stops a run once the growth figure passes
``min(HALT_GROWTH, 0.1 / kick)`` (motion still about a tenth of the overlap).
"""
from __future__ import annotations

import math
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np

from .lammps import ContactLaw, Sphere, _g, _parse_thermo, _rate, _window_growth, run_lmp

__all__ = [
    "LATTICES",
    "COORDINATION",
    "LatticeCase",
    "LatticeRun",
    "GROWTH_LIMIT",
    "WINDOW_LIMIT",
    "HALT_GROWTH",
    "lattice_sites",
    "build_inputs",
    "run_case",
    "run_many",
    "bisect_threshold",
    "extrapolated_threshold",
]

#: growth figure above which a run counts as growing (bounded runs: ~5-15 away from the boundary)
GROWTH_LIMIT = 3.0e3
#: envelope of the last quarter over the second quarter above which a run counts as growing
WINDOW_LIMIT = 10.0
#: growth figure at which LAMMPS stops a run (never above 0.1/kick)
HALT_GROWTH = 1.0e4

# fractional basis of the cubic cell and the cell edge in units of the neighbour distance
_BASIS: dict[str, tuple[tuple[tuple[float, float, float], ...], float]] = {
    "sc": (((0.0, 0.0, 0.0),), 1.0),
    "bcc": (((0.0, 0.0, 0.0), (0.5, 0.5, 0.5)), 2.0 / math.sqrt(3.0)),
    "fcc": (((0.0, 0.0, 0.0), (0.5, 0.5, 0.0), (0.5, 0.0, 0.5), (0.0, 0.5, 0.5)), math.sqrt(2.0)),
}
LATTICES = tuple(_BASIS)
COORDINATION = {"sc": 6, "bcc": 8, "fcc": 12}
_SKIN = 0.1  # neighbour skin in units of R


def lattice_sites(name: str, cells: int, spacing: float) -> tuple[np.ndarray, float]:
    """Centres of a periodic `name` lattice with neighbour distance `spacing`, and the box edge.

    The lattice is shifted by a tenth of a cell from the box corner so no centre sits on a face.
    """
    basis, edge = _BASIS[name]
    a = edge * spacing
    grid = np.stack(np.meshgrid(*(np.arange(cells),) * 3, indexing="ij"), -1).reshape(-1, 3)
    frac = (grid[:, None, :] + np.asarray(basis)[None, :, :]).reshape(-1, 3) + 0.1
    return frac * a, cells * a


@dataclass(frozen=True)
class LatticeCase:
    """A periodic SC/BCC/FCC lattice of equal spheres at a uniform overlap (module docstring)."""

    law: ContactLaw
    lattice: str
    cells: int
    sphere: Sphere
    overlap: float = 1.0e-6
    label: str = ""

    def __post_init__(self):
        if self.lattice not in _BASIS:
            raise ValueError(f"lattice must be one of {LATTICES}, not {self.lattice!r}")
        if not 0.0 < self.overlap < 0.1:
            raise ValueError("overlap must lie in (0, 0.1) (a fraction of R)")
        R = self.sphere.radius
        if self.box_length <= 2.0 * (2.0 * R + _SKIN * R):
            raise ValueError(f"{self.cells} cells of {self.lattice}: box {self.box_length / R:.3g} R is not "
                             "wider than twice the neighbour cutoff; contact partners would repeat")

    @property
    def delta0(self) -> float:
        return self.overlap * self.sphere.radius

    @property
    def spacing(self) -> float:
        return 2.0 * self.sphere.radius - self.delta0

    @property
    def box_length(self) -> float:
        return self.cells * _BASIS[self.lattice][1] * self.spacing

    @property
    def natoms(self) -> int:
        return self.cells**3 * len(_BASIS[self.lattice][0])

    @property
    def coordination(self) -> int:
        return COORDINATION[self.lattice]


@dataclass
class LatticeRun:
    """Outcome of one LAMMPS lattice run (see the module docstring for the figures)."""

    dt: float
    steps: int
    steps_run: int
    halted: bool
    growth: float
    force_growth: float
    energy_growth: float
    window_growth: float
    rate: float  # fitted growth factor per step of the deviation envelope (diagnostic)
    contacts_min: int
    contacts_max: int
    coordination: int
    series: dict[str, np.ndarray] = field(repr=False, default_factory=dict)

    @property
    def contacts_kept(self) -> bool:
        return self.contacts_min == self.contacts_max == self.coordination

    @property
    def bounded(self) -> bool:
        return (not self.halted and math.isfinite(self.growth) and self.growth < GROWTH_LIMIT
                and self.window_growth < WINDOW_LIMIT and self.contacts_kept)


def _kick(case: LatticeCase, kick: float, seed: int):
    rng = np.random.default_rng(seed)
    n = case.natoms
    a = kick * case.delta0
    vs = a * math.sqrt(case.law.kn / case.sphere.m)
    return (rng.uniform(-1.0, 1.0, (n, 3)) * a, rng.uniform(-1.0, 1.0, (n, 3)) * vs,
            rng.uniform(-1.0, 1.0, (n, 3)) * vs / case.sphere.radius)


def build_inputs(case: LatticeCase, dt: float, steps: int, *, kick: float = 1e-5, seed: int = 2022,
                 thermo_every: int | None = None, halt_growth: float = HALT_GROWTH) -> tuple[str, str]:
    """(input script, data file) for running `case` `steps` steps at time step `dt`."""
    law, s = case.law, case.sphere
    x, L = lattice_sites(case.lattice, case.cells, case.spacing)
    dx, v, w = _kick(case, kick, seed)
    x = x + dx
    ref = law.kn * kick * case.delta0
    halt_growth = min(halt_growth, 0.1 / kick)
    if thermo_every is None:
        thermo_every = max(1, steps // 20000)  # sparse sampling of a near-Nyquist mode aliases
    halt_every = max(1, min(10, thermo_every))

    data = ["LAMMPS data file (engine_harness lattice)", "", f"{case.natoms} atoms", "1 atom types", ""]
    data += [f"0.0 {_g(L)} {ax}lo {ax}hi" for ax in "xyz"] + ["", "Atoms # sphere", ""]
    for i, xi in enumerate(x, start=1):
        data.append(f"{i} 1 {_g(2.0 * s.radius)} {_g(s.rho)} {_g(xi[0])} {_g(xi[1])} {_g(xi[2])}")
    data += ["", "Velocities", ""]
    for i, (vi, wi) in enumerate(zip(v, w), start=1):
        data.append(f"{i} " + " ".join(_g(c) for c in (*vi, *wi)))
    data.append("")

    pair = (["pair_style granular", f"pair_coeff * * {law.args}"] if law.style == "granular"
            else [f"pair_style {law.style} {law.args}", "pair_coeff * *"])
    lines = [
        "# generated by tests/support/engines/lammps_lattice.py",
        "units si",
        "dimension 3",
        "atom_style sphere",
        "atom_modify map array sort 0 0.0",
        "boundary p p p",
        "newton off",
        "comm_modify vel yes",
        "read_data case.data",
        *pair,
        f"neighbor {_g(_SKIN * s.radius)} bin",
        "neigh_modify delay 0 every 1 check yes",
        f"timestep {_g(dt)}",
        "fix integ all nve/sphere",
        "compute tq all property/atom tqx tqy tqz radius",
        "variable fa atom sqrt(fx*fx+fy*fy+fz*fz)",
        "variable ta atom sqrt(c_tq[1]*c_tq[1]+c_tq[2]*c_tq[2]+c_tq[3]*c_tq[3])/c_tq[4]",
        "compute dev all reduce max v_fa v_ta",
        "compute cnt all contact/atom",
        "compute cmin all reduce min c_cnt",
        "compute cmax all reduce max c_cnt",
        "compute ket all ke",
        "compute ker all erotate/sphere",
        "variable etot equal c_ket+c_ker",
        f"variable grow equal 0.5*(c_dev[1]+c_dev[2]+abs(c_dev[1]-c_dev[2]))/{_g(ref)}",
        f"fix stop all halt {halt_every} v_grow > {_g(halt_growth)} error soft message no",
        "thermo_style custom step atoms v_etot c_dev[1] c_dev[2] v_grow c_cmin c_cmax",
        "thermo_modify format float %.17g norm no lost ignore flush no",
        f"thermo {thermo_every}",
        f"run {int(steps)}",
    ]
    return "\n".join(lines) + "\n", "\n".join(data)


_COLUMNS = ("step", "atoms", "etot", "fdev", "tdev", "grow", "cmin", "cmax")


def run_case(case: LatticeCase, dt: float, steps: int, *, kick: float = 1e-5, seed: int = 2022,
             lmp: str | None = None, keep_dir=None, timeout: float = 120.0) -> LatticeRun:
    """Run `case` for `steps` steps of size `dt` in LAMMPS and classify the outcome."""
    script, data = build_inputs(case, dt, steps, kick=kick, seed=seed)
    ser = _parse_thermo(run_lmp(script, data, lmp=lmp, keep_dir=keep_dir, timeout=timeout), _COLUMNS)
    if ser["step"].size == 0:
        raise RuntimeError("no thermo output parsed from the LAMMPS log")
    e0 = ser["etot"][0]
    finite = bool(np.all(np.isfinite(ser["grow"])) and np.all(np.isfinite(ser["etot"])))
    fg = float(np.max(ser["grow"])) if finite else math.inf
    eg = float(np.sqrt(np.max(ser["etot"]) / e0)) if finite and e0 > 0 else math.inf
    if np.any(ser["atoms"] < case.natoms):
        fg = math.inf
    steps_run = int(ser["step"][-1])
    halted = steps_run < steps
    wg = _window_growth(ser["step"], ser["grow"], steps) if not halted else math.inf
    return LatticeRun(dt=dt, steps=steps, steps_run=steps_run, halted=halted, growth=max(fg, eg),
                      force_growth=fg, energy_growth=eg, window_growth=wg, rate=_rate(ser["step"], ser["grow"]),
                      contacts_min=int(np.min(ser["cmin"])), contacts_max=int(np.max(ser["cmax"])),
                      coordination=case.coordination, series=ser)


def run_many(jobs, *, workers: int = 2, **kw) -> list[LatticeRun]:
    """``run_case(case, dt, steps, **kw)`` for each ``(case, dt, steps)`` of `jobs`, `workers` lmp at a time."""
    jobs = list(jobs)
    with ThreadPoolExecutor(max_workers=max(1, workers)) as pool:
        return list(pool.map(lambda job: run_case(*job, **kw), jobs))


def bisect_threshold(case: LatticeCase, lo: float, hi: float, rel_tol: float = 1e-4, *,
                     steps: int = 4000, workers: int = 2, **kw) -> tuple[float, float]:
    """Bracket ``(lo, hi)`` of `case`'s stability threshold in LAMMPS, relative width below `rel_tol`.

    Requires `lo` bounded and `hi` growing (both are checked).  Each round runs `workers` steps
    spread geometrically inside the bracket at once, narrowing it by a factor ``workers + 1``.
    """
    first = run_many([(case, lo, steps), (case, hi, steps)], workers=workers, **kw)
    if not first[0].bounded:
        raise ValueError(f"lower end dt={lo!r} is not bounded")
    if first[1].bounded:
        raise ValueError(f"upper end dt={hi!r} is not growing")
    while hi / lo - 1.0 > rel_tol:
        ratio = hi / lo
        trial = [lo * ratio ** (k / (workers + 1)) for k in range(1, workers + 1)]
        runs = run_many([(case, dt, steps) for dt in trial], workers=workers, **kw)
        for dt, run in zip(trial, runs):
            if run.bounded:
                lo = dt
            else:
                hi = dt
                break
    return lo, hi


def extrapolated_threshold(case: LatticeCase, dts, steps: int = 60000, *, onset: str = "sqrt",
                           workers: int = 2, **kw) -> tuple[float, list[LatticeRun]]:
    """`case`'s threshold from the growth rates of runs at steps `dts` just above it.

    Free of the detection limit of a finite run (which biases a bisection upward by about
    ``ln(WINDOW_LIMIT) / (kappa steps / 2)``): each run grows until halted, its envelope's growth
    factor per step ``z`` is fitted (``LatticeRun.rate``), and the fit is extrapolated to ``z = 1``.
    An undamped critical pair of eigenvalues splits off the unit circle as ``(ln z)^2 = 8 (dt/dt_c - 1)``
    (``onset="sqrt"``: fit ``(ln z)^2`` linearly in dt); a damped one crosses it with non-zero
    speed, ``ln z`` linear in dt (``onset="linear"``).  Every run must have grown (been halted).
    """
    if onset not in ("sqrt", "linear"):
        raise ValueError("onset must be 'sqrt' or 'linear'")
    dts = [float(d) for d in dts]
    runs = run_many([(case, dt, steps) for dt in dts], workers=workers, **kw)
    for dt, run in zip(dts, runs):
        if not run.halted or not run.rate > 1.0:
            raise ValueError(f"dt={dt!r} did not grow to the halt within {steps} steps; choose larger steps")
    y = np.log([run.rate for run in runs]) ** (2 if onset == "sqrt" else 1)
    slope, intercept = np.polyfit(dts, y, 1)
    return float(-intercept / slope), runs
