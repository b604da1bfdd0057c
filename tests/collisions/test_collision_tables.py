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


RECOMPUTED = [("velocity-verlet", "hertz", "liggghts", 0.9, 0.01), ("leapfrog", "hertz", "yade-mindlin", 0.5, 0.01),
              ("symplectic-euler", "hooke", "liggghts", 1.0, 0.001)]


def _stored(scheme, normal, damping, e, tol):
    return next(r for r in tables.load()["resolutions"] if (r["scheme"], r["normal"], r["damping"], r["restitution"],
                                                             r["tol"]) == (scheme, normal, damping, e, tol))


@pytest.mark.parametrize("case", RECOMPUTED)
def test_tabulated_resolution_steps_recompute(case):
    """The stored N_res is what ``resolve`` gives now, to the 6 digits stored."""
    from dtcrit.collisions.laws import scaled_law
    from dtcrit.collisions.resolution import resolve

    scheme, normal, damping, e, tol = case
    res = resolve(scheme, scaled_law(normal, damping, e), tol, ("restitution", "peak_overlap"))
    assert _stored(*case)["steps_per_collision"] == pytest.approx(res.steps_per_collision, rel=1e-5)  # 6 digits: half a unit is 5e-6


def test_resolution_step_reads_the_tables_for_the_engine_cases():
    """The engine acceptance cases are tabulated: ``resolution_step`` answers from the tables, fast."""
    import time

    from dtcrit.collisions import resolution_step

    t0 = time.perf_counter()
    for engine, damping, clip in (("lammps", "lammps-coeff-restitution", False), ("yade", "yade-mindlin", None)):
        for e in (0.9, 0.5, 0.1):
            res = resolution_step(engine=engine, normal="hertz", damping=damping, restitution=e, tol=0.01, clip=clip)
            scheme = "velocity-verlet" if engine == "lammps" else "leapfrog"
            assert res.steps_per_collision == _stored(scheme, "hertz", damping, e, 0.01)["steps_per_collision"]
    assert time.perf_counter() - t0 < 2.0
