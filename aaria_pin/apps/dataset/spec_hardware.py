"""A data set's hardware per run: its settings, the drawn values, their tables and attributes.

:class:`HardwareSpec` is the part of a :class:`~.spec.DatasetSpec` that turns its
:class:`~aaria_pin.aaria.hardware.HardwareConfig` (the IMU model and the joint models, each
number fixed or a range) into run k's settings: the ranges drawn from the run's ``hardware``
stream, so run k is a pure function of (S, k) and the spec, resumable and the same whatever the
workers. The drawn values are stored per run (the float64 table ``hardware_values``, named by
the file's attribute ``hardware_names``) so a run read back has its own models.
"""

from __future__ import annotations

from dataclasses import replace
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np

from aaria_pin.aaria.hardware import HARDWARE_VALUES, Hardware, HardwareConfig, hardware_leaves
from aaria_pin.files.dataset.layout import DatasetLayout

if TYPE_CHECKING:
    from aaria_pin.core.record import RunRecord
    from aaria_pin.core.run import RunSettings

__all__ = ["PROBED_RUNS", "HardwareSpec"]

PROBED_RUNS = 8
"""Runs tried, in order, for the two-sample run that tells the hardware's tables."""


class HardwareSpec:
    """The hardware of a data set's runs (a base of :class:`~.spec.DatasetSpec`).

    Attributes:
        hardware: the hardware tables (fixed values and ranges)
        seed: the data set's seed
        duration: run length [s]
        rate: sample rate [Hz]
        noise: add IMU noise
    """

    hardware: HardwareConfig
    n_runs: int
    seed: int
    duration: float
    rate: float
    noise: bool

    def robot_layout(self) -> DatasetLayout:
        """The robot's fixed per-run layout (the spec's robot)."""
        raise NotImplementedError

    def inputs(self, run: int) -> Any:
        """The inputs of run ``run`` (the spec's)."""
        raise NotImplementedError

    def run_robot(self, inputs: Any) -> Any:
        """The engine's robot of a run (the spec's)."""
        raise NotImplementedError

    def run_motion(self, inputs: Any) -> Any:
        """The engine's motion of a run (the spec's)."""
        raise NotImplementedError

    @property
    def samples(self) -> int:
        """Samples per run T (the spec's)."""
        raise NotImplementedError

    def run_settings(self, run: int | None = None) -> RunSettings:
        """The engine's settings of run ``run``: sampling, noise (held whole), hardware.

        Its hardware is :meth:`run_hardware` (None: every range at its middle).
        """
        from aaria_pin.core.run import RunSettings

        hardware = self.run_hardware(run).options()
        return RunSettings(self.duration, self.rate, None, self.noise, **hardware)

    def run_hardware(self, run: int | None) -> Hardware:
        """Run ``run``'s hardware (None: every range at its middle, the file's attributes)."""
        joints = self.joints if self.hardware.ranged else 0
        if run is None:
            return self.hardware.nominal(joints)
        return self.hardware.run_hardware(self.seed, run, joints)

    @property
    def joints(self) -> int:
        """n, the joints of every run."""
        return len(self.robot_layout().joint_names)

    def hardware_names(self) -> tuple[str, ...]:
        """The attribute paths of the values each run draws (none without ranges)."""
        return self.hardware.ranged_names(self.joints) if self.hardware.ranged else ()

    def hardware_tables(self, joints: int) -> dict[str, tuple[int, ...]]:
        """The per-run tables of the hardware and of the drawn values, by shape.

        The tables the engine records of the hardware (the joint channels' ``q_measured`` …,
        the IMU's drawn errors ``imu_error_*``) are those of a two-sample run of run 0's inputs
        (:attr:`probed_tables`), a time-axis table (a series) taking the data set's T; where
        no such run can be made, the joint channels' tables of the contract
        (:meth:`~aaria_pin.aaria.hardware.Hardware.tables`).
        """
        if not self.hardware.tables and self.hardware.imu_model is None:
            tables: dict[str, tuple[int, ...]] = {}
        else:
            probed = self.probed_tables
            tables = (
                self.run_hardware(None).tables(self.samples, joints) if probed is None else probed
            )
        names = self.hardware_names()
        return {**tables, HARDWARE_VALUES: (len(names),)} if names else tables

    @cached_property
    def probed_tables(self) -> dict[str, tuple[int, ...]] | None:
        """The hardware's tables in a two-sample run (None: no such run can be made).

        The run is the first of runs 0 to :data:`PROBED_RUNS` - 1 that can be made.
        """
        from aaria_pin.core.run import simulate
        from aaria_pin.core.run.sensor import is_sensor_table
        from aaria_pin.errors import AariaError

        record = None
        for run in range(min(self.n_runs, PROBED_RUNS)):
            try:
                inputs = self.inputs(run)
                settings = replace(self.run_settings(run), duration=1.0 / self.rate)
                robot, motion = self.run_robot(inputs), self.run_motion(inputs)
                record = simulate(robot, motion, settings, inputs.noise_seed)
                break
            except (AariaError, ValueError):
                continue
        if record is None:
            return None
        inputs_tables = set(self.robot_layout().tables)
        return {
            name: (self.samples, *np.shape(table)[1:]) if is_sensor_table(name) else np.shape(table)
            for name, table in record.tables.items()
            if name not in inputs_tables
        }

    def with_drawn_values(self, run: int, record: RunRecord) -> RunRecord:
        """Run ``run``'s record with its drawn values (``hardware_values``) when it has some.

        A value the run's attributes leave out (an IMU term drawn at its off value) is NaN.
        """
        names = self.hardware_names()
        if not names:
            return record
        drawn = hardware_leaves(self.run_hardware(run).attributes())
        values = np.array([drawn.get(name, np.nan) for name in names], dtype=np.float64)
        return replace(record, tables={**record.tables, HARDWARE_VALUES: values})

    def hardware_attributes(self) -> dict[str, Any]:
        """The file's ``hardware`` (the tables as given) and ``hardware_names`` attributes."""
        tables, names = self.hardware.as_dict(), self.hardware_names()
        return {
            **({"hardware": tables} if tables else {}),
            **({"hardware_names": list(names)} if names else {}),
        }
