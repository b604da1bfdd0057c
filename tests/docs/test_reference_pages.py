"""The generated reference pages hold every scene key, JSON key and command-line flag.

The built site (fixture ``built_site``, ``tests/docs/conftest.py``) is read with ``html.parser``; what
it must hold is taken from the code directly, not from the page generator: the scene-key registry's
tables, every ``properties`` name anywhere in each JSON schema (its own walk), and argparse's parser
(``dtcrit.cli.build_parser``: every subcommand and every option string of every action).
"""
from __future__ import annotations

import argparse
import json
from dataclasses import dataclass, field
from html.parser import HTMLParser
from pathlib import Path

import pytest
from support.paths import SRC

from dtcrit.cli import build_parser
from dtcrit.scenes.keys import bodies_file_tables, scene_tables

SCHEMAS = sorted((SRC / "dtcrit" / "schemas").glob("*.json"))
HEADINGS = {f"h{n}" for n in range(1, 7)}


@dataclass
class Section:
    """One ``<section>`` of a page: its id, heading text, and the code / kbd texts inside it."""

    id: str
    heading: str = ""
    codes: set[str] = field(default_factory=set)
    kbds: set[str] = field(default_factory=set)


class _Sections(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.sections: list[Section] = []
        self._open: list[Section] = []
        self._capture: str | None = None
        self._text = ""
        self._depth = 0

    def handle_starttag(self, tag, attrs):
        if tag == "section":
            section = Section(dict(attrs).get("id") or "")
            self.sections.append(section)
            self._open.append(section)
        elif tag in ("code", "kbd") or (tag in HEADINGS and self._open and not self._open[-1].heading):
            if self._capture is None:
                self._capture, self._text = tag, ""

    def handle_endtag(self, tag):
        if tag == "section" and self._open:
            self._open.pop()
        elif tag == self._capture:
            text = " ".join(self._text.replace("¶", "").split())
            for section in self._open:
                if tag == "code":
                    section.codes.add(text)
                elif tag == "kbd":
                    section.kbds.update(part.strip() for part in text.split(","))
            if tag in HEADINGS:
                self._open[-1].heading = text
            self._capture = None

    def handle_data(self, data):
        if self._capture:
            self._text += data


def _sections(path: Path) -> list[Section]:
    assert path.is_file(), f"missing page {path}"
    parser = _Sections()
    parser.feed(path.read_text())
    return parser.sections


def _property_names(node) -> set[str]:
    """Every key of every ``properties`` object anywhere in a schema (``$defs`` included)."""
    names: set[str] = set()
    if isinstance(node, dict):
        names |= set(node.get("properties", {}))
        for value in node.values():
            names |= _property_names(value)
    elif isinstance(node, list):
        for value in node:
            names |= _property_names(value)
    return names


def _subparsers(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    actions = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    return {name: sub for action in actions for name, sub in action.choices.items()}


def _flags(parser: argparse.ArgumentParser) -> set[str]:
    """Every option string (and positional metavar) of a parser, ``-h/--help`` excepted (sphinx-argparse omits it)."""
    flags = set()
    for action in parser._actions:
        if isinstance(action, (argparse._HelpAction, argparse._SubParsersAction)):
            continue
        flags |= set(action.option_strings) or {action.metavar or action.dest}
    return flags


@pytest.fixture(scope="module")
def reference(built_site) -> Path:
    """The reference folder of the built site."""
    return Path(built_site) / "reference"


@pytest.mark.parametrize("page, tables, least", [("scene-keys", scene_tables, 80), ("bodies-file", bodies_file_tables, 20)])
def test_every_key_of_the_registry_is_on_its_page(reference, page, tables, least):
    """Each table of the registry (scene files, bodies files) has its section, holding every key of the table."""
    sections = {s.heading: s for s in _sections(reference / "generated" / f"{page}.html")}
    tables = tables()
    assert sum(len(t.keys) for t in tables) > least
    for table in tables:
        assert table.name in sections, f"no section for {table.name}"
        missing = [k.name for k in table.keys if k.name not in sections[table.name].codes]
        assert not missing, f"{table.name}: keys missing from the page: {missing}"


@pytest.mark.parametrize("schema", SCHEMAS, ids=lambda p: p.stem)
def test_every_schema_property_is_on_its_json_page(reference, schema):
    """Every property name of the schema, at any depth, is a key on its page."""
    names = _property_names(json.loads(schema.read_text()))
    assert len(names) > 5
    page = _sections(reference / "generated" / f"json-{schema.stem}.html")[0]
    leaves = {code.rsplit(".", 1)[-1].removesuffix("[]") for code in page.codes}
    missing = sorted(names - leaves)
    assert not missing, f"{schema.name}: properties missing from the page: {missing}"


def test_every_json_document_is_listed(reference):
    """The JSON index links every document."""
    index = (reference / "generated" / "json.html").read_text()
    for schema in SCHEMAS:
        assert f"json-{schema.stem}.html" in index


def test_every_subcommand_and_flag_is_on_the_command_line_page(reference):
    """Each subcommand has its section with every flag argparse gives it."""
    parser = build_parser()
    by_id = {s.id: s for s in _sections(reference / "cli.html")}
    commands = _subparsers(parser)
    assert {"step", "packing", "audit"} <= set(commands)
    page = _sections(reference / "cli.html")[0]
    assert _flags(parser) <= page.kbds, sorted(_flags(parser) - page.kbds)
    for name, sub in commands.items():
        section = by_id.get(f"dtcrit-{name}")
        assert section is not None, f"no section for dtcrit {name}"
        missing = sorted(_flags(sub) - section.kbds)
        assert not missing, f"dtcrit {name}: flags missing from the page: {missing}"


def test_every_public_name_is_on_the_api_page(reference):
    """Every name of ``dtcrit.__all__`` has its autodoc entry."""
    import dtcrit

    html = (reference / "generated" / "api.html").read_text()
    missing = [name for name in dtcrit.__all__ if f'id="dtcrit.{name}"' not in html
               and f'id="module-dtcrit.{name}"' not in html]
    assert not missing, f"public names missing from the API page: {missing}"


def test_the_code_to_integrator_table_and_engine_conventions_are_on_their_page(reference):
    """Every code name, scheme, engine convention and damping convention is on the engines page."""
    from dtcrit.integrators import engines as codes
    from dtcrit.packing.conventions import engines as conventions
    from dtcrit.physics.damping_conventions import CONVENTIONS

    page = _sections(reference / "generated" / "engines.html")[0]
    expected = set(codes.ENGINES) | set(codes.AMBIGUOUS) | set(conventions.ENGINES)
    expected |= {scheme for scheme, _, _ in codes.ENGINES.values()}
    expected |= set(CONVENTIONS)
    assert expected <= page.codes, sorted(expected - page.codes)
