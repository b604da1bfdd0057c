"""Sphinx extension of dtcrit's site: the pages made from the repository when the site is built.

At ``builder-inited`` (before Sphinx lists the sources) it copies the teaching notebooks
(``notebooks/NN_name.py``) to ``tutorials/notebooks/NN_name.nbpy``, which myst-nb reads with jupytext
(``nb_custom_formats`` in ``conf.py``).  A copy is rewritten only when its text changed, so an
unchanged notebook is neither re-read nor re-executed.  It also writes ``_generated/reference_toctree.txt``,
which ``index.md`` includes: the reference section's toctree when ``reference/index`` exists, else
nothing (a toctree naming a missing page, or a glob matching none, is a warning, so an error here).
The derivation records and proofs get one page each (``record_stubs``), the gallery's figures are drawn
(``gallery.py``) and the benchmarks page is written (``benchmarks.py``).
"""
from __future__ import annotations

from pathlib import Path

from benchmarks import build_benchmarks
from gallery import build_gallery

DOCS = Path(__file__).resolve().parents[1]
ROOT = DOCS.parent


def write_if_changed(path: Path, text: str) -> bool:
    """Write ``text`` to ``path`` unless it already holds it.

    Parameters
    ----------
    path : pathlib.Path
        File to write (its folder is created).
    text : str
        The content.

    Returns
    -------
    bool
        True when the file was written.
    """
    if path.is_file() and path.read_text() == text:
        return False
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return True


def copy_notebooks(docs: Path = DOCS) -> list[Path]:
    """Copy ``notebooks/NN_*.py`` into ``tutorials/notebooks/`` as ``.nbpy`` sources; drop stale copies.

    Parameters
    ----------
    docs : pathlib.Path
        The documentation folder.

    Returns
    -------
    list of pathlib.Path
        The copies.
    """
    out = docs / "tutorials" / "notebooks"
    copies = []
    for source in sorted((docs.parent / "notebooks").glob("[0-9][0-9]_*.py")):
        copy = out / f"{source.stem}.nbpy"
        write_if_changed(copy, source.read_text())
        copies.append(copy)
    for stale in set(out.glob("*.nbpy")) - set(copies):
        stale.unlink()
    return copies


REFERENCE_TOCTREE = """```{toctree}
:caption: Reference
:maxdepth: 2

reference/index
```
"""


def reference_toctree(docs: Path = DOCS) -> str:
    """The index page's reference toctree (``REFERENCE_TOCTREE``), empty while the reference is missing.

    Parameters
    ----------
    docs : pathlib.Path
        The documentation folder.

    Returns
    -------
    str
        MyST text for ``index.md`` to include.
    """
    return REFERENCE_TOCTREE if any((docs / "reference").glob("index.*")) else ""


def record_stubs(docs: Path = DOCS) -> list[Path]:
    """Write one page per derivation record and proof, including the committed Markdown file.

    ``explanation/records/NAME.md`` includes ``derivations/records/NAME.md`` and
    ``explanation/proofs/NAME.md`` includes ``derivations/proofs/NAME.md`` (MyST ``{include}``, with
    the record's relative image paths rewritten), so the pages always show the committed records.

    Parameters
    ----------
    docs : pathlib.Path
        The documentation folder.

    Returns
    -------
    list of pathlib.Path
        The stubs.
    """
    stubs = []
    for kind in ("records", "proofs"):
        out = docs / "explanation" / kind
        for source in sorted((docs.parent / "derivations" / kind).glob("*.md")):
            stub = out / source.name
            rel = Path("..", "..", "..", "derivations", kind, source.name).as_posix()
            write_if_changed(stub, f"```{{include}} {rel}\n:relative-images:\n:relative-docs: figures/\n```\n")
            stubs.append(stub)
        for stale in set(out.glob("*.md")) - set(stubs):
            stale.unlink()
    return stubs


HOWTO_ORDER = ("step", "own_integrator", "python_api", "audit", "audit_lammps", "audit_yade", "collide",
               "codegen", "plan", "packing", "mpi")
"""The how-to pages in the order a user meets the tasks; other pages of ``howto/`` follow by name."""


def howto_toctree(docs: Path = DOCS) -> str:
    """The index page's how-to toctree: the pages of ``HOWTO_ORDER`` that exist, then any others.

    Parameters
    ----------
    docs : pathlib.Path
        The documentation folder.

    Returns
    -------
    str
        MyST text for ``index.md`` to include.
    """
    present = sorted(p.stem for p in (docs / "howto").glob("*.md"))
    names = [n for n in HOWTO_ORDER if n in present] + [n for n in present if n not in HOWTO_ORDER]
    entries = "".join(f"howto/{n}\n" for n in names)
    return f"```{{toctree}}\n:caption: How-to guides\n:maxdepth: 1\n\n{entries}```\n"


def _builder_inited(app) -> None:
    docs = Path(app.srcdir)
    copy_notebooks(docs)
    record_stubs(docs)
    build_gallery(docs)
    build_benchmarks(docs)
    write_if_changed(docs / "_generated" / "reference_toctree.txt", reference_toctree(docs))
    write_if_changed(docs / "_generated" / "howto_toctree.txt", howto_toctree(docs))


def setup(app) -> dict:
    """Register the build steps with Sphinx.

    Parameters
    ----------
    app : sphinx.application.Sphinx
        The application.

    Returns
    -------
    dict
        Extension metadata (safe for parallel reading and writing).
    """
    app.connect("builder-inited", _builder_inited)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
