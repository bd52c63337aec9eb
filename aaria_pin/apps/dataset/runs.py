"""Run k of a data set from its inputs: the one place the data sets call the run engine.

:meth:`~.spec.DatasetSpec.make_run` draws run k's inputs (:meth:`~.spec.DatasetSpec.inputs`)
and hands them to :func:`simulate_inputs`, which calls the producer of the spec's robot kind:
:func:`~aaria_pin.aaria.simulate.simulate_run` for an Aaria DH arm,
:func:`~aaria_pin.core.urdf_run.simulate_loaded_robot` for a URDF robot. Switching the data sets
to another engine entry point is a change of this module only.

The specs are typed ``Any`` here: this module imports no other module of the data sets (the spec
calls it), so it adds no import cycle.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from aaria_pin.errors import ParameterError

if TYPE_CHECKING:
    from aaria_pin.core.record import RunRecord

__all__ = ["simulate_inputs"]


def simulate_inputs(spec: Any, inputs: Any) -> RunRecord:
    """The run made from its inputs by the producer of the spec's robot kind.

    Args:
        spec: the data set (a :class:`~.spec.DatasetSpec`: its sampling, noise and motion
            settings, its robot)
        inputs: the run's input tables and noise seed (a :class:`~.spec.RunInputs`)

    Returns:
        The run as a record (every series in float64).

    Raises:
        ParameterError: a spec of a robot kind no producer is registered for.
    """
    producer = _PRODUCERS.get(spec.kind)
    if producer is None:
        raise ParameterError(parameter="spec", value=spec.kind, allowed=", ".join(_PRODUCERS))
    return producer(spec, inputs)


def _dh_run(spec: Any, inputs: Any) -> RunRecord:
    """An Aaria DH arm's run: :func:`~aaria_pin.aaria.simulate.simulate_run`."""
    from aaria_pin.aaria.simulate import simulate_run

    return simulate_run(
        inputs.tables["senSenDH"],
        inputs.tables["senSenJ"],
        inputs.tables["senSenB"],
        **_settings(spec, inputs),
        robot_name=spec.robot_name(),
        keep_urdf=False,
    )


def _urdf_run(spec: Any, inputs: Any) -> RunRecord:
    """A URDF robot's run: :func:`~aaria_pin.core.urdf_run.simulate_loaded_robot`."""
    from aaria_pin.core.urdf_run import simulate_loaded_robot

    return simulate_loaded_robot(
        spec.source.load(),
        inputs.tables["joint_table"],
        inputs.tables.get("base_table"),
        moving_base=spec.source.moving_base,
        source=spec.source.source,
        **_settings(spec, inputs),
    )


def _settings(spec: Any, inputs: Any) -> dict[str, Any]:
    """The producers' common keywords: sampling, noise (seed and model), motion."""
    return {
        "duration": spec.duration,
        "rate": spec.rate,
        "seed": inputs.noise_seed,
        "noise": spec.noise,
        "noise_model": spec.noise_model,
        "motion": spec.run_motion(inputs),
    }


_PRODUCERS: dict[str, Callable[[Any, Any], RunRecord]] = {"dh": _dh_run, "urdf": _urdf_run}
"""The producer of each robot kind (:attr:`~.spec.DatasetSpec.kind`)."""
