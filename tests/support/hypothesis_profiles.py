"""Seeded, reproducible hypothesis profiles: ``ci`` (the default), ``dev`` and ``thorough``.

Loaded by ``tests/conftest.py``; ``HYPOTHESIS_PROFILE`` picks another profile.
"""
import os

from hypothesis import HealthCheck, settings

settings.register_profile(
    "ci",
    derandomize=True,
    deadline=None,
    database=None,
    max_examples=60,
    print_blob=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile(
    "dev",
    deadline=None,
    max_examples=200,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile(
    "thorough",
    deadline=None,
    max_examples=2000,
    suppress_health_check=[HealthCheck.too_slow],
)


def load() -> None:
    """Load the profile named by ``HYPOTHESIS_PROFILE`` (``ci`` when unset)."""
    settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))
