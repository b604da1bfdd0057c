"""Code emission as an API: the per-contact critical step of a scene as C, NumPy or Fortran source.

The API behind ``dtcrit codegen``.  The kernel is built in SymPy from the symbolic layer (the
integrators' exact stability boundaries; Peng et al. 2020, Eqs. (26), (29)-(30), (54), (56)),
specialised to the scene's structure and printed with a deterministic header
(:mod:`dtcrit.codegen`).  The emitted kernel carries the normal and tangential springs and dashpots
only: a scene with rotational springs, dashpots or bonds is refused.
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Mapping

from dtcrit.codegen.render import DEFAULT_NAME, LANGUAGES
from dtcrit.errors import InputError

if TYPE_CHECKING:
    from dtcrit.scenes.model import Scene

__all__ = ["EmittedCode", "emit_code", "emitted_code", "refuse_what_the_kernel_leaves_out"]


@dataclass(frozen=True)
class EmittedCode:
    """Emitted source text with what it computes and from what.

    Parameters
    ----------
    language : str
        ``c``, ``numpy`` or ``fortran``.
    function : str
        The emitted function's name.
    source : str
        The source text.
    metadata : Mapping
        The ``dtcrit codegen --json`` document (schema ``dtcrit-codegen/1``): integrator, arguments
        with units, equations, specialisations, derivation hashes and the source.

    Examples
    --------
    >>> from dtcrit import emitted_code
    >>> code = emitted_code("examples/mixed_pair.toml", "fortran", "contact_dt")
    >>> code.language, code.to_json()["source"] == code.source
    ('fortran', True)
    """

    language: str
    function: str
    source: str = field(repr=False)
    metadata: Mapping[str, Any] = field(repr=False, compare=False)

    def to_json(self) -> dict:
        """The document ``dtcrit codegen --json`` prints (schema ``dtcrit-codegen/1``).

        Returns
        -------
        dict
            A new dictionary of the metadata, the source included.
        """
        return dict(self.metadata)


def refuse_what_the_kernel_leaves_out(scene: Scene) -> None:
    """Refuse a scene whose step the emitted kernel would overestimate.

    The kernel has the normal and tangential springs and dashpots only: with rotational springs or
    dashpots (rolling, twisting, bonds) its step would exceed the scene's (``dtcrit step`` gives it).

    Parameters
    ----------
    scene : Scene
        The scene to emit.

    Raises
    ------
    InputError
        ``key`` ``contact``: the scene has bond springs or rotational springs or dashpots.
    """
    law = scene.contact
    walls = [w for w in scene.walls if any(getattr(w, k, 0.0) for k in ("kr", "ktw", "cr", "ctw"))]
    if law.bond is not None or law.rotational is not None or walls:
        what = "bond springs" if law.bond is not None else "rotational springs or dashpots (kr, ktw, cr, ctw)"
        raise InputError("contact", f"the emitted kernel does not carry {what} yet, so its step would exceed "
                                    "the scene's; dtcrit step gives the step of this scene")


def _scene(scene: Scene | str | os.PathLike) -> Scene:
    if isinstance(scene, (str, os.PathLike)):
        from pathlib import Path

        from dtcrit.scenes.scene import load_scene

        return load_scene(scene if isinstance(scene, str) else Path(scene))
    return scene


def emitted_code(scene: Scene | str | os.PathLike, lang: str, name: str = DEFAULT_NAME, *,
                 command: str | None = None) -> EmittedCode:
    """The per-contact critical step of a scene as source code, with its metadata.

    Parameters
    ----------
    scene : Scene or str or os.PathLike
        A scene (``dtcrit.load_scene``) or the path of a scene file.
    lang : {'c', 'numpy', 'fortran'}
        Output language.
    name : str
        The emitted function's name (an identifier of every language, not a keyword).
    command : str, optional
        The header's "Regenerate with" command.

    Returns
    -------
    EmittedCode
        The source and the ``dtcrit codegen --json`` document.

    Raises
    ------
    InputError
        A bad ``name`` (key ``name``), a scene the kernel does not carry (key ``contact``), an
        unknown language (key ``lang``).

    Examples
    --------
    >>> from dtcrit import emitted_code
    >>> code = emitted_code("examples/mixed_pair.toml", "numpy")
    >>> code.function, code.to_json()["language"]
    ('dtcrit_dt_crit', 'numpy')
    """
    from dtcrit.codegen import metadata
    from dtcrit.codegen.names import check_name

    if lang not in LANGUAGES:
        raise InputError("lang", f"unknown language {lang!r}; choose one of {', '.join(LANGUAGES)}")
    check_name(name)
    scene = _scene(scene)
    refuse_what_the_kernel_leaves_out(scene)
    doc = metadata(scene, lang, name, command)
    return EmittedCode(language=lang, function=name, source=doc["source"], metadata=MappingProxyType(doc))


def emit_code(scene: Scene | str | os.PathLike, lang: str, name: str = DEFAULT_NAME, *,
              command: str | None = None) -> str:
    """The per-contact critical step of a scene as C, NumPy or Fortran source text.

    Parameters
    ----------
    scene : Scene or str or os.PathLike
        A scene (``dtcrit.load_scene``) or the path of a scene file.
    lang : {'c', 'numpy', 'fortran'}
        Output language.
    name : str
        The emitted function's name.
    command : str, optional
        The header's "Regenerate with" command.

    Returns
    -------
    str
        The source text ``dtcrit codegen`` prints.

    Examples
    --------
    >>> from dtcrit import emit_code
    >>> source = emit_code("examples/mixed_pair.toml", "c", "contact_dt")
    >>> "double contact_dt(" in source
    True
    """
    return emitted_code(scene, lang, name, command=command).source
