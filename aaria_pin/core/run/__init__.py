"""The run engine: any robot kind, any motion, one set of settings → one run record.

- :mod:`~aaria_pin.core.run.settings`: :class:`RunSettings` and the attributes every run records
- :mod:`~aaria_pin.core.run.robot`: the :class:`RunRobot` adapter protocol and the registry of
  run kinds (:func:`register_kind`, :func:`kind_of`)
- :mod:`~aaria_pin.core.run_metadata`: :class:`RunMetadata`, a record's attributes as fields
- :mod:`~aaria_pin.core.run.motion`: the motions (sine table, Fourier, sampled trajectory)
  and how each stores and loads itself
- :mod:`~aaria_pin.core.run.drives`: how the joints are driven (followed, the torque drive) and
  the drive a record stores
- :mod:`~aaria_pin.core.run.closed_loop`: the closed-loop drives (a controller tracks a motion)
- :mod:`~aaria_pin.core.run.sensor`: the sensors (the IMU; any other registered one)
- :mod:`~aaria_pin.core.run.measured`: the joint channels (encoders, torque sensors, actuators)
- :mod:`~aaria_pin.core.run.series`: the series every run computes (IMUs, tool, torques, wrench)
- :mod:`~aaria_pin.core.run.chunks`: a long run in time pieces
- :mod:`~aaria_pin.core.run.engine`: :func:`simulate` and :func:`simulate_pieces`
- :mod:`~aaria_pin.core.run.deprecation`: the producers of earlier releases, over the requests
"""

from aaria_pin.core.run.chunks import CHUNK_SAMPLES, chunk_bounds, join_chunks, run_length
from aaria_pin.core.run.closed_loop import ClosedLoopDrive
from aaria_pin.core.run.deprecation import deprecated_producer, warn_deprecated
from aaria_pin.core.run.drives import TorqueDrive, driven, motion_from_record, recorded_dynamics
from aaria_pin.core.run.engine import (
    RunRequest,
    RunTables,
    Seeds,
    check_options,
    simulate,
    simulate_pieces,
)
from aaria_pin.core.run.motion import (
    FollowedMotion,
    FourierMotion,
    Motion,
    SampledTrajectory,
    SineTable,
    as_motion,
)
from aaria_pin.core.run.robot import FixedMount, RunKind, RunRobot, kind_of, register_kind
from aaria_pin.core.run.sensor import (
    IMU,
    ImuSensor,
    Sensor,
    SensorState,
    register_sensor,
    sensor,
)
from aaria_pin.core.run.series import (
    ImuSlots,
    Payload,
    RunSeries,
    carry_payload,
    noise_stream,
    simulate_series,
)
from aaria_pin.core.run.settings import (
    DEFAULT_DURATION,
    DEFAULT_RATE,
    UNITS,
    RunSettings,
    sampling_attributes,
)
from aaria_pin.core.run_metadata import RunMetadata, stored_sampling

__all__ = [
    "CHUNK_SAMPLES",
    "DEFAULT_DURATION",
    "DEFAULT_RATE",
    "IMU",
    "UNITS",
    "ClosedLoopDrive",
    "FixedMount",
    "FollowedMotion",
    "FourierMotion",
    "ImuSensor",
    "ImuSlots",
    "Motion",
    "Payload",
    "RunKind",
    "RunMetadata",
    "RunRequest",
    "RunRobot",
    "RunSeries",
    "RunSettings",
    "RunTables",
    "SampledTrajectory",
    "Seeds",
    "Sensor",
    "SensorState",
    "SineTable",
    "TorqueDrive",
    "as_motion",
    "carry_payload",
    "check_options",
    "chunk_bounds",
    "deprecated_producer",
    "driven",
    "join_chunks",
    "kind_of",
    "motion_from_record",
    "noise_stream",
    "recorded_dynamics",
    "register_kind",
    "register_sensor",
    "run_length",
    "sampling_attributes",
    "sensor",
    "simulate",
    "simulate_pieces",
    "simulate_series",
    "stored_sampling",
    "warn_deprecated",
]
