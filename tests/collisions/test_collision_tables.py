"""The shipped error curves (``_generated/collision_tables.json``) are what the sources produce now."""
import pytest

from dtcrit.collisions import tables


def test_the_tables_were_generated_from_the_current_sources():
    data = tables.load()
    assert data["derivation_hash"] == tables.source_hash(), "collision tables drifted: run `python3 dev.py generate`"
    assert data["steps_per_collision"] == list(tables.STEPS)
    keys = {(c["scheme"], c["normal"], c["damping"], c["restitution"]) for c in data["cases"]}
    assert len(keys) == len(tables.SCHEMES) * len(tables.LAWS) * len(tables.RESTITUTIONS)


@pytest.mark.parametrize("index", [0, 17, 61, 118])
def test_entries_recompute(index):
    case = tables.load()["cases"][index]
    again = tables.curve(case["scheme"], case["normal"], case["damping"], case["restitution"])
    assert again.keys() == case["errors"].keys()
    for key, values in case["errors"].items():  # stored to 6 digits: a last-bit change may move the 6th
        assert again[key] == pytest.approx(values, rel=2e-6, abs=1e-300), key


def test_the_curves_fall_with_n_for_velocity_verlet():
    case = next(c for c in tables.load()["cases"] if c["scheme"] == "velocity-verlet" and c["normal"] == "hertz"
                and c["damping"] == "liggghts" and c["restitution"] == 1.0)
    err = case["errors"]["restitution"]
    assert err[-1] < 1e-4 < err[0]
