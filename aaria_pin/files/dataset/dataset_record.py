"""One run of a data set of format version 2 as a run record (its stored arrays read and checked).

:meth:`DatasetReader.record <aaria_pin.files.dataset.reader.DatasetReader.record>` calls it; a
version 1 file's run is :func:`~.legacy_datasets.legacy_record`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from aaria_pin.core.record import RunRecord, mounts_from_poses
from aaria_pin.files.dataset.header import DatasetHeader
from aaria_pin.files.dataset.layout import DatasetLayout, record_attributes
from aaria_pin.files.dataset.verify import RunCheck

__all__ = ["NOISE_STREAM", "dataset_record"]

NOISE_STREAM = 3
"""The noise stream of a run when the file records none (as the engine draws it)."""


def dataset_record(
    handle: Any, check: RunCheck, header: DatasetHeader, layout: DatasetLayout, index: int
) -> RunRecord:
    """Run ``index`` of an open version 2 data set as a record (arrays in float64).

    Args:
        handle: the open h5py file
        check: how the run's arrays are read and checked (:class:`~.verify.RunCheck`)
        header: the file's attributes
        layout: the file's per-run layout
        index: a complete run

    Raises:
        InputFileError: the run is damaged or not finite (see :mod:`.verify`).
    """
    arrays = {
        name: np.asarray(check.checked(handle, name, index), dtype=float) for name in layout.names
    }
    mounts = mounts_from_poses(layout.imu_names, layout.imu_parents, arrays["imu_mount"])
    stream = NOISE_STREAM if header.noise_stream is None else header.noise_stream
    return RunRecord(
        time=arrays["time"],
        joint_names=layout.joint_names,
        q=arrays["q"],
        qd=arrays["qd"],
        qdd=arrays["qdd"],
        tau=arrays["tau"],
        base_pose=arrays["base_pose"],
        base_wrench=arrays["base_wrench"],
        tool_pose=arrays["tool_pose"],
        imu=arrays["imu"],
        imu_mounts=mounts,
        urdf=layout.urdf,
        tables={name: arrays[name] for name in layout.tables},
        views=dict(layout.views),
        attributes=record_attributes(
            header.attributes, index, stream, arrays.get("hardware_values")
        ),
    )
