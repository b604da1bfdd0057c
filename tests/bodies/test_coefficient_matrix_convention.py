"""``dtcrit.coefficient_matrix`` names its rotation convention: ``body_to_world=(R1, R2)``, keyword only.
A call in the retired form (a rotation positional or as ``R1=``/``R2=``, read as world to body by an
older dtcrit) raises a TypeError that states the convention instead of answering with the inverse
rotation; the keyword call equals the matrix built by hand with NumPy from the world-frame inertia
tensor ``Q diag(I) Q^T`` and the arm's cross-product matrix, the rotation taken from SciPy's quaternion
(active, body to world) -- not from dtcrit's Eq. (7) code."""
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import dtcrit
from dtcrit.bodies import Box, Ellipsoid, Sphere, Superquadric
from dtcrit.errors import InputError

SHAPES = [Ellipsoid(3.0, 2.0, 1.0, density=1000.0), Box(3.0, 2.0, 1.0, density=1000.0),
          Superquadric(2.0, 1.5, 1.0, 0.4, 0.6, density=2500.0), Sphere(1.0, density=7800.0),
          Ellipsoid(1e-3, 4e-4, 2e-4, density=2.5e3)]
quaternions = st.tuples(*[st.floats(-1, 1)] * 4).filter(lambda q: sum(c * c for c in q) > 1e-2)
arms = st.tuples(*[st.floats(-3, 3)] * 3)


def _cross(r):
    return np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])


def _by_hand(p1, p2, Q1, Q2, r1, r2):
    """xdd_c = A F for force F on 2 (-F on 1): A = (1/m1 + 1/m2) 1 + sum_i [r_i]x^T (Q_i I_i Q_i^T)^-1 [r_i]x."""
    A = (1.0 / p1.mass + 1.0 / p2.mass) * np.eye(3)
    for p, Q, r in ((p1, Q1, r1), (p2, Q2, r2)):
        inertia_world = Q @ np.diag(p.inertia) @ Q.T
        S = _cross(np.asarray(r, float))
        A += S.T @ np.linalg.solve(inertia_world, S)
    return A


def _matrix(q):
    q = np.asarray(q, float) / np.linalg.norm(q)
    return Rotation.from_quat([q[1], q[2], q[3], q[0]]).as_matrix()  # SciPy: (x, y, z, w), active


@given(st.sampled_from(range(len(SHAPES))), st.sampled_from(range(len(SHAPES))), quaternions, quaternions, arms, arms,
       st.floats(-4, 1))
def test_the_keyword_call_equals_the_matrix_built_by_hand(i, j, q1, q2, r1, r2, log_scale):
    p1, p2 = SHAPES[i], SHAPES[j]
    s = 10.0**log_scale
    r1, r2 = np.array(r1) * s, np.array(r2) * s
    Q1, Q2 = _matrix(q1), _matrix(q2)
    ref = _by_hand(p1, p2, Q1, Q2, r1, r2)
    scale = np.max(np.abs(ref))
    for rotations in ((q1, q2), (Q1, Q2)):
        A = dtcrit.coefficient_matrix(p1, p2, r1, r2, body_to_world=rotations)
        np.testing.assert_allclose(A, ref, rtol=0, atol=1e-12 * scale)


def test_the_convention_matters_here_so_the_old_reading_would_differ():
    """The same matrix read the other way (world to body) gives a clearly different A: the case the
    TypeError guards against."""
    e, r1, r2 = SHAPES[0], np.array([3.0, 0.0, 0.0]), np.array([-1.0, 1.0, 0.5])
    Q2 = _matrix([np.cos(0.4), 0.3, -0.5, 0.2])
    A = dtcrit.coefficient_matrix(e, e, r1, r2, body_to_world=(None, Q2))
    inverse = dtcrit.coefficient_matrix(e, e, r1, r2, body_to_world=(None, Q2.T))
    np.testing.assert_allclose(A, _by_hand(e, e, np.eye(3), Q2, r1, r2), rtol=1e-13)
    assert np.max(np.abs(A - inverse)) > 0.05 * np.max(np.abs(A))


@pytest.mark.parametrize("call", [
    lambda e, r: dtcrit.coefficient_matrix(e, e, r, -r, None, np.eye(3)),
    lambda e, r: dtcrit.coefficient_matrix(e, e, r, -r, np.eye(3)),
    lambda e, r: dtcrit.coefficient_matrix(e, e, r, -r, R1=np.eye(3)),
    lambda e, r: dtcrit.coefficient_matrix(e, e, r, -r, R2=[1.0, 0.0, 0.0, 0.0]),
    lambda e, r: dtcrit.coefficient_matrix(e, e, r, -r, R1=None, R2=None),
])
def test_an_old_style_call_raises_a_type_error_naming_the_convention(call):
    e, r = SHAPES[0], np.array([3.0, 0.0, 0.0])
    with pytest.raises(TypeError, match=r"body_to_world=\(R1, R2\).*body to world.*Eq \(5\).*transpose"):
        call(e, r)


@pytest.mark.parametrize("value", [np.eye(3), [1.0, 0.0, 0.0, 0.0], "identity", (None, None, None), 3.0,
                                   {"R1": None, "R2": None}])
def test_a_body_to_world_that_is_no_pair_is_refused(value):
    e = SHAPES[0]
    with pytest.raises(InputError) as err:
        dtcrit.coefficient_matrix(e, e, [3.0, 0, 0], [-3.0, 0, 0], body_to_world=value)
    assert err.value.key == "body_to_world"


def test_a_bad_member_of_the_pair_is_named():
    e = SHAPES[0]
    with pytest.raises(InputError) as err:
        dtcrit.coefficient_matrix(e, e, [3.0, 0, 0], [-3.0, 0, 0], body_to_world=(None, 2 * np.eye(3)))
    assert err.value.key == "body_to_world[2]"
