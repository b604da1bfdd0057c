"""One home for the checks of input values, with structured error locations.

Every reader of user input -- scene files (``dtcrit.scenes``), the ``[[particle]]`` shape tables
(``dtcrit.bodies.spec``), the packing readers (``dtcrit.packing.readers``) -- checks its values with
these functions, so that one kind of bad value gives one message.  Each problem is one
:class:`dtcrit.errors.InputError` whose :class:`dtcrit.errors.Location` names the source, the line
and the key of the value.

Modules: ``text`` (values shown in messages), ``values`` (numbers, strings, choices, ids),
``arrays`` (vectors, rows, vertex lists), ``keys`` (unknown and missing keys of a table), ``files``
(bounded reads of text files and locating errors in them).  Imports only the standard library,
NumPy and ``dtcrit.errors``.
"""
