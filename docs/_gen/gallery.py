"""The gallery: the figures dtcrit makes, drawn from the code when the site is built.

Each entry of ``FIGURES`` is a ``dtcrit`` command (the audit and collide figures take ``dev.py``'s
``AUDIT_FIGURE`` and ``COLLIDE_FIGURE`` arguments, with the output path moved) run in a fresh process
with Matplotlib's Agg backend, writing into ``docs/gallery/_generated`` (gitignored), and
``figures.md`` there lists each figure with the command that made it.  The figures are redrawn only
when a stamp (a hash of ``src/dtcrit`` and the commands) changed, so an unchanged tree does not pay
for them again.  The bench's work-precision figure is the one its committed run drew
(``docs/benchmarks/data``, see ``benchmarks.py``).
"""
from __future__ import annotations

import hashlib
import importlib.util
import os
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parents[1]
ROOT = DOCS.parent


def dev_module():
    """``dev.py`` imported as a module (its task table and figure arguments).

    Returns
    -------
    module
        The module.
    """
    spec = importlib.util.spec_from_file_location("dtcrit_dev", ROOT / "dev.py")
    dev = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(dev)
    return dev


def _moved(args: tuple[str, ...], flag: str, path: str) -> list[str]:
    args = list(args)
    args[args.index(flag) + 1] = path
    return args


def figures() -> list[dict]:
    """The gallery's entries: title, the ``dtcrit`` arguments (``OUT`` is the output folder), images.

    Returns
    -------
    list of dict
        ``title``, ``args``, ``images`` (file names written into the output folder), ``text``.
    """
    dev = dev_module()
    return [
        {"title": "The paper's Figures 3-6 and the Appendix A search, with the verified bounds beside them",
         "args": ["figures", "--out", "OUT"],
         "images": ["fig3_damping.png", "fig4_stiffness.png", "fig5_density.png", "fig6_aspect_ratio.png",
                    "figA2_centre_moved.png", "figA4_orientation_changed.png", "figA_shapes.png"],
         "text": "Peng et al. (2020)'s figures recomputed, each beside dtcrit's verified step "
                 "(derivation records sec6_numerics and appendix_a)."},
        {"title": "A time-stepped impact: exit over entry speed against omega dt and the entry phase",
         "args": ["impact", "--integrator", "velocity-verlet", "--zeta", "0.05", "--out", "OUT"],
         "images": ["impact_velocity-verlet_zeta0.05_ratio.png", "impact_velocity-verlet_hertz.png"],
         "text": "Velocity Verlet on a lightly damped linear contact, and the Hertz study of the sweep "
                 "(derivation record cfl_impact)."},
        {"title": "An audit's governing mode and the top of the spectrum",
         "args": _moved(dev.AUDIT_FIGURE, "--plot", "OUT/audit.png"), "images": ["audit.png"],
         "text": "The particles coloured by their share of the governing mode's kinetic energy, and the "
                 "steps of the ten highest modes with dt_crit, dt_safe and the estimators marked."},
        {"title": "Resolving collisions: the worst error against the step, per collision",
         "args": _moved(dev.COLLIDE_FIGURE, "--plot", "OUT/collide.png"), "images": ["collide.png"],
         "text": "Restitution and peak-overlap errors over every entry phase, with the chosen step marked."},
    ]


def _stamp(entries: list[dict]) -> str:
    digest = hashlib.sha256()
    for path in sorted((ROOT / "src" / "dtcrit").rglob("*")):
        if path.is_file() and path.suffix in (".py", ".json", ".c", ".f90", ".txt"):
            digest.update(str(path.relative_to(ROOT)).encode() + path.read_bytes())
    digest.update(repr([e["args"] for e in entries]).encode())
    return digest.hexdigest()


def run_dtcrit(args: list[str], out: Path) -> None:
    """Run ``python -m dtcrit ARGS`` from the repository root (``OUT`` in ARGS replaced by ``out``).

    Parameters
    ----------
    args : list of str
        The command's arguments.
    out : pathlib.Path
        The output folder.

    Raises
    ------
    RuntimeError
        When the command fails (its output is in the message).
    """
    env = dict(os.environ, MPLBACKEND="Agg")
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT / "src"), os.environ.get("PYTHONPATH")]))
    args = [a.replace("OUT", str(out)) for a in args]
    done = subprocess.run([sys.executable, "-m", "dtcrit", *args], cwd=ROOT, env=env, capture_output=True,
                          text=True, timeout=600)
    if done.returncode != 0:
        raise RuntimeError(f"dtcrit {shlex.join(args)} failed:\n{done.stdout}{done.stderr}")


def page_text(entries: list[dict], bench_figure: str | None) -> str:
    """The gallery's Markdown: per figure its title, what it shows, the command and the images.

    Parameters
    ----------
    entries : list of dict
        From ``figures``.
    bench_figure : str or None
        The bench's figure file name in the output folder, when there is one.

    Returns
    -------
    str
        MyST Markdown (included by ``gallery/index.md``).
    """
    lines = []
    for e in entries:
        shown = shlex.join(a.replace("OUT", "out") for a in e["args"])
        lines += [f"## {e['title']}", "", e["text"], "", "```console", f"$ dtcrit {shown}", "```", ""]
        lines += [f"![{image}]({image})" for image in e["images"]] + [""]
    if bench_figure:
        lines += ["## Work against precision: every route of the bench", "",
                  "Seconds per scene against the largest error in ulps, per route (the bench's own figure; "
                  "where the run came from is on the benchmarks page).", "",
                  "```console", "$ dtcrit bench --quick --out out", "```", "", f"![{bench_figure}]({bench_figure})", ""]
    return "\n".join(lines)


def build_gallery(docs: Path = DOCS) -> Path:
    """Draw the gallery's figures (unless the stamp is unchanged) and write its page fragment.

    Parameters
    ----------
    docs : pathlib.Path
        The documentation folder.

    Returns
    -------
    pathlib.Path
        The written ``gallery/_generated/figures.md``.
    """
    out = docs / "gallery" / "_generated"
    out.mkdir(parents=True, exist_ok=True)
    entries = figures()
    stamp_file, stamp = out / ".stamp", _stamp(entries)
    if not stamp_file.is_file() or stamp_file.read_text() != stamp:
        for entry in entries:
            run_dtcrit(entry["args"], out)
        stamp_file.write_text(stamp)
    bench_png = docs / "benchmarks" / "data" / "work_precision.png"
    bench_figure = None
    if bench_png.is_file():
        if not (out / bench_png.name).is_file() or (out / bench_png.name).read_bytes() != bench_png.read_bytes():
            shutil.copyfile(bench_png, out / bench_png.name)
        bench_figure = bench_png.name
    page = out / "figures.md"
    if not page.is_file() or page.read_text() != page_text(entries, bench_figure):
        page.write_text(page_text(entries, bench_figure))
    return page
