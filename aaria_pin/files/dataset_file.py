"""The HDF5 file of a data set (layout: :mod:`aaria_pin.files.dataset`); kept importable here."""

from aaria_pin.files.dataset.layout import (
    DATASET_FORMAT,
    DATASET_FORMAT_VERSION,
    DatasetLayout,
    EncodedRun,
    encode_run,
    run_arrays,
)
from aaria_pin.files.dataset.store import (
    DatasetFile,
    check_dataset_path,
    decode_attributes,
    is_dataset_file,
    read_dataset_attributes,
)

__all__ = [
    "DATASET_FORMAT",
    "DATASET_FORMAT_VERSION",
    "DatasetFile",
    "DatasetLayout",
    "EncodedRun",
    "check_dataset_path",
    "decode_attributes",
    "encode_run",
    "is_dataset_file",
    "read_dataset_attributes",
    "run_arrays",
]
