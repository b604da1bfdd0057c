"""The documentation site builds with no warning and holds the pages of each kind.

The build itself (``sphinx-build`` with warnings as errors, nitpicky) is the ``built_site`` fixture
of ``conftest.py``; these tests read what it wrote: the pages of each kind, the notebooks myst-nb
executed (with their figures kept as PNG), the gallery's images and the benchmarks page.
"""
from __future__ import annotations

import json
import re

from support.paths import REPO_ROOT

from dtcrit.notebooks import sources

PAGES = [
    "index.html", "search.html", "genindex.html",
    "tutorials/getting_started.html",
    "howto/step.html", "howto/own_integrator.html", "howto/codegen.html", "howto/collide.html",
    "howto/audit.html", "howto/audit_lammps.html", "howto/audit_yade.html", "howto/packing.html",
    "howto/mpi.html", "howto/python_api.html",
    "explanation/index.html", "explanation/verified_steps.html", "explanation/findings.html",
    "explanation/conventions.html", "explanation/audit_conventions.html", "explanation/code_layout.html",
    "gallery/index.html", "benchmarks/index.html",
]
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
GALLERY_IMAGES = ["fig3_damping.png", "fig6_aspect_ratio.png", "figA_shapes.png", "audit.png", "collide.png",
                  "impact_velocity-verlet_zeta0.05_ratio.png"]


def test_the_site_builds_without_warnings(site_build):
    assert site_build["returncode"] == 0, site_build["output"]
    assert site_build["warnings"].strip() == "", site_build["warnings"]


def test_the_pages_of_each_kind_exist(built_site):
    missing = [page for page in PAGES if not (built_site / page).is_file()]
    assert not missing, missing


def test_every_notebook_is_a_page_with_its_figures(built_site):
    """Each teaching notebook is a tutorial page showing at least one PNG figure its cells drew (a cell
    that fails, or writes to standard error, fails the build itself)."""
    for source in sources():
        page_path = built_site / "tutorials" / "notebooks" / f"{source.stem}.html"
        images = re.findall(r'<img[^>]+src="([^"]+\.png)"', page_path.read_text())
        assert images, f"{source.stem}: no figure on its page"
        for image in images:
            assert (page_path.parent / image).read_bytes()[:8] == PNG_SIGNATURE, (source.stem, image)


def test_every_record_and_proof_is_a_page(built_site):
    for kind in ("records", "proofs"):
        for record in sorted((REPO_ROOT / "derivations" / kind).glob("*.md")):
            page = built_site / "explanation" / kind / f"{record.stem}.html"
            assert page.is_file(), page
            first_heading = next(line for line in record.read_text().splitlines() if line.startswith("# "))
            words = re.findall(r"[A-Za-z]{4,}", first_heading)[:3]
            assert all(word in page.read_text() for word in words), (record.name, words)


def test_the_gallery_shows_each_figure_with_its_command(built_site):
    page = (built_site / "gallery" / "index.html").read_text()
    for image in GALLERY_IMAGES:
        assert f'src="../_images/{image}"' in page, image
        assert (built_site / "_images" / image).stat().st_size > 1000, image
    text = re.sub(r"<[^>]+>", "", page)  # the commands are highlighted token by token
    for command in ("dtcrit figures", "dtcrit impact", "dtcrit audit", "dtcrit collide"):
        assert command in text, command


def test_the_benchmarks_page_shows_the_bench_document_and_the_machine(built_site):
    page = (built_site / "benchmarks" / "index.html").read_text()
    bench = json.loads((REPO_ROOT / "docs" / "benchmarks" / "data" / "bench.json").read_text())
    assert bench["schema"] == "dtcrit-bench/1"
    for route in bench["routes"]:
        assert route["name"] in page, route["name"]
    assert "Measured on:" in page and "This site was built on:" in page
    assert "logical cores" in page


def test_the_index_links_every_kind(built_site):
    index = (built_site / "index.html").read_text()
    for target in ("tutorials/getting_started.html", "howto/step.html", "explanation/index.html",
                   "gallery/index.html", "benchmarks/index.html", "tutorials/notebooks/01_quaternions_to_amax.html"):
        assert f'href="{target}"' in index, target
