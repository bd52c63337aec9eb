"""simulate_inputs: run k of a data set from its inputs, by the producer of its robot kind."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest

from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.apps.dataset.dh import DhDatasetSpec
from aaria_pin.apps.dataset.runs import simulate_inputs
from aaria_pin.errors import ParameterError


def test_a_dh_run_is_simulate_run_of_its_drawn_tables() -> None:
    spec = DhDatasetSpec(n_runs=3, seed=4, duration=0.2)
    inputs = spec.inputs(2)
    record = simulate_inputs(spec, inputs)
    written_out = simulate_run(  # the single-run producer, its arguments given by hand
        inputs.tables["senSenDH"],
        inputs.tables["senSenJ"],
        inputs.tables["senSenB"],
        duration=0.2,
        rate=spec.rate,
        seed=np.random.SeedSequence(4, spawn_key=(2, 3)),
    )
    for name in ("q", "qd", "qdd", "tau", "imu", "base_wrench", "tool_pose"):
        np.testing.assert_array_equal(getattr(record, name), getattr(written_out, name), name)


@dataclass(frozen=True)
class _ToySpec(DhDatasetSpec):
    @property
    def kind(self) -> str:
        return "toy"


def test_a_robot_kind_without_a_producer_is_refused() -> None:
    spec = _ToySpec(n_runs=1, vary=("joints",), dh_table=get_preset("aaria-fig2").table)
    with pytest.raises(ParameterError, match="spec is 'toy'; allowed: dh, urdf") as refused:
        simulate_inputs(spec, spec.inputs(0))
    assert refused.value.parameter == "spec"
