"""The ``dtcrit`` command line: it only parses arguments, calls the API and prints.

Each subcommand lives in ``dtcrit.cli.<name>`` and exposes ``add_parser(subparsers)`` and
``run(args) -> int``.  Bad input (``dtcrit.errors.InputError`` or ``ValueError``) is reported as a
single line on standard error with exit status 2, never a traceback.
"""
from __future__ import annotations

import argparse
import importlib
import os
import sys

# Subcommands in the order ``dtcrit --help`` lists them.
COMMANDS: tuple[str, ...] = ("step", "collide", "codegen", "packing", "audit", "plan", "impact", "figures", "bench", "notebooks")


def one_line(text: str) -> str:
    """``text`` as one line: whitespace runs become one space, other control characters their escapes.

    Parameters
    ----------
    text : str
        Any text (a message, a path as given).

    Returns
    -------
    str
        One printable line.
    """
    text = " ".join(str(text).split())
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


def _shorten(text: str, limit: int = 200) -> str:
    """A source label (a path as given) of at most ``limit`` characters: its start and its end."""
    return text if len(text) <= limit else f"{text[: limit // 2 - 2]}...{text[-(limit // 2 - 1):]}"


def help_width() -> int:
    """The width argparse wraps help to, ``shutil.get_terminal_size().columns - 2``, found as shutil finds
    it (``$COLUMNS``, else standard output's terminal, else 80) without importing shutil, whose
    compression modules would load at every start (argparse sizes a formatter for each option added).

    Returns
    -------
    int
        The width in characters.
    """
    try:
        columns = int(os.environ["COLUMNS"])
    except (KeyError, ValueError):
        columns = 0
    if columns <= 0:
        try:
            columns = os.get_terminal_size(sys.__stdout__.fileno()).columns  # type: ignore[union-attr]
        except (AttributeError, ValueError, OSError):
            columns = 0
    return (columns or 80) - 2


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit status 2 (argparse's own convention)
        sys.stderr.write(f"{one_line(self.prog)}: {one_line(message)}\n")
        raise SystemExit(2)

    def _get_formatter(self):
        return self.formatter_class(prog=self.prog, width=help_width())


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The ``dtcrit`` argument parser with every subcommand of ``COMMANDS``, or with one of them.

    Parameters
    ----------
    only : str, optional
        A command of ``COMMANDS``: the parser has that subcommand alone, so that a command line
        naming it imports no other command's module (``main`` passes the one named).

    Returns
    -------
    argparse.ArgumentParser
        A parser whose errors are one line with exit status 2.
    """
    from dtcrit import __version__

    parser = _Parser(prog="dtcrit", description="Critical time steps for explicit DEM simulations.")
    parser.add_argument("--version", action="version", version=f"dtcrit {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name in COMMANDS if only is None else (only,):
        importlib.import_module(f"dtcrit.cli.{name}").add_parser(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the ``dtcrit`` command line.

    Parameters
    ----------
    argv : list of str, optional
        The arguments (None: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status: 0, or 2 for bad input (one line on standard error, no traceback).
    """
    words = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser(words[0] if words and words[0] in COMMANDS else None)
    args = parser.parse_args(words)
    if not getattr(args, "run", None):
        sys.stderr.write(f"dtcrit: give a command, one of {', '.join(COMMANDS)} (dtcrit --help says what each does)\n")
        return 2
    try:
        return int(args.run(args) or 0)
    except ValueError as exc:  # includes dtcrit.errors.InputError
        source = getattr(args, "source_label", None)
        prefix = f"{_shorten(one_line(source))}:" if source else "dtcrit: "
        sys.stderr.write(f"{prefix}{one_line(str(exc))}\n")
        return 2
    except BrokenPipeError:
        return 0
