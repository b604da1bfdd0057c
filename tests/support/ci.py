"""Whether the suite runs under CI, where missing tools fail the run instead of skipping tests."""
from __future__ import annotations

import os


def in_ci() -> bool:
    """Tell whether the run is under CI.

    Returns
    -------
    bool
        True when the environment variable ``CI`` is ``true``, ``1`` or ``yes`` (any case).
    """
    return os.environ.get("CI", "").strip().lower() in {"true", "1", "yes"}
