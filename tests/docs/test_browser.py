"""The built documentation opened in a real browser: headless Debian chromium driven by chromedriver.

The site (fixture ``built_site``) is served by ``http.server`` on localhost; chromium runs with a fresh
profile and no network services of its own (no component updates, sync or background requests).
Checked: the index and one page of each kind render; every ``<img>`` of every page loads (natural width
> 0); every internal link resolves, its ``#fragment`` included (the site is crawled from the index); the
search page finds "velocity Verlet"; a screenshot of the index is written to
``docs/_build/screenshots/index.png`` for a person to look at.  With ``CI=true`` a missing browser
fails the test; elsewhere it skips, saying what to install (``python3 dev.py test`` installs chromium
and chromium-driver with apt when run as root).
"""
from __future__ import annotations

import functools
import os
import shutil
import threading
import time
import urllib.error
import urllib.request
from collections.abc import Iterator
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from urllib.parse import urldefrag, urlsplit

import pytest
from support.paths import REPO_ROOT

KINDS = ("tutorials", "howto", "reference", "explanation", "gallery")
"""Folders of the site, one per kind of page (and the gallery): one page of each must render."""
SCREENSHOT = REPO_ROOT / "docs" / "_build" / "screenshots" / "index.png"
CHROMIUM_FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                  "--disable-background-networking", "--disable-component-update", "--disable-sync",
                  "--window-size=1280,1024")
SEARCH_TIMEOUT = 30.0


def _missing() -> str:
    """Why the browser cannot run here, or ``""``."""
    try:
        import selenium  # noqa: F401
    except ImportError:
        return "selenium is not installed (pip install -e '.[test]')"
    for tool, package in (("chromium", "chromium"), ("chromedriver", "chromium-driver")):
        if shutil.which(tool) is None:
            return f"{tool} is not installed (apt-get install {package}; python3 dev.py test does it as root)"
    return ""


class _Quiet(SimpleHTTPRequestHandler):
    def log_message(self, format, *args):  # noqa: A002 - http.server's signature
        pass


@pytest.fixture(scope="module")
def site(built_site) -> Iterator[str]:
    """The built site served on localhost: its base URL."""
    handler = functools.partial(_Quiet, directory=str(built_site))
    server = ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}/"
    finally:
        server.shutdown()
        server.server_close()


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    """Headless chromium through chromedriver (a fresh profile); fails under CI=true when missing."""
    why = _missing()
    if why:
        if os.environ.get("CI") == "true":
            pytest.fail(f"the docs browser test must run in CI: {why}")
        pytest.skip(why)
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = shutil.which("chromium")
    for flag in (*CHROMIUM_FLAGS, f"--user-data-dir={tmp_path_factory.mktemp('chromium-profile')}"):
        options.add_argument(flag)
    offline = os.environ.get("SE_OFFLINE")
    os.environ["SE_OFFLINE"] = "true"  # Selenium Manager: never download a browser or driver
    try:
        driver = webdriver.Chrome(options=options, service=Service(executable_path=shutil.which("chromedriver")))
    finally:
        if offline is None:
            del os.environ["SE_OFFLINE"]
        else:
            os.environ["SE_OFFLINE"] = offline
    driver.set_page_load_timeout(60)
    try:
        yield driver
    finally:
        driver.quit()


_PAGE_STATE = """
const imgs = Array.from(document.images).map(i => [i.currentSrc || i.src, i.complete ? i.naturalWidth : -1]);
const links = Array.from(document.querySelectorAll('a[href]')).map(a => a.href);
const ids = Array.from(document.querySelectorAll('[id], a[name]')).map(e => e.id || e.getAttribute('name'));
return [document.title, document.body ? document.body.innerText.length : 0, imgs, links, ids];
"""


_PAINTED = """
const done = arguments[arguments.length - 1];
document.fonts.ready.then(() => requestAnimationFrame(() => requestAnimationFrame(() => done(true))));
"""
"""Resolves once the fonts are loaded and two frames are painted (the screenshot shows the page)."""


def _open(browser, url: str) -> dict:
    """Load ``url`` and wait until its images have finished loading; what the page holds."""
    browser.get(url)
    deadline = time.monotonic() + 15
    while True:
        title, length, imgs, links, ids = browser.execute_script(_PAGE_STATE)
        if (length > 0 and all(width >= 0 for _, width in imgs)) or time.monotonic() > deadline:
            return {"title": title, "text": length, "imgs": imgs, "links": links, "ids": set(ids)}
        time.sleep(0.1)


def _status(url: str) -> int:
    try:
        with urllib.request.urlopen(url, timeout=30) as response:  # noqa: S310 - localhost only
            return response.status
    except urllib.error.HTTPError as error:
        return error.code


@pytest.fixture(scope="module")
def crawl(site, browser) -> dict[str, dict]:
    """Every HTML page reachable from the index, opened in the browser: URL -> page state."""
    pages: dict[str, dict] = {}
    queue = [site + "index.html"]
    while queue:
        url = queue.pop()
        if url in pages:
            continue
        pages[url] = _open(browser, url)
        for link in pages[url]["links"]:
            target = urldefrag(link)[0]
            if target.startswith(site) and _is_page(target) and target not in pages:
                queue.append(target)
    return pages


def _is_page(url: str) -> bool:
    path = urlsplit(url).path
    return (path.endswith(".html") or path.endswith("/")) and "/_sources/" not in path and "/_static/" not in path


def test_the_index_renders_and_its_screenshot_is_written(site, browser):
    """The index has a title and text; its screenshot is written for a person to look at."""
    page = _open(browser, site + "index.html")
    assert page["title"] and page["text"] > 200
    SCREENSHOT.parent.mkdir(parents=True, exist_ok=True)
    SCREENSHOT.unlink(missing_ok=True)
    browser.execute_async_script(_PAINTED)
    assert browser.save_screenshot(str(SCREENSHOT))
    assert SCREENSHOT.stat().st_size > 10_000, "the screenshot is blank (a white page is about 8 kB)"


@pytest.mark.parametrize("kind", KINDS)
def test_one_page_of_each_kind_renders(built_site, site, browser, kind):
    """The first page of each kind's folder renders: a title, a heading, text."""
    pages = sorted((Path(built_site) / kind).rglob("*.html"))
    assert pages, f"the site has no {kind} pages"
    page = _open(browser, site + pages[0].relative_to(built_site).as_posix())
    assert page["title"] and page["text"] > 100
    assert browser.execute_script("return document.querySelector('h1') !== null")


def test_the_crawl_reaches_every_kind(crawl, site):
    """The crawl from the index reaches pages of each kind (so the checks below see the whole site)."""
    assert len(crawl) > 10
    for kind in KINDS:
        assert any(url.startswith(f"{site}{kind}/") for url in crawl), f"no {kind} page linked from the index"


def test_every_image_loads(crawl):
    """Every <img> of every page has a natural width > 0 (loaded and decoded)."""
    broken = [f"{url}: {src}" for url, page in crawl.items() for src, width in page["imgs"] if width <= 0]
    assert not broken, "images that did not load:\n" + "\n".join(broken)


def _has_element(browser, crawl: dict, url: str, fragment: str) -> bool:
    """Whether page ``url`` has an element ``#fragment``; a miss is checked once more on a fresh load."""
    if url in crawl and fragment in crawl[url]["ids"]:
        return True
    crawl[url] = _open(browser, url)
    return fragment in crawl[url]["ids"]


def test_every_internal_link_resolves(crawl, site, browser):
    """Every link to the site reaches a page (HTTP 200) and, with a #fragment, an element of that id."""
    broken, checked = [], {}
    for url, page in crawl.items():
        for link in page["links"]:
            target, fragment = urldefrag(link)
            if not target.startswith(site):
                continue
            if target not in checked:
                checked[target] = _status(target)
            if checked[target] != 200:
                broken.append(f"{url} -> {link} (HTTP {checked[target]})")
            elif fragment and _is_page(target) and not _has_element(browser, crawl, target, fragment):
                broken.append(f"{url} -> {link} (no element #{fragment})")
    assert checked, "no internal link found"
    assert not broken, f"{len(broken)} broken internal links:\n" + "\n".join(sorted(set(broken))[:50])


def test_search_finds_velocity_verlet(site, browser):
    """The search page, run in the browser, lists at least one result for "velocity Verlet"."""
    browser.get(site + "search.html?q=velocity+Verlet")
    script = "return document.querySelectorAll('#search-results ul.search li').length"
    deadline = time.monotonic() + SEARCH_TIMEOUT
    while browser.execute_script(script) == 0 and time.monotonic() < deadline:
        time.sleep(0.2)
    assert browser.execute_script(script) > 0, "no search result for 'velocity Verlet'"



def test_formulas_are_typeset_offline(built_site, site, browser):
    """A record's formulas are typeset by the MathJax copied into the site (no network).

    The page's ``span.math`` elements turn into MathJax output, not raw TeX text.
    """
    if not (Path(built_site) / "_static" / "mathjax" / "MathJax.js").is_file():
        assert os.environ.get("CI") != "true", "the site has no local MathJax: apt-get install libjs-mathjax"
        pytest.skip("no local MathJax (Debian's libjs-mathjax): formulas load from a CDN")
    pages = [p for p in sorted((Path(built_site) / "explanation" / "records").glob("*.html"))
             if 'class="math' in p.read_text(encoding="utf-8")]
    assert pages, "no record page has formulas"
    browser.get(site + pages[0].relative_to(built_site).as_posix())
    script = "return document.querySelectorAll('.MathJax_CHTML, mjx-container').length"
    deadline = time.monotonic() + SEARCH_TIMEOUT
    while browser.execute_script(script) == 0 and time.monotonic() < deadline:
        time.sleep(0.2)
    assert browser.execute_script(script) > 0, f"no formula typeset on {pages[0].name}"
