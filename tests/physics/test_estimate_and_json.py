"""One estimate type and its one tolerance (``dtcrit.physics.estimate``), non-finite numbers in JSON
(``dtcrit.physics.json_numbers``) and the damping conventions (``dtcrit.physics.damping_conventions``)."""
import json
import math

import mpmath as mp
import numpy as np
import pytest

from dtcrit.physics.damping_conventions import (CONVENTIONS, damping_ratio_from_restitution, lammps_gran_defaults,
                                                tsuji_alpha)
from dtcrit.physics.estimate import SAFE_RTOL, Estimate, RatedEstimate, is_safe
from dtcrit.physics.json_numbers import finite_or_none, json_safe


def test_one_tolerance_for_every_rating():
    assert SAFE_RTOL == 1e-9
    assert is_safe(1.0 + 0.5e-9, 1.0) and not is_safe(1.0 + 2e-9, 1.0)
    assert not is_safe(math.nan, 1.0)
    r = RatedEstimate(Estimate("x", 2.0, "heuristic", "why"), 1.0)
    assert r.ratio == 2.0 and r.safe is False and r.unsafe is True
    assert RatedEstimate(Estimate("x", None), 1.0).safe is None
    assert RatedEstimate(Estimate("x", 1.0), math.inf).ratio != RatedEstimate(Estimate("x", 1.0), math.inf).ratio


def test_estimate_from_omega2():
    e = Estimate.from_omega2("g", 16.0, "lower bound on dt")
    assert e.dt == 0.5 and e.omega2 == 16.0
    assert Estimate.from_omega2("g", 0.0, "x").dt == math.inf


def test_rated_estimate_json_shape():
    r = RatedEstimate(Estimate("n", 1.0, "k", "d", "l"), 4.0)
    assert r.to_json() == {"name": "n", "dt": 1.0, "ratio": 0.25, "safe": True, "kind": "k", "detail": "d",
                           "label": "l"}


def test_non_finite_numbers_are_null():
    assert finite_or_none(math.inf) is None and finite_or_none(math.nan) is None and finite_or_none(None) is None
    assert finite_or_none(np.float64(2.5)) == 2.5
    doc = json_safe({"a": [np.float64(np.inf), np.int64(3), np.bool_(True)], "b": (1.0, -math.inf)})
    assert json.dumps(doc, allow_nan=False) == '{"a": [null, 3, true], "b": [1.0, null]}'


@pytest.mark.parametrize("e", [0.05, 0.3, 0.7, 0.95])
def test_damping_ratio_reproduces_the_restitution(e):
    """A linear spring-dashpot with this zeta leaves with speed ratio exp(-zeta pi / sqrt(1 - zeta^2))."""
    zeta = damping_ratio_from_restitution(e)
    with mp.workdps(30):
        assert float(mp.exp(-zeta * mp.pi / mp.sqrt(1 - mp.mpf(zeta) ** 2))) == pytest.approx(e, rel=1e-14)


def test_lammps_defaults_and_tsuji():
    """pair_gran: Kt NULL -> 2/7 Kn, gamma_t NULL -> gamma_n/2; LAMMPS's tsuji polynomial at e = 1 and 0."""
    assert lammps_gran_defaults(7.0, None, 4.0, None) == (2.0, 2.0)
    assert lammps_gran_defaults(7.0, 1.0, 4.0, 3.0) == (1.0, 3.0)
    assert tsuji_alpha(0.0) == 1.2728
    assert tsuji_alpha(1.0) == pytest.approx(1.2728 - 4.2783 + 11.087 - 22.348 + 27.467 - 18.022 + 4.8218, rel=1e-12)
    assert CONVENTIONS["lammps"].dashpots(0.5, 4.0, 4.0, 1.0) == (2.0, 1.0)
