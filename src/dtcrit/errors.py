"""Errors raised for bad user input.

``InputError`` carries the offending key so that the command line can print the one-line form
``SOURCE:key: reason`` and exit with status 2.  It subclasses ``ValueError`` so that library users
can catch it as the ordinary Python error for a bad argument.
"""
from __future__ import annotations


class InputError(ValueError):
    """A bad argument or scene entry: ``key`` names it, ``reason`` says what is wrong."""

    def __init__(self, key: str, reason: str):
        self.key = key
        self.reason = reason
        super().__init__(f"{key}: {reason}")
