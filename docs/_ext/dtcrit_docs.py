"""Sphinx extension ``dtcrit_docs``: the reference pages, generated from the code at build time.

On ``builder-inited`` it writes reStructuredText into ``docs/reference/generated/`` (git-ignored;
a file is rewritten only when its text changes, so an unchanged page is not rebuilt):

* ``scene-keys.rst`` -- every table and key of a scene file, from ``dtcrit.scenes.keys.scene_tables``;
* ``bodies-file.rst`` -- every key of a ``dtcrit-bodies/1`` file, from ``dtcrit.scenes.keys.bodies_file_tables``;
* ``json-*.rst`` -- every JSON document, every property (nested ones as dotted paths), from
  ``src/dtcrit/schemas/*.json``;
* ``api.rst`` -- the public Python API (``dtcrit.__all__``) with autodoc and numpydoc;
* ``engines.rst`` -- the engine conventions of ``dtcrit audit`` (``dtcrit.packing.conventions.engines``)
  and the code-to-integrator table (``dtcrit.integrators.engines``).

The command line is ``docs/reference/cli.rst``: the ``sphinx-argparse`` directive on
``dtcrit.cli.build_parser``.  The extension loads autodoc, numpydoc and sphinx-argparse itself.
"""
from __future__ import annotations

import json
import re
import sys
from dataclasses import dataclass
from pathlib import Path

from docutils.transforms import Transform

ROOT = Path(__file__).resolve().parents[2]
GENERATED = ROOT / "docs" / "reference" / "generated"
SCHEMAS = ROOT / "src" / "dtcrit" / "schemas"
if str(ROOT / "src") not in sys.path:  # a build from a fresh clone, dtcrit not installed
    sys.path.insert(0, str(ROOT / "src"))

_SPECIAL = re.compile(r"([\\*`_|])")


def text(value: str) -> str:
    """Plain text made safe for reStructuredText (inline-markup characters escaped, one line)."""
    return _SPECIAL.sub(r"\\\1", " ".join(str(value).split()))


@dataclass(frozen=True)
class SchemaRow:
    """One property of a JSON schema: dotted path, type, required or not, description."""

    path: str
    kind: str
    required: bool
    description: str


def _resolve(schema: dict, node: dict, seen: tuple[str, ...]) -> tuple[dict, tuple[str, ...]]:
    while isinstance(node, dict) and "$ref" in node and node["$ref"] not in seen:
        ref = node["$ref"]
        target: dict = schema
        for part in ref.lstrip("#/").split("/"):
            target = target[part]
        merged = {**target, **{k: v for k, v in node.items() if k != "$ref"}}
        node, seen = merged, (*seen, ref)
    return node, seen


def _kind(schema: dict, node: dict, seen: tuple[str, ...]) -> str:
    node, seen = _resolve(schema, node, seen)
    if "const" in node:
        return json.dumps(node["const"])
    if "enum" in node:
        return " | ".join(json.dumps(v) for v in node["enum"])
    for key in ("oneOf", "anyOf"):
        if key in node:
            return " or ".join(dict.fromkeys(_kind(schema, n, seen) for n in node[key]))
    if node.get("allOf") and "type" not in node:
        return _kind(schema, node["allOf"][0], seen)
    kind = node.get("type", "any")
    kind = " or ".join(kind) if isinstance(kind, list) else kind
    if "array" in kind and isinstance(node.get("items"), dict):
        kind = kind.replace("array", f"array of {_kind(schema, node['items'], seen)}", 1)
    return kind


def _children(schema: dict, node: dict, path: str, seen: tuple[str, ...]) -> list[SchemaRow]:
    node, seen = _resolve(schema, node, seen)
    rows: list[SchemaRow] = []
    required = set(node.get("required", ()))
    properties = node.get("properties", {})
    for key, child in properties.items():
        full = f"{path}.{key}" if path else key
        resolved, _ = _resolve(schema, child, seen)
        description = child.get("description") or resolved.get("description", "")
        rows.append(SchemaRow(full, _kind(schema, child, seen), key in required, description))
        rows += _children(schema, child, full, seen)
    extra = node.get("additionalProperties")
    kind = _kind(schema, extra, seen) if isinstance(extra, dict) else "any"
    for key in sorted(required - set(properties)):  # required, described by its parent
        rows.append(SchemaRow(f"{path}.{key}" if path else key, kind, True, ""))
    if isinstance(extra, dict):
        rows += _children(schema, extra, f"{path}.*", seen)
    for pattern, child in node.get("patternProperties", {}).items():
        rows += _children(schema, child, f"{path}.*", seen)
    for key in ("items", "contains"):
        if isinstance(node.get(key), dict):
            rows += _children(schema, node[key], f"{path}[]", seen)
    for item in node.get("prefixItems", ()):
        rows += _children(schema, item, f"{path}[]", seen)
    for key in ("allOf", "anyOf", "oneOf"):
        for branch in node.get(key, ()):
            rows += _children(schema, branch, path, seen)
    return rows


def schema_rows(schema: dict) -> list[SchemaRow]:
    """Every property of a JSON schema, nested ones included, each once (first description wins).

    Parameters
    ----------
    schema : dict
        A JSON schema (draft 2020-12): ``properties``, ``items``, ``additionalProperties``,
        ``patternProperties``, ``$ref`` into ``$defs`` and the ``*Of`` combinators are followed.

    Returns
    -------
    list of SchemaRow
        In document order.
    """
    rows: dict[str, SchemaRow] = {}
    for row in _children(schema, schema, "", ()):
        old = rows.get(row.path)
        if old is None or (not old.description and row.description):
            rows[row.path] = row if old is None else SchemaRow(old.path, old.kind, old.required or row.required,
                                                               row.description)
    return list(rows.values())


def _table(header: tuple[str, ...], rows: list[tuple[str, ...]], widths: str = "") -> list[str]:
    lines = [".. list-table::", "   :header-rows: 1", "   :width: 100%", "   :class: dtcrit-reference"]
    if widths:
        lines.append(f"   :widths: {widths}")
    lines.append("")
    for row in [header, *rows]:
        lines.append(f"   * - {row[0] or ' '}")
        lines += [f"     - {cell or ' '}" for cell in row[1:]]
    return lines + [""]


def _title(title: str, char: str = "=") -> list[str]:
    return [title, char * len(title), ""]


def _key_tables(tables) -> list[str]:
    lines: list[str] = []
    for table in tables:
        lines += [f".. _keys-{table.anchor}:", "", *_title(f"``{table.name}``", "-")]
        header = ("key", table.applies_to, "meaning") if table.applies_to else ("key", "meaning")
        rows = [(f"``{k.name}``", k.applies, k.description) if table.applies_to else (f"``{k.name}``", k.description)
                for k in table.keys]
        lines += _table(header, rows, "20 15 65" if table.applies_to else "25 75")
    return lines


def scene_keys_page() -> str:
    """The scene-key reference: one table per scene table, every key with what it means."""
    from dtcrit.scenes.keys import scene_tables

    return "\n".join([".. _scene-keys:", "", *_title("Scene keys"),
                      "Every key a scene file (TOML) may hold, table by table, generated from the scene-key "
                      "registry ``dtcrit.scenes.keys`` (which reads the parsers' own key lists).  Units are in "
                      "brackets; ``[-]`` is dimensionless.", "", *_key_tables(scene_tables())])


def bodies_file_page() -> str:
    """The ``dtcrit-bodies/1`` file reference (``dtcrit packing BODIES.json``), every key described."""
    from dtcrit.scenes.keys import bodies_file_tables

    return "\n".join([".. _bodies-file:", "", *_title("Bodies file (``dtcrit-bodies/1``)"),
                      "The JSON file of non-spherical bodies ``dtcrit packing BODIES.json`` reads, generated from "
                      "the reader's key lists (``dtcrit.packing.readers.bodies_file``) with the descriptions of "
                      "``dtcrit.scenes.keys``.", "", *_key_tables(bodies_file_tables())])


def schema_page(path: Path) -> tuple[str, str]:
    """(page name, text) of one JSON document's reference, every property of its schema."""
    schema = json.loads(path.read_text())
    name = path.stem
    lines = [f".. _json-{name}:", "", *_title(f"``{schema['$id']}``: {schema.get('title', '')}"),
             text(schema.get("description", "")), "",
             f"Schema: ``src/dtcrit/schemas/{path.name}`` (JSON Schema draft 2020-12).  Nested keys are "
             "dotted paths: ``a.b`` a key of the object ``a``, ``a[]`` an item of the array ``a``, ``a.*`` "
             "any key of the object ``a``.  **required** marks keys every document holds.", ""]
    rows = [(f"``{row.path}``", text(row.kind) + (" (**required**)" if row.required else ""), text(row.description))
            for row in schema_rows(schema)]
    lines += _table(("key", "type", "meaning"), rows, "30 20 50")
    return f"json-{name}", "\n".join(lines)


def json_index(names: list[str]) -> str:
    """The JSON-output page: the envelope, then a toctree of the documents."""
    lines = [".. _json-output:", "", *_title("JSON documents"),
             "Every command's ``--json`` output is one JSON document with the envelope ``schema``, "
             "``dtcrit_version``, ``units`` and ``derivation_hashes``; its keys are listed below, "
             "generated from the JSON schemas that the tests validate the output against.", "",
             ".. toctree::", "   :maxdepth: 1", ""]
    return "\n".join(lines + [f"   {name}" for name in names] + [""])


API_GROUPS = {
    "bodies": "Shapes and contact kinematics", "scenes": "Scenes (``dtcrit step``)",
    "packing": "Packings and simulation snapshots (``dtcrit packing``, ``dtcrit audit``)",
    "codegen": "Code for your simulator (``dtcrit codegen``)", "paper": "The paper's printed formulas",
    "errors": "Errors", "integrators": "The exact step of one contact", "impact": "The 1-D impact (``dtcrit impact``)",
}
"""Top-level package of a public name -> the API page's section (in the order ``dtcrit._API`` lists them)."""


def api_page() -> str:
    """The public API: autodoc entries for every name of ``dtcrit.__all__``, grouped by package.

    Returns
    -------
    str
        The page (reStructuredText).
    """
    import inspect

    import dtcrit

    lines = [".. _python-api:", "", *_title("Python API"),
             "``import dtcrit`` exposes these names (``dtcrit.__all__``); each returns or is what its "
             "command prints, and each result's ``to_json()`` is the command's ``--json`` document.", "",
             ".. currentmodule:: dtcrit", ""]
    groups: dict[str, list[str]] = {}
    for name in dtcrit._API:  # the order the package lists its API in, which is dtcrit.__all__ sorted
        groups.setdefault(dtcrit._API[name].split(".")[0], []).append(name)
    for package in groups:
        lines += _title(API_GROUPS.get(package, package), "-")
        for name in groups[package]:
            obj = getattr(dtcrit, name)
            if inspect.ismodule(obj):
                lines += [f".. automodule:: {obj.__name__}", "   :members:", "", ".. currentmodule:: dtcrit", ""]
            elif inspect.isclass(obj):
                lines += [f".. autoclass:: {name}", "   :members:", ""]
            elif callable(obj):
                lines += [f".. autofunction:: {name}", ""]
            else:
                lines += [f".. autodata:: {name}", "   :no-value:", ""]
    return "\n".join(lines)


_SHEAR = {"half": "c_n/2", "same": "c_n", "two_sevenths": "(2/7) c_n"}


def _factor(value: float) -> str:
    return "" if value == 1.0 else f"{value:.6g} x "


def _damping_conventions() -> list[str]:
    """The damping conventions of ``[contact] damping_convention``, from ``dtcrit.physics.damping_conventions``."""
    from dataclasses import replace

    from dtcrit.physics.damping_conventions import CONVENTIONS, DEFAULT_CONVENTION, liggghts_hertz

    conventions = []
    for c in CONVENTIONS.values():
        if c.name == "liggghts":  # LIGGGHTS's hooke law, and its Hertz law (liggghts_hertz)
            conventions += [replace(c, models=tuple(m for m in c.models if m != "hertz")),
                            replace(liggghts_hertz(), models=("hertz",))]
        else:
            conventions.append(c)
    rows = []
    for c in conventions:
        normal = f"{_factor(c.factor_n)}2 zeta sqrt(k_n m*)"
        mass = "" if c.mass_t == 1.0 else f"{c.mass_t:.6g} "
        shear = _SHEAR.get(c.shear_rule, f"{_factor(c.factor_t)}2 zeta sqrt(k_t {mass}m*)")
        default = [model for model in c.models if DEFAULT_CONVENTION.get(model) == c.name]
        rows.append((f"``{c.name}``", text(c.code), f"``{normal}``", f"``{shear}``", f"``{c.wall_mass:g} m``",
                     ", ".join(c.models) + (f"; default for {', '.join(default)}" if default else "")))
    return [*_title("Damping conventions (``[contact] damping_convention``)", "-"),
            "How a damping ratio zeta (or a restitution coefficient) becomes dashpots, per code "
            "(``dtcrit.physics.damping_conventions.CONVENTIONS``): ``m*`` is the pair's reduced mass, "
            "``k_n``, ``k_t`` the springs (for Hertz the tangent stiffnesses ``S_n``, ``S_t``).", "",
            *_table(("convention", "code", "normal c_n", "tangential c_t", "wall mass", "contact models"), rows,
                    "12 28 18 18 9 15")]


def engines_page() -> str:
    """The engine conventions and the code-to-integrator table, from the objects that hold them."""
    from dtcrit.integrators import engines as codes
    from dtcrit.packing.conventions import engines as conventions

    lines = [".. _engine-conventions:", "", *_title("Engines and integrators"),
             *_title("Which scheme your code runs (``integrator = \"<code>\"``)", "-"),
             "A scene's ``integrator`` may name a DEM code; dtcrit then uses the scheme that code "
             "integrates with (``dtcrit.integrators.engines.ENGINES``).", ""]
    rows = [(f"``{code}``", f"``{scheme}``", text(velocity), text(source))
            for code, (scheme, velocity, source) in codes.ENGINES.items()]
    rows += [(f"``{code}``", "refused", "", text(reason)) for code, reason in codes.AMBIGUOUS.items()]
    lines += _table(("code", "scheme", "damping uses", "source"), rows, "18 18 12 52")
    lines += [*_title("Engine conventions (``dtcrit audit --engine``)", "-"),
              "How each engine builds the contacts whose stiffness sets its step "
              "(``dtcrit.packing.conventions.engines.ENGINES``).", ""]
    rows = [(f"``{c.name}``", f"``{c.integrator}``", f"``{c.arm}``", "yes" if c.preload else "no", text(c.contacts),
             text(c.source)) for c in conventions.ENGINES.values()]
    lines += _table(("engine", "integrator", "contact arms", "pre-load", "contacts", "source"), rows,
                    "10 15 12 8 20 35")
    lines += _damping_conventions()
    lines += ["What each engine convention is and how it was checked (the module's own account):", "",
              ".. automodule:: dtcrit.packing.conventions.engines", "   :no-members:", "   :no-index:", ""]
    return "\n".join(lines)


def _write(name: str, body: str) -> None:
    path = GENERATED / f"{name}.rst"
    if not path.is_file() or path.read_text() != body:
        path.write_text(body)


def generate(app=None) -> None:
    """Write every generated reference page (the ``builder-inited`` handler).

    Parameters
    ----------
    app : sphinx.application.Sphinx or None
        The application (unused; the pages depend on the code only).
    """
    GENERATED.mkdir(parents=True, exist_ok=True)
    _write("scene-keys", scene_keys_page())
    _write("bodies-file", bodies_file_page())
    names = []
    for path in sorted(SCHEMAS.glob("*.json")):
        name, body = schema_page(path)
        _write(name, body)
        names.append(name)
    _write("json", json_index(names))
    _write("api", api_page())
    _write("engines", engines_page())


class _LiteralFlags(Transform):
    """Keep ``--flag`` as typed on the reference pages: no smart quotes there (``--`` is not a dash)."""

    default_priority = 700  # before Sphinx's SmartQuotes (750)

    def apply(self, **kwargs) -> None:
        """Switch smart quotes off for the reference pages (Sphinx's documented workaround)."""
        env = self.document.settings.env
        if env.docname.startswith("reference/"):
            self.document.settings.smart_quotes = False


def _find(dotted: str) -> bool:
    """True when ``dotted`` names an importable module or an attribute of one (``a.b.c``)."""
    import importlib

    parts = dotted.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        for name in parts[cut:]:
            if not hasattr(obj, name):
                return False
            obj = getattr(obj, name)
        return True
    return False


def _code_reference(app, env, node, contnode):
    """A Python cross-reference to dtcrit code the reference does not document, shown as plain code.

    Docstrings name internal functions and modules (``:func:`check_integrator```); the API page
    documents the public names only.  A target that exists in the code (absolute, relative to the
    docstring's module, or under ``dtcrit``) is rendered unlinked; one that does not exist stays a
    warning (a broken reference).
    """
    if node.get("refdomain") != "py":
        return None
    target = node["reftarget"].lstrip("~.")
    where = re.search(r"docstring of ([\w.]+)", node.source or "")
    owner = (where.group(1) if where else node.get("py:module") or "").split(".")
    scopes = {".".join(owner[:cut]) for cut in range(1, len(owner) + 1)} | {"dtcrit"}
    candidates = [target, *(f"{scope}.{target}" for scope in scopes)]
    if any(_find(name) for name in candidates if name.startswith("dtcrit")):
        return contnode
    return None


def _configure(app, config) -> None:
    config.html_static_path = [*config.html_static_path, str(Path(__file__).resolve().parent / "static")]
    config.numpydoc_show_class_members = False
    config.numpydoc_class_members_toctree = False
    config.autodoc_member_order = "bysource"


def setup(app):
    """Register the extension: the extensions it needs, its configuration and the page generator.

    Parameters
    ----------
    app : sphinx.application.Sphinx
        The application.

    Returns
    -------
    dict
        Sphinx's extension metadata.
    """
    for extension in ("sphinx.ext.autodoc", "numpydoc", "sphinxarg.ext"):
        app.setup_extension(extension)
    app.add_transform(_LiteralFlags)
    app.add_css_file("dtcrit-reference.css")
    app.connect("config-inited", _configure)
    app.connect("builder-inited", generate)
    app.connect("missing-reference", _code_reference)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
