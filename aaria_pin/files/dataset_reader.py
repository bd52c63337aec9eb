"""Reading a data set (see :mod:`aaria_pin.files.dataset.reader`); kept importable here."""

from aaria_pin.files.dataset.reader import DatasetReader, dataset_summary

__all__ = ["DatasetReader", "dataset_summary"]
