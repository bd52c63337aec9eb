"""simulate_inputs: run k of a data set from its inputs, by the run engine."""

from __future__ import annotations

import warnings

import numpy as np

from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
from aaria_pin.apps.dataset.runs import simulate_inputs


def test_a_dh_run_is_simulate_run_of_its_drawn_tables() -> None:
    spec = DhDatasetSpec(n_runs=3, seed=4, duration=0.2)
    inputs = spec.inputs(2)
    record = simulate_inputs(spec, inputs, spec.run_settings(2))
    with warnings.catch_warnings():  # the single-run producer, perhaps deprecated
        warnings.simplefilter("ignore", DeprecationWarning)
        written_out = simulate_run(  # its arguments given by hand
            inputs.tables["senSenDH"],
            inputs.tables["senSenJ"],
            inputs.tables["senSenB"],
            duration=0.2,
            rate=spec.rate,
            seed=np.random.SeedSequence(4, spawn_key=(2, 3)),
        )
    for name in ("q", "qd", "qdd", "tau", "imu", "base_wrench", "tool_pose"):
        np.testing.assert_array_equal(getattr(record, name), getattr(written_out, name), name)


def test_a_urdf_run_is_simulate_urdf_run_of_its_drawn_tables() -> None:
    from aaria_pin.apps.dataset.urdf_spec import UrdfDatasetSpec, UrdfSource
    from aaria_pin.core.catalogue import find_robot
    from aaria_pin.core.urdf_robot import read_urdf_file
    from aaria_pin.core.urdf_run import simulate_urdf_run

    urdf = read_urdf_file(find_robot("ur5").urdf)
    spec = UrdfDatasetSpec(
        n_runs=2, seed=3, duration=0.2, vary=("joints", "base"), robot=UrdfSource(urdf, "ur5")
    )
    inputs = spec.inputs(1)
    record = simulate_inputs(spec, inputs, spec.run_settings(1))
    with warnings.catch_warnings():  # the single-run producer, perhaps deprecated
        warnings.simplefilter("ignore", DeprecationWarning)
        written_out = simulate_urdf_run(
            urdf,
            inputs.tables["joint_table"],
            inputs.tables["base_table"],
            duration=0.2,
            rate=spec.rate,
            seed=np.random.SeedSequence(3, spawn_key=(1, 3)),
            source="ur5",
        )
    for name in ("q", "qd", "qdd", "tau", "imu", "base_wrench", "tool_pose"):
        np.testing.assert_array_equal(getattr(record, name), getattr(written_out, name), name)
