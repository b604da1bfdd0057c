"""The documented JSON form of a ``dtcrit step`` result (schema ``dtcrit-step/1``; ``docs/howto/step.md``,
section "JSON", its keys on the reference page ``docs/reference/generated/json-dtcrit-step-1``).  New keys
may be added; existing keys keep their meaning.
"""
from __future__ import annotations

from dtcrit.json_meta import envelope
from dtcrit.physics.json_numbers import finite_or_none as _finite

JSON_SCHEMA = "dtcrit-step/1"
UNITS = {
    # times
    "dt": "s", "dt_crit": "s", "dt_isolated": "s", "dt_dense": "s", "dt_recommended": "s", "dt_normal": "s",
    "dt_shear": "s", "dt_translation": "s", "dt_rotation": "s",
    # contact springs, dashpots and the inverse-inertia coefficient of xdd = -A (K x + C xd)
    "k": "N/m", "kn": "N/m", "ks": "N/m", "c": "N s/m", "cn": "N s/m", "cs": "N s/m",
    "A": "1/kg", "A_max": "1/kg", "A_bound": "1/kg", "A_normal": "1/kg", "A_shear": "1/kg",
    # dense-packing bound: largest eigenvalue of M^-1 K, and of M^-1 C
    "lambda_k": "1/s^2", "lambda_c": "1/s",
    # particles
    "mass": "kg", "m_star": "kg", "density": "kg/m^3", "inertia": "kg m^2", "half_lengths": "m", "max_arm": "m",
    "equivalent_radius": "m", "radius_i": "m", "radius_j": "m", "radii": "m", "median": "m", "min": "m", "max": "m",
    # Hertz linearisation and rotation
    "e_star": "Pa", "g_star": "Pa", "r_star": "m", "delta_max": "m", "velocity": "m/s", "curvature_radius": "m",
    "omega_max": "rad/s",
    # rotational springs and dashpots of the contact element, and their modes
    "kr": "N m/rad", "ktw": "N m/rad", "cr": "N m s/rad", "ctw": "N m s/rad", "stiffness": "N m/rad",
    "dashpot": "N m s/rad", "A_rotation": "1/(kg m^2)", "omega2": "1/s^2", "dt_contact": "s",
    "contact_radius": "m", "k_roll": "N/m", "gamma_roll": "N s/m", "k_twist": "N m/rad", "gamma_twist": "N m s/rad",
    "bond_youngs_modulus": "Pa", "bond_shear_modulus": "Pa", "bond_radius": "m", "bond_length": "m",
    "contact_kn": "N/m", "contact_ks": "N/m", "centre_of_mass": "m", "spheres": "m", "inertia_tensor": "kg m^2",
}
"""The unit of every dimensional key, wherever it appears in the document (SI).  Every other number is
dimensionless: damping ratios (``zeta*``, ``damping_ratio``), ``restitution``, ``safety``, ``ks_ratio``,
``fractions``, ``sigma`` (of ln R), ``B_max``/``B_sum`` (Eq. (54): ``dt = 2/(omega_max (B_i + B_j))``),
the ``dense_factors`` and counts (``number``, ``coordination_max``, ``particles``)."""
TRANSLATION_EQUATIONS = ("Peng et al. 2020, Eqs. (26), (29)-(30); exact integrator boundary (amplification matrix, "
                         "Jury conditions)")
ROTATION_EQUATIONS = "Peng et al. 2020, Eqs. (54), (56)-(57)"


def _direction_json(d) -> dict:
    return {"k": d.k, "c": d.c, "A": d.A, "zeta": d.zeta, "zeta_mode": _finite(d.zeta_mode), "regime": d.regime,
            "dt": _finite(d.dt)}


def _rotational_json(d) -> dict:
    bound = d.direction == "translation+rotation"
    return {"direction": d.direction, "stiffness": None if bound else d.k, "dashpot": None if bound else d.c,
            "A_rotation": None if bound else d.A, "omega2": d.k * d.A, "lambda_c": d.c * d.A,
            "zeta_mode": _finite(d.zeta_mode), "regime": d.regime, "dt": _finite(d.dt), "reason": d.reason}


def pair_json(p) -> dict:
    """One contact's entry of ``pairs`` in schema ``dtcrit-step/1``.

    Parameters
    ----------
    p : dtcrit.scenes.pair_modes.PairStep
        The contact's step.

    Returns
    -------
    dict
        The entry.
    """
    c = p.contact
    out = {
        "pair": p.label,
        "wall": c.wall,
        "radius_i": c.radius_i,
        "radius_j": c.radius_j,
        "m_star": c.m_star,
        "kn": c.kn,
        "ks": c.ks,
        "cn": c.cn,
        "cs": c.cs,
        "zeta_normal": c.zeta_n,
        "zeta_shear": c.zeta_s,
        "method": p.method,
        "A_max": p.A_max,
        "A_bound": p.A_bound,
        "A_normal": p.normal.A,
        "A_shear": p.shear.A,
        "dt_normal": p.normal.dt,
        "dt_shear": _finite(p.shear.dt),
        "dt_translation": p.translational_direction.dt,
        "normal": _direction_json(p.normal),
        "shear": _direction_json(p.shear),
        "B_sum": p.B_sum,
        "dt_rotation": p.dt_rotation,
        "kr": c.kr, "ktw": c.ktw, "cr": c.cr, "ctw": c.ctw,
        "rotational_modes": [_rotational_json(d) for d in p.rotational],
        "shear_coupled": p.shear_coupled,
        "dt_contact": _finite(p.dt_translation),
    }
    if c.delta_max is not None:
        out.update(e_star=c.e_star, g_star=c.g_star, r_star=c.r_star, delta_max=c.delta_max, velocity=c.velocity)
    return out


def _particle_json(p, b_max: float) -> dict:
    s = p.shape
    out = {
        "number": p.number,
        "name": p.name,
        "shape": p.kind,
        "mass": s.mass,
        "density": s.density,
        "inertia": list(s.inertia),
        "half_lengths": list(s.half_lengths),
        "max_arm": s.max_arm,
        "equivalent_radius": s.equivalent_radius,
        "B_max": b_max,
    }
    if p.sizes is not None and p.sizes.kind != "single":
        out["size_distribution"] = {"kind": p.sizes.kind, "radii": list(p.sizes.radii),
                                    "fractions": list(p.sizes.fractions) or None, "parameters": p.sizes.parameters}
    return out


def _contact_json(sc, convention: str | None) -> dict:
    law = sc.contact
    out = {"model": law.model, "damping": law.damping, "damping_ratio": law.damping_ratio, "restitution": law.restitution,
           "damping_convention": convention}
    given = law.damping in ("coefficients", "none")  # otherwise the dashpots are per pair (pairs[].cn, cs)
    cn, cs = (law.cn or 0.0, law.cs or 0.0) if given else (None, None)
    if law.model == "linear":
        out.update(kn=law.kn, ks=law.ks, cn=cn, cs=cs)
    elif law.model == "yade":
        out.update(ks_ratio=law.ks_ratio, cn=cn, cs=cs)
    elif law.model == "bond":
        b = law.bond
        out.update(kn=law.kn, ks=law.ks, cn=cn, cs=cs, bond={"kn": b.kn, "ks": b.ks, "kr": b.kr, "ktw": b.ktw,
                                                              "contact_kn": b.contact_kn, "contact_ks": b.contact_ks,
                                                              "source": b.source})
    else:
        out.update(velocity=law.velocity, curvature_radius=law.curvature_radius)
    r = law.rotational
    if r is not None:
        out["rotational"] = {"kr": r.kr, "ktw": r.ktw, "cr": r.cr, "ctw": r.ctw, "rolling_model": r.rolling_model,
                             "twisting_model": r.twisting_model, **dict(r.params)}
    return out


def _estimate_json(rated, dense: bool) -> dict:
    """Schema ``dtcrit-step/1``'s form of a rated estimate (the common shape's ``detail`` is its ``note``)."""
    common = rated.to_json()
    return {"dt": common["dt"], "unsafe": rated.unsafe, "unsafe_dense": rated.unsafe if dense else None,
            "label": common["label"], "note": common["detail"]}


def _dense_json(d) -> dict | None:
    if d is None:
        return None
    return {"coordination_max": d.coordination, "dt": d.dt, "lambda_k": d.lambda_k, "lambda_c": d.lambda_c,
            "attained_at": d.particle, "reason": d.reason}


def step_json(result) -> dict:
    """The document of schema ``dtcrit-step/1`` (``docs/howto/step.md``, section "JSON").

    Parameters
    ----------
    result : dtcrit.scenes.timestep.StepResult
        The step of a scene.

    Returns
    -------
    dict
        The document.
    """
    sc = result.scene
    t = result.translation
    g = t.translational_direction
    top = t.governing_direction
    contact_rotation = None
    if top.direction not in ("normal", "shear"):
        contact_rotation = {"pair": t.label, **_rotational_json(top)}
    rot = None
    if sc.omega_max is not None:
        r = result.rotation
        rot = {
            "omega_max": sc.omega_max,
            "B_max": max(result.B_max.values()),
            "B_sum": None if r is None else r.B_sum,
            "pair": None if r is None else r.label,
            "dt": None if r is None else r.dt_rotation,
            "equations": ROTATION_EQUATIONS,
        }
    return {
        **envelope(JSON_SCHEMA, UNITS),
        "scene": sc.source,
        "title": sc.title,
        "integrator": sc.integrator,
        "order_of_accuracy": order_of_accuracy_json(sc.integrator),
        "dt_crit": result.dt_crit,
        "holds_for": result.holds_for,
        "headline_basis": result.basis,
        "headline_note": result.basis_note or None,
        "isolated": sc.isolated,
        "dt_isolated": result.dt_isolated,
        "dt_dense": result.dt_dense,
        "coordination_max": sc.coordination_max,
        "coordination": None if result.coordination is None else
        {"coordination_max": result.coordination.z, "attained_at": result.coordination.where, "how": result.coordination.how},
        "dense": _dense_json(result.dense),
        "dense_factors": {str(z): f for z, f in result.dense_factors.items()} or None,
        "safety": sc.safety,
        "dt_recommended": result.dt_recommended,
        "governing": result.governing,
        "bound": result.bound,
        "formula": result.formula,
        "translation": {
            "A_max": t.A_max,
            "A_bound": t.A_bound,
            "A": g.A,
            "method": t.method,
            "dt": g.dt,
            "pair": t.label,
            "direction": g.direction,
            "k": g.k,
            "c": g.c,
            "zeta": g.zeta,
            "zeta_mode": _finite(g.zeta_mode),
            "regime": g.regime,
            "reason": g.reason,
            "equations": TRANSLATION_EQUATIONS,
        },
        "rotation": rot,
        "contact_rotation": contact_rotation,
        "estimators": {e.estimate.name: _estimate_json(e, result.dense is not None) for e in result.estimates},
        "pairs": [pair_json(p) for p in result.pairs],
        "particles": [_particle_json(p, result.B_max[p.number]) for p in sc.particles],
        "contact": _contact_json(sc, result.pairs[0].contact.convention),
        "walls": [_wall_json(w) for w in sc.walls],
        "warnings": [f"{k}: {m}" for k, m in sc.warnings],
    }


def _wall_json(w) -> dict:
    """A ``[[wall]]`` entry; a Hertz wall adds its law (its springs depend on the particle: ``kn``, ``ks`` null)."""
    out = {"number": w.number, "name": w.name, "kn": w.kn, "ks": w.ks, "damping": w.damping,
           "damping_ratio": w.damping_ratio, "restitution": w.restitution, "particles": list(w.particles)}
    if w.model != "linear":
        out.update(model=w.model, kn=None, ks=None, overlap=w.overlap, velocity=w.velocity,
                   youngs_modulus=w.youngs_modulus, poisson_ratio=w.poisson_ratio)
    return out


def order_of_accuracy_json(integrator: str) -> dict | None:
    """The order of accuracy found for a user-written scheme, with and without damping.

    From ``dtcrit.integrators.user_rules.order_of``: its principal eigenvalues are
    ``e^{h lambda} + O(h^{p+1})`` (``dtcrit.integrators.user_consistency``).

    Parameters
    ----------
    integrator : str
        Integrator name.

    Returns
    -------
    dict or None
        ``{"damped": p, "undamped": p}``; ``None`` for a built-in scheme or when not found.
    """
    from dtcrit.integrators.schemes import USER_INTEGRATORS

    if integrator not in USER_INTEGRATORS:  # a built-in scheme: the rule parser is not loaded
        return None
    from dtcrit.integrators.user_rules import order_of

    order = order_of(USER_INTEGRATORS[integrator])
    return None if order is None else {"damped": order[0], "undamped": order[1]}
