"""What the audit does with every field of a ``dtcrit-yade-export/1`` file: modelled, derived, a record,
or refused in one line naming it ("never answer for what you did not model").

Every key the exporter (``dtcrit/engine_scripts/yade_export.py``) writes has a decision in
:data:`TOP`, :data:`BODY` or :data:`INTERACTION` (``tests/packing/readers/test_every_term.py`` fails on a
key without one).  The kinds:

* ``modelled`` -- the field enters the step (masses, springs, arms, ...);
* ``derived`` -- recomputed from other fields (the normal from the positions);
* ``record`` -- no effect on the dynamics (ids, version, the step the run used);
* ``refused`` -- a YADE setting the audit does not model: :func:`check_export_terms` raises
  :class:`dtcrit.errors.InputError` naming it whenever its value changes the dynamics.

The refusals, each with the YADE source that makes it change the dynamics (``pkg/dem/``,
``pkg/common/``, ``core/`` of YADE 2023.02a):

* ``density_scaling`` true (``NewtonIntegrator.densityScaling``: every body's inertial mass is scaled by
  ``state.densityScaling``, NewtonIntegrator.cpp);
* ``exact_aspherical_rot`` false on a free body with unequal principal moments (NewtonIntegrator's
  ``leapfrogSphericalRotate`` then integrates an aspherical body as a sphere);
* homothetic cell motion, ``cell_vel_grad`` or ``cell_next_vel_grad`` (Cell.cpp: the velocity field
  ``velGrad x`` is added to every body), when its largest entry times ``dt_crit`` exceeds
  :data:`CELL_MOTION_TOL` (:func:`check_cell_motion`, after the audit).  It perturbs the leapfrog's
  amplification matrix by ``O(|velGrad| dt)``, which moves the threshold by as much relative: a
  residual rate of a stopped compression (``|velGrad| dt ~ 1e-8``) is negligible, a shear at a strain
  rate comparable to ``1/dt`` is not;
* a Law2 functor in ``laws`` that is not :data:`KNOWN_LAWS`, or one with an option in
  :data:`REFUSED_LAW_OPTIONS` on (creep: a viscous term);
* a non-zero ``shift2`` in an export that is not periodic (YADE writes zero there);
* an interaction whose ``phys`` is not :data:`KNOWN_PHYS` (e.g. ViscElPhys: its law takes the shear
  velocity at the contact point and adds a rolling resistance ``mR``; MindlinPhys: its ``kn`` is a
  secant) or whose ``geom`` is not :data:`KNOWN_GEOM`;
* a body with some but not all of its six degrees of freedom in ``blocked_dofs`` (State.hpp: a blocked
  DOF keeps its velocity, an infinite mass along one global axis only);
* a body with ``is_damped`` false under local damping (``newton_damping`` > 0: NewtonIntegrator damps
  every body whose ``state.isDamped`` is set, this one not).

``newton_damping`` itself is read by ``dtcrit.packing.readers.yade_export`` (local damping).
``NewtonIntegrator.kinSplit`` only splits the kinetic energy it reports, and ``gravity`` is a constant
force: neither changes the step, and neither is exported.
"""
from __future__ import annotations

import math

from dtcrit.errors import InputError
from dtcrit.inputs.text import show

#: Physics classes whose law the audit models (harness-checked: tests/engines/test_engine_yade*.py)
KNOWN_PHYS = ("FrictPhys", "CohFrictPhys")
#: Geometry classes whose kinematics the audit models (Ig2_Sphere_Sphere_ScGeom(6D))
KNOWN_GEOM = ("ScGeom", "ScGeom6D")
#: Law2 functors the audit models
KNOWN_LAWS = ("Law2_ScGeom_FrictPhys_CundallStrack", "Law2_ScGeom6D_CohFrictPhys_CohesionMoment")
#: Law2 options that add a term the audit does not model when on
REFUSED_LAW_OPTIONS = ("shear_creep", "twist_creep")

#: largest ``|velGrad| dt_crit`` accepted: the relative change of the threshold it may cause
CELL_MOTION_TOL = 1e-6

MODELLED, DERIVED, RECORD, REFUSED = "modelled", "derived", "record", "refused"

#: top-level keys: (kind, what the audit does with it)
TOP = {
    "schema": (RECORD, "the format's name"),
    "yade_version": (RECORD, "the YADE version"),
    "dt": (RECORD, "O.dt, rated against dt_crit (it does not change dt_crit)"),
    "iter": (RECORD, "O.iter"),
    "newton_damping": (MODELLED, "local (Cundall) damping NewtonIntegrator.damping"),
    "periodic": (MODELLED, "periodic cell"),
    "cell_hsize": (MODELLED, "the periodic cell's vectors"),
    "cell_vel_grad": (REFUSED, "refused when |O.cell.velGrad| dt_crit > 1e-6 (homothetic cell motion)"),
    "cell_next_vel_grad": (REFUSED, "refused when |O.cell.nextVelGrad| dt_crit > 1e-6 (homothetic cell motion)"),
    "density_scaling": (REFUSED, "refused when true: NewtonIntegrator.densityScaling scales the inertia"),
    "exact_aspherical_rot": (REFUSED, "refused when false with an aspherical free body"),
    "laws": (REFUSED, "refused: a Law2 functor not in " + ", ".join(KNOWN_LAWS) + ", or creep on"),
    "avoid_granular_ratcheting": (MODELLED, "the shear kinematics (alpha) of ScGeom"),
    "wall_no_ratch": (MODELLED, "the shear kinematics (alpha) of sphere-Wall contacts (yade_walls)"),
    "bodies": (MODELLED, "the bodies (BODY)"),
    "interactions": (MODELLED, "the interactions (INTERACTION)"),
}

#: per-body keys
BODY = {
    "id": (RECORD, "the body's id"),
    "shape": (MODELLED, "a Wall or Facet is a fixed wall (yade_walls); other shapes need a radius (spheres)"),
    "axis": (RECORD, "a Wall's axis: its contacts' normals are exported"),
    "sense": (RECORD, "a Wall's side: its contacts' normals are exported"),
    "vertices": (RECORD, "a Facet's corners: its contacts' points are exported"),
    "pos": (MODELLED, "the centre (contact geometry, arms)"),
    "radius": (MODELLED, "the sphere's radius (arms)"),
    "mass": (MODELLED, "the mass"),
    "inertia": (MODELLED, "the principal moments"),
    "clump_id": (MODELLED, "clump membership (one rigid body)"),
    "is_clump": (MODELLED, "a clump (rigid body)"),
    "ori": (MODELLED, "a clump's orientation (member arms, inertia axes)"),
    "fixed": (MODELLED, "a fixed body (infinite mass and inertia)"),
    "blocked_dofs": (REFUSED, "refused when some but not all six DOFs are blocked"),
    "is_damped": (REFUSED, "refused when false under local damping"),
}

#: per-interaction keys
INTERACTION = {
    "id1": (MODELLED, "body 1"),
    "id2": (MODELLED, "body 2"),
    "kn": (MODELLED, "normal spring"),
    "ks": (MODELLED, "shear spring (times alpha)"),
    "kr": (MODELLED, "rolling spring"),
    "ktw": (MODELLED, "twisting spring"),
    "cn": (MODELLED, "normal dashpot"),
    "cs": (MODELLED, "shear dashpot"),
    "fn": (MODELLED, "normal force (pre-load's geometric stiffness)"),
    "penetration": (MODELLED, "the pre-load kn x penetration when fn is not given"),
    "shift2": (MODELLED, "the periodic image of body 2"),
    "normal": (DERIVED, "recomputed from the positions (a Wall or Facet contact's is used, yade_walls)"),
    "point": (DERIVED, "recomputed from the positions and radii (R - penetration/2; a wall contact's is used)"),
    "radius1": (DERIVED, "the bodies' radii are used (a wall contact's refR1 gives its alpha)"),
    "radius2": (DERIVED, "the bodies' radii are used (a wall contact's refR2 gives its alpha)"),
    "bonded": (RECORD, "the exporter already gives kr, ktw only where the moment law acts"),
    "geom": (REFUSED, "refused when not one of " + ", ".join(KNOWN_GEOM)),
    "phys": (REFUSED, "refused when not one of " + ", ".join(KNOWN_PHYS)),
}


def _flag(key: str, value) -> bool | None:
    if value is None or isinstance(value, bool):
        return value
    raise InputError(key, f"expected true, false or null, found {show(value)}")


def _largest_entry(key: str, value) -> float:
    if value is None:
        return 0.0
    entries = [x for row in value for x in row] if isinstance(value, list) and all(
        isinstance(row, list) for row in value) else None
    if entries is None or len(entries) != 9 or not all(
            isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) for x in entries):
        raise InputError(key, f"expected a 3 x 3 matrix of finite numbers, found {show(value)}")
    return max(abs(float(x)) for x in entries)


def cell_strain_rate(doc: dict, path) -> float:
    """The largest entry of the export's cell velocity gradients (``velGrad``, ``nextVelGrad``) [1/s].

    Parameters
    ----------
    doc : dict
        The export as read from JSON.
    path : str or pathlib.Path
        The export, named in errors.

    Returns
    -------
    float
        ``max |L_ab|`` over both matrices; 0 without them.
    """
    return max(_largest_entry(f"{path}: {key}", doc.get(key)) for key in ("cell_vel_grad", "cell_next_vel_grad"))


def check_cell_motion(rate: float, dt_crit: float) -> None:
    """Refuse homothetic cell motion fast enough to move the threshold (module docstring).

    Parameters
    ----------
    rate : float
        :func:`cell_strain_rate` [1/s].
    dt_crit : float
        The audit's critical step [s].

    Raises
    ------
    InputError
        Keyed ``cell_vel_grad`` when ``rate * dt_crit > CELL_MOTION_TOL``.
    """
    if rate * dt_crit > CELL_MOTION_TOL:
        raise InputError("cell_vel_grad", f"homothetic cell motion at a velocity gradient of {rate:g}/s is "
                                          f"{rate * dt_crit:.3g} per critical step (above {CELL_MOTION_TOL:g}): it "
                                          "changes the step and is not modelled by the audit")


def _check_laws(path, laws) -> None:
    if laws is None:
        return
    if not isinstance(laws, list):
        raise InputError(f"{path}: laws", f"expected a list of Law2 functors, found {show(laws)}")
    for k, law in enumerate(laws):
        where = f"{path}: laws[{k}]"
        name = law.get("class") if isinstance(law, dict) else None
        if not isinstance(name, str):
            raise InputError(where, f"expected an object with the functor's 'class', found {show(law)}")
        if name not in KNOWN_LAWS:
            raise InputError(where, f"the contact law {name} is not modelled by the audit (modelled: "
                                    f"{', '.join(KNOWN_LAWS)})")
        for option in REFUSED_LAW_OPTIONS:
            if _flag(f"{where}.{option}", law.get(option)):
                raise InputError(f"{where}.{option}", f"{name}.{option} adds a creep (viscous) term the audit does "
                                                      "not model")


def _aspherical(body: dict) -> bool:
    inertia = body.get("inertia")
    if body.get("fixed") or body.get("clump_id") is not None or not isinstance(inertia, list):
        return False
    values = [x for x in inertia if isinstance(x, (int, float)) and not isinstance(x, bool)]
    return len(values) == 3 and max(values) - min(values) > 1e-12 * max(abs(x) for x in values)


def _check_body(where: str, body: dict, damping: float) -> None:
    blocked = body.get("blocked_dofs")
    if blocked is not None and not isinstance(blocked, str):
        raise InputError(f"{where}.blocked_dofs", f"expected a string of x y z X Y Z, found {show(blocked)}")
    moving = not body.get("fixed") and body.get("clump_id") is None
    if blocked and moving and set(blocked) != set("xyzXYZ"):
        raise InputError(f"{where}.blocked_dofs", f"body {show(body.get('id'))} has {blocked!r} blocked, some but not "
                                                  "all of its six degrees of freedom: not modelled by the audit")
    if moving and damping > 0 and _flag(f"{where}.is_damped", body.get("is_damped")) is False:
        raise InputError(f"{where}.is_damped", f"body {show(body.get('id'))} is not damped (state.isDamped false) "
                                               "while the others are (local damping): not modelled by the audit")


def _check_interaction(where: str, it: dict, periodic: bool) -> None:
    shift = it.get("shift2")
    if not periodic and isinstance(shift, list) and any(isinstance(x, (int, float)) and x != 0 for x in shift):
        raise InputError(f"{where}.shift2", f"a periodic image shift {show(shift)} in an export that is not periodic")
    for key, what, known in (("phys", "physics", KNOWN_PHYS), ("geom", "geometry", KNOWN_GEOM)):
        name = it.get(key)
        if name is not None and name not in known:
            raise InputError(f"{where}.{key}", f"the interaction {what} class {show(name)} is not modelled by the "
                                               f"audit (modelled: {', '.join(known)})")


def check_export_terms(doc: dict, path) -> None:
    """Refuse, in one line naming it, every setting of a YADE export that the audit does not model.

    The refusals are listed in the module docstring; fields without a value (``null`` or absent, e.g.
    in exports written by hand) pass.

    Parameters
    ----------
    doc : dict
        The export as read from JSON.
    path : str or pathlib.Path
        The export, named in errors.

    Raises
    ------
    InputError
        Keyed ``PATH: field`` (``PATH: bodies[k].blocked_dofs``, ...) for the first refused setting.
    """
    if _flag(f"{path}: density_scaling", doc.get("density_scaling")):
        raise InputError(f"{path}: density_scaling", "NewtonIntegrator.densityScaling scales every body's inertia "
                                                     "(state.densityScaling): not modelled by the audit")
    cell_strain_rate(doc, path)  # well-formed; its size is checked against dt_crit after the audit
    _check_laws(path, doc.get("laws"))
    bodies: list = doc["bodies"] if isinstance(doc.get("bodies"), list) else []
    damping = doc.get("newton_damping")
    damping = damping if isinstance(damping, (int, float)) and not isinstance(damping, bool) else 0.0
    for k, body in enumerate(bodies):
        if isinstance(body, dict):
            _check_body(f"{path}: bodies[{k}]", body, damping)
    if _flag(f"{path}: exact_aspherical_rot", doc.get("exact_aspherical_rot")) is False:
        odd = next((b for b in bodies if isinstance(b, dict) and _aspherical(b)), None)
        if odd is not None:
            raise InputError(f"{path}: exact_aspherical_rot", f"false: NewtonIntegrator integrates the aspherical body "
                                                              f"{show(odd.get('id'))} as a sphere, which the "
                                                              "audit does not model")
    inters: list = doc["interactions"] if isinstance(doc.get("interactions"), list) else []
    for k, it in enumerate(inters):
        if isinstance(it, dict):
            _check_interaction(f"{path}: interactions[{k}]", it, bool(doc.get("periodic")))


def refusal_lines() -> list[str]:
    """One line per refused YADE export field, for the docs' list of refused inputs
    (``docs/explanation/audit_conventions.md``, section "Inputs dtcrit refuses").

    Returns
    -------
    list of str
        ``"field: when it is refused"`` for every ``refused`` key of :data:`TOP`, :data:`BODY` and
        :data:`INTERACTION`.
    """
    out = []
    for prefix, table in (("", TOP), ("bodies[].", BODY), ("interactions[].", INTERACTION)):
        out += [f"{prefix}{key}: {text}" for key, (kind, text) in table.items() if kind == REFUSED]
    return out
