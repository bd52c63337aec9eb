"""aaria_pin: kinematics, dynamics and simulated sensor data of serial manipulators, on Pinocchio.

The front door. A robot (:func:`preset_arm`, :func:`dh_arm`, :func:`urdf_robot_run`), a motion
(:class:`SineTable`, :class:`FourierMotion`, :class:`SampledTrajectory`, :class:`TorqueDrive`),
:class:`RunSettings` and :class:`RunSeeds` go into the one :func:`simulate` (or
:func:`simulate_pieces`), which returns a :class:`RunRecord`; :func:`write_run` and
:func:`open_record` (any run file, or run K of a data set) store and read it. Data sets:
:func:`generate_dataset` of :class:`DatasetSources` ``.spec()`` and a :class:`DatasetJob`. The
spherical wrist: :func:`wrist_fk`, :func:`wrist_ik`; rotations in every Tait-Bryan and Euler
sequence: :func:`matrix_from_angles`, :func:`angles_from_matrix`. Recordings (a ROS 1/ROS 2 bag,
an MCAP file, a CSV): :func:`import_recordings` and :func:`open_recorded` read them (or a run
file) as a :class:`RecordedRun`, :func:`export_run` writes one. Identification:
:func:`identify_kinematics`, :func:`identify_dynamics` (its torques a :class:`TorqueSource`),
:func:`identified_urdf` (the fitted bodies and friction in the run's URDF), and from IMU signals
alone :func:`identify_rigid` (two IMUs on one body) and :func:`identify_joint` (the joint between
two bodies)::

    import aaria_pin as ap

    record = ap.simulate(ap.preset_arm("aaria-fig2"), settings=ap.RunSettings(duration=2.0))
    ap.write_run("run.h5", record)
    again = ap.open_record("run.h5")
    again.imu_signals("imu_tool")        # T × 6: wx wy wz [rad/s], fx fy fz [m/s²]

Every name below is imported on first use (:mod:`aaria_pin.core.lazy_exports`), so ``import
aaria_pin`` (and the ``aaria`` command line) stays fast: Pinocchio, h5py and scipy load only when
a model, a file or a simulation needs them. Type checkers see the real objects through the
``TYPE_CHECKING`` imports. ``simulate_run`` and ``simulate_urdf_run``, the entry points of
earlier releases, still answer here for one release (with a ``DeprecationWarning``; use
:func:`simulate`) but are no longer listed in ``__all__``.

Every public function and input class checks the types of its arguments
(:func:`aaria_pin.core.arguments.checked`): a wrong type raises :class:`ParameterTypeError`, a
:class:`ParameterError` that is also a ``TypeError``, naming the parameter in one line.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

# The Aaria layer registers the arm of 0.1.0's DH files with the files layer's readers.
import aaria_pin.aaria.legacy_v0_1  # noqa: F401
from aaria_pin._version import __version__
from aaria_pin.core.lazy_exports import lazy_exports
from aaria_pin.errors import (
    AariaError,
    InputFileError,
    MeshWarning,
    ModelError,
    OutputFileError,
    ParameterError,
    ParameterTypeError,
    TableError,
    TableTypeError,
    UrdfError,
)

if TYPE_CHECKING:
    from aaria_pin.aaria.arm_run import DHArmSpec, dh_arm, preset_arm
    from aaria_pin.aaria.dh import KinematicChain, chain_from_table
    from aaria_pin.aaria.dh_robot import BodyDimensions, DHRobot, build_dh_robot
    from aaria_pin.aaria.presets import Preset, get_preset
    from aaria_pin.aaria.simulate import dh_fourier_excitation, dh_request
    from aaria_pin.apps.dataset import (
        DatasetJob,
        DatasetReport,
        DatasetSources,
        DatasetSpec,
        generate_dataset,
    )
    from aaria_pin.apps.identify import identify_dynamics, identify_kinematics
    from aaria_pin.apps.identify.inertial_torques import TorqueSource
    from aaria_pin.apps.identify.inertial_urdf import identified_urdf
    from aaria_pin.apps.identify.rigid import identify_rigid
    from aaria_pin.apps.identify.rigid_joint import identify_joint
    from aaria_pin.apps.record_model import record_mjcf, replay_in_mujoco
    from aaria_pin.apps.recordings import export_run, import_recordings, open_recorded
    from aaria_pin.apps.wrist import WristSolutions, wrist_fk, wrist_ik
    from aaria_pin.core.catalogue import find_robot
    from aaria_pin.core.excitation import fourier_motion
    from aaria_pin.core.model import RobotModel, build_model
    from aaria_pin.core.record import ColumnView, ImuMount, RunRecord
    from aaria_pin.core.recording import RecordedRun
    from aaria_pin.core.rotations import Angles, angles_from_matrix, matrix_from_angles
    from aaria_pin.core.run import (
        FourierMotion,
        RunRequest,
        RunSettings,
        SampledTrajectory,
        SineTable,
        TorqueDrive,
        simulate,
        simulate_pieces,
    )
    from aaria_pin.core.run.urdf_kind import UrdfRunSpec, urdf_robot_run
    from aaria_pin.core.sampled_motion import trajectory_from_samples
    from aaria_pin.core.seeds import RunSeeds
    from aaria_pin.core.urdf import RobotDescription
    from aaria_pin.core.urdf_emitter import emit_urdf
    from aaria_pin.core.urdf_robot import UrdfRobot, load_urdf_robot
    from aaria_pin.core.urdf_run import urdf_fourier_excitation, urdf_request
    from aaria_pin.files.dataset.reader import DatasetReader
    from aaria_pin.files.dataset.windows import WindowDataset
    from aaria_pin.files.io import read_table
    from aaria_pin.files.runfile import read_run, read_run_inputs, write_run
    from aaria_pin.files.source import open_record

_LAZY = {
    # robots
    "KinematicChain": "aaria_pin.aaria.dh",
    "chain_from_table": "aaria_pin.aaria.dh",
    "BodyDimensions": "aaria_pin.aaria.dh_robot",
    "DHRobot": "aaria_pin.aaria.dh_robot",
    "build_dh_robot": "aaria_pin.aaria.dh_robot",
    "Preset": "aaria_pin.aaria.presets",
    "get_preset": "aaria_pin.aaria.presets",
    "find_robot": "aaria_pin.core.catalogue",
    "UrdfRobot": "aaria_pin.core.urdf_robot",
    "load_urdf_robot": "aaria_pin.core.urdf_robot",
    "RobotModel": "aaria_pin.core.model",
    "build_model": "aaria_pin.core.model",
    "RobotDescription": "aaria_pin.core.urdf",
    "emit_urdf": "aaria_pin.core.urdf_emitter",
    # runs
    "simulate": "aaria_pin.core.run",
    "simulate_pieces": "aaria_pin.core.run",
    "RunRequest": "aaria_pin.core.run",
    "dh_request": "aaria_pin.aaria.simulate",
    "urdf_request": "aaria_pin.core.urdf_run",
    "RunSettings": "aaria_pin.core.run",
    "RunSeeds": "aaria_pin.core.seeds",
    "dh_arm": "aaria_pin.aaria.arm_run",
    "DHArmSpec": "aaria_pin.aaria.arm_run",
    "preset_arm": "aaria_pin.aaria.arm_run",
    "urdf_robot_run": "aaria_pin.core.run.urdf_kind",
    "UrdfRunSpec": "aaria_pin.core.run.urdf_kind",
    # motions
    "SineTable": "aaria_pin.core.run",
    "FourierMotion": "aaria_pin.core.run",
    "SampledTrajectory": "aaria_pin.core.run",
    "TorqueDrive": "aaria_pin.core.run",
    "dh_fourier_excitation": "aaria_pin.aaria.simulate",
    "urdf_fourier_excitation": "aaria_pin.core.urdf_run",
    "trajectory_from_samples": "aaria_pin.core.sampled_motion",
    "simulate_run": "aaria_pin.aaria.simulate",
    "simulate_urdf_run": "aaria_pin.core.urdf_run",
    "RunRecord": "aaria_pin.core.record",
    "ImuMount": "aaria_pin.core.record",
    "ColumnView": "aaria_pin.core.record",
    # files
    "read_run": "aaria_pin.files.runfile",
    "write_run": "aaria_pin.files.runfile",
    "DatasetReader": "aaria_pin.files.dataset.reader",
    "read_table": "aaria_pin.files.io",
    "read_run_inputs": "aaria_pin.files.runfile",
    "open_record": "aaria_pin.files.source",
    "WindowDataset": "aaria_pin.files.dataset.windows",
    "fourier_motion": "aaria_pin.core.excitation",
    "record_mjcf": "aaria_pin.apps.record_model",
    "replay_in_mujoco": "aaria_pin.apps.record_model",
    "identify_kinematics": "aaria_pin.apps.identify",
    "identify_dynamics": "aaria_pin.apps.identify",
    "identify_rigid": "aaria_pin.apps.identify.rigid",
    "identify_joint": "aaria_pin.apps.identify.rigid_joint",
    "identified_urdf": "aaria_pin.apps.identify.inertial_urdf",
    "TorqueSource": "aaria_pin.apps.identify.inertial_torques",
    # recordings
    "RecordedRun": "aaria_pin.core.recording",
    "open_recorded": "aaria_pin.apps.recordings",
    "import_recordings": "aaria_pin.apps.recordings",
    "export_run": "aaria_pin.apps.recordings",
    # data sets
    "generate_dataset": "aaria_pin.apps.dataset",
    "DatasetSources": "aaria_pin.apps.dataset",
    "DatasetSpec": "aaria_pin.apps.dataset",
    "DatasetJob": "aaria_pin.apps.dataset",
    "DatasetReport": "aaria_pin.apps.dataset",
    # the wrist and rotations
    "wrist_fk": "aaria_pin.apps.wrist",
    "wrist_ik": "aaria_pin.apps.wrist",
    "WristSolutions": "aaria_pin.apps.wrist",
    "matrix_from_angles": "aaria_pin.core.rotations",
    "angles_from_matrix": "aaria_pin.core.rotations",
    "Angles": "aaria_pin.core.rotations",
}

__all__ = [
    "AariaError",
    "Angles",
    "BodyDimensions",
    "ColumnView",
    "DHArmSpec",
    "DHRobot",
    "DatasetJob",
    "DatasetReader",
    "DatasetReport",
    "DatasetSources",
    "DatasetSpec",
    "FourierMotion",
    "ImuMount",
    "InputFileError",
    "KinematicChain",
    "MeshWarning",
    "ModelError",
    "OutputFileError",
    "ParameterError",
    "ParameterTypeError",
    "Preset",
    "RecordedRun",
    "RobotDescription",
    "RobotModel",
    "RunRecord",
    "RunRequest",
    "RunSeeds",
    "RunSettings",
    "SampledTrajectory",
    "SineTable",
    "TableError",
    "TableTypeError",
    "TorqueDrive",
    "TorqueSource",
    "UrdfError",
    "UrdfRobot",
    "UrdfRunSpec",
    "WindowDataset",
    "WristSolutions",
    "__version__",
    "angles_from_matrix",
    "build_dh_robot",
    "build_model",
    "chain_from_table",
    "dh_arm",
    "dh_fourier_excitation",
    "dh_request",
    "emit_urdf",
    "export_run",
    "find_robot",
    "fourier_motion",
    "generate_dataset",
    "get_preset",
    "identified_urdf",
    "identify_dynamics",
    "identify_joint",
    "identify_kinematics",
    "identify_rigid",
    "import_recordings",
    "load_urdf_robot",
    "matrix_from_angles",
    "open_record",
    "open_recorded",
    "preset_arm",
    "read_run",
    "read_run_inputs",
    "read_table",
    "record_mjcf",
    "replay_in_mujoco",
    "simulate",
    "simulate_pieces",
    "trajectory_from_samples",
    "urdf_fourier_excitation",
    "urdf_request",
    "urdf_robot_run",
    "wrist_fk",
    "wrist_ik",
    "write_run",
]

__getattr__ = lazy_exports(__name__, _LAZY)


def __dir__() -> list[str]:
    return __all__
