"""Data sets of a URDF robot: one robot, random joint and base motions.

A data set of a URDF robot keeps the robot fixed (its structure cannot vary) and draws each
run's joint oscillation table (:func:`~aaria_pin.aaria.randomize.random_urdf_joint_table`) and base
table from the same streams as an Aaria data set; run k is simulated by
:func:`aaria_pin.core.urdf_run.simulate_loaded_robot` (:mod:`.runs`). Its layout: the robot's
actuated joints
in model order, its IMU layout, the tables ``joint_table`` (n × 5) and, on a moving base,
``base_table`` (6 × 4), ``inertial_parameters`` ((n + 1) × 10, :mod:`.inertial_table`), and the
robot's URDF text; with a Fourier excitation
(``motion="fourier"``) also ``fourier_coefficients`` (n × (1 + 2L):
:func:`~aaria_pin.core.urdf_run.urdf_fourier_excitation`, drawn from the run's joint stream;
its ``joint_table`` is then the robot's default, not followed). The file's ``robot_info``
attribute records the robot (source, name, base and tool frames, moving base, joint names,
IMU names, parents and poses, the URDF's SHA-256), compared on resume.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from aaria_pin.apps.dataset.inertial_table import INERTIAL_TABLE, inertial_shape
from aaria_pin.apps.dataset.spec import DatasetSpec, RunInputs
from aaria_pin.core.record import ImuMount
from aaria_pin.errors import ParameterError
from aaria_pin.files.dataset.layout import DatasetLayout

if TYPE_CHECKING:
    from aaria_pin.core.run import RunRobot
    from aaria_pin.core.urdf_robot import UrdfRobot

__all__ = ["UrdfDatasetSpec", "UrdfSource"]


_LOADED: dict[tuple[Any, ...], UrdfRobot] = {}
"""The robot last loaded in this process, by its source's settings."""
_LAYOUTS: dict[tuple[Any, ...], DatasetLayout] = {}
"""The layout of that robot's data set."""


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


@dataclass(frozen=True)
class UrdfDatasetSpec(DatasetSpec):
    """A data set of one URDF robot (settings: :class:`~.spec.DatasetSpec`).

    Its fixed ``joint_table``, if any, has one row per actuated joint, in model order.

    Attributes:
        robot: the robot (required)
    """

    robot: UrdfSource | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.robot is None:
            raise ParameterError(parameter="robot", value=None, allowed="a URDF robot")
        if "structure" in self.vary:
            raise ParameterError(
                parameter="vary",
                value="structure",
                element="a part",
                allowed="joints, base (a URDF robot's structure is fixed)",
            )
        if self.joint_table is not None and "joints" not in self.vary:
            from aaria_pin.core.urdf_robot import validate_urdf_joint_table

            validate_urdf_joint_table(self.joint_table, self.robot.load())
        if not self.robot.moving_base and "base" in self.vary:
            raise ParameterError(
                parameter="vary",
                value="base",
                element="a part",
                allowed="joints (the robot's base is fixed)",
            )

    @property
    def source(self) -> UrdfSource:
        """The robot (checked present)."""
        assert self.robot is not None
        return self.robot

    @property
    def kind(self) -> str:
        """``"urdf"``."""
        return "urdf"

    def robot_name(self) -> str:
        """The robot's name in its URDF."""
        return str(self.source.load().summary.name)

    def robot_attributes(self) -> dict[str, Any]:
        """See :meth:`UrdfSource.attributes`."""
        return self.source.attributes()

    def robot_layout(self) -> DatasetLayout:
        """The robot's joints and IMUs, ``joint_table`` (and ``base_table``), its URDF.

        Kept per process with the loaded robot: every run's encoding asks for it.
        """
        key = (*self.source._key(), "layout", self.motion, self.harmonics)
        if key not in _LAYOUTS:
            _LAYOUTS.clear()
            _LAYOUTS[key] = self._make_layout()
        return _LAYOUTS[key]

    def _make_layout(self) -> DatasetLayout:
        loaded = self.source.load()
        tables = {"joint_table": (loaded.robot.n_joints, 5)}
        if self.source.moving_base:
            tables["base_table"] = (6, 4)
        if self.motion == "fourier":
            harmonics = self.fourier_settings()["harmonics"]
            tables["fourier_coefficients"] = (loaded.robot.n_joints, 1 + 2 * harmonics)
        tables[INERTIAL_TABLE] = inertial_shape(len(loaded.robot.joint_names))
        return DatasetLayout(
            loaded.robot.joint_names,
            tuple(mount.name for mount in loaded.imu_mounts),
            tuple(mount.parent for mount in loaded.imu_mounts),
            tables,
            {},
            loaded.urdf,
        )

    def inputs(self, run: int) -> RunInputs:
        """``joint_table``, ``base_table`` (6 × 4; none on a fixed base) and the noise seed."""
        from aaria_pin.aaria.randomize import random_urdf_joint_table
        from aaria_pin.core.seeds import RunSeeds
        from aaria_pin.core.urdf_robot import default_urdf_joint_table

        loaded = self.source.load()
        fourier = self.motion == "fourier"
        if "joints" in self.vary and not fourier:
            joint_table = random_urdf_joint_table(
                self.config, loaded.joints, RunSeeds(self.seed, run).generator("joints")
            )
        elif self.joint_table is not None:
            joint_table = np.asarray(self.joint_table, dtype=float)
        else:
            joint_table = default_urdf_joint_table(loaded)
        base_table, noise_seed = self.base_and_noise(run)
        tables = {"joint_table": joint_table}
        if self.source.moving_base:
            tables["base_table"] = base_table
        if fourier:
            from aaria_pin.core.urdf_run import urdf_fourier_excitation

            excitation = urdf_fourier_excitation(
                loaded,
                self.duration,
                self.rate,
                seed=self.fourier_seed(run),
                **self.fourier_settings(),
            )
            tables["fourier_coefficients"] = excitation.table()
        return RunInputs(tables, noise_seed)

    def run_robot(self, inputs: RunInputs) -> RunRobot:
        """The robot with the run's ``joint_table`` (and ``base_table``).

        :func:`~aaria_pin.core.run.urdf_kind.urdf_robot_run`.
        """
        from aaria_pin.core.run.urdf_kind import UrdfRunSpec, urdf_robot_run

        run = UrdfRunSpec(
            inputs.tables["joint_table"],
            inputs.tables.get("base_table"),
            self.source.moving_base,
            self.source.source,
        )
        return urdf_robot_run(self.source.load(), run)

    def check_inputs(self, inputs: RunInputs) -> None:
        """The joint table against the robot's joints, and the base table.

        Raises:
            TableError: a table no run can use.
        """
        from aaria_pin.core.urdf_robot import validate_urdf_joint_table

        super().check_inputs(inputs)
        validate_urdf_joint_table(inputs.tables["joint_table"], self.source.load())
