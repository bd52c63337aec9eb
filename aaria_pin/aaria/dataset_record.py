"""One run of a data set as a :class:`~aaria_pin.aaria.sensen.RunRecord` (for run-level tools)."""

from __future__ import annotations

import numpy as np

from aaria_pin.aaria.sensen import RunRecord
from aaria_pin.files.dataset_reader import DatasetReader

__all__ = ["dataset_run_record"]


def dataset_run_record(path: str, run: int) -> RunRecord:
    """Run ``run`` of a data set, with the data set's attributes, in float64."""
    with DatasetReader(path) as reader:
        arrays = {name: np.asarray(value, dtype=float) for name, value in reader.run(run).items()}
        attributes = reader.attributes
    return RunRecord(**arrays, attributes=attributes)
