"""Run k of a data set from its inputs: the one place the data sets call the run engine.

:meth:`~.spec.DatasetSpec.make_run` draws run k's inputs (:meth:`~.spec.DatasetSpec.inputs`)
and hands them to :func:`simulate_inputs`, which runs the engine
(:func:`~aaria_pin.core.run.simulate`) on the spec's robot of those inputs (its kind's adapter,
:meth:`~.spec.DatasetSpec.run_robot`: :func:`~aaria_pin.aaria.arm_run.dh_arm` for an Aaria DH
arm, :func:`~aaria_pin.core.run.urdf_kind.urdf_robot_run` for a URDF robot), its motion
(:meth:`~.spec.DatasetSpec.run_motion`), its settings (:meth:`~.spec.DatasetSpec.run_settings`:
its hardware drawn from the config's ranges),
the run's noise stream and the spec's extra sensors; the record then gets the robot's standard
inertial parameters as its table ``inertial_parameters`` (:mod:`.inertial_table`).

The specs are typed ``Any`` here: this module imports no other module of the data sets (the spec
calls it), so it adds no import cycle.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from aaria_pin.core.record import RunRecord

__all__ = ["simulate_inputs"]


def simulate_inputs(spec: Any, inputs: Any, settings: Any) -> RunRecord:
    """The run made from its inputs by the run engine.

    Args:
        spec: the data set (a :class:`~.spec.DatasetSpec`: its motion settings, its robot)
        inputs: the run's input tables and noise seed (a :class:`~.spec.RunInputs`)
        settings: the run's settings (:meth:`~.spec.DatasetSpec.run_settings`: sampling,
            noise, its hardware)

    Returns:
        The run as a record (every series in float64), with its table ``inertial_parameters``.
    """
    from dataclasses import replace

    from aaria_pin.apps.dataset.inertial_table import INERTIAL_TABLE, inertial_table
    from aaria_pin.core.run import simulate

    robot, motion = spec.run_robot(inputs), spec.run_motion(inputs)
    record = simulate(robot, motion, settings, inputs.noise_seed, spec.sensors)
    return replace(record, tables={**record.tables, INERTIAL_TABLE: inertial_table(robot)})
