"""The one reader of "a run file, or run K of a data set".

:func:`open_record` reads one run as a :class:`~aaria_pin.core.record.RunRecord` from either
kind of file (told apart by :func:`~aaria_pin.files.detection.file_format`), with one rule for
``run``: required for a data set, refused for a run file.

Example::

    from aaria_pin.files.source import open_record

    record = open_record("run.h5")            # a run file
    second = open_record("ds.h5", run=1)      # run 1 of a data set
"""

from __future__ import annotations

import os

from aaria_pin.core.arguments import checked
from aaria_pin.core.record import RunRecord
from aaria_pin.errors import ParameterError
from aaria_pin.files.dataset.reader import DatasetReader
from aaria_pin.files.detection import existing_run_source, file_format
from aaria_pin.files.runfile import read_run

__all__ = ["open_record"]


@checked
def open_record(path: str | os.PathLike[str], run: int | None = None) -> RunRecord:
    """One run as a record: a run file's (any version or robot), or run ``run`` of a data set.

    Args:
        path: a run file (``.h5``, ``.hdf5``, ``.mat``) or a data set (``.h5``)
        run: the run of a data set (0-based); required for a data set, None for a run file

    Returns:
        The run record (arrays in float64; a data set's run has the attributes of one run).

    Raises:
        InputFileError: a missing, unreadable or unknown file (``parameter="file"``).
        ParameterError: ``run`` None for a data set, given for a run file, outside the data
            set or not complete (``parameter="run"``).
    """
    file = existing_run_source(path)
    kind = file_format(file)
    if kind == "dataset":
        if run is None:
            raise ParameterError(parameter="run", value=None, allowed="a run index for a data set")
        with DatasetReader(file) as reader:
            return reader.record(run)
    if run is not None:
        raise ParameterError(f"run is for a data set; {file} is a run file", parameter="run")
    return read_run(file)
