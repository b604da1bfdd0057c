"""Real engines collide two spheres: LAMMPS and YADE against the continuum and against dtcrit.

Harness: ``support.engines.collisions`` (cases, laws, measures), ``collisions_lammps`` and
``collisions_yade`` (one engine process per batch, many pairs far apart), reference
``support.collision_reference`` (SciPy ``solve_ivp`` of the same force laws, rtol 1e-12).

(a) At N = t_c/dt = 4000 every engine outcome equals the continuum of the law as read from the
    engine's source to ~1e-3: this validates the harness and pins what the engines do --
    LAMMPS 2021 ``tsuji`` is ``alpha(e) sqrt(meff F/delta)`` (secant stiffness, not clipped),
    ``coeff_restitution`` (absent from this build) is written as ``tsuji`` with the coefficient
    whose polynomial equals its prefactor and restitutes e exactly, ``limit_damping`` clips;
    YADE 2023.02a maps ``en`` by Thornton et al. (2013) B6 and clips, so it restitutes en.
(b) At N = 5..40 and several entry phases the engines' outcomes equal dtcrit's
    ``collisions.step_collision`` for the same engine, law, N and phase to 1e-9.
(c) Acceptance: at dtcrit's ``resolution_step`` (tol 1 %) the engines' restitution and peak overlap
    errors, worst over 16 entry phases, are within 1 %; at 1.2x that step one phase exceeds 1 %.
(d) Engine against engine, independent of dtcrit: YADE's clipped law written in LAMMPS gives the
    same coarse-step outcomes at any phase (measured: 3e-15 apart).

Conventions (b) and (c) assume of ``dtcrit.collisions``: ``phase`` = the continuous contact starts
``phase*dt`` before the first step that sees overlap; ``restitution`` = the coefficient the engine
takes (LAMMPS ``tsuji``: its polynomial's argument; ``coeff_restitution``: e; YADE: en; ``none``: 1);
``peak_overlap`` = the largest overlap at the steps over the elastic peak; ``duration`` over the
elastic t_c, interpolated (the overlap linear between steps, exact for the drift of both engines).
"""
from __future__ import annotations

import functools
import math
from dataclasses import replace

import pytest

from support.collision_reference import head_on, oblique_sliding, oblique_sticking
from support.engines import require_engine
from support.engines import collisions_lammps, collisions_yade
from support.engines.collisions import design, tsuji_alpha

DT = 1.0e-6
FINE_N = 4000
PHASE = 0.37

# (normal, damping, coefficient, extra design keywords)
LAMMPS_FINE = [
    ("hertz", "lammps-tsuji", 0.5, {}),
    ("hertz", "lammps-tsuji", 0.1, {"clip": True}),
    ("hooke", "lammps-tsuji", 0.5, {}),
    ("hertz", "lammps-coeff-restitution", 0.1, {}),
    ("hertz", "lammps-coeff-restitution", 0.5, {}),
    ("hertz", "lammps-coeff-restitution", 0.9, {}),
    ("hooke", "lammps-coeff-restitution", 0.5, {}),
    ("hooke", "lammps-mass-velocity", 100.0, {}),
    ("hertz", "none", 0.0, {}),
]
YADE_FINE: list[tuple[str, str, float, dict]] = [("hertz", "yade-mindlin", e, {}) for e in (0.1, 0.5, 0.9)] + [("hertz", "none", 1.0, {})]


def _fine(spec):
    normal, damping, coef, kw = spec
    return design(normal, damping, coef, dt=DT, steps_per_collision=FINE_N, phase=PHASE, **kw)


def _oblique():
    base = _fine(("hertz", "none", 0.0, {}))
    return replace(base, tangential_speed=2.0 * base.speed, friction=0.1)


def _oblique_sticking():
    base = _fine(("hertz", "none", 0.0, {}))
    return replace(base, tangential_speed=base.speed, friction=1.0e4)


def _rel(a, b):
    return abs(a - b) / abs(b)


@pytest.fixture(scope="module")
def lammps_fine():
    """Impacts and LAMMPS outcomes at N = 4000 (one LAMMPS run)."""
    require_engine("lammps")
    imps = [_fine(s) for s in LAMMPS_FINE] + [_oblique_sticking(), _oblique()]
    return imps, collisions_lammps.collide(imps, DT)


@pytest.fixture(scope="module")
def yade_fine():
    """Impacts and YADE outcomes at N = 4000 (one YADE run)."""
    require_engine("yade")
    imps = [_fine(s) for s in YADE_FINE] + [_oblique()]
    return imps, collisions_yade.collide(imps, DT)


def _assert_continuum(imp, got, ref):
    label = f"{imp.normal}/{imp.damping} {imp.coefficient} clip={imp.clip}"
    assert got.separated, label
    for name, tol in (("restitution", 1e-3), ("peak_overlap", 1e-3), ("duration", 1e-3), ("energy_ratio", 2.5e-3)):
        a, b = getattr(got, name), getattr(ref, name)
        assert _rel(a, b) < tol, f"{label}: {name} engine {a:.9g} vs continuum {b:.9g}"


@pytest.mark.parametrize("k", range(len(LAMMPS_FINE)))
def test_lammps_fine_step_matches_the_continuum_of_its_law(lammps_fine, k):
    """LAMMPS at N = 4000: restitution, peak overlap, duration, energy as the continuum (1e-3)."""
    imps, outs = lammps_fine
    _assert_continuum(imps[k], outs[k], head_on(imps[k]))


@pytest.mark.parametrize("k", range(len(YADE_FINE)))
def test_yade_fine_step_matches_the_continuum_of_its_law(yade_fine, k):
    """YADE at N = 4000: restitution, peak overlap, duration, energy as the continuum (1e-3)."""
    imps, outs = yade_fine
    _assert_continuum(imps[k], outs[k], head_on(imps[k]))


def test_lammps_oblique_sticking_mindlin_matches_the_continuum(lammps_fine):
    """Oblique impact, LAMMPS ``mindlin`` history sticking (mu = 1e4): tangential restitution and spin.

    Absolute 1e-3 (spin in units of v_t/R, small: the spring's impulses nearly cancel): LAMMPS
    converges to the continuum at first order, because the first contact step adds the whole
    step's slip ``vtr dt`` to the history, the part before touch included (measured: the gaps
    shrink fourfold as N quadruples: 2.1e-3, 5.3e-4, 1.3e-4 in e_t at N = 1000, 4000, 16000).
    """
    imps, outs = lammps_fine
    imp, got = imps[-2], outs[-2]
    ref = oblique_sticking(imp)
    _assert_continuum(imp, got, ref)
    assert abs(got.tangential_restitution - ref.tangential_restitution) < 1e-3
    assert abs(got.spin - ref.spin) < 1e-3


@pytest.mark.parametrize("fixture", ["lammps_fine", "yade_fine"])
def test_oblique_sliding_mindlin_matches_the_continuum(fixture, request):
    """Oblique impact, Mindlin tangential law sliding: tangential restitution and spin (1e-3)."""
    imps, outs = request.getfixturevalue(fixture)
    imp, got = imps[-1], outs[-1]
    ref = oblique_sliding(imp)
    _assert_continuum(imp, got, ref)
    assert _rel(got.tangential_restitution, ref.tangential_restitution) < 1e-3
    assert _rel(got.spin, ref.spin) < 1e-3
    # Coulomb sliding throughout: the slip velocity drops by 3.5 mu (1 + e) v_n (solid spheres)
    assert got.tangential_restitution == pytest.approx(1.0 - 3.5 * 0.1 * 2.0 / 2.0, abs=5e-3)


def test_lammps_tsuji_prefactor_is_the_secant_one_and_coeff_restitution_is_exact(lammps_fine):
    """Tell the candidate laws apart: tsuji with the tangent stiffness (sqrt(3/2) larger) would
    restitute 0.595 instead of 0.616 for the coefficient 0.5; coeff_restitution restitutes e.
    """
    imps, outs = lammps_fine
    tsuji = imps[0]
    alt = head_on(replace(tsuji, coefficient=_tsuji_coefficient(tsuji_alpha(0.5) * math.sqrt(1.5))))
    assert abs(outs[0].restitution - alt.restitution) > 1e-2
    assert outs[0].restitution == pytest.approx(0.616076, abs=1e-3)
    for k in (3, 4, 5, 6):
        assert outs[k].restitution == pytest.approx(imps[k].coefficient, rel=1e-3)


def test_yade_en_is_thorntons_clipped_restitution_not_the_unclipped_beta(yade_fine):
    """YADE 2023.02a restitutes en with its clipped force; the older 2 sqrt(5/6) beta(en)
    mapping, clipped, would give 0.55 for en = 0.5 and 0.25 for en = 0.1.
    """
    imps, outs = yade_fine
    for imp, got in zip(imps[:3], outs[:3]):
        assert got.restitution == pytest.approx(imp.coefficient, rel=1.5e-3)
    old = head_on(replace(imps[1], damping="lammps-coeff-restitution", clip=True))
    assert old.restitution > 0.54


def _tsuji_coefficient(prefactor):
    from support.engines.collisions import tsuji_coefficient_for

    return tsuji_coefficient_for(prefactor)


# ----------------------------------------------------------------------------- (b) dtcrit's map

COARSE_N = (5, 12, 40)
COARSE_PHASES = (0.1, 0.5, 0.93)
LAMMPS_LAWS = [
    ("hertz", "lammps-tsuji", 0.5, False),
    ("hertz", "lammps-tsuji", 0.1, True),
    ("hertz", "lammps-coeff-restitution", 0.1, False),
    ("hertz", "lammps-coeff-restitution", 0.9, False),
    ("hooke", "lammps-coeff-restitution", 0.5, False),
    ("hertz", "none", 1.0, False),
]
YADE_LAWS = [("hertz", "yade-mindlin", e, True) for e in (0.1, 0.5, 0.9)] + [("hertz", "none", 1.0, True)]


LAMMPS_2021 = {"lammps-tsuji": "lammps-tsuji-2021"}  # the harness's key -> dtcrit's key for Debian's lmp


def _coarse(laws):
    return [(law, n, p, design(law[0], law[1], law[2], dt=DT, steps_per_collision=n, phase=p, clip=law[3]))
            for law in laws for n in COARSE_N for p in COARSE_PHASES]


def _dtcrit_outcome(engine, law, n, phase):
    """The outcome dtcrit's ``step_collision`` gives for the law as this engine build applies it.

    LAMMPS ``tsuji`` changed after the 2021 release Debian ships (the current source multiplies the
    polynomial by sqrt(2)); dtcrit's damping key ``lammps-tsuji-2021`` is that release's law.
    """
    from dtcrit.collisions import step_collision

    normal, damping, coef, clip = law
    return step_collision(engine=engine, normal=normal, damping=LAMMPS_2021.get(damping, damping), restitution=coef,
                          steps_per_collision=n, phase=phase, clip=clip if engine == "lammps" else None)


def _assert_same_map(engine, cases, outs):
    bad = []
    for (law, n, p, _), got in zip(cases, outs):
        want = _dtcrit_outcome(engine, law, n, p)
        for name in ("restitution", "peak_overlap", "energy_ratio"):
            if _rel(getattr(got, name), getattr(want, name)) > 1e-9:
                bad.append(f"{law} N={n} phase={p}: {name} engine {getattr(got, name)!r} dtcrit {getattr(want, name)!r}")
        if _rel(got.duration, want.duration) > 1e-9:  # interpolated: the overlap linear between steps
            bad.append(f"{law} N={n} phase={p}: duration engine {got.duration!r} dtcrit {want.duration!r}")
    assert not bad, "\n".join(bad[:12])


def test_contact_time_is_the_elastic_duration_the_harness_uses():
    """The t_c of dtcrit is the elastic duration the harness designs its impacts with."""
    from dtcrit.collisions import contact_time

    hz = design("hertz", "none", 1.0, dt=DT, steps_per_collision=20, phase=0.5)
    hk = design("hooke", "none", 1.0, dt=DT, steps_per_collision=20, phase=0.5)
    assert contact_time("hertz", m_eff=hz.meff, E_eff=hz.estar, R_eff=hz.reff, v_impact=hz.speed) == pytest.approx(
        20 * DT, rel=1e-12)
    assert contact_time("hooke", m_eff=hk.meff, k=hk.kn) == pytest.approx(20 * DT, rel=1e-12)


def test_lammps_coarse_steps_equal_dtcrits_step_collision():
    """LAMMPS at N = 5, 12, 40 and three phases: dtcrit's step_collision to 1e-9."""
    require_engine("lammps")
    cases = _coarse(LAMMPS_LAWS)
    outs = collisions_lammps.collide([c[3] for c in cases], DT)
    _assert_same_map("lammps", cases, outs)


def test_yade_coarse_steps_equal_dtcrits_step_collision():
    """YADE at N = 5, 12, 40 and three phases: dtcrit's step_collision to 1e-9."""
    require_engine("yade")
    cases = _coarse(YADE_LAWS)
    outs = collisions_yade.collide([c[3] for c in cases], DT)
    _assert_same_map("yade", cases, outs)


# ----------------------------------------------------------------------------- (c) acceptance

TOL = 0.01
PHASES16 = tuple((k + 0.5) / 16 for k in range(16))
ACCEPT = {
    "lammps": [("hertz", "lammps-coeff-restitution", e, False) for e in (0.9, 0.5, 0.1)] + [("hertz", "none", 1.0, False)],
    "yade": [("hertz", "yade-mindlin", e, True) for e in (0.9, 0.5, 0.1)] + [("hertz", "none", 1.0, True)],
}


@functools.lru_cache(maxsize=None)
def _continuum(law):
    """Continuum outcome of ``law``: the same at every speed and size (power-law damping), so
    one solve per law serves every step and phase.
    """
    normal, damping, coef, clip = law
    return head_on(design(normal, damping, coef, dt=DT, steps_per_collision=100.0, phase=0.5, clip=clip))


def _worst_errors(engine):
    """{law: (N_res, worst error at N_res, worst error at N_res/1.2)} from one engine run."""
    from dtcrit.collisions import resolution_step

    runner = collisions_lammps if engine == "lammps" else collisions_yade
    plan, imps = [], []
    for law in ACCEPT[engine]:
        normal, damping, coef, clip = law
        res = resolution_step(engine=engine, normal=normal, damping=damping, restitution=coef, tol=TOL)
        for factor in (1.0, 1.2):
            n = res.steps_per_collision / factor  # 1.2x the step: 1/1.2 the steps per collision
            for p in PHASES16:
                imps.append(design(normal, damping, coef, dt=DT, steps_per_collision=n, phase=p, clip=clip))
                plan.append((law, factor, res.steps_per_collision))
    outs = runner.collide(imps, DT)
    worst: dict = {}
    for (law, factor, n_res), imp, got in zip(plan, imps, outs):
        ref = _continuum(law)
        err = max(_rel(got.restitution, ref.restitution), _rel(got.peak_overlap, ref.peak_overlap))
        entry = worst.setdefault(law, [n_res, 0.0, 0.0])
        k = 1 if factor == 1.0 else 2
        entry[k] = max(entry[k], err)
    return worst


@pytest.mark.parametrize("engine", ["lammps", "yade"])
def test_engine_error_within_tolerance_at_resolution_step_and_beyond_at_1_2x(engine):
    """Acceptance: within 1 % over 16 phases at the resolution step, beyond 1 % at 1.2x it."""
    require_engine(engine)
    worst = _worst_errors(engine)
    msgs = []
    for law, (n_res, at, beyond) in worst.items():
        if not at <= TOL * (1 + 1e-6):
            msgs.append(f"{law}: N={n_res:.4g} worst error {at:.4g} > {TOL}")
        if not beyond > TOL:
            msgs.append(f"{law}: at 1.2x the step (N={n_res / 1.2:.4g}) worst error {beyond:.4g} <= {TOL}")
    assert not msgs, "\n".join(msgs)


# ----------------------------------------------------------------------------- engine against engine

def test_lammps_and_yade_step_the_same_collision_alike():
    """Independent of dtcrit: YADE's clipped Thornton law written in LAMMPS (``tsuji`` with the
    coefficient whose polynomial is ``2 beta_T(en) sqrt(3/2)``, ``limit_damping``) gives the same
    outcomes at coarse steps and any phase to 1e-9: both engines step a collision alike (position
    Verlet, the half-step velocity in the dashpot, contact when the step's overlap is positive,
    clipping of the total normal force).
    """
    require_engine("lammps")
    require_engine("yade")
    from support.engines.collisions import thornton_beta, tsuji_coefficient_for

    yade_imps, lmp_imps = [], []
    for en in (0.1, 0.5, 0.9, 1.0):
        for n in COARSE_N:
            for p in COARSE_PHASES:
                y = design("hertz", "yade-mindlin" if en < 1.0 else "none", en, dt=DT, steps_per_collision=n, phase=p)
                coef = tsuji_coefficient_for(2.0 * thornton_beta(en) * math.sqrt(1.5)) if en < 1.0 else 0.0
                yade_imps.append(y)
                lmp_imps.append(replace(y, damping="lammps-tsuji" if en < 1.0 else "none", coefficient=coef,
                                        clip=True))
    y_out = collisions_yade.collide(yade_imps, DT)
    l_out = collisions_lammps.collide(lmp_imps, DT)
    bad = []
    for imp, a, b in zip(yade_imps, y_out, l_out):
        for name in ("restitution", "peak_overlap", "duration", "energy_ratio"):
            if _rel(getattr(a, name), getattr(b, name)) > 1e-9:
                bad.append(f"en={imp.coefficient} N={imp.contact_time / DT:.3g} phase={imp.phase}: {name} "
                           f"YADE {getattr(a, name)!r} LAMMPS {getattr(b, name)!r}")
    assert not bad, "\n".join(bad[:12])
