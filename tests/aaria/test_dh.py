from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from conftest import W_T_DH, Rx, Rz, Tx, Tz, paper_tool_pose, wrist_equation_9
from hypothesis import given, settings
from hypothesis import strategies as st

from aaria_pin.aaria.dh import chain_from_table, validate_aaria_table, validate_dh_table
from aaria_pin.aaria.dh_robot import build_dh_robot
from aaria_pin.aaria.presets import get_preset
from aaria_pin.errors import TableError

ANGLES = st.sampled_from([-np.pi / 2, 0.0, np.pi / 2]) | st.floats(-np.pi, np.pi)
LENGTHS = st.sampled_from([0.0, 0.1]) | st.floats(0.0, 1.0)


def _pin_tool_pose(robot_model, q_joints: np.ndarray) -> np.ndarray:
    model = robot_model.model
    data = model.createData()
    pin.framesForwardKinematics(model, data, q_joints)
    return data.oMf[robot_model.frame_id("tool_tip")].homogeneous


def _random_joint_values(chain, rng: np.random.Generator) -> np.ndarray:
    return np.array(
        [
            rng.uniform(j.lower, j.upper) if j.kind == "prismatic" else rng.uniform(-np.pi, np.pi)
            for j in chain.joints
        ]
    )


@pytest.mark.parametrize("name", ["aaria-fig2", "aaria-fig3"])
def test_preset_tool_pose_equals_paper_matrix_product(name: str, rng) -> None:
    table = get_preset(name).table
    robot = build_dh_robot(table)
    model = robot.model()
    for _ in range(20):
        q = _random_joint_values(robot.chain, rng)
        expected = paper_tool_pose(table, q)
        np.testing.assert_allclose(_pin_tool_pose(model, q), expected, atol=1e-12)
        np.testing.assert_allclose(robot.chain.T_base_tool(q), expected, atol=1e-12)


def test_fig3_has_no_joint_for_the_empty_module() -> None:
    robot = build_dh_robot(get_preset("aaria-fig3").table)
    model = robot.model()
    assert model.joint_names == ("joint1", "joint3", "joint4", "joint5", "joint6")
    assert [model.model.joints[i].shortname() for i in range(1, 6)] == [
        "JointModelPZ",
        "JointModelPZ",
        "JointModelPZ",
        "JointModelRZ",
        "JointModelRZ",
    ]
    assert not model.model.existFrame("link2")
    assert not model.model.existFrame("imu_link2_a")


@st.composite
def aaria_tables(draw) -> np.ndarray:
    rows = []
    for _ in range(6):
        rows.append(
            [
                draw(ANGLES),
                draw(LENGTHS),
                draw(ANGLES),
                draw(LENGTHS),
                draw(st.sampled_from([0, 1, 2])),
            ]
        )
    if all(row[4] == 0 for row in rows):
        rows[draw(st.integers(0, 5))][4] = draw(st.sampled_from([1, 2]))
    rows.append([draw(ANGLES), draw(LENGTHS), draw(ANGLES), draw(LENGTHS), 1])
    rows.append([0.0, 0.0, 0.0, 0.0, 1])
    return np.array(rows, dtype=float)


@settings(max_examples=40, deadline=None)
@given(table=aaria_tables(), seed=st.integers(0, 2**32 - 1))
def test_random_tables_tool_pose_equals_paper_matrix_product(table: np.ndarray, seed: int) -> None:
    robot = build_dh_robot(table)
    model = robot.model()
    q = _random_joint_values(robot.chain, np.random.default_rng(seed))
    np.testing.assert_allclose(_pin_tool_pose(model, q), paper_tool_pose(table, q), atol=1e-11)
    assert model.n_joints == int(np.count_nonzero(table[:6, 4]))


def test_post_joint_frame_is_the_frame_after_the_joint(rng) -> None:
    table = get_preset("aaria-fig2").table
    robot = build_dh_robot(table)
    model = robot.model()
    data = model.model.createData()
    q = _random_joint_values(robot.chain, rng)
    pin.framesForwardKinematics(model.model, data, q)
    T = W_T_DH.copy()
    for i, (alpha, a, theta, d, link_type) in enumerate(table[:6]):
        if link_type == 1:
            T = T @ Rx(alpha) @ Tz(d) @ Rz(q[i])
        else:
            T = T @ Rx(alpha) @ Rz(theta) @ Tz(q[i])
        np.testing.assert_allclose(
            data.oMf[model.frame_id(f"link{i + 1}")].homogeneous, T, atol=1e-12
        )
        T = T @ Tx(a)


def test_standard_wrist_table_gives_equation_9(rng) -> None:
    robot = build_dh_robot(get_preset("spherical-wrist").table, "standard")
    model = robot.model()
    for _ in range(20):
        q = rng.uniform(-np.pi, np.pi, 3)
        np.testing.assert_allclose(
            _pin_tool_pose(model, q), wrist_equation_9(*q, d=0.132), atol=1e-12
        )


@settings(max_examples=25, deadline=None)
@given(
    rows=st.lists(
        st.tuples(ANGLES, LENGTHS, ANGLES, LENGTHS, st.sampled_from([1, 2])), min_size=1, max_size=7
    ),
    seed=st.integers(0, 2**32 - 1),
)
def test_standard_and_modified_tables_match_their_products(rows, seed: int) -> None:
    table = np.array(rows, dtype=float)
    q = np.random.default_rng(seed).uniform(-0.5, 0.5, len(rows))
    standard, modified = np.eye(4), np.eye(4)
    for (alpha, a, theta, d, link_type), qi in zip(table, q, strict=True):
        if link_type == 1:
            standard = standard @ Rz(theta + qi) @ Tz(d) @ Tx(a) @ Rx(alpha)
            modified = modified @ Rx(alpha) @ Tx(a) @ Rz(theta + qi) @ Tz(d)
        else:
            standard = standard @ Rz(theta) @ Tz(d + qi) @ Tx(a) @ Rx(alpha)
            modified = modified @ Rx(alpha) @ Tx(a) @ Rz(theta) @ Tz(d + qi)
    for convention, expected in (("standard", standard), ("modified", modified)):
        model = build_dh_robot(table, convention).model()
        np.testing.assert_allclose(_pin_tool_pose(model, q), expected, atol=1e-11)


def _fig2() -> np.ndarray:
    return get_preset("aaria-fig2").table.copy()


@pytest.mark.parametrize(
    ("edit", "pattern"),
    [
        (lambda t: t[:7], r"shape \(7, 5\).*8 × 5"),
        (lambda t: t[:, :4], r"shape \(8, 4\)"),
        (lambda t: (t.__setitem__((2, 1), np.nan), t)[1], r"row 3, column 2 \(a\) is nan"),
        (lambda t: (t.__setitem__((0, 0), np.inf), t)[1], r"row 1, column 1 \(alpha\) is inf"),
        (
            lambda t: (t.__setitem__((3, 4), 3), t)[1],
            r"row 4, column 5 \(link type\) is 3; allowed: 0",
        ),
        (lambda t: (t.__setitem__((1, 4), 1.5), t)[1], r"row 2, column 5 .* is 1.5"),
        (
            lambda t: (t.__setitem__((4, 1), -0.2), t)[1],
            r"row 5, column 2 \(a\) is -0.2 m; allowed",
        ),
        (lambda t: (t.__setitem__((5, 3), -0.1), t)[1], r"row 6, column 4 \(d\) is -0.1 m"),
        (lambda t: (t.__setitem__((6, 1), -1), t)[1], r"row 7, column 2 \(a\)"),
        (lambda t: (t.__setitem__((slice(0, 6), 4), 0), t)[1], r"every module .* is empty"),
    ],
)
def test_bad_aaria_tables_are_refused_naming_row_and_column(edit, pattern: str) -> None:
    with pytest.raises(TableError, match=pattern):
        validate_aaria_table(edit(_fig2()))


def test_empty_rows_are_ignored_even_with_negative_lengths() -> None:
    table = _fig2()
    table[1] = [0.3, -1.0, 0.2, -5.0, 0]
    chain = chain_from_table(table)
    assert chain.modules == (1, 3, 4, 5, 6)


def test_bad_standard_tables() -> None:
    with pytest.raises(TableError, match="link type"):
        validate_dh_table(np.array([[0, 0.1, 0, 0, 0.0]]), "standard")
    with pytest.raises(TableError, match="rows"):
        validate_dh_table(np.zeros((0, 5)), "standard")
    with pytest.raises(TableError, match="convention is 'spong'; allowed"):
        chain_from_table(np.zeros((1, 5)), "spong")  # type: ignore[arg-type]


def test_prismatic_range_is_centred_rail_and_revolute_range() -> None:
    chain = chain_from_table(get_preset("aaria-fig2").table)
    joint1 = chain.joints[0]
    assert joint1.kind == "prismatic"
    assert (joint1.lower, joint1.upper) == pytest.approx((-0.07, 0.07))
    model = build_dh_robot(get_preset("aaria-fig2").table).model().model
    np.testing.assert_allclose(model.lowerPositionLimit[0], -0.07)
    np.testing.assert_allclose(model.upperPositionLimit[0], 0.07)


@settings(max_examples=30, deadline=None)
@given(table=aaria_tables(), seed=st.integers(0, 2**32 - 1), moving_base=st.booleans())
def test_direct_model_equals_the_parsed_urdf(
    table: np.ndarray, seed: int, moving_base: bool
) -> None:
    _assert_same_models(build_dh_robot(table), moving_base, seed)


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_direct_model_equals_the_parsed_urdf_for_dh_tables(convention) -> None:
    table = np.array([[0.3, 0.2, 0.1, 0.05, 1], [-1.2, 0.0, 0.4, 0.3, 2], [0.7, 0.4, -0.5, 0.0, 1]])
    _assert_same_models(build_dh_robot(table, convention), True, 3)


def test_direct_model_equals_the_parsed_urdf_with_custom_mounts() -> None:
    from aaria_pin.aaria.dh_robot import ImuSlot

    table = get_preset("aaria-fig3").table
    slots = tuple(
        ImuSlot(slot.name, slot.parent, Rz(0.3 * k) @ Rx(0.2) @ Tx(0.01 * k))
        for k, slot in enumerate(build_dh_robot(table).imu_slots)
    )
    _assert_same_models(build_dh_robot(table, imu_slots=slots), False, 5)


def _assert_same_models(robot, moving_base: bool, seed: int) -> None:
    from aaria_pin.core.model import build_model

    direct = robot.model(moving_base=moving_base).model
    parsed = build_model(robot.urdf, moving_base=moving_base).model
    assert direct.nq == parsed.nq and list(direct.names) == list(parsed.names)
    for a, b in zip(direct.jointPlacements, parsed.jointPlacements, strict=True):
        np.testing.assert_allclose(a.homogeneous, b.homogeneous, atol=1e-12)
    for a, b in zip(direct.inertias, parsed.inertias, strict=True):
        np.testing.assert_allclose(a.toDynamicParameters(), b.toDynamicParameters(), atol=1e-12)
    np.testing.assert_allclose(direct.lowerPositionLimit, parsed.lowerPositionLimit)
    np.testing.assert_allclose(direct.upperPositionLimit, parsed.upperPositionLimit)
    assert sorted(f.name for f in direct.frames) == sorted(f.name for f in parsed.frames)
    rng = np.random.default_rng(seed)
    q = pin.randomConfiguration(parsed)
    v, a = rng.normal(size=parsed.nv), rng.normal(size=parsed.nv)
    np.testing.assert_allclose(
        pin.rnea(direct, direct.createData(), q, v, a),
        pin.rnea(parsed, parsed.createData(), q, v, a),
        atol=1e-9,
    )
    d_direct, d_parsed = direct.createData(), parsed.createData()
    pin.framesForwardKinematics(direct, d_direct, q)
    pin.framesForwardKinematics(parsed, d_parsed, q)
    for frame in parsed.frames:
        np.testing.assert_allclose(
            d_direct.oMf[direct.getFrameId(frame.name)].homogeneous,
            d_parsed.oMf[parsed.getFrameId(frame.name)].homogeneous,
            atol=1e-12,
        )
