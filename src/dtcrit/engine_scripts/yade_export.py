"""Export a YADE scene (bodies and real interactions) to JSON for ``dtcrit audit FILE --engine yade``.

Runs inside YADE (it imports only the standard library and ``yade``; dtcrit need not be installed
in YADE's Python).  Three ways to use it:

* from your YADE script, after (or during) ``O.run``::

      import sys; sys.path.insert(0, "DIR")        # DIR: the directory holding this file
      from yade_export import export
      export("snapshot.json")

* ``exec(open("DIR/yade_export.py").read())`` in your script, then ``export("snapshot.json")``;
* on a saved scene: ``yade -n -x DIR/yade_export.py SCENE.yade.gz snapshot.json`` (``O.load`` then
  export).

The file is written to a temporary name and renamed, so a reader never sees half of it.

Format ``dtcrit-yade-export/1`` (SI units; vectors are ``[x, y, z]``; non-finite numbers are ``null``):

=======================  ===================================================================
key                      meaning
=======================  ===================================================================
``schema``               ``"dtcrit-yade-export/1"``
``yade_version``         ``yade.config.version``
``dt``, ``iter``         ``O.dt`` [s], ``O.iter``
``newton_damping``       ``NewtonIntegrator.damping`` (Cundall's non-viscous damping), ``null``
                         without a NewtonIntegrator
``periodic``             ``O.periodic``
``cell_hsize``           ``O.cell.hSize`` as 3 rows (columns are the cell vectors), ``null``
                         when not periodic
``cell_vel_grad``        ``O.cell.velGrad`` and ``O.cell.nextVelGrad`` as 3 rows (homothetic
``cell_next_vel_grad``   cell motion), ``null`` when not periodic
``density_scaling``      ``NewtonIntegrator.densityScaling`` (per-body inertia scaling), ``null``
                         without a NewtonIntegrator
``exact_aspherical_rot`` ``NewtonIntegrator.exactAsphericalRot``, ``null`` without one
``laws``                 one object per Law2 functor of the InteractionLoops: ``class`` and its
                         attributes that change the force (``shear_creep``, ``twist_creep``,
                         ``always_use_moment_law``, ...)
``bodies``               one object per body (below)
``interactions``         one object per *real* interaction (``i.isReal``; below)
=======================  ===================================================================

Body: ``id``; ``shape`` (the class name: ``Sphere``, ``Wall``, ``Facet``, ...); ``axis``, ``sense`` (a
``Wall``'s, else ``null``); ``vertices`` (a ``Facet``'s corners in global coordinates, else ``null``); ``pos`` (``state.pos``, unwrapped in
periodic scenes); ``radius`` (the sphere's
radius, ``null`` for any other shape and for clumps); ``mass`` (``state.mass``); ``inertia``
(``state.inertia``: principal moments in the body frame); ``clump_id`` (the clump of a clump member,
else ``null``); ``is_clump``; ``fixed`` (``not b.dynamic`` or all six DOFs blocked); ``blocked_dofs``
(``state.blockedDOFs``, e.g. ``"xyZ"``); ``is_damped`` (``state.isDamped``: local damping acts on it).

Interaction: ``id1``, ``id2``; ``kn``, ``ks`` [N/m] (``phys.kn``, ``phys.ks``); ``kr``, ``ktw``
[N m/rad] (rolling and twisting springs when the moment law acts on this interaction: CohFrictPhys
with ``momentRotationLaw`` and an unbroken bond or a law with ``always_use_moment_law``; any other
physics exporting ``kr``/``ktw``; else ``null``); ``cn``, ``cs`` [N s/m] (viscous dashpots, e.g.
ViscElPhys, else ``null``; dtcrit's reader refuses ViscElPhys, whose law takes the slip at the
contact point and adds a rolling resistance, and every physics class it does not model: see
``dtcrit.packing.readers.yade_terms``); ``normal`` (``geom.normal``, unit, from body 1 towards body 2);
``point`` (``geom.contactPoint``); ``penetration`` (``geom.penetrationDepth``, positive when
overlapping; YADE does not save it, so on a scene just loaded it is computed from the two spheres); ``radius1``, ``radius2`` (``geom.refR1``, ``geom.refR2``); ``bonded`` (a cohesive
bond is active: ``not phys.cohesionBroken``, or ``phys.isCohesive``); ``shift2`` (the periodic
shift of body 2, ``O.cell.hSize * i.cellDist``; ``[0, 0, 0]`` when not periodic).

Extra keys (every key written here has a decision in ``dtcrit.packing.readers.yade_terms``: modelled,
derived, a record, or refused when it changes the dynamics): top level ``avoid_granular_ratcheting``
(``Ig2_Sphere_Sphere_ScGeom(6D).avoidGranularRatcheting`` of the scene's InteractionLoop, ``null``
without that functor), ``wall_no_ratch`` (``Ig2_Wall_Sphere_ScGeom.noRatch``, ``null`` without that
functor: the ratcheting correction of sphere-wall contacts, ``pkg/dem/Ig2_Facet_Sphere_ScGeom.cpp``);
body ``ori`` (``state.ori`` as ``[w, x, y, z]``); interaction ``geom``,
``phys`` (class names) and ``fn`` [N] (``phys.normalForce . normal``: the normal force, positive
in compression; the pre-load of the contact's geometric stiffness).

YADE conventions a reader needs (YADE sources, pkg/dem/): the contact point is
``x1 + (R1 - penetration/2) n`` (Ig2_Sphere_Sphere_ScGeom.cpp); Law2_ScGeom_FrictPhys_CundallStrack
and Law2_ScGeom6D_CohFrictPhys_CohesionMoment apply forces at that point, i.e. torque arms
``R_i - penetration/2`` (ElasticContactLaw.cpp, CohesiveFrictionalContactLaw.cpp); with
``avoidGranularRatcheting`` (the default) the shear increment is the tangential part of
``(alpha (v2 - v1) + R2 n x w2 + R1 n x w1) dt``, ``alpha = (R1 + R2)/(R1 + R2 - penetration)``
(ScGeom.cpp, ``getIncidentVel``); NewtonIntegrator is leapfrog (velocities at half steps).
"""
from __future__ import annotations

import json
import math
import os
import sys
import tempfile

SCHEMA = "dtcrit-yade-export/1"

__all__ = ["SCHEMA", "export", "snapshot"]


def _omega():
    from yade import wrapper

    return wrapper.Omega()


def _num(x):
    """A finite float, or None."""
    try:
        v = float(x)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


def _vec(v):
    return [_num(v[k]) for k in range(3)]


def _engines(O):
    """Every engine of the scene, with the functors of InteractionLoops."""
    for e in O.engines:
        yield e
        for attr in ("geomDispatcher", "physDispatcher", "lawDispatcher"):
            disp = getattr(e, attr, None)
            for f in getattr(disp, "functors", ()) or ():
                yield f


def _newton_damping(O):
    for e in O.engines:
        if type(e).__name__ == "NewtonIntegrator":
            return _num(e.damping)
    return None


def _newton(O):
    """The scene's NewtonIntegrator, or None."""
    return next((e for e in O.engines if type(e).__name__ == "NewtonIntegrator"), None)


def _newton_flag(O, name):
    """A NewtonIntegrator attribute as a bool, None without a NewtonIntegrator."""
    newton = _newton(O)
    return None if newton is None else bool(getattr(newton, name))


def _density_scaling(O):
    """``NewtonIntegrator.densityScaling``; its getter warns without a GlobalStiffnessTimeStepper, so
    without one it is read only when a body carries a manual ``state.densityScaling``.
    """
    if _newton(O) is None:
        return None
    stepper = any(type(e).__name__ == "GlobalStiffnessTimeStepper" for e in O.engines)
    manual = any(b is not None and float(getattr(b.state, "densityScaling", -1.0)) > 0 for b in O.bodies)
    return _newton_flag(O, "densityScaling") if stepper or manual else False


#: Law2 attributes that change the force (the rest -- label, neverErase, traceEnergy -- do not)
_LAW_OPTIONS = ("always_use_moment_law", "shear_creep", "twist_creep", "useIncrementalForm", "sphericalBodies",
                "includeAdhesion", "includeMoment", "preventGranularRatcheting")


def _laws(O):
    out = []
    for f in _engines(O):
        name = type(f).__name__
        if name.startswith("Law2_"):
            entry = {"class": name}
            entry.update({k: bool(getattr(f, k)) for k in _LAW_OPTIONS if hasattr(f, k)})
            out.append(entry)
    return out


def _vel_grads(O):
    if not O.periodic:
        return None, None
    c = O.cell
    return ([[_num(c.velGrad[r, k]) for k in range(3)] for r in range(3)],
            [[_num(c.nextVelGrad[r, k]) for k in range(3)] for r in range(3)])


def _ratcheting(O):
    for f in _engines(O):
        if type(f).__name__ in ("Ig2_Sphere_Sphere_ScGeom", "Ig2_Sphere_Sphere_ScGeom6D"):
            return bool(f.avoidGranularRatcheting)
    return None


def _wall_no_ratch(O):
    """``Ig2_Wall_Sphere_ScGeom.noRatch`` of the scene's InteractionLoop (``null`` without that functor)."""
    for f in _engines(O):
        if type(f).__name__ == "Ig2_Wall_Sphere_ScGeom":
            return bool(f.noRatch)
    return None


def _always_moment_law(O) -> bool:
    return any(type(f).__name__ == "Law2_ScGeom6D_CohFrictPhys_CohesionMoment" and bool(f.always_use_moment_law)
               for f in _engines(O))


def _facet_vertices(b):
    """The global corners of a Facet (``pos + ori * vertex``)."""
    st = b.state
    return [_vec(st.pos + st.ori * v) for v in b.shape.vertices]


def _body(b) -> dict:
    st = b.state
    shape = type(b.shape).__name__ if b.shape is not None else None
    blocked = str(getattr(st, "blockedDOFs", ""))
    q = st.ori  # minieigen indexes a quaternion as (x, y, z, w)
    return {
        "shape": shape,
        "axis": int(b.shape.axis) if shape == "Wall" else None,
        "sense": int(b.shape.sense) if shape == "Wall" else None,
        "vertices": _facet_vertices(b) if shape == "Facet" else None,
        "id": int(b.id),
        "pos": _vec(st.pos),
        "radius": _num(b.shape.radius) if shape == "Sphere" and not b.isClump else None,
        "mass": _num(st.mass),
        "inertia": _vec(st.inertia),
        "clump_id": int(b.clumpId) if b.isClumpMember else None,
        "is_clump": bool(b.isClump),
        "fixed": (not bool(b.dynamic)) or all(c in blocked for c in "xyzXYZ"),
        "blocked_dofs": blocked,
        "is_damped": bool(getattr(st, "isDamped", True)),
        "ori": [_num(q[3]), _num(q[0]), _num(q[1]), _num(q[2])],
    }


def _moments(phys, always: bool):
    """(kr, ktw) when the moment law acts on this interaction, else (None, None)."""
    if not (hasattr(phys, "kr") or hasattr(phys, "ktw")):
        return None, None
    if hasattr(phys, "momentRotationLaw"):  # CohFrictPhys: Law2_..._CohesionMoment's condition
        acts = bool(phys.momentRotationLaw) and (not bool(getattr(phys, "cohesionBroken", False)) or always)
        if not acts:
            return None, None
    return _num(getattr(phys, "kr", None)), _num(getattr(phys, "ktw", None))


def _bonded(phys) -> bool:
    if hasattr(phys, "cohesionBroken"):
        return not bool(phys.cohesionBroken)
    return bool(getattr(phys, "isCohesive", False))


def _shift(O, i):
    if not O.periodic:
        return [0.0, 0.0, 0.0]
    h, d = O.cell.hSize, i.cellDist
    return [_num(sum(h[r, c] * float(d[c]) for c in range(3))) for r in range(3)]


def _penetration(O, i, shift):
    """``geom.penetrationDepth``; YADE does not save it (``Attr::noSave``), so on a scene just loaded
    it is NaN until the next step: for two spheres it is then ``R1 + R2 - |x2 + shift2 - x1|``."""
    value = _num(getattr(i.geom, "penetrationDepth", None))
    if value is not None:
        return value
    b1, b2 = O.bodies[i.id1], O.bodies[i.id2]
    kinds = (type(b1.shape).__name__, type(b2.shape).__name__)
    if sorted(kinds) == ["Sphere", "Wall"]:  # Ig2_Wall_Sphere_ScGeom: R - |distance to the plane|
        second = kinds[0] == "Wall"  # the sphere is body 2 (shifted by shift2)
        wall, ball = (b1, b2) if second else (b2, b1)
        ax = int(wall.shape.axis)
        gap = ball.state.pos[ax] - wall.state.pos[ax] + (shift[ax] if second else -shift[ax])
        return _num(ball.shape.radius - abs(gap))
    if kinds != ("Sphere", "Sphere"):
        return None
    x1, x2 = b1.state.pos, b2.state.pos
    d = math.sqrt(sum((x2[k] + shift[k] - x1[k]) ** 2 for k in range(3)))
    return _num(b1.shape.radius + b2.shape.radius - d)


def _interaction(O, i, always: bool) -> dict:
    g, p = i.geom, i.phys
    normal = g.normal
    kr, ktw = _moments(p, always)
    nf = getattr(p, "normalForce", None)
    shift = _shift(O, i)
    return {
        "id1": int(i.id1),
        "id2": int(i.id2),
        "kn": _num(getattr(p, "kn", None)),
        "ks": _num(getattr(p, "ks", None)),
        "kr": kr,
        "ktw": ktw,
        "cn": _num(getattr(p, "cn", None)),
        "cs": _num(getattr(p, "cs", None)),
        "normal": _vec(normal),
        "point": _vec(g.contactPoint),
        "penetration": _penetration(O, i, shift),
        "radius1": _num(getattr(g, "refR1", None)),
        "radius2": _num(getattr(g, "refR2", None)),
        "bonded": _bonded(p),
        "shift2": shift,
        "geom": type(g).__name__,
        "phys": type(p).__name__,
        "fn": _num(sum(nf[k] * normal[k] for k in range(3))) if nf is not None else None,
    }


def snapshot() -> dict:
    """The current scene as the ``dtcrit-yade-export/1`` dictionary (module docstring)."""
    import yade.config

    O = _omega()
    always = _always_moment_law(O)
    periodic = bool(O.periodic)
    hsize = None
    if periodic:
        h = O.cell.hSize
        hsize = [[_num(h[r, c]) for c in range(3)] for r in range(3)]
    vel_grad, next_vel_grad = _vel_grads(O)
    return {
        "schema": SCHEMA,
        "yade_version": str(yade.config.version),
        "dt": _num(O.dt),
        "iter": int(O.iter),
        "newton_damping": _newton_damping(O),
        "periodic": periodic,
        "cell_hsize": hsize,
        "cell_vel_grad": vel_grad,
        "cell_next_vel_grad": next_vel_grad,
        "density_scaling": _density_scaling(O),
        "exact_aspherical_rot": _newton_flag(O, "exactAsphericalRot"),
        "laws": _laws(O),
        "avoid_granular_ratcheting": _ratcheting(O),
        "wall_no_ratch": _wall_no_ratch(O),
        "bodies": [_body(b) for b in O.bodies if b is not None],
        "interactions": [_interaction(O, i, always) for i in O.interactions if i.isReal],
    }


def export(path) -> str:
    """Write the current scene to ``path`` (JSON, module docstring); returns the path."""
    data = snapshot()
    path = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix=".yade_export_", suffix=".json", dir=folder)
    try:
        with os.fdopen(fd, "w") as fh:
            json.dump(data, fh, allow_nan=False)
            fh.write("\n")
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


def _main(argv) -> int:
    if len(argv) != 3:
        sys.stderr.write("usage: yade -n -x yade_export.py SCENE OUT.json\n")
        return 2
    _omega().load(argv[1])
    export(argv[2])
    return 0


if __name__ == "__main__" and os.path.basename(sys.argv[0] if sys.argv else "") == "yade_export.py":
    sys.exit(_main(sys.argv))
