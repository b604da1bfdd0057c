"""``dtcrit audit``: the critical step of a simulation snapshot as its engine integrates it.

Modules: ``run`` (``read_snapshot`` and ``audit_snapshot``, the API), ``results`` (``Snapshot``, ``SnapshotAudit``, ``DumpReadError``), ``snapshot`` (the analysis), ``output`` (text and JSON, schema ``dtcrit-audit/1``), ``mode_character`` (what governs: the governing mode's spring shares, rotational share and participation ratio), ``plot_data`` (the data of ``--plot``), ``local_damping`` (local (Cundall) damping: the coefficient
from a YADE export or the flags, the damped step, what is not modelled with it).
"""
