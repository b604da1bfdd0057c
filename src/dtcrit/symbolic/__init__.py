"""SymPy derivations.  Imported only when deriving or generating code, never by the runtime."""
