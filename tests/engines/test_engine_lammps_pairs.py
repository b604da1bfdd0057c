"""LAMMPS (real engine) agrees with the analytic critical step of small granular contacts.

Each case runs the `lmp` binary (Debian `lammps`, GRANULAR package) through
``support.engines.lammps`` at 0.99x and 1.01x of a critical step computed *here* from
closed-form formulas, and asserts that LAMMPS stays bounded below and grows above.

Analytic step (LAMMPS velocity Verlet; forces at x_{n+1} use the half-step velocity
v_{n+1/2}).  A linear contact mode x'' = -k A x - c A x' (A: inverse inertia of the mode)
follows the recurrence  (x_{n+1} - 2x_n + x_{n-1}) = -h^2 x_n - 2 zeta h (x_n - x_{n-1})
with h = omega dt, omega = sqrt(k A), zeta = c A / (2 omega).  Its characteristic
polynomial z^2 + (h^2 + 2 zeta h - 2) z + (1 - 2 zeta h) has P(1) = h^2 > 0, and the root
z = -1 is crossed first (P(-1) = 4 - h^2 - 4 zeta h = 0, which comes before |1 - 2 zeta h| = 1),
so  dt_c = 2 / (omega (zeta + sqrt(zeta^2 + 1))).
A mode with k = 0, c > 0 (the tangential dashpot of gran/hooke, which has no tangential
spring) updates its half-step velocity as w_{n+3/2} = (1 - c A dt) w_{n+1/2}: stable while
c A dt <= 2, so dt_c = 2 / (c A) (the k -> 0 limit of the formula above).

LAMMPS conventions used (checked in the GRANULAR sources, see support/engines/lammps.py):
  * normal force kn*delta - meff*gamman*v_n, meff = m1 m2/(m1+m2)  ->  c_n = meff*gamman;
  * tangential kt*(slip) + meff*gammat*v_t (gammat IS multiplied by meff, like gamman);
    gran/hooke has the dashpot only (kt unused);  NULL kt -> 2/7 kn, NULL gammat -> gamman/2,
    dampflag 0 -> gammat = 0;
  * slip velocity and torques use the full radius R_i as arm, I = 2/5 m R^2 (fix nve/sphere);
  * fix wall/gran: meff = the sphere's own mass, arm R.
  * pair_style granular (optional cases; hooke + linear_history + damping mass_velocity):
    the same forces, but torques use the arm R_i - delta/2 while the slip velocity uses R_i
    (checked separately below).
Modes: two spheres, normal A = 1/m1 + 1/m2; tangential (sliding coupled with rotation)
A = 1/m1 + 1/m2 + R1^2/I1 + R2^2/I2 (= 7/m for equal spheres m).  Sphere on a fixed wall:
normal A = 1/m, tangential A = 1/m + R^2/I = 7/(2m).  The pair's step is the minimum over
its modes; each parametrisation below says which mode governs.
"""
from __future__ import annotations

import math

import pytest

from support.engines import engine_available, require_engine
from support.engines.lammps import ContactLaw, PairCase, Sphere, WallCase, run_case

STEPS = 2000  # enough for >1e7 growth at 1.01x in the slowest case; ~0.5 s per run


# ----------------------------------------------------------------------------- analytic


def _mass(radius: float, density: float) -> float:
    return 4.0 / 3.0 * math.pi * radius**3 * density


def _dt_mode(k: float, c: float, A: float) -> float:
    """Exact critical step of x'' = -kA x - cA x' under velocity Verlet (half-step v)."""
    if k == 0.0:
        return 2.0 / (c * A) if c > 0.0 else math.inf
    omega = math.sqrt(k * A)
    zeta = c * A / (2.0 * omega)
    return 2.0 / (omega * (zeta + math.sqrt(zeta * zeta + 1.0)))


def _lammps_coefficients(law: ContactLaw) -> tuple[float, float, float, float]:
    """(kn, kt, gamman, gammat) as LAMMPS resolves the pair_style arguments."""
    if law.style == "granular":  # explicit kt; tangential dashpot = x_t * meff*gamman
        gammat = (law.gammat or 0.0) if law.gamman > 0.0 else 0.0
        return law.kn, law.kt, law.gamman, gammat
    kt = 0.0 if law.style == "gran/hooke" else (2.0 / 7.0 * law.kn if law.kt is None else law.kt)
    if law.dampflag == 0:
        gammat = 0.0
    else:
        gammat = 0.5 * law.gamman if law.gammat is None else law.gammat
    return law.kn, kt, law.gamman, gammat


def analytic_modes(case, torque_arm_shift: float = 0.0) -> dict[str, float]:
    """Critical step of each contact mode of `case`, from the formulas in the docstring.

    torque_arm_shift: for two spheres, torques applied with the arm R_i - shift while the
    slip velocity uses R_i, so A_t = 1/m1 + 1/m2 + sum R_i (R_i - shift) / I_i (the
    `pair_style granular` convention has shift = delta/2; the gran/* styles have 0).
    """
    kn, kt, gn, gt = _lammps_coefficients(case.law)
    if isinstance(case, PairCase):
        s1, s2 = case.sphere1, case.sphere2
        m1, m2 = _mass(s1.radius, s1.density), _mass(s2.radius, s2.density)
        meff = m1 * m2 / (m1 + m2)
        A_n = 1.0 / m1 + 1.0 / m2
        A_t = (A_n + s1.radius * (s1.radius - torque_arm_shift) / (0.4 * m1 * s1.radius**2)
               + s2.radius * (s2.radius - torque_arm_shift) / (0.4 * m2 * s2.radius**2))
    else:
        s = case.sphere
        m = _mass(s.radius, s.density)
        meff = m  # fix wall/gran: the sphere's own mass
        A_n = 1.0 / m
        A_t = A_n + s.radius**2 / (0.4 * m * s.radius**2)
    modes = {"normal": _dt_mode(kn, meff * gn, A_n)}
    if kt > 0.0 or gt > 0.0:
        modes["tangential"] = _dt_mode(kt, meff * gt, A_t)
    return modes


# ----------------------------------------------------------------------------- cases

R, RHO, KN = 1.0e-3, 2500.0, 1.0e5
SMALL = Sphere(radius=R, density=RHO)
BIG = Sphere(radius=1.6e-3, density=7800.0)  # unequal partner: other radius and density
M = _mass(R, RHO)
W_PAIR = math.sqrt(KN * 2.0 / M)  # undamped normal omega of two equal spheres
W_WALL = math.sqrt(KN / M)  # undamped normal omega of a sphere on a wall
W_UNEQ = math.sqrt(KN * (1.0 / M + 1.0 / _mass(BIG.radius, BIG.density)))


def _gamman(zeta: float, omega: float) -> float:
    # normal mode: c A = meff*gamman*(1/m1 + 1/m2) = gamman (pair) or m*gamman/m (wall),
    # so zeta_n = gamman / (2 omega_n) whatever the masses
    return 2.0 * zeta * omega


HH = "gran/hooke/history"
CASES = [
    # (id, case, governing mode(s), why)
    ("pair-normal-undamped", PairCase(ContactLaw(KN, kt=0.0), SMALL, SMALL),
     {"normal"}, "kt=0, no damping: only the normal mode, dt = 2/omega_n"),
    ("pair-normal-zeta0.05", PairCase(ContactLaw(KN, kt=0.0, gamman=_gamman(0.05, W_PAIR)), SMALL, SMALL),
     {"normal"}, "kt=0: normal mode only, zeta_n = 0.05"),
    ("pair-normal-zeta0.5", PairCase(ContactLaw(KN, kt=0.0, gamman=_gamman(0.5, W_PAIR)), SMALL, SMALL),
     {"normal"}, "kt=0: normal mode only, zeta_n = 0.5"),
    ("pair-normal-zeta2", PairCase(ContactLaw(KN, kt=0.0, gamman=_gamman(2.0, W_PAIR)), SMALL, SMALL),
     {"normal"}, "kt=0: normal mode only, zeta_n = 2 (overdamped)"),
    ("pair-ktNULL-undamped", PairCase(ContactLaw(KN, kt=None), SMALL, SMALL),
     {"normal", "tangential"},
     "default kt = 2/7 kn: kt*7/m = kn*2/m, normal and tangential have the same omega (tie)"),
    ("pair-kt=kn-normal-damping", PairCase(ContactLaw(KN, kt=KN, gamman=_gamman(0.5, W_PAIR)), SMALL, SMALL),
     {"tangential"}, "omega_t = sqrt(3.5) omega_n, undamped (dampflag 0) -> tangential, by 14%"),
    ("pair-kt=kn-overlap10%", PairCase(ContactLaw(KN, kt=KN), SMALL, SMALL, overlap=0.1),
     {"tangential"},
     "tangential; 10% overlap makes the arm convention visible: an arm R - delta/2 would move "
     "the step by +3.7%"),
    ("pair-hooke-dashpot", PairCase(ContactLaw(KN, gamman=_gamman(0.5, W_PAIR), gammat=_gamman(0.5, W_PAIR),
                                                dampflag=1, style="gran/hooke"), SMALL, SMALL),
     {"tangential"},
     "gran/hooke tangential dashpot, no spring: dt = 2/(meff*gammat*7/m) = 0.46x the normal step"),
    ("pair-hooke-weak-dashpot", PairCase(ContactLaw(KN, gamman=_gamman(0.5, W_PAIR), gammat=0.1 * W_PAIR,
                                                     dampflag=1, style="gran/hooke"), SMALL, SMALL),
     {"normal"}, "gran/hooke, small gammat: dashpot limit 4.6x away, damped normal mode governs"),
    ("unequal-kt=kn/2-undamped", PairCase(ContactLaw(KN, kt=KN / 2.0), SMALL, BIG),
     {"tangential"}, "unequal spheres: A_t = 3.5 A_n for any two solid spheres; kt = kn/2 -> tangential"),
    ("unequal-ktNULL-damped", PairCase(ContactLaw(KN, kt=None, gamman=_gamman(0.3, W_UNEQ), gammat=None,
                                                   dampflag=1), SMALL, BIG),
     {"tangential"},
     "same omega (default kt) but zeta_t = 1.75 zeta_n (gammat = gamman/2, times meff, times "
     "A_t = 3.5 A_n) -> tangential; checks gammat*meff with unequal masses"),
    ("wall-kt=kn", WallCase(ContactLaw(KN, kt=KN), SMALL),
     {"tangential"}, "wall, kt = kn: A_t = 3.5/m -> tangential (omega_t = 1.87 omega_n)"),
    ("wall-kt=kn-overlap10%", WallCase(ContactLaw(KN, kt=KN), SMALL, overlap=0.1),
     {"tangential"}, "wall tangential; an arm R - delta would move the step by +7.6%"),
    ("wall-ktNULL-normal-damping", WallCase(ContactLaw(KN, kt=None, gamman=_gamman(0.5, W_WALL)), SMALL),
     {"normal"}, "wall, default kt (same omega as normal), dampflag 0: damped normal mode governs"),
    ("pair-granular-normal-zeta0.5",
     PairCase(ContactLaw(KN, kt=0.0, gamman=_gamman(0.5, W_PAIR), style="granular"), SMALL, SMALL),
     {"normal"}, "pair_style granular (hooke, damping mass_velocity): same normal law as gran/hooke"),
    ("wall-granular-kt=kn-overlap10%", WallCase(ContactLaw(KN, kt=KN, style="granular"), SMALL, overlap=0.1),
     {"tangential"}, "fix wall/gran granular: tangential; its torque arm is the full radius R"),
    ("wall-hooke-dashpot", WallCase(ContactLaw(KN, gamman=_gamman(0.2, W_WALL), gammat=_gamman(0.2, W_WALL),
                                                dampflag=1, style="gran/hooke"), SMALL),
     {"tangential"}, "wall gran/hooke dashpot: dt = 2/(m*gammat*3.5/m); checks wall meff = m"),
]

PARAMS = [pytest.param(case, gov, id=cid) for cid, case, gov, _why in CASES]


# ----------------------------------------------------------------------------- dtcrit's prediction


def _scene_text(case) -> str:
    """The dtcrit scene of a case: LAMMPS's coefficients as given (cn = meff gamman, cs = meff gammat)."""
    kn, kt, gn, gt = _lammps_coefficients(case.law)
    if isinstance(case, PairCase):
        s1, s2 = case.sphere1, case.sphere2
        m1, m2 = _mass(s1.radius, s1.density), _mass(s2.radius, s2.density)
        meff = m1 * m2 / (m1 + m2)
        same = s1 == s2
        parts = [s1] if same else [s1, s2]
        head = "" if same else 'pairs = "unlike"\n'
        contact = f"kn = {kn!r}\nks = {kt!r}\ncn = {meff * gn!r}\ncs = {meff * gt!r}\n"
        walls = ""
    else:
        parts, head = [case.sphere], ""
        m = _mass(case.sphere.radius, case.sphere.density)
        contact = "kn = 1.0\nks = 1.0\n"  # no particle-particle contact in the run; the wall pair is read below
        walls = f"[[wall]]\nkn = {kn!r}\nks = {kt!r}\ncn = {m * gn!r}\ncs = {m * gt!r}\n"
    spheres = "".join(f'[[particle]]\nshape = "sphere"\nradius = {s.radius!r}\ndensity = {s.density!r}\n' for s in parts)
    return f'integrator = "velocity-verlet"\n{head}{spheres}[contact]\nmodel = "linear"\n{contact}{walls}'


def dtcrit_step(case) -> float:
    """``dtcrit step``'s isolated-contact step of the case (the wall contact's own for a wall case)."""
    from dtcrit.scenes.scene import parse_scene
    from dtcrit.scenes.timestep import critical_step

    result = critical_step(parse_scene(_scene_text(case)))
    if isinstance(case, PairCase):
        return result.dt_isolated
    return next(p for p in result.pairs if p.contact.wall is not None).dt_translation


GRAN = [pytest.param(case, gov, id=cid) for cid, case, gov, _why in CASES if case.law.style != "granular"]


@pytest.mark.parametrize("case, governing", GRAN)
def test_dtcrit_step_equals_the_analytic_mode_step(case, governing):
    """`dtcrit step` on the same contact (LAMMPS's own coefficients) gives the analytic step to 1e-9."""
    assert dtcrit_step(case) == pytest.approx(min(analytic_modes(case).values()), rel=1e-9)


@pytest.mark.parametrize("case, governing", GRAN)
def test_lammps_bounded_below_and_grows_above_dtcrit(lmp, case, governing):
    """LAMMPS itself, at 0.99x and 1.01x of the step `dtcrit step` prints for that contact."""
    dt = dtcrit_step(case)
    below = run_case(case, 0.99 * dt, STEPS, lmp=lmp)
    above = run_case(case, 1.01 * dt, STEPS, lmp=lmp)
    assert below.bounded, f"LAMMPS grows at 0.99x dtcrit's {dt:.6e}: growth={below.growth:.3g}"
    assert not above.bounded and (above.rate > 1.0 or above.halted), f"LAMMPS bounded at 1.01x dtcrit's {dt:.6e}"


@pytest.fixture(scope="module")
def lmp() -> str:
    return require_engine("lammps")


@pytest.mark.parametrize("case, governing", PARAMS)
def test_documented_governing_mode(case, governing):
    """The governing mode stated for each case is what the formulas give (no engine needed)."""
    modes = analytic_modes(case)
    dt = min(modes.values())
    assert {k for k, v in modes.items() if v <= dt * (1.0 + 1e-12)} == governing
    if len(governing) == 1 and len(modes) > 1:
        # the other mode is clearly slower, so the 1.01x check tests the governing one
        assert sorted(modes.values())[1] > 1.1 * dt


GRANULAR = [pytest.param(case, gov, id=cid) for cid, case, gov, _why in CASES if case.law.style == "granular"]


@pytest.mark.parametrize("case, governing", GRANULAR)
def test_lammps_bounded_below_analytic_step(lmp, case, governing):
    dt = min(analytic_modes(case).values())
    res = run_case(case, 0.99 * dt, STEPS, lmp=lmp)
    assert res.bounded, (
        f"LAMMPS grows at 0.99x the analytic step {dt:.6e} ({governing}): growth={res.growth:.3g}, "
        f"window={res.window_growth:.3g}, halted={res.halted} at step {res.steps_run}")


@pytest.mark.parametrize("case, governing", GRANULAR)
def test_lammps_grows_above_analytic_step(lmp, case, governing):
    dt = min(analytic_modes(case).values())
    res = run_case(case, 1.01 * dt, STEPS, lmp=lmp)
    assert not res.bounded, (
        f"LAMMPS stays bounded at 1.01x the analytic step {dt:.6e} ({governing}): "
        f"growth={res.growth:.3g}, window={res.window_growth:.3g}")
    assert res.rate > 1.0 or res.halted


# ----------------------------------------------------------------------------- granular arm

GRANULAR_ARM_CASE = PairCase(ContactLaw(KN, kt=KN, style="granular"), SMALL, SMALL, overlap=0.1)


def test_lammps_pair_granular_uses_reduced_torque_arm(lmp):
    """`pair_style granular` applies torques at R_i - delta/2 but computes slip with R_i.

    Unlike the gran/* styles (and fix wall/gran granular), so the full-radius formula is off
    for it: with a 10 % overlap the tangential step is 1.8 % longer.  LAMMPS is bounded at
    1.01x the full-radius step, and brackets the mixed-arm step at 0.99x / 1.01x.
    """
    case = GRANULAR_ARM_CASE
    full = min(analytic_modes(case).values())
    mixed = min(analytic_modes(case, torque_arm_shift=case.delta0 / 2.0).values())
    assert mixed / full == pytest.approx(math.sqrt(7.0 / 6.75), rel=1e-12)
    assert run_case(case, 1.01 * full, STEPS, lmp=lmp).bounded
    assert run_case(case, 0.99 * mixed, STEPS, lmp=lmp).bounded
    assert not run_case(case, 1.01 * mixed, STEPS, lmp=lmp).bounded


# ----------------------------------------------------------------------------- harness


def test_require_engine_skips_locally_and_fails_in_ci(monkeypatch):
    monkeypatch.setenv("LAMMPS_BINARY", "/nonexistent/lmp-for-test")
    assert not engine_available("lammps")
    monkeypatch.setenv("CI", "false")
    with pytest.raises(pytest.skip.Exception, match="apt-get install lammps"):
        require_engine("lammps")
    monkeypatch.setenv("CI", "true")
    with pytest.raises(pytest.fail.Exception, match="never skipped in CI"):
        require_engine("lammps")
