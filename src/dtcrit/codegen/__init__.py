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
from dtcrit.codegen.render import DEFAULT_NAME, LANGUAGES, count_c_operations, render
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
    "general_structure",
    "render",
    "structure_of_scene",
]


def emit_for_scene(scene, lang: str, name: str = DEFAULT_NAME, command: str | None = None) -> str:
    """Source text of the kernel a scene needs, in ``lang`` (``c``, ``numpy`` or ``fortran``)."""
    from pathlib import Path

    kernel = build_kernel(structure_of_scene(scene))
    label = Path(scene.source).name + (f" ({scene.title})" if scene.title else "")
    return render(kernel, lang, name, label, command)
