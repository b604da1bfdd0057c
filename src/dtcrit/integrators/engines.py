"""Which scheme each DEM code ships: the code's name -> a scheme of ``dtcrit.integrators.schemes``.

``resolve_integrator(name) -> (key, note)``: a scheme key is returned as is (note ""); a code's name
(``"chrono"``, ``"mfix-ab2"``, ...) gives the scheme that code integrates with by default, with a note
saying which and where that was read.  A name whose meaning is not unambiguous (EDEM's first-order
"Euler": its documentation does not say whether the position advances with the old or the new
velocity, which decides between ``forward-euler`` and ``symplectic-euler``) is refused with the
choices.  Each row was read in the code's source or documentation (``SOURCES``).
"""
from __future__ import annotations

from dtcrit.errors import InputError
from dtcrit.integrators.schemes import INTEGRATORS, USER_INTEGRATORS

# code name -> (scheme key, velocity the dashpot sees, source)
ENGINES: dict[str, tuple[str, str, str]] = {
    "lammps": ("velocity-verlet", "v_{n+1/2}", "LAMMPS fix nve/sphere (fix_nve_sphere.cpp), pair gran/*"),
    "liggghts": ("velocity-verlet", "v_{n+1/2}", "LIGGGHTS fix nve/sphere (fix_nve_sphere.cpp)"),
    "liggghts-superquadric": ("velocity-verlet", "v_{n+1/2}",
                              "LIGGGHTS fix nve/superquadric (fix_nve_asphere_base.cpp): v and the angular momentum "
                              "get half kicks around the drift for every integration_scheme 0-4; the schemes differ "
                              "only in the orientation (quaternion) update, which the linear step does not see"),
    "pfc": ("velocity-verlet", "v_{n+1/2}", "PFC documentation: velocities half a step out of phase"),
    "mercurydpm": ("velocity-verlet", "v_{n+1/2}", "MercuryDPM DPMBase::computeOneTimeStep (velocity Verlet)"),
    "yade": ("leapfrog", "v_{n-1/2}", "YADE NewtonIntegrator (leapfrog; velocities at half steps)"),
    "woo": ("leapfrog", "v_{n-1/2}", "woo Leapfrog engine"),
    "chrono": ("extended-taylor", "v_n", "Chrono DEM-Engine src/DEM/API.h (default EXTENDED_TAYLOR), "
               "src/kernel/DEMIntegrationKernels.cu, DEMCustomizablePolicies/IntegrationVelPassOnExtendedTaylor.cu"),
    "chrono-extended-taylor": ("extended-taylor", "v_n", "as chrono"),
    "chrono-forward-euler": ("forward-euler", "v_n", "DEMCustomizablePolicies/IntegrationVelPassOnForwardEuler.cu"),
    "chrono-centered-difference": ("symplectic-euler", "v_n", "DEMCustomizablePolicies/IntegrationVelPassOnCenteredDiff.cu"),
    "mfix": ("symplectic-euler", "v_n", "MFiX model/des/cfnewvalues.f (INTG_EULER: v first, then x with the new v)"),
    "mfix-euler": ("symplectic-euler", "v_n", "as mfix"),
    "mfix-ab2": ("adams-bashforth-2", "v_n", "MFiX model/des/cfnewvalues.f (INTG_ADAMS_BASHFORTH)"),
    "kratos": ("symplectic-euler", "v_n", "Kratos DEMApplication symplectic_euler_scheme.cpp (the examples' default)"),
    "kratos-symplectic-euler": ("symplectic-euler", "v_n", "as kratos"),
    "kratos-forward-euler": ("forward-euler", "v_n", "Kratos DEMApplication forward_euler_scheme.cpp"),
    "kratos-taylor": ("extended-taylor", "v_n", "Kratos DEMApplication taylor_scheme.cpp"),
    "kratos-velocity-verlet": ("velocity-verlet", "v_{n+1/2}", "Kratos DEMApplication velocity_verlet_scheme.cpp "
                               "(PREDICT: x, v_{n+1/2}; forces; CORRECT)"),
    "lethe": ("velocity-verlet", "v_{n+1/2}", "Lethe DEM velocity Verlet integrator (its default)"),
    "lethe-explicit-euler": ("symplectic-euler", "v_n", "Lethe source/dem/explicit_euler_integrator.cc (v first, then x)"),
}

AMBIGUOUS: dict[str, str] = {
    "edem": "EDEM's default 'Euler' is documented only as first order (Altair EDEM help, Simulator Settings); "
            "whether x advances with the old or the new velocity is not stated: choose 'forward-euler' "
            "(unstable undamped) or 'symplectic-euler'",
    "rocky": "Rocky's documentation (Ansys Rocky DEM Technical Manual) does not name its integrator; "
             "choose a scheme key",
}


def resolve_integrator(name, key: str = "integrator") -> tuple[str, str]:
    """(scheme key, note) for a scheme key or a DEM code's name; InputError for an ambiguous one.

    Unknown names are returned unchanged with note "" (the caller's check names the choices).

    Parameters
    ----------
    name : str
        A scheme key (``"leapfrog"``), a DEM code's name (``"chrono"``, ``"mfix-ab2"``, table ``ENGINES``)
        or anything else (returned as is).
    key : str
        The input key named in the error.

    Returns
    -------
    tuple of (str, str)
        The scheme key and a note saying which scheme the code uses and where that was read ("" for a
        scheme key).
    """
    if not isinstance(name, str):
        return name, ""
    if name in INTEGRATORS or name in USER_INTEGRATORS:
        return name, ""
    low = name.strip().lower()
    if low in AMBIGUOUS:
        raise InputError(key, f"'{name}' is ambiguous: {AMBIGUOUS[low]}")
    if low in ENGINES:
        scheme, velocity, source = ENGINES[low]
        return scheme, f"'{name}' integrates with '{scheme}' (dashpot velocity {velocity}; {source})"
    return name, ""
