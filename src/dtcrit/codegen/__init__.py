"""``dtcrit codegen``: emit the critical time step of one contact as C, NumPy or Fortran code.

The kernel is built in SymPy from the symbolic layer (the integrators' exact boundaries of
``dtcrit.symbolic``; Peng et al. 2020, Eqs. (26), (29)-(30), (54), (56)), specialised to the
scene's structure (identical particles, spheres, damping, rotation bound), reduced by
common-subexpression elimination and printed with a deterministic header.  This package imports
SymPy; the runtime (``dtcrit step``) never imports it.
"""
from __future__ import annotations

from dtcrit.codegen.kernel import Argument, ContactKernel, build_kernel
from dtcrit.codegen.kernel_mp import evaluate_mp
from dtcrit.codegen.render import DEFAULT_NAME, LANGUAGES, count_c_operations, render, render_step
from dtcrit.codegen.structure import KernelStructure, general_structure, structure_of_scene

__all__ = [
    "Argument",
    "ContactKernel",
    "KernelStructure",
    "DEFAULT_NAME",
    "LANGUAGES",
    "build_kernel",
    "count_c_operations",
    "emit_for_scene",
    "evaluate_mp",
    "metadata",
    "general_structure",
    "render",
    "render_step",
    "structure_of_scene",
]


CODEGEN_UNITS = {"dt": "s", "kn": "N/m", "ks": "N/m", "cn": "N s/m", "cs": "N s/m", "m": "kg", "I": "kg m^2",
                 "r": "m", "A": "1/kg", "omega_max": "rad/s"}


def metadata(scene, lang: str, name: str = DEFAULT_NAME, command: str | None = None) -> dict:
    """The ``dtcrit codegen --json`` document (schema ``dtcrit-codegen/1``): what the emitted code computes
    and from what -- language, integrator, function and arguments with units, the equations, the
    specialisations, the derivation hash of the kernel and of the careful step it calls -- and the source.

    Parameters
    ----------
    scene : dtcrit.scenes.model.Scene
        The parsed scene whose contact kernel is emitted.
    lang : str
        ``"c"``, ``"numpy"`` or ``"fortran"``.
    name : str
        Name of the emitted function (checked by ``dtcrit.codegen.names.check_name``).
    command : str, optional
        Command line quoted in the emitted header; a default one when omitted.

    Returns
    -------
    dict
        The JSON document, including the emitted ``source``.
    """
    import dtcrit.codegen.step as step
    from dtcrit.json_meta import envelope
    from dtcrit.symbolic.closed_forms import formula_text

    kernel = build_kernel(structure_of_scene(scene))
    label = scene_label(scene)
    source = render(kernel, lang, name, label, command)
    st = kernel.structure
    doc = envelope("dtcrit-codegen/1", CODEGEN_UNITS)
    doc.update({
        "language": lang,
        "integrator": st.integrator,
        "function": name,
        "scene": label,
        "arguments": [{"name": a.name, "unit": a.unit, "meaning": a.meaning} for a in kernel.arguments],
        "returns": {"name": "dt", "unit": "s", "meaning": "critical time step of the contact (0: no positive step "
                    "is stable; NaN: a NaN or negative argument)"},
        "formulas": {"tau": formula_text(st.integrator), "equations": list(kernel.equations),
                     "careful_step": {step.SUFFIX[d]: list(step.chain(st.integrator, d).equations)
                                      for d in kernel.step_variants}},
        "structure": {"identical": st.identical, "sides": list(st.sides), "damped_normal": st.damped_normal,
                      "damped_shear": st.damped_shear, "rotation": st.rotation},
        "specialisations": st.specialisations(),
        "kernel_hash": kernel.hash(),
        "step_hashes": {step.SUFFIX[d]: step.chain_hash(st.integrator, d) for d in kernel.step_variants},
        "op_count": kernel.op_count(),
        "source": source,
    })
    return doc


def emit_for_scene(scene, lang: str, name: str = DEFAULT_NAME, command: str | None = None) -> str:
    """Source text of the kernel a scene needs, in ``lang`` (``c``, ``numpy`` or ``fortran``).

    Parameters
    ----------
    scene : dtcrit.scenes.model.Scene
        The parsed scene.
    lang : str
        ``"c"``, ``"numpy"`` or ``"fortran"``.
    name : str
        Name of the emitted function.
    command : str, optional
        Command line quoted in the emitted header; a default one when omitted.

    Returns
    -------
    str
        The emitted source file, header included.
    """
    kernel = build_kernel(structure_of_scene(scene))
    return render(kernel, lang, name, scene_label(scene), command)


def scene_label(scene) -> str:
    """``FILE (TITLE)``: the scene's file name and title as given (the header's comment makes any text safe,
    ``dtcrit.codegen.comment_text``; the JSON keeps it verbatim).

    Parameters
    ----------
    scene : dtcrit.scenes.model.Scene
        The parsed scene (its ``source`` path and optional ``title``).

    Returns
    -------
    str
        The label, e.g. ``"spheres.toml (Two glass beads)"``.
    """
    from pathlib import Path

    return Path(scene.source).name + (f" ({scene.title})" if scene.title else "")
