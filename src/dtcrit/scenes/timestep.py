"""The API behind ``dtcrit step``: a scene -> the critical time step of the simulation it describes.

* **Isolated contacts** (``dt_isolated``): every pair of particle types that can touch, at every
  size of their distributions, and every particle-wall contact, mode by mode
  (:mod:`dtcrit.scenes.pair_modes`: exact for spheres, a verified bound for other shapes).
* **Rotation** (Peng et al. 2020, Section 5, only with ``omega_max``): ``dt = 2/(omega_max (B_i + B_j))``,
  Eq. (56), with ``B`` of Eq. (54); over all pairs this is Eq. (57).
* **Dense packings** (:mod:`dtcrit.scenes.dense`): a step that holds for every packing of these
  particles with at most ``z`` contacts each (``dt_dense``), ``z`` = ``coordination_max`` when given,
  else the largest coordination the particles' shapes and sizes allow
  (:mod:`dtcrit.scenes.coordination`).

``dt_crit`` (the headline) is the step of the simulation the scene describes: ``dt_dense`` (with
rotation) unless the scene sets ``isolated = true``, which asks for the isolated-contact step
``dt_isolated`` (then the factors for z = 4, 6 and 12 are reported); ``headline_basis`` says which.
``dt_recommended = safety * dt_crit``.  The estimates DEM codes use are rated against ``dt_crit``, one
verdict each (:mod:`dtcrit.scenes.code_estimates`, rated by :mod:`dtcrit.physics.estimate`).  No SymPy is imported here or below.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

from dtcrit.errors import InputError
from dtcrit.physics.estimate import RatedEstimate
from dtcrit.scenes.coordination import Coordination, scene_coordination
from dtcrit.scenes.dense import FACTOR_COORDINATIONS, DenseStep, block_terms, dense_step, sphere_bound
from dtcrit.scenes.laws import convention_of, resolve_pair, resolve_wall
from dtcrit.scenes.model import Scene
from dtcrit.scenes.pair_modes import DirectionStep, PairStep, pair_step
from dtcrit.scenes.code_estimates import scene_estimates
from dtcrit.scenes.step_json import JSON_SCHEMA, step_json

__all__ = ["DirectionStep", "PairStep", "StepResult", "critical_step", "JSON_SCHEMA"]

MAX_SIZE_PAIRS = 5_000
"""Contacts evaluated one by one at most: above it a size distribution is refused (naming its ``radii``)
unless the contact law admits the reduction of :func:`_reducible` (then two radii per type suffice)."""
DEFAULT_SPHERE_GRID = (1e-2, 48)
"""``(rtol, n_theta)`` of the sphere-packing bound for the default headline: 0.2 s instead of 1-3 s per
species, at most ~0.5 % below the sharper grid used with ``coordination_max`` (tightness, not validity)."""
BASIS_ANY, BASIS_COORDINATION, BASIS_ISOLATED = "any packing", "coordination_max", "isolated"


@dataclass(frozen=True)
class StepResult:
    """The critical step of a scene and everything ``dtcrit step`` prints about it (module docstring).

    Parameters
    ----------
    scene : Scene
        The scene.
    pairs : tuple of PairStep
        Per pair of particle types (and per particle-wall pair): its governing size.
    dt_crit : float
        The headline step [s]: ``dt_dense`` unless ``isolated = true``, then ``dt_isolated``.
    governing : str
        ``translation``, ``contact rotation`` (a rotational spring's mode), ``rotation`` or ``dense``.
    bound : str
        Which bound governs, in words.
    translation : PairStep
        The contact whose isolated translation step is smallest.
    rotation : PairStep or None
        The pair whose rotation step ``2/(omega_max (B_i + B_j))`` (Peng et al. 2020, Eq. (56)) is
        smallest; ``None`` without a rotation bound.
    B_max : dict
        Particle number -> ``B`` of Peng et al. 2020, Eq. (54).
    estimates : tuple of RatedEstimate
        The codes' estimates, each rated against ``dt_crit``.
    dt_isolated : float
        The isolated-contact step [s], ``min`` of translation and rotation.
    dense : DenseStep or None
        The dense-packing step (``None`` with ``isolated = true``).
    dense_factors : dict
        ``z -> dt_dense(z) / dt_isolated`` for z = 4, 6, 12 (``isolated = true``).
    basis : str
        What the headline holds for: ``BASIS_ANY``, ``BASIS_COORDINATION`` or ``BASIS_ISOLATED``.
    coordination : Coordination or None
        The geometric coordination bound (``BASIS_ANY``).
    basis_note : str
        Why the headline is not the packing step the scene asks for (no packing bound), else empty.

    Examples
    --------
    >>> from dtcrit import load_scene, critical_step
    >>> result = critical_step(load_scene("examples/mixed_pair.toml"))
    >>> len(result.pairs), result.governing   # three pairs of particle types; a dense packing governs
    (3, 'dense')
    """

    scene: Scene
    pairs: tuple[PairStep, ...]  # per pair of particle types (and per particle-wall pair): its governing size
    dt_crit: float
    governing: str  # translation | contact rotation (a rotational spring's mode) | rotation | dense
    bound: str  # which bound, in words
    translation: PairStep  # the contact whose isolated translation step is smallest
    rotation: PairStep | None  # the pair whose rotation step is smallest (None: no rotation bound)
    B_max: dict = field(default_factory=dict)  # particle number -> Eq. (54)
    estimates: tuple[RatedEstimate, ...] = ()  # each rated against dt_crit (the headline)
    dt_isolated: float = math.nan
    dense: DenseStep | None = None  # the packing step (None with isolated = true)
    dense_factors: dict = field(default_factory=dict)  # z -> dt_dense(z) / dt_isolated (isolated = true)
    basis: str = BASIS_ISOLATED  # what the headline holds for: BASIS_ANY, BASIS_COORDINATION or BASIS_ISOLATED
    coordination: Coordination | None = None  # the geometric coordination bound (BASIS_ANY)
    basis_note: str = ""  # why the headline is not the packing step the scene asks for (no packing bound)

    @property
    def dt_recommended(self) -> float:
        """``safety x dt_crit`` [s]."""
        return self.scene.safety * self.dt_crit

    @property
    def dt_dense(self) -> float | None:
        """The dense-packing step [s], None with ``isolated = true``."""
        return None if self.dense is None else self.dense.dt

    @property
    def holds_for(self) -> str:
        """What the headline holds for, in words."""
        if self.basis == BASIS_ISOLATED:
            return "an isolated contact"
        if self.basis == BASIS_COORDINATION:
            assert self.dense is not None  # a coordination basis always carries its dense step
            return f"any packing with at most {self.dense.coordination} contacts per particle"
        assert self.dense is not None  # so does the any-packing basis
        return (f"any packing of these particles: at most {self.dense.coordination} contacts per particle, "
                "the most their shapes and sizes allow")

    @property
    def formula(self) -> str:
        """The closed form of the integrator's step, in words."""
        from dtcrit._generated.critical_steps import FORMULAS

        return FORMULAS.get(self.scene.integrator,
                            "exact stability boundary of the amplification matrix of the user-written rules "
                            "(50-digit spectral radius, bisection)")

    def to_json(self) -> dict:
        """The documented JSON form (schema ``dtcrit-step/1``; see ``docs/howto/step.md``, section "JSON").

        Returns
        -------
        dict
            The document of ``dtcrit.scenes.step_json.step_json``.
        """
        return step_json(self)


def _reducible(scene: Scene) -> bool:
    """Whether two radii per sphere type (its smallest and largest) carry every extreme the step needs.

    Linear law (given ``kn``, ``ks``): each mode's ``A`` decreases in both radii, ``k`` and ``c`` are fixed
    or ``c ~ sqrt(k m*)`` keeps the mode's damping ratio fixed, and the step is non-increasing in ``A``:
    the smallest radii govern (:mod:`dtcrit.scenes.sizes`).  YADE's law with damping from a ratio (mode
    damping ratio fixed): ``omega^2 = k_n (1/m_1 + 1/m_2)``, ``k_n = 2/(1/(E_1 R_1) + 1/(E_2 R_2))``, is, in
    each radius with the other fixed, ``a/(R^2 (R + b)) + c R/(R + b)``-shaped, whose derivative changes
    sign at most once (from - to +): its maximum over a box of radii sits at a corner.  The dense block
    terms (:func:`dtcrit.scenes.dense.block_terms`) ``k/m_i``, ``c/m_i`` decrease in the particle's own radius
    and increase in its partner's: the corner (smallest, largest) carries them.  Rotational springs,
    bonds, Hertz and given YADE dashpots are evaluated size pair by size pair.
    """
    return _not_reducible(scene) is None


def _not_reducible(scene: Scene) -> str | None:
    """Why :func:`_reducible` does not hold (None when it does)."""
    from dtcrit.integrators.schemes import INTEGRATORS

    law = scene.contact
    if scene.integrator not in INTEGRATORS:  # its step is not proven non-increasing in A
        return f"the user-written integrator {scene.integrator!r}"
    if law.bond is not None:
        return "a bond"
    if law.rotational is not None or any(w.kr or w.ktw or w.cr or w.ctw for w in scene.walls):
        return "rotational springs"
    if law.model == "yade" and law.damping == "coefficients":
        return "YADE's law with given dashpots cn, cs"
    if law.model not in ("linear", "yade"):
        return f"the {law.model} law"
    return None


def _sizes(part, reduce: bool) -> tuple:
    if not part.radii:
        return (None,)
    return (part.radii[0], part.radii[-1]) if reduce and len(part.radii) > 2 else part.radii


def _check_size_pairs(scene: Scene, reduce: bool) -> None:
    """Refuse up front, naming the ``radii`` key, a distribution whose size pairs would take too long."""
    if reduce:
        return
    n = {p.number: len(_sizes(p, False)) for p in scene.particles}
    count = (sum(n[i] * (n[i] + 1) // 2 if i == j else n[i] * n[j] for i, j in scene.pair_numbers())
             + sum(n[i] for w in scene.walls for i in w.particles))
    if count > MAX_SIZE_PAIRS:
        part = max(scene.particles, key=lambda p: n[p.number])
        key = f"particle[{part.number}].radii" if part.sizes is not None and part.sizes.kind == "discrete" else \
            f"particle[{part.number}].lognormal"
        raise InputError(key, f"{n[part.number]} radii give {count} size pairs to evaluate one by one (at most "
                         f"{MAX_SIZE_PAIRS}): with {_not_reducible(scene)} no pair of sizes is proven to govern (for linear and "
                         "YADE laws the extreme radii do); give fewer radii")


def _contact_steps(scene: Scene) -> list[PairStep]:
    reduce = _reducible(scene)
    _check_size_pairs(scene, reduce)
    steps = []
    for i, j in scene.pair_numbers():
        p, q = scene.particle(i), scene.particle(j)
        for r1 in _sizes(p, reduce):
            for r2 in _sizes(q, reduce):
                if i == j and r1 is not None and r2 is not None and r2 < r1:
                    continue  # the same pair of sizes, the other way round
                pc = resolve_pair(scene, i, j, r1, r2)
                steps.append(pair_step(scene.integrator, pc, p.shape_at(r1), q.shape_at(r2), p.kind, q.kind))
    for w in scene.walls:
        for i in w.particles:
            p = scene.particle(i)
            for r in _sizes(p, reduce):
                steps.append(pair_step(scene.integrator, resolve_wall(scene, w, i, r), p.shape_at(r), None, p.kind, None))
    return steps


def _with_rotation(scene: Scene, s: PairStep, b_max: dict) -> PairStep:
    if scene.omega_max is None:
        return s
    from dataclasses import replace

    b_sum = b_max[s.contact.i] + (0.0 if s.contact.wall is not None else b_max[s.contact.j])
    dt_rot = 2.0 / (scene.omega_max * b_sum) if b_sum > 0 else None  # Eq. (56)
    return replace(s, B_sum=b_sum, dt_rotation=dt_rot if dt_rot is not None and math.isfinite(dt_rot) else None)


def _governing_per_pair(steps: list[PairStep]) -> tuple[PairStep, ...]:
    best: dict[str, PairStep] = {}
    for s in steps:
        if s.label not in best or s.dt_translation < best[s.label].dt_translation:
            best[s.label] = s
    return tuple(best.values())


def _rotation_step(p: PairStep) -> float:
    """The rotation step of a pair that has one (``inf`` otherwise, never reached by the callers)."""
    return math.inf if p.dt_rotation is None else p.dt_rotation


def critical_step(scene: Scene) -> StepResult:
    """The critical time step of a scene (module docstring).

    Isolated contacts mode by mode, the rotation bound of Peng et al. 2020, Eqs (54)-(57), and the
    dense-packing step, with the codes' estimates rated against the headline.

    Parameters
    ----------
    scene : Scene
        The parsed scene (particles, contact law, integrator, safety).

    Returns
    -------
    StepResult
        The headline ``dt_crit`` [s] and everything ``dtcrit step`` prints.

    Examples
    --------
    >>> from dtcrit import load_scene, critical_step
    >>> result = critical_step(load_scene("examples/glass_spheres_hertz.toml"))
    >>> result.dt_crit > 0, result.to_json()["schema"]
    (True, 'dtcrit-step/1')
    """
    from dtcrit.bodies import contact

    b_max = {p.number: float(contact.b_max(p.shape)) for p in scene.particles}
    steps = [_with_rotation(scene, s, b_max) for s in _contact_steps(scene)]
    pairs = _governing_per_pair(steps)
    t = min(pairs, key=lambda p: p.dt_translation)
    with_rot = [p for p in pairs if p.dt_rotation is not None]
    r = min(with_rot, key=_rotation_step) if with_rot else None
    g = t.governing_direction
    dt_rot = math.inf if r is None else _rotation_step(r)
    dt_isolated = min(t.dt_translation, dt_rot)
    terms = block_terms(scene, steps)
    dense: DenseStep | None = None
    factors: dict[int, float | None] = {}
    coordination: Coordination | None = None
    basis, note = BASIS_ISOLATED, ""
    if not scene.isolated:
        z = scene.coordination_max
        if z is None:
            coordination = scene_coordination(scene)
            z = coordination.z
        particle_steps = [s for s in steps if s.contact.wall is None]
        spheres = (sphere_bound(scene, particle_steps, z) if scene.coordination_max is not None
                   else sphere_bound(scene, particle_steps, z, *DEFAULT_SPHERE_GRID))
        packing = dense_step(scene.integrator, terms, z, spheres, scene.overlap_max)
        basis = BASIS_ANY if scene.coordination_max is None else BASIS_COORDINATION
        if packing.dt is None and scene.coordination_max is not None:
            raise InputError("coordination_max", packing.reason + "; remove coordination_max for the isolated-contact step")
        if packing.dt is None:
            basis, note = BASIS_ISOLATED, packing.reason
        else:
            dense = packing
    if dense is None:
        for z in FACTOR_COORDINATIONS:
            d = dense_step(scene.integrator, terms, z)
            factors[z] = None if d.dt is None or not dt_isolated > 0 else min(d.dt, dt_rot) / dt_isolated
    dt_dense = None if dense is None else dense.dt  # not None when dense is set (see above)
    dt_translation = t.dt_translation if dt_dense is None else dt_dense
    if dense is not None and dt_dense is not None and dt_dense <= dt_rot:
        governing, dt = "dense", dt_dense
        what = "coordination_max" if basis == BASIS_COORDINATION else "the most contacts the shapes and sizes allow"
        bound = f"dense packing (z = {dense.coordination}, {what}): {dense.reason}"
    elif r is not None and dt_rot < dt_translation:
        governing, dt = "rotation", dt_rot
        bound = (f"rotation-dominant, pair {r.label}: dt = 2/(omega_max (B_i + B_j)) "
                 f"= 2/({scene.omega_max:g} x {r.B_sum:.6g}) (Peng et al. 2020, Eqs. (54), (56))")
    else:
        governing = "translation" if g.direction in ("normal", "shear") else "contact rotation"
        dt = t.dt_translation
        what = "no positive step is stable" if dt == 0.0 else f"exact '{scene.integrator}' boundary"
        given = g.direction == "normal" or convention_of(scene, t.contact).shear_rule == "zeta"
        zeta = ("" if g.zeta is None else f", zeta = {g.zeta:.6g} as given" if given
                else f", zeta_s = c_s/(2 sqrt(k_s m*)) = {g.zeta:.6g}")
        if g.direction in ("normal", "shear"):
            springs = f"k = {g.k:.6g} N/m, c = {g.c:.6g} N s/m, A = {g.A:.6g} 1/kg"
        elif g.direction == "translation+rotation":
            springs = f"omega^2 <= {g.k:.6g} 1/s^2, c/m <= {g.c:.6g} 1/s"
        else:
            springs = f"k = {g.k:.6g} N m/rad, c = {g.c:.6g} N m s/rad, A = {g.A:.6g} 1/(kg m^2)"
        bound = (f"translation-dominant, {'wall contact' if t.contact.wall else 'pair'} {t.label}, {g.direction} mode "
                 f"({t.method}): {what} with {springs} ({g.regime}{zeta}, mode zeta = {g.zeta_mode:.6g})")
        if g.direction not in ("normal", "shear"):
            bound = bound.replace("translation-dominant", "contact-dominant", 1) + f"; {g.reason}"
    estimates = tuple(RatedEstimate(e, dt) for e in scene_estimates(scene, steps))
    from dtcrit.scenes.local_damping import apply as with_local_damping

    return with_local_damping(StepResult(scene, pairs, dt, governing, bound, t, r, b_max, estimates, dt_isolated, dense,
                                         factors, basis, coordination, note))
