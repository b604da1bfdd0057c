"""The documentation site builds with no warning and holds the pages of each kind."""
from __future__ import annotations

EXPECTED_PAGES = [
    "index.html",
    "tutorials/getting_started.html",
    "search.html",
]


def test_the_site_builds_without_warnings(site_build):
    assert site_build["returncode"] == 0, site_build["output"]
    assert site_build["warnings"].strip() == "", site_build["warnings"]


def test_the_expected_pages_exist(built_site):
    missing = [page for page in EXPECTED_PAGES if not (built_site / page).is_file()]
    assert not missing, missing
