"""Run LAMMPS (the `lmp` binary, GRANULAR package) on one- and two-sphere contact cases.

Two geometries:

* ``PairCase`` -- two spheres in contact in a big non-periodic box, no gravity.  The contact
  is kept closed by a preload of constant magnitude P acting along the *current* centre line
  (two ``fix addforce`` commands driven by equal-style variables of the atoms' positions).
  A preload of fixed direction would make the pair buckle (the pair rotates and the preload
  grows a lateral component), whatever the step.
* ``WallCase`` -- one sphere resting on a ``fix wall/gran ... zplane 0.0 NULL`` wall, pushed
  onto it by a constant force -P along z.

Both start from the static equilibrium overlap delta0 = P/kn (a linear Hooke spring), with
tiny random displacements, velocities and spins (displacements of about ``eps*delta0``) so
every mode is excited while the motion stays linear and the contact stays closed.  The default
eps = 1e-7 (not 1e-10): near the boundary of a strongly damped mode (zeta ~ 2) or of a pure
tangential dashpot, the critical (period-2) mode receives only ~1e-3 of the kick, because
LAMMPS starts from full-step velocities and that mode has nearly zero full-step velocity; at
eps = 1e-10 this leaves it a few ulps of the positions, where rounding locks it into a
period-2 orbit that does not grow, biasing a bisected threshold upward by ~0.5 %.  At 1e-7 the
deviations stay ~1e-7 of the overlap (fully linear) and the bias is only the finite-run
detection limit, about ln(10)/(kappa*N/2) with kappa = d(rho)/d(dt/dt_c) ~ 2.

Classification (``run_case``/``bounded``): LAMMPS reports, every few steps, the largest net
force |f_i| and |torque_i|/R_i over the atoms (both vanish at equilibrium, so they measure
the deviation), the normal spring-force deviation kn*|delta - delta0| and the kinetic energy
(translational + rotational).  The growth figure is the largest of those deviations divided by
``eps*P`` (the size the initial kick produces) and the square root of the kinetic-energy ratio
to its initial value.  Forces are judged as well as the energy because, at the boundary, the
critical mode of velocity Verlet has zero full-step velocity, so kinetic energy alone
under-reports growth.  A run also counts as growing when the envelope of the last quarter
exceeds ``WINDOW_LIMIT`` times that of the second quarter.  A ``fix halt`` ends a run early
once the growth figure passes ``min(HALT_GROWTH, 0.01/eps)`` (clearly unstable, deviation
still 1 % of the preload, so the contact never opens).

LAMMPS conventions this relies on (29Sep2021 sources of the GRANULAR package; confirmed by
the measured thresholds with Debian's lmp 20220106):
  * fix nve/sphere: velocity Verlet, half kick of v and omega, drift, forces at x_{n+1}
    with the half-step v and omega, half kick; I = 0.4 m R^2 (``inertia = 0.4``).
  * gran/hooke(/history): normal kn*delta - meff*gamman*v_n, meff = mi mj/(mi + mj);
    tangential -(kt*shear + meff*gammat*vtr) (gran/hooke: dashpot only); the shear history
    is accumulated as vtr*dt with vtr from the half-step velocities and projected on the
    tangent plane; slip velocity vt + n x (Ri wi + Rj wj) and torques -Ri n x fs: full
    radius arm.  kt NULL -> 2/7 kn, gammat NULL -> gamman/2, dampflag 0 -> gammat = 0,
    0 <= xmu <= 1e4.
  * fix wall/gran (hooke, hooke/history, granular): meff = rmass[i] (the sphere's mass),
    the same force expressions with the full radius R.
"""
from __future__ import annotations

import math
import os
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import engine_executable

__all__ = [
    "ContactLaw",
    "Sphere",
    "PairCase",
    "WallCase",
    "RunResult",
    "GROWTH_LIMIT",
    "WINDOW_LIMIT",
    "HALT_GROWTH",
    "build_inputs",
    "run_case",
    "bounded",
    "bisect_threshold",
    "run_lmp",
    "LammpsError",
]

#: growth figure above which a run counts as growing (stable runs stay O(1..10))
GROWTH_LIMIT = 1.0e3
#: ratio of the deviation envelope in the last quarter of the run to the second quarter
#: above which a run counts as growing (stable runs: <= ~1)
WINDOW_LIMIT = 10.0
#: growth figure at which LAMMPS is told to stop the run (clearly unstable)
HALT_GROWTH = 1.0e7

_STYLES = ("gran/hooke", "gran/hooke/history", "granular")


class LammpsError(RuntimeError):
    """LAMMPS failed for a reason other than the dynamics (bad input, missing binary...)."""


def _g(x: float) -> str:
    """Round-trip exact decimal text of a float for the LAMMPS input."""
    return repr(float(x))


@dataclass(frozen=True)
class ContactLaw:
    """A LAMMPS `gran/hooke` or `gran/hooke/history` law (also used for `fix wall/gran`).

    kt=None and gammat=None are written as NULL (LAMMPS then uses kt = 2/7 kn and
    gammat = gamman/2).  dampflag=0 makes LAMMPS drop the tangential dashpot (gammat = 0).
    xmu defaults to 1e4, the largest value LAMMPS accepts, so contacts never slide.

    style="granular" writes the equivalent `pair_style granular` law:
    ``hooke kn gamman tangential linear_history kt gammat/gamman xmu damping mass_velocity``
    (normal dashpot meff*gamman; tangential dashpot = (gammat/gamman)*meff*gamman, so a
    tangential dashpot needs gamman > 0; kt must be given; dampflag is ignored).  NB
    `pair_style granular` applies torques with the arm R_i - delta/2 while its slip velocity
    uses R_i; `fix wall/gran granular` uses R for both (measured, and in the sources).
    """

    kn: float
    kt: float | None = 0.0
    gamman: float = 0.0
    gammat: float | None = 0.0
    dampflag: int = 0
    xmu: float = 1.0e4
    style: str = "gran/hooke/history"

    def __post_init__(self):
        if self.style not in _STYLES:
            raise ValueError(f"style must be one of {_STYLES}, not {self.style!r}")
        if self.dampflag not in (0, 1):
            raise ValueError("dampflag must be 0 or 1")
        if self.style == "granular" and self.kt is None:
            raise ValueError("granular: give kt explicitly (no NULL default)")

    @property
    def args(self) -> str:
        """Coefficients: `Kn Kt gamma_n gamma_t xmu dampflag`, or the granular model text."""
        if self.style == "granular":
            gt = self.gammat or 0.0
            if gt > 0.0 and self.gamman <= 0.0:
                raise ValueError("granular: a tangential dashpot needs gamman > 0")
            xt = gt / self.gamman if self.gamman > 0.0 else 0.0
            return (f"hooke {_g(self.kn)} {_g(self.gamman)} tangential linear_history "
                    f"{_g(self.kt)} {_g(xt)} {_g(self.xmu)} damping mass_velocity")
        kt = "NULL" if self.kt is None else _g(self.kt)
        gt = "NULL" if self.gammat is None else _g(self.gammat)
        return f"{_g(self.kn)} {kt} {_g(self.gamman)} {gt} {_g(self.xmu)} {self.dampflag}"

    # effective values as LAMMPS resolves them (settings(): NULL defaults, dampflag)
    @property
    def kt_value(self) -> float:
        if self.style == "gran/hooke":
            return 0.0  # no tangential spring in gran/hooke
        return self.kn * 2.0 / 7.0 if self.kt is None else float(self.kt)

    @property
    def gammat_value(self) -> float:
        if self.style == "granular":
            return float(self.gammat or 0.0) if self.gamman > 0.0 else 0.0
        if self.dampflag == 0:
            return 0.0
        return 0.5 * self.gamman if self.gammat is None else float(self.gammat)


@dataclass(frozen=True)
class Sphere:
    """A solid sphere; give its density or its mass (not both)."""

    radius: float
    density: float | None = None
    mass: float | None = None

    def __post_init__(self):
        if (self.density is None) == (self.mass is None):
            raise ValueError("give exactly one of density, mass")

    @property
    def volume(self) -> float:
        return 4.0 / 3.0 * math.pi * self.radius**3

    @property
    def rho(self) -> float:
        return self.density if self.density is not None else self.mass / self.volume

    @property
    def m(self) -> float:
        return self.mass if self.mass is not None else self.density * self.volume

    @property
    def inertia(self) -> float:
        return 0.4 * self.m * self.radius**2


@dataclass(frozen=True)
class PairCase:
    """Two spheres in contact along `direction`, at the equilibrium overlap under preload.

    overlap: static overlap delta0 as a fraction of the smaller radius; the preload is
    P = kn * delta0.
    """

    law: ContactLaw
    sphere1: Sphere
    sphere2: Sphere
    overlap: float = 0.01
    direction: tuple[float, float, float] = (1.0, 0.0, 0.0)
    label: str = ""

    @property
    def spheres(self) -> tuple[Sphere, ...]:
        return (self.sphere1, self.sphere2)

    @property
    def delta0(self) -> float:
        return self.overlap * min(self.sphere1.radius, self.sphere2.radius)


@dataclass(frozen=True)
class WallCase:
    """One sphere on a fixed `fix wall/gran` zplane at z = 0, pushed on it by -P z."""

    law: ContactLaw
    sphere: Sphere
    overlap: float = 0.01
    label: str = ""

    @property
    def spheres(self) -> tuple[Sphere, ...]:
        return (self.sphere,)

    @property
    def delta0(self) -> float:
        return self.overlap * self.sphere.radius


Case = PairCase | WallCase


@dataclass
class RunResult:
    """Outcome of one LAMMPS run."""

    dt: float
    steps: int  # requested
    steps_run: int  # last step reached (smaller when fix halt stopped the run)
    halted: bool
    growth: float  # max over the run of the growth figure (see module docstring)
    force_growth: float
    energy_growth: float
    window_growth: float  # envelope of the last quarter / envelope of the second quarter
    rate: float  # fitted growth factor per step of the deviation envelope (diagnostic)
    series: dict[str, np.ndarray] = field(repr=False, default_factory=dict)
    log: str = field(repr=False, default="")

    @property
    def bounded(self) -> bool:
        return (not self.halted and math.isfinite(self.growth) and self.growth < GROWTH_LIMIT
                and self.window_growth < WINDOW_LIMIT)


# ----------------------------------------------------------------------------- inputs


def _geometry(case: Case) -> tuple[list[np.ndarray], float]:
    """Equilibrium centres and the preload P."""
    law = case.law
    d0 = case.delta0
    P = law.kn * d0
    if isinstance(case, PairCase):
        n = np.asarray(case.direction, dtype=float)
        n = n / np.linalg.norm(n)
        r0 = case.sphere1.radius + case.sphere2.radius - d0
        m1, m2 = case.sphere1.m, case.sphere2.m
        # centre of mass at the origin
        x1 = -n * r0 * m2 / (m1 + m2)
        x2 = n * r0 * m1 / (m1 + m2)
        return [x1, x2], P
    z0 = case.sphere.radius - d0
    return [np.array([0.0, 0.0, z0])], P


def _kick(case: Case, eps: float, seed: int) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Random (displacement, velocity, spin) per sphere, displacements of about eps*delta0.

    Displacements as well as velocities: LAMMPS starts from full-step velocities, and near
    the boundary the first half kick all but cancels the critical mode's share of a velocity
    kick (that mode has ~zero full-step velocity), leaving it only a few ulps of the
    positions, where rounding can lock it into a period-2 orbit instead of letting it grow.
    """
    rng = np.random.default_rng(seed)
    mmin = min(s.m for s in case.spheres)
    a = eps * case.delta0
    vs = a * math.sqrt(case.law.kn / mmin)
    out = []
    for s in case.spheres:
        dx = rng.uniform(-1.0, 1.0, 3) * a
        v = rng.uniform(-1.0, 1.0, 3) * vs
        w = rng.uniform(-1.0, 1.0, 3) * vs / s.radius
        out.append((dx, v, w))
    return out


def _wall_style(law: ContactLaw) -> str:
    return "granular" if law.style == "granular" else law.style.split("/", 1)[1]


def build_inputs(case: Case, dt: float, steps: int, *, eps: float = 1e-7, seed: int = 12345,
                 thermo_every: int | None = None, halt_growth: float = HALT_GROWTH
                 ) -> tuple[str, str]:
    """(input script, data file) for running `case` `steps` steps at time step `dt`."""
    centres, P = _geometry(case)
    kicks = _kick(case, eps, seed)
    law = case.law
    spheres = case.spheres
    natoms = len(spheres)
    rmax = max(s.radius for s in spheres)
    rmin = min(s.radius for s in spheres)
    L = 20.0 * rmax
    ref = eps * P
    # stop well before the contact could open (deviation 1% of the preload)
    halt_growth = min(halt_growth, 0.01 / eps)
    if thermo_every is None:
        # every step (up to 20000 samples): sparse sampling of a near-Nyquist mode aliases
        thermo_every = max(1, steps // 20000)
    halt_every = max(1, min(10, thermo_every))

    data = ["LAMMPS data file (engine_harness)", "", f"{natoms} atoms", "1 atom types", ""]
    data += [f"{_g(-L)} {_g(L)} xlo xhi", f"{_g(-L)} {_g(L)} ylo yhi", f"{_g(-L)} {_g(L)} zlo zhi", ""]
    data += ["Atoms # sphere", ""]
    for i, (s, x, (dx, _, _)) in enumerate(zip(spheres, centres, kicks), start=1):
        x = x + dx
        data.append(f"{i} 1 {_g(2.0 * s.radius)} {_g(s.rho)} {_g(x[0])} {_g(x[1])} {_g(x[2])}")
    data += ["", "Velocities", ""]
    for i, (_, v, w) in enumerate(kicks, start=1):
        data.append(f"{i} " + " ".join(_g(c) for c in (*v, *w)))
    data.append("")

    lines = [
        "# generated by tests/support/engines/lammps.py",
        "units si",
        "dimension 3",
        "atom_style sphere",
        "atom_modify map array sort 0 0.0",
        "boundary f f f",
        "newton off",
        "comm_modify vel yes",
        "read_data case.data",
        *( ["pair_style granular", f"pair_coeff * * {law.args}"] if law.style == "granular"
           else [f"pair_style {law.style} {law.args}", "pair_coeff * *"] ),
        f"neighbor {_g(0.2 * rmin)} bin",
        "neigh_modify delay 0 every 1 check yes",
        f"timestep {_g(dt)}",
    ]
    if isinstance(case, PairCase):
        r0 = case.sphere1.radius + case.sphere2.radius - case.delta0
        lines += [
            "group a1 id 1",
            "group a2 id 2",
            "variable ex equal x[2]-x[1]",
            "variable ey equal y[2]-y[1]",
            "variable ez equal z[2]-z[1]",
            "variable rr equal sqrt(v_ex*v_ex+v_ey*v_ey+v_ez*v_ez)",
            # constant magnitude P along the current centre line, pushing the spheres together
            f"variable p1x equal {_g(P)}*v_ex/v_rr",
            f"variable p1y equal {_g(P)}*v_ey/v_rr",
            f"variable p1z equal {_g(P)}*v_ez/v_rr",
            "variable p2x equal -v_p1x",
            "variable p2y equal -v_p1y",
            "variable p2z equal -v_p1z",
            "fix pre1 a1 addforce v_p1x v_p1y v_p1z",
            "fix pre2 a2 addforce v_p2x v_p2y v_p2z",
            f"variable ndev equal {_g(law.kn)}*abs(v_rr-{_g(r0)})",
        ]
    else:
        z0 = centres[0][2]
        lines += [
            f"fix wall all wall/gran {_wall_style(law)} {law.args} zplane 0.0 NULL",
            f"fix pre all addforce 0.0 0.0 {_g(-P)}",
            f"variable ndev equal {_g(law.kn)}*abs(z[1]-{_g(z0)})",
        ]
    lines += [
        "fix integ all nve/sphere",
        "compute tq all property/atom tqx tqy tqz radius",
        "variable fa atom sqrt(fx*fx+fy*fy+fz*fz)",
        "variable ta atom sqrt(c_tq[1]*c_tq[1]+c_tq[2]*c_tq[2]+c_tq[3]*c_tq[3])/c_tq[4]",
        "compute dev all reduce max v_fa v_ta",
        "compute ket all ke",
        "compute ker all erotate/sphere",
        "variable etot equal c_ket+c_ker",
        # max(a, b) = (a + b + |a - b|)/2 (no two-argument max in equal-style formulas)
        "variable dm equal 0.5*(c_dev[1]+c_dev[2]+abs(c_dev[1]-c_dev[2]))",
        f"variable grow equal 0.5*(v_dm+v_ndev+abs(v_dm-v_ndev))/{_g(ref)}",
        f"fix stop all halt {halt_every} v_grow > {_g(halt_growth)} error soft message no",
        "thermo_style custom step atoms v_etot c_dev[1] c_dev[2] v_ndev v_grow",
        "thermo_modify format float %.17g norm no lost ignore flush no",
        f"thermo {thermo_every}",
        f"run {int(steps)}",
    ]
    return "\n".join(lines) + "\n", "\n".join(data)


# ----------------------------------------------------------------------------- running

_COLUMNS = ("step", "atoms", "etot", "fdev", "tdev", "ndev", "grow")


def _parse_thermo(log: str, columns: tuple[str, ...] = _COLUMNS) -> dict[str, np.ndarray]:
    """The thermo table of a LAMMPS log as arrays named by `columns` (rows of another width end it)."""
    rows: list[list[float]] = []
    inside = False
    for line in log.splitlines():
        s = line.split()
        if not s:
            continue
        if s[0] == "Step":
            inside = True
            continue
        if inside:
            if s[0] == "Loop" or len(s) != len(columns):
                inside = False
                continue
            try:
                rows.append([float(t) for t in s])
            except ValueError:
                inside = False
    arr = np.array(rows, dtype=float).reshape(-1, len(columns))
    return {name: arr[:, k] for k, name in enumerate(columns)}


def _window_growth(step: np.ndarray, grow: np.ndarray, nsteps: int) -> float:
    """max(grow) over steps in [3N/4, N] divided by max(grow) over [N/4, N/2].

    Judges growth from the run's own envelope rather than from the initial kick: near the
    boundary the kick puts only a small fraction of its size into the critical mode (the
    first half kick nearly cancels that mode's full-step velocity), which would otherwise
    bias the measured threshold upward.
    """
    if not np.all(np.isfinite(grow)):
        return float("inf")
    w1 = (step >= 0.25 * nsteps) & (step <= 0.5 * nsteps)
    w2 = step >= 0.75 * nsteps
    if not w1.any() or not w2.any():
        return float("nan")  # run ended early (halted): classified by `halted`
    a, b = float(np.max(grow[w1])), float(np.max(grow[w2]))
    return b / a if a > 0 else (float("inf") if b > 0 else 1.0)


def _rate(step: np.ndarray, grow: np.ndarray) -> float:
    """Growth factor per step fitted to the log of the running-max envelope (second half)."""
    ok = np.isfinite(grow) & (grow > 0)
    if ok.sum() < 4:
        return float("nan")
    st, g = step[ok], np.maximum.accumulate(grow[ok])
    half = st >= st[0] + 0.5 * (st[-1] - st[0])
    if half.sum() < 2 or st[half][-1] == st[half][0]:
        return float("nan")
    slope = np.polyfit(st[half], np.log(g[half]), 1)[0]
    return float(math.exp(slope))


def run_lmp(script: str, data: str, *, lmp: str | None = None,
            keep_dir: str | os.PathLike | None = None, timeout: float = 120.0) -> str:
    """Run `lmp` on an input script (which reads ``case.data``) in a scratch directory; its log.

    Debian's `lmp` is an Open MPI program run as a singleton: ``ess_singleton_isolated`` keeps
    it from starting an MPI daemon, and a start-up that still fails in ``MPI_Init`` (seen when
    several `lmp` start at once on a busy machine) is retried twice.
    """
    exe = lmp or engine_executable("lammps")
    if exe is None:
        raise LammpsError("LAMMPS binary `lmp` not found (apt-get install lammps)")
    env = dict(os.environ, OMP_NUM_THREADS="1", OMPI_MCA_ess_singleton_isolated="1")
    for attempt in range(3):
        with tempfile.TemporaryDirectory(prefix="lmp_case_") as tmp:
            work = Path(keep_dir) if keep_dir is not None else Path(tmp)
            work.mkdir(parents=True, exist_ok=True)
            (work / "in.case").write_text(script)
            (work / "case.data").write_text(data)
            proc = subprocess.run(
                [exe, "-in", "in.case", "-log", "log.lammps", "-screen", "none", "-nocite"],
                cwd=work, env=env, capture_output=True, text=True, timeout=timeout,
            )
            logfile = work / "log.lammps"
            log = logfile.read_text() if logfile.exists() else ""
        if not (proc.returncode != 0 and not log and "MPI_Init" in proc.stdout + proc.stderr):
            break
    if proc.returncode != 0 or "ERROR" in log:
        tail = "\n".join((log or proc.stdout + proc.stderr).splitlines()[-15:])
        raise LammpsError(f"lmp failed (exit {proc.returncode}):\n{tail}")
    return log


def run_case(case: Case, dt: float, steps: int, *, eps: float = 1e-7, seed: int = 12345,
             lmp: str | None = None, keep_dir: str | os.PathLike | None = None,
             timeout: float = 120.0) -> RunResult:
    """Run `case` for `steps` steps of size `dt` in LAMMPS and classify the outcome."""
    script, data = build_inputs(case, dt, steps, eps=eps, seed=seed)
    log = run_lmp(script, data, lmp=lmp, keep_dir=keep_dir, timeout=timeout)
    ser = _parse_thermo(log)
    if ser["step"].size == 0:
        raise LammpsError("no thermo output parsed from the LAMMPS log")
    natoms = len(case.spheres)
    e0 = ser["etot"][0]
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        fg = float(np.max(ser["grow"])) if np.all(np.isfinite(ser["grow"])) else float("inf")
        eg = float(np.sqrt(np.max(ser["etot"]) / e0)) if (e0 > 0 and np.all(np.isfinite(ser["etot"]))) else float("inf")
    if np.any(ser["atoms"] < natoms):
        fg = float("inf")
    steps_run = int(ser["step"][-1])
    halted = steps_run < steps
    wg = _window_growth(ser["step"], ser["grow"], steps) if not halted else float("inf")
    return RunResult(dt=dt, steps=steps, steps_run=steps_run, halted=halted,
                     growth=max(fg, eg), force_growth=fg, energy_growth=eg, window_growth=wg,
                     rate=_rate(ser["step"], ser["grow"]), series=ser, log=log)


def bounded(case: Case, dt: float, steps: int, **kw) -> bool:
    """True when LAMMPS stays bounded for `steps` steps at `dt` (see `run_case`)."""
    return run_case(case, dt, steps, **kw).bounded


def bisect_threshold(case: Case, lo: float, hi: float, rel_tol: float = 1e-3, *,
                     steps: int = 2000, **kw) -> float:
    """Stability threshold of `case` in LAMMPS by bisection of dt in [lo, hi].

    Requires `lo` bounded and `hi` growing; returns the midpoint of the final bracket,
    whose relative width is below `rel_tol`.
    """
    if not bounded(case, lo, steps, **kw):
        raise ValueError(f"lower end dt={lo!r} is not bounded")
    if bounded(case, hi, steps, **kw):
        raise ValueError(f"upper end dt={hi!r} is not growing")
    while hi / lo - 1.0 > rel_tol:
        mid = math.sqrt(lo * hi)
        if bounded(case, mid, steps, **kw):
            lo = mid
        else:
            hi = mid
    return math.sqrt(lo * hi)
