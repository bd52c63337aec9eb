"""The run's built-in joint channels (encoders, torque sensors, actuators): CONTRACT STUB.

:func:`run_sensors` turns a run's settings into the per-run sensor objects the engine measures
with (each drawing its per-run values from its own stream of the run's sensor seed).
"""

from __future__ import annotations

import numpy as np

from aaria_pin.core.run.robot import RunRobot
from aaria_pin.core.run.settings import RunSettings

__all__ = ["run_sensors"]


def run_sensors(
    robot: RunRobot, settings: RunSettings, seed: int | np.random.SeedSequence
) -> tuple[object, ...]:
    """The run's encoder, torque-sensor and actuator channels (none while every model is off)."""
    return ()
