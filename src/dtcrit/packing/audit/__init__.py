"""``dtcrit audit``: the critical step of a simulation snapshot as its engine integrates it.

Modules: ``snapshot`` (the analysis), ``output`` (text and JSON, schema ``dtcrit-audit/1``).
"""
