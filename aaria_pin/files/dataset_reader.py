"""Reading a data set (see :mod:`aaria_pin.files.dataset.reader`); kept importable here."""

from aaria_pin.files.dataset.reader import DatasetReader, dataset_summary
from aaria_pin.files.dataset.windows import WindowDataset, split_runs

__all__ = ["DatasetReader", "WindowDataset", "dataset_summary", "split_runs"]
