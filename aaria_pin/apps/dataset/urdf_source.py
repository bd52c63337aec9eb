"""Data sets of a URDF robot: one robot, random joint and base motions, the generic run layout.

A data set of a URDF robot keeps the robot fixed (its structure cannot vary) and draws each
run's joint oscillation table (:func:`~aaria_pin.aaria.randomize.random_urdf_joint_table`) and base
table from the same streams as an Aaria data set. Its file holds, per run, the arrays of a
generic run file with a leading run axis: ``signals`` (N × T × C, attribute ``columns``),
``joint_table`` (N × n × 5), ``base_table`` (N × 6 × 4; zeros on a fixed base), ``q``, ``qd``,
``qdd``, ``tau`` (N × T × n), ``base_wrench`` (N × T × 6), ``tool_pose`` (N × T × 4 × 4) and
``imu_mount`` (N × S × 4 × 4); the URDF text is the string dataset ``urdf``, and the file
attributes add ``robot`` (source, name, base and tool frames, moving base, joint names, IMU
names, parents and poses, the URDF's SHA-256).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from aaria_pin.core.record import ImuMount, signal_columns
from aaria_pin.core.se3 import Array
from aaria_pin.files.dataset_file import RunLayout

if TYPE_CHECKING:
    from aaria_pin.apps.dataset.engine import DatasetSpec
    from aaria_pin.core.urdf_robot import UrdfRobot

__all__ = ["URDF_INPUTS", "UrdfSource", "urdf_layout", "urdf_run_arrays", "urdf_run_inputs"]

URDF_INPUTS = ("joint_table", "base_table", "imu_mount")
"""The run inputs of a URDF robot's data set, stored as float64."""


_LOADED: dict[tuple[Any, ...], UrdfRobot] = {}
"""The robot last loaded in this process, by its source's settings."""


@dataclass(frozen=True, eq=False)
class UrdfSource:
    """The robot of a data set: its URDF and how it is simulated.

    Attributes:
        urdf: the URDF text
        source: where it came from (a robot name or a file), for the record
        urdf_dir: its folder, for relative mesh paths (None: text only)
        moving_base: carry the root link on the base motion
        tool_frame: the tool frame (None: the default choice)
        imu_layout: the IMUs (None: the default layout)
    """

    urdf: str
    source: str = ""
    urdf_dir: str | None = None
    moving_base: bool = True
    tool_frame: str | None = None
    imu_layout: tuple[ImuMount, ...] | None = None

    def _key(self) -> tuple[Any, ...]:
        layout = None
        if self.imu_layout is not None:
            layout = tuple((m.name, m.parent, m.T_parent_imu.tobytes()) for m in self.imu_layout)
        return (self.urdf, self.urdf_dir, self.moving_base, self.tool_frame, layout)

    def load(self) -> UrdfRobot:
        """The checked robot, with its IMU frames (kept per process: runs share it)."""
        import warnings
        from pathlib import Path

        from aaria_pin.core.urdf_robot import load_urdf_robot

        key = self._key()
        if key not in _LOADED:
            with warnings.catch_warnings():  # missing meshes were reported when the job started
                warnings.simplefilter("ignore")
                loaded = load_urdf_robot(
                    self.urdf,
                    urdf_dir=None if self.urdf_dir is None else Path(self.urdf_dir),
                    moving_base=True,  # held at rest for a fixed base (see urdf_run)
                    tool_frame=self.tool_frame,
                    imu_layout=self.imu_layout,
                )
            _LOADED.clear()  # one robot per data set: keep the last only
            _LOADED[key] = loaded
        return _LOADED[key]

    def attributes(self) -> dict[str, Any]:
        """What a data set file records of the robot (compared on resume)."""
        loaded = self.load()
        return {
            "source": self.source,
            "name": loaded.summary.name,
            "urdf_sha256": hashlib.sha256(self.urdf.encode("utf-8")).hexdigest(),
            "moving_base": self.moving_base,
            "base_frame": loaded.robot.base_frame,
            "tool_frame": loaded.robot.tool_frame,
            "joint_names": list(loaded.robot.joint_names),
            "imu_names": [mount.name for mount in loaded.imu_mounts],
            "imu_parents": [mount.parent for mount in loaded.imu_mounts],
            "imu_poses": [mount.T_parent_imu.tolist() for mount in loaded.imu_mounts],
        }


def urdf_layout(source: UrdfSource) -> RunLayout:
    """The run layout of a URDF robot's data set (see the module docstring)."""
    loaded = source.load()
    n, imus = loaded.robot.n_joints, len(loaded.imu_mounts)
    columns = signal_columns(loaded.robot.joint_names, [m.name for m in loaded.imu_mounts])
    shapes: dict[str, tuple[int, ...]] = {
        "signals": (-1, len(columns)),
        "joint_table": (n, 5),
        "base_table": (6, 4),
        "q": (-1, n),
        "qd": (-1, n),
        "qdd": (-1, n),
        "tau": (-1, n),
        "base_wrench": (-1, 6),
        "tool_pose": (-1, 4, 4),
        "imu_mount": (imus, 4, 4),
    }
    return RunLayout(shapes, URDF_INPUTS, columns, {"urdf": source.urdf})


def urdf_run_inputs(
    spec: DatasetSpec, run: int, loaded: UrdfRobot
) -> tuple[Array, Array, np.random.SeedSequence]:
    """Joint table, base table (6 × 4) and noise seed of run ``run`` of a URDF data set."""
    from aaria_pin.aaria.randomize import random_urdf_joint_table, run_streams
    from aaria_pin.apps.dataset.engine import base_and_noise_inputs
    from aaria_pin.core.urdf_robot import default_urdf_joint_table

    _, joints, base, _ = run_streams(spec.seed, run)
    if "joints" in spec.vary:
        joint_table = random_urdf_joint_table(spec.config, loaded.joints, joints)
    elif spec.joint_table is not None:
        joint_table = np.asarray(spec.joint_table, dtype=float)
    else:
        joint_table = default_urdf_joint_table(loaded)
    base_table, noise_seed = base_and_noise_inputs(spec, run, base)
    return joint_table, base_table, noise_seed


def urdf_run_arrays(spec: DatasetSpec, run: int) -> dict[str, Array]:
    """The arrays of run ``run`` of a URDF robot's data set, a pure function of spec and run."""
    from aaria_pin.core.urdf_run import simulate_loaded_robot

    source = spec.urdf
    assert source is not None
    loaded = source.load()
    joint_table, base_table, noise_seed = urdf_run_inputs(spec, run, loaded)
    record = simulate_loaded_robot(
        loaded,
        joint_table,
        base_table,
        moving_base=source.moving_base,
        duration=spec.duration,
        rate=spec.rate,
        seed=noise_seed,
        noise=spec.noise,
    )
    arrays = {
        "signals": record.signals,
        "joint_table": joint_table,
        "base_table": base_table if source.moving_base else np.zeros((6, 4)),
        "q": record.q,
        "qd": record.qd,
        "qdd": record.qdd,
        "tau": record.tau,
        "base_wrench": record.base_wrench,
        "tool_pose": record.tool_pose,
        "imu_mount": np.array([m.T_parent_imu for m in record.imu_mounts]).reshape(-1, 4, 4),
    }
    return {
        name: np.asarray(value, dtype=float if name in URDF_INPUTS else spec.dtype)
        for name, value in arrays.items()
    }
