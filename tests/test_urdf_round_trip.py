"""Round trip: every URDF the tool writes loads in ``--urdf`` and gives its source's arrays.

For each writer of URDF (``aaria urdf`` of each preset and of a random Aaria table, ``aaria arm
urdf``) the URDF is simulated with the motion of a run of the robot it came from (its joint
and base tables, or its trajectory), and the two runs are compared array by array. The
expectation is the source run itself, made by the tool's own robot (the DH arm, the wrist, the
pick-and-place arm), never the URDF run. Bit for bit: ``q``, ``qd``, ``qdd``, ``base_pose`` and
the IMU mounts (the same sines or samples, the URDF's numbers written exactly). Within 1e-12 of
the array's largest value: ``tau``, ``base_wrench``, ``tool_pose`` and ``imu``: the URDF's
joint origins are roll-pitch-yaw angles, which urdfdom turns into rotation matrices by its own
arithmetic, not the DH chain's (differences of a few 1e-16).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from aaria_pin.aaria.dh import chain_from_aaria
from aaria_pin.aaria.randomize import load_config, random_dh_table
from aaria_pin.cli import main
from aaria_pin.core.record import RunRecord
from aaria_pin.files.runfile import read_run

SHORT = ["--duration", "0.2", "--rate", "100", "--no-noise"]
EXACT = ("q", "qd", "qdd", "base_pose")
CLOSE = ("tau", "base_wrench", "tool_pose", "imu")


def _aaria(*argv: object) -> str:
    result = CliRunner().invoke(main, [str(a) for a in argv])
    assert result.exit_code == 0, result.output
    return result.output


def _close(name: str, got: np.ndarray, expected: np.ndarray) -> None:
    assert got.shape == expected.shape, name
    scale = max(float(np.abs(expected).max()), 1e-300)
    assert np.abs(got - expected).max() <= 1e-12 * scale, name


def _dh_source(kind: str, folder: Path) -> list[str]:
    """The ``--preset``/``--dh`` arguments of a DH arm: a preset, or a random Aaria table."""
    if kind != "random":
        return ["--preset", kind]
    table = random_dh_table(load_config(None), np.random.default_rng(28))
    np.save(folder / "random.npy", table)
    return ["--dh", str(folder / "random.npy")]


@pytest.mark.parametrize("kind", ["aaria-fig2", "aaria-fig3", "random"])
def test_dh_arm_urdf_simulates_as_its_table(kind: str, tmp_path: Path) -> None:
    source = _dh_source(kind, tmp_path)
    urdf = tmp_path / "arm.urdf"
    _aaria("urdf", *source, "-o", urdf)
    _aaria("simulate", *source, *SHORT, "-o", tmp_path / "dh.h5")
    dh = read_run(tmp_path / "dh.h5")
    modules = [joint.module - 1 for joint in chain_from_aaria(dh.tables["senSenDH"]).joints]
    np.save(tmp_path / "joints.npy", dh.tables["senSenJ"][modules])
    np.save(tmp_path / "base.npy", dh.tables["senSenB"])
    _aaria(
        "simulate", "--urdf", urdf, "--joints", tmp_path / "joints.npy",
        "--base", tmp_path / "base.npy", *SHORT, "-o", tmp_path / "urdf.h5",
    )  # fmt: skip
    run = read_run(tmp_path / "urdf.h5")
    # The DH run lays out six module columns and 14 IMU slots (zeros for an empty module);
    # the URDF run has the arm's joints and the IMUs that exist.
    assert run.joint_names == tuple(dh.joint_names[m] for m in modules)
    slots = [k for k, mount in enumerate(dh.imu_mounts) if mount.parent]
    assert [(m.name, m.parent) for m in run.imu_mounts] == [
        (dh.imu_mounts[k].name, dh.imu_mounts[k].parent) for k in slots
    ]
    assert run.metadata.tool_frame == dh.metadata.tool_frame == "tool_tip"
    assert np.array_equal(run.time, dh.time)
    assert np.array_equal(run.imu_mount, dh.imu_mount[slots])
    for name in EXACT:
        expected = np.asarray(getattr(dh, name))
        expected = expected[:, modules] if expected.ndim == 2 and name != "base_pose" else expected
        assert np.array_equal(getattr(run, name), expected), name
    _close("tau", run.tau, dh.tau[:, modules])
    _close("base_wrench", run.base_wrench, dh.base_wrench)
    _close("tool_pose", run.tool_pose, dh.tool_pose)
    _close("imu", run.imu, dh.imu[:, slots])
    # The URDF run re-makes itself from its file, and the URDF compiles as MJCF.
    _aaria("simulate", "--from", tmp_path / "urdf.h5", "-o", tmp_path / "again.h5")
    again = read_run(tmp_path / "again.h5")
    for name in (*EXACT, *CLOSE, "imu_mount"):
        assert np.array_equal(getattr(again, name), getattr(run, name)), name
    mjcf = _aaria("mjcf", "--urdf", urdf, "-o", tmp_path / "arm.xml")
    assert f"{len(slots)} IMU sites" in mjcf
    _replays_in_mujoco(run)


def _replays_in_mujoco(run: RunRecord) -> None:
    """MuJoCo's sensors and inverse dynamics on the URDF's MJCF give the URDF run's IMUs, tau."""
    pytest.importorskip("mujoco")
    from aaria_pin.apps.record_model import record_mjcf, replay_in_mujoco

    xml, _ = record_mjcf(run)
    imu, tau = replay_in_mujoco(run, xml)
    assert np.abs(imu - run.imu).max() <= 1e-9 * np.abs(run.imu).max()
    assert np.abs(tau - run.tau).max() <= 1e-9 * np.abs(run.tau).max()


def test_view_and_dataset_take_the_written_urdf(tmp_path: Path) -> None:
    urdf = tmp_path / "fig2.urdf"
    _aaria("urdf", "--preset", "aaria-fig2", "-o", urdf)
    _aaria("simulate", "--urdf", urdf, *SHORT, "-o", tmp_path / "run.h5")
    _aaria("view", tmp_path / "run.h5", "-o", tmp_path / "run.html")
    assert "imu_link6_b" in (tmp_path / "run.html").read_text(encoding="utf-8")
    _aaria(
        "dataset", "--urdf", urdf, "-n", "2", "--duration", "0.2", "--workers", "1",
        "--quiet", "-o", tmp_path / "set.h5",
    )  # fmt: skip
    assert "14 IMUs, tool tool_tip" in _aaria("info", tmp_path / "set.h5")


def _same_motion(run: RunRecord, source: RunRecord, rows: np.ndarray | slice) -> None:
    for name in ("q", "qd", "qdd", "tool_pose"):
        got, expected = np.asarray(getattr(run, name)), np.asarray(getattr(source, name))
        if name == "tool_pose":
            _close(name, got[rows], expected[rows])
        else:
            assert np.array_equal(got, expected), name


def test_wrist_urdf_simulates_as_the_wrist(tmp_path: Path) -> None:
    urdf = tmp_path / "wrist.urdf"
    _aaria("urdf", "--preset", "spherical-wrist", "-o", urdf)
    _aaria(
        "wrist", "simulate", "60", "45", "-30", "--duration", "2.3", "--rate", "20",
        "--speed", "400", "--acceleration", "2000", "-o", tmp_path / "wrist.h5",
    )  # fmt: skip
    _aaria(
        "simulate", "--urdf", urdf, "--fixed-base", "--trajectory", tmp_path / "wrist.h5",
        "--no-noise", "-o", tmp_path / "urdf.h5",
    )  # fmt: skip
    wrist, run = read_run(tmp_path / "wrist.h5"), read_run(tmp_path / "urdf.h5")
    assert np.abs(wrist.q).max() > 0.5  # the wrist moved within the run
    _same_motion(run, wrist, slice(None))
    assert [m.name for m in run.imu_mounts] == [m.name for m in wrist.imu_mounts]
    assert np.array_equal(run.imu_mount, wrist.imu_mount)
    for name in ("tau", "base_wrench", "imu"):
        _close(name, np.asarray(getattr(run, name)), np.asarray(getattr(wrist, name)))


def test_pick_place_arm_urdf_simulates_as_the_arm(tmp_path: Path) -> None:
    _aaria("arm", "urdf", "-o", tmp_path / "arm")
    _aaria(
        "arm", "pick-place", "--cylinder", "0.35", "0.1", "--place", "0.2", "-0.3",
        "--rate", "20", "-o", tmp_path / "pp.h5",
    )  # fmt: skip
    _aaria(
        "simulate", "--urdf", tmp_path / "arm" / "pick_place_arm.urdf", "--tool", "grasp",
        "--fixed-base", "--trajectory", tmp_path / "pp.h5", "--no-noise",
        "-o", tmp_path / "urdf.h5",
    )  # fmt: skip
    task, run = read_run(tmp_path / "pp.h5"), read_run(tmp_path / "urdf.h5")
    # The task's torques carry the cylinder while it is held; the URDF is the bare arm.
    start, end = task.attributes["held_interval"]
    free = (task.time < start) | (task.time > end)
    assert 0 < free.sum() < free.size
    _same_motion(run, task, slice(None))
    for name in ("tau", "base_wrench"):
        _close(name, np.asarray(getattr(run, name))[free], np.asarray(getattr(task, name))[free])
