"""Shared test configuration: seeded, reproducible hypothesis profiles (see ``support.hypothesis_profiles``)."""
from support import hypothesis_profiles

hypothesis_profiles.load()
