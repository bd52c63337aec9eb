from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from aaria_pin.core.rotations import TAIT_BRYAN, angles_from_matrix, as_rotation, matrix_from_angles
from aaria_pin.errors import ParameterError

SEQUENCES = [*TAIT_BRYAN, "ZYZ", "zyz", "XYX", "yzy"]


@pytest.mark.parametrize("seq", SEQUENCES)
def test_matrices_match_scipy(seq: str) -> None:
    angles = np.random.default_rng(1).uniform(-np.pi, np.pi, (500, 3))
    np.testing.assert_allclose(
        matrix_from_angles(angles, seq), Rotation.from_euler(seq, angles).as_matrix(), atol=1e-13
    )


@pytest.mark.parametrize("seq", SEQUENCES)
def test_round_trips_on_random_rotations(seq: str) -> None:
    R = Rotation.random(2000, random_state=2).as_matrix()
    result = angles_from_matrix(R, seq)
    np.testing.assert_allclose(matrix_from_angles(result.angles, seq), R, atol=1e-12)
    np.testing.assert_allclose(result.angles, Rotation.from_matrix(R).as_euler(seq), atol=1e-9)
    again = angles_from_matrix(matrix_from_angles(result.angles, seq), seq)
    np.testing.assert_allclose(again.angles, result.angles, atol=1e-9)
    assert not result.locked.any()


@pytest.mark.parametrize("seq", SEQUENCES)
@pytest.mark.parametrize("offset", [0.0, 1e-9, 1e-7, -1e-7, 5e-7])
def test_at_and_near_gimbal_lock(seq: str, offset: float) -> None:
    proper = seq[0].lower() == seq[2].lower()
    rng = np.random.default_rng(3)
    for middle in (0.0, np.pi) if proper else (np.pi / 2, -np.pi / 2):
        angles = rng.uniform(-np.pi, np.pi, (200, 3))
        angles[:, 1] = middle + (
            abs(offset) if proper and middle == 0 else -abs(offset) if proper else offset
        )
        R = matrix_from_angles(angles, seq)
        result = angles_from_matrix(R, seq)
        assert result.locked.all()
        np.testing.assert_allclose(matrix_from_angles(result.angles, seq), R, atol=1e-9)
        if offset == 0.0:  # the canonical choice: the rightmost factor's angle is zero
            np.testing.assert_array_equal(result.angles[:, 2 if seq.isupper() else 0], 0.0)


@settings(max_examples=200, deadline=None)
@given(angles=st.tuples(*[st.floats(-np.pi, np.pi)] * 3), seq=st.sampled_from(SEQUENCES))
def test_angles_in_their_full_ranges(angles, seq: str) -> None:
    R = matrix_from_angles(np.array(angles), seq)
    result = angles_from_matrix(R, seq)
    a, b, c = result.angles
    assert -np.pi <= a <= np.pi and -np.pi <= c <= np.pi
    if seq[0].lower() == seq[2].lower():
        assert 0 <= b <= np.pi
    else:
        assert -np.pi / 2 <= b <= np.pi / 2
    np.testing.assert_allclose(matrix_from_angles(result.angles, seq), R, atol=1e-9)


def test_angles_beyond_ninety_degrees_keep_their_sign() -> None:
    # the report's acos formulas lose these: x = 120°, z = -150° about fixed axes
    angles = np.radians([120.0, 30.0, -150.0])
    result = angles_from_matrix(matrix_from_angles(angles, "xyz"), "xyz")
    np.testing.assert_allclose(result.angles, angles, atol=1e-12)


@pytest.mark.parametrize(
    ("matrix", "pattern"),
    [
        (np.eye(4), r"shape \(4, 4\)"),
        (np.full((3, 3), np.nan), "NaN"),
        (np.diag([1.0, 1.0, -1.0]), "det = -1"),
        (np.eye(3) * 1.01, "not a rotation"),
    ],
)
def test_bad_matrices(matrix: np.ndarray, pattern: str) -> None:
    with pytest.raises(ParameterError, match=pattern):
        angles_from_matrix(matrix, "xyz")


def test_projection_to_the_nearest_rotation() -> None:
    R = Rotation.from_euler("xyz", [0.3, -0.2, 1.0]).as_matrix()
    noisy = R + 1e-3 * np.random.default_rng(4).normal(size=(3, 3))
    projected, flag = as_rotation(noisy, project=True)
    assert flag
    np.testing.assert_allclose(projected.T @ projected, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(projected, R, atol=5e-3)
    same, flag = as_rotation(R, project=True)
    assert not flag and np.array_equal(same, R)


@pytest.mark.parametrize("seq", ["xy", "xxz", "XyZ", "abc", 3])
def test_bad_sequences(seq) -> None:
    pattern = "rotation sequence" if isinstance(seq, str) else r"seq is 3 \(int\)"
    with pytest.raises(ParameterError, match=pattern):
        matrix_from_angles([0.1, 0.2, 0.3], seq)


def test_bad_angles() -> None:
    with pytest.raises(ParameterError, match="NaN"):
        matrix_from_angles([0.1, np.nan, 0.3], "xyz")
    with pytest.raises(ParameterError, match=r"shape \(2,\)"):
        matrix_from_angles([0.1, 0.2], "xyz")


PROPER_EULER = tuple(a + b + a for a in "xyz" for b in "xyz" if a != b) + tuple(
    a + b + a for a in "XYZ" for b in "XYZ" if a != b
)
EVERY_SEQUENCE = (*TAIT_BRYAN, *PROPER_EULER)


def _near_lock_angles(seq: str, delta: float, side: int, outer: np.ndarray) -> np.ndarray:
    """Angles whose middle one is ``delta`` from one of the sequence's two locks [rad]."""
    proper = seq[0].lower() == seq[2].lower()
    if proper:
        middle = delta if side == 0 else np.pi - delta
    else:
        middle = np.pi / 2 - delta if side == 0 else -np.pi / 2 + delta
    return np.column_stack([outer[:, 0], np.full(len(outer), middle), outer[:, 1]])


@settings(max_examples=300, deadline=None)
@given(
    seq=st.sampled_from(EVERY_SEQUENCE),
    exponent=st.floats(-13.0, -6.0),
    side=st.sampled_from([0, 1]),
    seed=st.integers(0, 2**32 - 1),
)
def test_near_gimbal_lock_round_trips_to_machine_precision(
    seq: str, exponent: float, side: int, seed: int
) -> None:
    # built with scipy, whose matrices have rounded small entries (matrix_from_angles' exact
    # zeros hid the loss): the separate formulas lost 1e-16/δ (2.2e-6 at δ = 1e-11)
    delta = 10.0**exponent
    outer = np.random.default_rng(seed).uniform(-np.pi, np.pi, (40, 2))
    angles = _near_lock_angles(seq, delta, side, outer)
    R = Rotation.from_euler(seq, angles).as_matrix()
    result = angles_from_matrix(R, seq)
    assert result.locked.all() or delta > 0.9e-6  # the flag's edge: LOCK_TOLERANCE = 1e-6
    np.testing.assert_allclose(Rotation.from_euler(seq, result.angles).as_matrix(), R, atol=5e-15)
    np.testing.assert_allclose(result.angles[:, 1], angles[:, 1], atol=1e-14)  # well conditioned
    outer_found = result.angles[:, [0, 2]]
    assert np.all((outer_found > -np.pi) & (outer_found <= np.pi))


@settings(max_examples=200, deadline=None)
@given(
    seq=st.sampled_from(EVERY_SEQUENCE),
    exponent=st.floats(-6.0, -1.0),
    side=st.sampled_from([0, 1]),
    seed=st.integers(0, 2**32 - 1),
)
def test_angles_match_scipy_where_they_are_defined(
    seq: str, exponent: float, side: int, seed: int
) -> None:
    # δ >= 1e-6: scipy is exact here and each angle is defined to about 1e-16/δ
    delta = 10.0**exponent
    outer = np.random.default_rng(seed).uniform(-np.pi, np.pi, (40, 2))
    R = Rotation.from_euler(seq, _near_lock_angles(seq, delta, side, outer)).as_matrix()
    ours = angles_from_matrix(R, seq).angles
    theirs = Rotation.from_matrix(R).as_euler(seq)
    difference = np.angle(np.exp(1j * (ours - theirs)))  # modulo 2π
    np.testing.assert_allclose(difference, 0.0, atol=1e-14 / delta)
    np.testing.assert_allclose(Rotation.from_euler(seq, ours).as_matrix(), R, atol=5e-15)


def test_the_issue_example_xyz_eleven_orders_from_lock() -> None:
    R = Rotation.from_euler("XYZ", [0.4, np.pi / 2 - 1e-11, -1.3]).as_matrix()
    angles = angles_from_matrix(R, "XYZ").angles
    error = np.abs(Rotation.from_euler("XYZ", angles).as_matrix() - R).max()
    assert error < 2e-15  # was 2.2e-6; scipy 1.17: 5e-12


@pytest.mark.parametrize("seq", EVERY_SEQUENCE)
def test_exact_lock_from_scipy_keeps_the_canonical_member(seq: str) -> None:
    outer = np.random.default_rng(8).uniform(-np.pi, np.pi, (50, 2))
    for side in (0, 1):
        R = Rotation.from_euler(seq, _near_lock_angles(seq, 0.0, side, outer)).as_matrix()
        result = angles_from_matrix(R, seq)
        np.testing.assert_array_equal(result.angles[:, 2 if seq.isupper() else 0], 0.0)
        np.testing.assert_allclose(
            Rotation.from_euler(seq, result.angles).as_matrix(), R, atol=5e-15
        )


@pytest.mark.parametrize("seq", ["xyz", "ZYX", "ZYZ", "xzx"])
def test_never_minus_pi(seq: str) -> None:
    # entries of -0.0 make atan2 return -π; (-π, π] is promised
    half_turns = np.array([[np.pi, 0.3, np.pi], [-np.pi, 0.3, -np.pi], [np.pi, 0.0, 0.0]])
    matrices = Rotation.from_euler(seq, half_turns).as_matrix()
    signed_zeros = np.where(np.abs(matrices) < 1e-15, -0.0, matrices)
    for R in (matrices, signed_zeros, -0.0 + matrices):
        angles = angles_from_matrix(R, seq).angles
        assert np.all(angles[:, [0, 2]] > -np.pi)
