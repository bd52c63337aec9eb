"""Running out of room (``files/_space.py``): the one error, the checks, HDF5 closed safely."""

from __future__ import annotations

import errno
import os
import shutil
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest

from aaria_pin.errors import NoSpaceError
from aaria_pin.files import _space
from aaria_pin.files._space import check_space, close_hdf5, no_space, no_space_error, spare_room


def test_the_one_wording_names_the_output() -> None:
    error = no_space_error("out/run.h5")
    assert str(error) == "no space left on device writing out/run.h5; nothing was replaced"
    assert error.parameter == "path" and isinstance(error, OSError)


@pytest.mark.parametrize(
    ("error", "full"),
    [
        (OSError(errno.ENOSPC, "No space left on device"), True),
        (OSError(errno.EDQUOT, "Disk quota exceeded"), True),
        (OSError(errno.EFBIG, "File too large"), True),
        (RuntimeError("Can't decrement id ref count (… errno = 28, error message = …)"), True),
        (OSError(errno.EACCES, "Permission denied"), False),
        (ValueError("No space left on device"), False),  # not an error of the system
    ],
)
def test_no_space_knows_the_errors_of_a_full_device(error: BaseException, full: bool) -> None:
    assert no_space(error) is full


def _free(monkeypatch: pytest.MonkeyPatch, free: int) -> None:
    usage = shutil.disk_usage(".")
    monkeypatch.setattr(
        _space.shutil, "disk_usage", lambda _: type(usage)(usage.total, usage.used, free)
    )


def test_check_space_counts_the_metadata(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    _free(monkeypatch, 10_000 + _space.METADATA_BYTES)
    check_space(tmp_path / "run.h5", 10_000)  # exactly room: fine
    with pytest.raises(NoSpaceError, match=r"writing .*run\.h5; nothing was replaced"):
        check_space(tmp_path / "run.h5", 10_001)


def test_spare_room_holds_the_bytes_and_goes(tmp_path: Path) -> None:
    (tmp_path / "ds.h5").write_bytes(b"data")
    with spare_room(tmp_path / "ds.h5", 50_000) as free:
        spares = [p for p in tmp_path.iterdir() if p.name.startswith(".aaria-spare.")]
        assert len(spares) == 1 and spares[0].stat().st_blocks * 512 >= 50_000
        free()
        free()  # idempotent
        assert not spares[0].exists()
    assert [p.name for p in tmp_path.iterdir()] == ["ds.h5"]


def test_spare_room_refuses_a_full_device_leaving_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def full(*_: Any) -> None:
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(_space.os, "posix_fallocate", full)
    with pytest.raises(NoSpaceError), spare_room(tmp_path / "ds.h5", 50_000):
        pytest.fail("the block must not run")
    assert list(tmp_path.iterdir()) == []


def test_close_hdf5_keeps_a_good_file(tmp_path: Path) -> None:
    path = tmp_path / "t.h5"
    handle = h5py.File(path, "w")
    handle.create_dataset("x", data=np.arange(5.0))
    close_hdf5(handle, failed=False)
    assert not handle.id.valid
    with h5py.File(path, "r") as reread:
        assert reread["x"][()].tolist() == [0.0, 1.0, 2.0, 3.0, 4.0]


def test_close_hdf5_empties_a_failed_file_and_closes_every_id(tmp_path: Path) -> None:
    path = tmp_path / "t.h5"
    handle = h5py.File(path, "w")
    dataset = handle.create_dataset("x", data=np.zeros(100_000))
    made: list[Any] = []
    close_hdf5(handle, failed=True, make_room=lambda: made.append(True))
    assert made == [True] and not handle.id.valid and not dataset.id.valid
    handle = h5py.File(path, "w")
    handle.create_dataset("x", data=np.zeros(100_000))
    close_hdf5(handle, failed=True)  # default: the temporary is emptied before its close
    assert not handle.id.valid and os.path.getsize(path) < 100_000 * 8
