"""What a benchmark task is: a fixed data-set spec, fields in and out, a metric over test runs.

A task is any object with the attributes and the ``score`` method of :class:`BenchTask`; the
three of the toolkit are in :mod:`.structure`, :mod:`.inverse_dynamics` and
:mod:`.sensor_to_state`, listed by :data:`~.registry.TASKS`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import asdict, dataclass, replace
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from aaria_pin.core.joint_sensors import EncoderModel

if TYPE_CHECKING:
    from aaria_pin.apps.dataset.spec import DatasetSpec
    from aaria_pin.files.dataset.reader import DatasetReader

__all__ = ["FRACTIONS", "SPLIT_SEED", "BenchTask", "TaskSpec"]

FRACTIONS = (0.6, 0.2, 0.2)
"""The share of a task's runs in its training, validation and test splits (by run)."""

SPLIT_SEED = 0
"""The seed of every task's split (:func:`~aaria_pin.files.dataset.windows.split_runs`)."""


@dataclass(frozen=True)
class TaskSpec:
    """A task's data set: random Aaria DH arms (structure, joints, base), sine motion.

    Attributes:
        n_runs: runs (arms) N
        seed: the data set's seed
        duration: run length [s]
        rate: sample rate [Hz]
        noise: IMU noise (ADIS16485)
        dtype: the stored series' number type
        encoder: the joint encoders of every run (the data set's ``q_measured``; None: no
            encoder, the runs record the true ``q`` only)
    """

    n_runs: int
    seed: int
    duration: float
    rate: float
    noise: bool = True
    dtype: str = "float32"
    encoder: EncoderModel | None = None

    def to_json(self) -> dict[str, Any]:
        """The spec as a JSON-ready dict (``encoder``, a dict of its fields, only when set)."""
        return {key: value for key, value in asdict(self).items() if value is not None}

    def dataset_spec(self) -> DatasetSpec:
        """The checked spec of the task's data set.

        ``aaria dataset -n N --seed S --duration D --rate R [--no-noise] --dtype T`` makes the
        same data set, with ``--config FILE`` whose ``[encoder]`` table holds the encoder's
        fields when the spec has one.

        Raises:
            ParameterError: a setting the data set refuses.
        """
        from aaria_pin.aaria.hardware import HardwareConfig
        from aaria_pin.apps.dataset.spec_sources import DatasetSources

        settings = {key: value for key, value in self.to_json().items() if key != "encoder"}
        spec = DatasetSources(**settings).spec()
        if self.encoder is None:
            return spec
        hardware = HardwareConfig.from_mapping(
            {"encoder": asdict(self.encoder)},
            "the task's spec",
            "config",
            imu_model=spec.hardware.imu_model,
        )
        return replace(spec, hardware=hardware)

    def shrunk(self, n_runs: int | None = None, duration: float | None = None) -> TaskSpec:
        """The same spec with fewer runs or a shorter duration (for tests and smoke runs)."""
        return replace(
            self,
            n_runs=self.n_runs if n_runs is None else n_runs,
            duration=self.duration if duration is None else duration,
        )


class BenchTask(Protocol):
    """A benchmark task: its read-only attributes below, and its scorer."""

    @property
    def name(self) -> str:
        """Its name on the command line (``structure``)."""
        ...

    @property
    def summary(self) -> str:
        """One line."""
        ...

    @property
    def spec(self) -> TaskSpec:
        """Its fixed data set."""
        ...

    @property
    def inputs(self) -> tuple[str, ...]:
        """The fields a model reads (stored arrays, views or labels of the data set)."""
        ...

    @property
    def target(self) -> str:
        """The stored per-run array it predicts (a prediction has its shape)."""
        ...

    @property
    def metric(self) -> str:
        """The metric, in words."""
        ...

    def score(self, reader: DatasetReader, predictions: Mapping[int, np.ndarray]) -> dict[str, Any]:
        """The metric of predictions of some runs (run index → the target's array).

        Args:
            reader: the task's open data set
            predictions: one checked, finite array of the target's shape per test run
        """
        ...
