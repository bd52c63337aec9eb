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
from typing import TYPE_CHECKING, Any

import numpy as np

from aaria_pin.aaria.hardware import HARDWARE_VALUES, Hardware, HardwareConfig, hardware_leaves
from aaria_pin.files.dataset.layout import DatasetLayout

if TYPE_CHECKING:
    from aaria_pin.core.record import RunRecord
    from aaria_pin.core.run import RunSettings

__all__ = ["HardwareSpec"]


class HardwareSpec:
    """The hardware of a data set's runs (a base of :class:`~.spec.DatasetSpec`).

    Attributes:
        hardware: the hardware tables (fixed values and ranges)
        seed: the data set's seed
        duration: run length [s]
        rate: sample rate [Hz]
        noise: add IMU noise
        drive: the runs' drive (a closed-loop one has a controller)
    """

    hardware: HardwareConfig
    n_runs: int
    seed: int
    duration: float
    rate: float
    noise: bool
    drive: str

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
        settings = RunSettings(self.duration, self.rate, None, self.noise, **hardware)
        return settings.for_drive(self.drive)

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

        The tables the engine records of the hardware: the IMU's drawn errors
        (:func:`~aaria_pin.core.imu_errors.imu_error_shapes`) and the joint channels'
        (:func:`~aaria_pin.core.run.measured.joint_table_shapes`), of the runs with every range
        at its middle, its low and its high end (a term whose range holds 0, such as a time
        offset in [-0.01, 0.01], is on in every run but at the middle), then
        ``hardware_values``.

        Raises:
            ParameterError: a joint model's per-joint value that has not one value per joint
                (parameter ``config``), before any run is made.
        """
        from aaria_pin.core.imu_errors import imu_error_shapes
        from aaria_pin.core.run import RunSettings
        from aaria_pin.core.run.measured import check_joint_values, joint_table_shapes

        tables: dict[str, tuple[int, ...]] = {}
        slots = len(self.robot_layout().imu_names)
        for hardware in (self.run_hardware(None), *self.hardware.ends(self.joints)):
            settings = RunSettings(self.duration, self.rate, None, self.noise, **hardware.options())
            settings = settings.for_drive(self.drive)
            check_joint_values(settings, joints, parameter="config")
            if settings.noise:
                tables.update(imu_error_shapes(settings.noise_model, self.samples, slots))
            tables.update(joint_table_shapes(settings, self.samples, joints))
        names = self.hardware_names()
        return {**tables, HARDWARE_VALUES: (len(names),)} if names else tables

    def describe_drawn(self, run: int) -> str:
        """`` hardware: controller/frequency/0=41.2 ...``: run ``run``'s drawn values ('': none)."""
        names = self.hardware_names()
        if not names:
            return ""
        drawn = hardware_leaves(self.run_hardware(run).attributes())
        return " hardware: " + " ".join(f"{k}={drawn[k]:.6g}" for k in names if k in drawn)

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
