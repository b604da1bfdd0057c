"""Quaternion rotation matrices in the one convention, body to world (dtcrit.numerics.rotations),
against Rodrigues' formula at 50 digits and against the generated Eq. (7) kernel.
"""
import mpmath as mp
import numpy as np
import pytest

from dtcrit._generated import contact as generated
from dtcrit.numerics.rotations import body_to_world_matrix, unit_body_to_world_matrix, world_to_body_matrix


def _rodrigues_mp(axis, angle):
    """Active rotation by ``angle`` about the unit ``axis``: cos t 1 + sin t [n]x + (1 - cos t) n n^T."""
    with mp.workdps(50):
        n = mp.matrix([mp.mpf(a) for a in axis])
        n = n / mp.norm(n)
        K = mp.matrix([[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]])
        t = mp.mpf(angle)
        return mp.eye(3) * mp.cos(t) + K * mp.sin(t) + (n * n.T) * (1 - mp.cos(t))


@pytest.mark.parametrize("axis,angle", [((0, 0, 1), 0.5), ((1, 2, -3), 2.0), ((0.3, -0.1, 0.9), -1.2)])
def test_quaternion_of_an_axis_angle_rotates_body_to_world(axis, angle):
    n = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    q = np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * n])
    R = body_to_world_matrix(q)
    ref = _rodrigues_mp(axis, angle)
    assert np.max(np.abs(R - np.array(ref.tolist(), dtype=float))) < 1e-15
    assert np.array_equal(world_to_body_matrix(q), R.T)


def test_body_x_axis_turns_to_world_y_about_z():
    q = (np.cos(np.pi / 4), 0.0, 0.0, np.sin(np.pi / 4))  # +90 degrees about z
    assert np.allclose(body_to_world_matrix(q) @ np.array([1.0, 0.0, 0.0]), [0.0, 1.0, 0.0], atol=1e-15)


def test_vectorised_and_the_generated_eq7_kernel_agree():
    rng = np.random.default_rng(5)
    q = rng.normal(size=(20, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    R = body_to_world_matrix(q)
    assert R.shape == (20, 3, 3)
    for i in range(20):
        assert np.array_equal(R[i], body_to_world_matrix(q[i]))
        gen = np.array([float(e) for e in generated.rotation_matrix(*q[i])]).reshape(3, 3)
        assert np.max(np.abs(gen - R[i])) < 4e-16
        assert np.max(np.abs(R[i] @ R[i].T - np.eye(3))) < 1e-15


def test_refuses_a_non_quaternion():
    with pytest.raises(ValueError):
        body_to_world_matrix([1.0, 0.0, 0.0])


@pytest.mark.parametrize("axis,angle", [((0, 0, 1), 0.5), ((1, 2, -3), 2.0), ((0.3, -0.1, 0.9), -1.2), ((1, 1, 1), 3.1)])
def test_the_unit_form_is_the_same_rotation(axis, angle):
    """The readers' form (1 - 2 (y^2 + z^2) ...) against Rodrigues at 50 digits, batched and single."""
    n = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    q = np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * n])
    ref = np.array(_rodrigues_mp(axis, angle).tolist(), dtype=float)
    assert np.max(np.abs(unit_body_to_world_matrix(q) - ref)) < 1e-15
    assert np.array_equal(unit_body_to_world_matrix(np.stack([q, q]))[1], unit_body_to_world_matrix(q))
