"""Data set files: many runs of one layout in one HDF5 file (``"aaria_pin dataset"``, version 2).

Each number is stored once. Per run, the series of its :class:`~aaria_pin.core.record.RunRecord`
with a leading run axis: ``time`` (N × T), ``q``, ``qd``, ``qdd``, ``tau`` (N × T × n),
``base_pose`` and ``tool_pose`` (N × T × 4 × 4), ``base_wrench`` (N × T × 6), ``imu``
(N × T × S × 6); ``imu_mount`` (N × S × 4 × 4) and the input tables (e.g. ``senSenDH``,
``senSenJ`` N × 8 × 5, ``senSenB`` N × 6 × 4; or ``joint_table``, ``base_table``). The series
take the data set's dtype, the inputs stay float64. ``time`` is stored per run, like every
series: a view column must map onto stored numbers one to one (an HDF5 virtual dataset cannot
repeat a source element), so one shared ``time`` would need a mapping per run in the file's
metadata, and a run's time row costs about 0.4 % of the run once compressed.

Once per file: the string datasets ``joint_names``, ``imu_names``, ``imu_parents`` and
``urdf``, and the column views as HDF5 virtual datasets over the series in the same file (source
file ``"."``, so the file stays valid when renamed or moved; h5py and MATLAB's ``h5read`` read
them, HDF5 1.10 or newer): every data set has ``signals`` (N × T × C: time, joint values, IMU
signals), an Aaria data set also ``senSen`` (N × T × 91). Each view has a ``columns``
attribute; ``layout_json`` records the tables and the views' sources.

Bookkeeping: ``complete`` (N, uint8: 1 once a run is written and flushed), ``failed`` (N, uint8),
``checksum`` (N × arrays, uint32: the CRC-32 of each run's chunks before deflate, so it depends
on the numbers only; checked on resume, where a file of an earlier 0.2 that recorded the CRC-32
of the deflated bytes is still accepted).
Chunks hold one run (see :mod:`.layout`), compressed with gzip level 1 after the shuffle filter.
File attributes: ``format``, ``format_version``, ``N``, ``samples``, ``dtype``, ``kind``,
``robot``, the run settings (rate, duration, noise, noise parameters, gravity, units, version,
``seed``, ``noise_stream``), the data set's (``vary``, ``config``, ``fixed_tables``,
``robot_info``) and ``failures_json`` (failed runs and their errors), encoded as a run file's
attributes are (:func:`aaria_pin.files._stored.encode_attributes`: a dict or a list that is not
of two or more numbers is a JSON string under its name plus ``_json``).

A data set made on a Dask cluster is a **manifest** (:mod:`.manifest`): the same file, whose
per-run arrays are virtual datasets over shard files written by the workers (paths relative to
the manifest's folder; attributes ``shard_dir`` and ``shard_prefix``). Every data set records
``command`` (the command line that made it, ``""`` from the library) and ``versions_json``
(aaria_pin, Pinocchio, NumPy, h5py, HDF5, Python).

Version 1 files (aaria_pin 0.1) still read (:mod:`.legacy_datasets`); they cannot be resumed.
"""

from aaria_pin.files._stored import decode_attributes
from aaria_pin.files.dataset.layout import (
    DATASET_FORMAT,
    DATASET_FORMAT_VERSION,
    DatasetLayout,
    EncodedRun,
    encode_run,
    run_arrays,
    signals_view,
)
from aaria_pin.files.dataset.manifest import missing_shards, shard_files
from aaria_pin.files.dataset.reader import DatasetReader
from aaria_pin.files.dataset.resume import read_dataset_attributes
from aaria_pin.files.dataset.store import DatasetFile, check_dataset_path
from aaria_pin.files.dataset.summary import dataset_summary

__all__ = [
    "DATASET_FORMAT",
    "DATASET_FORMAT_VERSION",
    "DatasetFile",
    "DatasetLayout",
    "DatasetReader",
    "EncodedRun",
    "check_dataset_path",
    "dataset_summary",
    "decode_attributes",
    "encode_run",
    "missing_shards",
    "read_dataset_attributes",
    "run_arrays",
    "shard_files",
    "signals_view",
]
