"""Joint limits of torque-driven runs (``--limits stop|clamp|ignore``): the policies on
hand-made trajectories, and the issue's own example through the command line (aaria-fig2 driven
by the torques of its sine run drifts out of its rails: ``stop`` ends it with exit 1 and writes
nothing; ``ignore`` keeps it; ``clamp`` holds it on its stops, within 1 mm past its rails;
``--from`` keeps the stored policy; old files read as ``ignore``)."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from conftest import run_cli

from aaria_pin.core.joint_limits import (
    JointBounds,
    limit_policy,
    model_velocity_limits,
    stored_limits,
)
from aaria_pin.core.run import TorqueDrive, motion_from_record
from aaria_pin.core.trajectory import JointTrajectory
from aaria_pin.errors import InputFileError, JointLimitError, ParameterError
from aaria_pin.files.runfile import read_run

FIXTURES = Path(__file__).resolve().parent.parent / "fixtures" / "v0_3_0"
TWO_PI = 2 * np.pi
FIG2_LOWER = np.array([-0.07, -TWO_PI, -TWO_PI, -TWO_PI, -0.065, -TWO_PI])
"""aaria-fig2's joint limits: modules 1 and 5 are rails of ±0.07 and ±0.065 m, the rest ±2π."""
FIG2_SPEED = 100.0
"""The velocity limit the DH arm's URDF gives every joint [rad/s or m/s]."""

BOUNDS = JointBounds(("a", "b"), np.array([-1.0, -0.5]), np.array([1.0, 0.5]), np.array([2.0, 9.0]))


def _trajectory(q: list[list[float]], qd: list[list[float]]) -> JointTrajectory:
    q_, qd_ = np.array(q), np.array(qd)
    return JointTrajectory(0.1 * np.arange(len(q), dtype=float), q_, qd_, np.zeros_like(q_))


def test_stop_keeps_a_trajectory_within_its_limits_as_it_is() -> None:
    inside = _trajectory([[1.0, -0.5], [0.0, 0.5 + 1e-13]], [[2.0, -9.0], [0.0, 0.0]])
    assert limit_policy("stop").applied(inside, BOUNDS) is inside


def test_stop_names_the_first_joint_its_time_value_and_limit() -> None:
    out = _trajectory([[0.0, 0.0], [0.2, 0.0], [0.3, 0.6], [1.5, 0.7]], [[0.0] * 2] * 4)
    with pytest.raises(JointLimitError) as caught:
        limit_policy("stop").applied(out, BOUNDS)
    message = str(caught.value)
    assert message.startswith("b position at t = 0.2 s is 0.6; allowed: -0.5 to 0.5")
    assert "\n" not in message and caught.value.parameter == "limits"


def test_stop_reports_a_velocity_beyond_the_model_limit_and_a_value_that_is_not_a_number() -> None:
    fast = _trajectory([[0.0, 0.0], [0.0, 0.0]], [[0.0, 0.0], [-2.5, 0.0]])
    with pytest.raises(JointLimitError, match=r"^a velocity at t = 0.1 s is -2.5; allowed: "):
        limit_policy("stop").applied(fast, BOUNDS)
    lost = _trajectory([[0.0, np.nan]], [[0.0, 0.0]])
    with pytest.raises(JointLimitError, match=r"^b position at t = 0 s is nan"):
        limit_policy("stop").applied(lost, BOUNDS)


def test_ignore_and_clamp_keep_the_trajectory_and_an_unknown_name_is_refused() -> None:
    out = _trajectory([[5.0, np.inf]], [[99.0, 0.0]])
    assert limit_policy("ignore").applied(out, BOUNDS) is out
    assert limit_policy("clamp").applied(out, BOUNDS) is out  # its stops act in the dynamics
    assert limit_policy("ignore").forward_options(BOUNDS) == {}
    assert limit_policy("stop").forward_options(BOUNDS) == {}
    lower, upper = limit_policy("clamp").forward_options(BOUNDS)["stops"]
    np.testing.assert_array_equal(lower, [-1.0, -0.5])
    np.testing.assert_array_equal(upper, [1.0, 0.5])
    with pytest.raises(ParameterError, match="allowed: stop, clamp, ignore") as caught:
        limit_policy("hold")
    assert caught.value.parameter == "limits"


def test_a_record_without_the_attribute_reads_as_ignore() -> None:
    assert stored_limits({}) == "ignore"
    assert stored_limits({"limits": "stop"}) == "stop"
    assert stored_limits({"limits": "clamp"}) == "clamp"
    with pytest.raises(InputFileError, match="limits"):
        stored_limits({"limits": "hold"})
    old = read_run(FIXTURES / "dh_torque.h5")  # written by 0.3.0, before the policy
    drive = motion_from_record(old.tables, old.attributes)
    assert isinstance(drive, TorqueDrive) and drive.limits == "ignore"


def test_model_velocity_limits_are_the_urdf_s_and_inf_where_unset() -> None:
    from aaria_pin.core.catalogue import find_robot
    from aaria_pin.core.urdf_robot import load_urdf_robot, read_urdf_file

    ur5 = load_urdf_robot(read_urdf_file(find_robot("ur5").urdf), moving_base=True).robot
    assert ur5.base_nv == 6  # the free-flyer's entries are left out
    speed = model_velocity_limits(ur5)
    np.testing.assert_array_equal(speed, [3.15, 3.15, 3.15, 3.2, 3.2, 3.2])  # the URDF's
    unset = SimpleNamespace(
        model=SimpleNamespace(velocityLimit=[7.0, 0.0, 1.8e308, 2.0]), base_nv=1
    )
    np.testing.assert_array_equal(model_velocity_limits(unset), [np.inf, np.inf, 2.0])  # type: ignore[arg-type]


@pytest.fixture(scope="module")
def fig2(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """aaria-fig2 sine runs of 2 s (replayed open loop, it drifts out) and 0.2 s (it stays in)."""
    folder = tmp_path_factory.mktemp("limits")
    for name, duration in (("run.h5", "2"), ("short_run.h5", "0.2")):
        code, _, err = run_cli("simulate", "--preset", "aaria-fig2", "--duration", duration,
                               "--no-noise", "-o", str(folder / name))  # fmt: skip
        assert code == 0, err
    return folder


def _drive(folder: Path, output: str, *more: str, run: str = "run.h5") -> tuple[int, str, str]:
    torques = str(folder / run)
    return run_cli("simulate", "--preset", "aaria-fig2", "--drive", "torque",
                   "--torques", torques, *more, "-o", str(folder / output))  # fmt: skip


def test_stop_ends_a_run_that_drifts_out_with_exit_1_and_no_file(fig2: Path) -> None:
    code, _, err = _drive(fig2, "ignored.h5", "--limits", "ignore")
    assert code == 0, err
    ignored = read_run(fig2 / "ignored.h5")
    assert ignored.attributes["limits"] == "ignore"
    q, qd = ignored.q, ignored.qd
    outside = (np.abs(q) > -FIG2_LOWER) | (np.abs(qd) > FIG2_SPEED)
    row = int(np.flatnonzero(outside.any(axis=1))[0])
    joint = int(np.flatnonzero(outside[row])[0])
    assert abs(q[row, joint]) > -FIG2_LOWER[joint]  # drifts out of a rail first
    code, out, err = _drive(fig2, "stopped.h5")  # stop: the default
    assert code == 1 and out == ""
    assert not (fig2 / "stopped.h5").exists()
    assert err.strip() == (
        f"aaria: error: joint{joint + 1} position at t = {ignored.time[row]:.6g} s is "
        f"{q[row, joint]:.6g}; allowed: {FIG2_LOWER[joint]:.6g} to {-FIG2_LOWER[joint]:.6g} "
        "(the model's limits; the run stops there: limits stop)"
    )


def test_a_run_within_its_limits_is_unchanged_and_from_keeps_the_policy(fig2: Path) -> None:
    code, _, err = _drive(fig2, "short.h5", run="short_run.h5")
    assert code == 0, err
    short = read_run(fig2 / "short.h5")
    assert short.attributes["limits"] == "stop" and short.attributes["drive"] == "torque"
    code, _, err = _drive(fig2, "short_ignored.h5", "--limits", "ignore", run="short_run.h5")
    assert code == 0, err
    np.testing.assert_array_equal(read_run(fig2 / "short_ignored.h5").q, short.q)
    code, _, err = run_cli("simulate", "--from", str(fig2 / "ignored.h5"), "-o",
                           str(fig2 / "again.h5"))  # fmt: skip
    assert code == 0, err  # the stored ignore, not the default stop
    again = read_run(fig2 / "again.h5")
    assert again.attributes["limits"] == "ignore"
    np.testing.assert_array_equal(again.q, read_run(fig2 / "ignored.h5").q)
    code, _, err = run_cli("simulate", "--from", str(fig2 / "ignored.h5"), "--limits", "stop",
                           "-o", str(fig2 / "again_stop.h5"))  # fmt: skip
    assert code == 1 and "limits stop" in err and not (fig2 / "again_stop.h5").exists()


def test_clamp_holds_the_drifting_run_within_1_mm_past_its_limits(fig2: Path) -> None:
    code, _, err = _drive(fig2, "clamped.h5", "--limits", "clamp")
    assert code == 0, err
    clamped = read_run(fig2 / "clamped.h5")
    assert clamped.attributes["limits"] == "clamp"
    beyond = np.abs(clamped.q) + FIG2_LOWER  # > 0: past a limit (they are symmetric)
    ignored = read_run(fig2 / "ignored.h5")
    assert (np.abs(ignored.q) + FIG2_LOWER).max() > 0.01  # without stops it leaves by far
    assert 0 < beyond.max() < 1e-3  # on its stops, under 1 mm past them (the documented figure)
    code, _, err = run_cli("simulate", "--from", str(fig2 / "clamped.h5"), "-o",
                           str(fig2 / "clamped_again.h5"))  # fmt: skip
    assert code == 0, err
    np.testing.assert_array_equal(read_run(fig2 / "clamped_again.h5").q, clamped.q)


def test_a_run_within_its_limits_is_the_same_bit_for_bit_under_clamp(fig2: Path) -> None:
    code, _, err = _drive(fig2, "short_clamp.h5", "--limits", "clamp", run="short_run.h5")
    assert code == 0, err
    code, _, err = _drive(fig2, "short_free.h5", "--limits", "ignore", run="short_run.h5")
    assert code == 0, err
    clamped, free = read_run(fig2 / "short_clamp.h5"), read_run(fig2 / "short_free.h5")
    assert (np.abs(free.q) + FIG2_LOWER).max() < 0  # inside its limits throughout
    for name in ("q", "qd", "qdd"):
        np.testing.assert_array_equal(getattr(clamped, name), getattr(free, name))


def test_limits_without_a_torque_drive_are_refused_with_exit_2(fig2: Path) -> None:
    code, _, err = run_cli("simulate", "--preset", "aaria-fig2", "--limits", "ignore",
                           "-o", str(fig2 / "x.h5"))  # fmt: skip
    assert code == 2 and "--limits goes with --drive torque" in err


def test_a_urdf_robot_s_torque_run_records_its_policy_and_is_made_again_under_it() -> None:
    from aaria_pin.core.catalogue import find_robot
    from aaria_pin.core.urdf_robot import read_urdf_file
    from aaria_pin.core.urdf_run import urdf_request, urdf_request_from_record

    urdf = read_urdf_file(find_robot("ur5").urdf)
    settings = {"duration": 0.2, "rate": 100.0, "noise": False, "source": "ur5"}
    tau = np.zeros((21, 6))  # it falls under gravity from the sines' start
    run = urdf_request(urdf, torques=tau, limits="ignore", **settings).record()  # type: ignore[arg-type]
    assert run.attributes["limits"] == "ignore"
    again = urdf_request_from_record(run)
    assert isinstance(again.motion, TorqueDrive) and again.motion.limits == "ignore"
    np.testing.assert_array_equal(again.record().q, run.q)
    assert urdf_request(urdf, torques=tau, **settings).motion.limits == "stop"  # type: ignore[arg-type, union-attr]
