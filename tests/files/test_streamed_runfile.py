"""The run file written in time pieces (``RunFileWriter``, ``write_run_chunks``).

A record cut into pieces of unequal length and streamed into a file reads back as the record;
its views, read straight from the file's virtual datasets, are the record's columns; a failure
at any point leaves no file (and an existing file as it was).
"""

from __future__ import annotations

import dataclasses
import itertools
from pathlib import Path

import h5py
import numpy as np
import pytest

from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.core.record import SERIES, RunRecord
from aaria_pin.errors import OutputFileError
from aaria_pin.files.runfile import RunFileWriter, read_run, write_run, write_run_chunks

SAMPLES = 51


@pytest.fixture(scope="module")
def record() -> RunRecord:
    preset = get_preset("aaria-fig3")
    return simulate_run(
        preset.table, preset.joint_table, preset.base_table, duration=0.5, rate=100.0, seed=3
    )


def piece(record: RunRecord, start: int, stop: int, **changes: object) -> RunRecord:
    """Samples start … stop - 1 of a record (an independent cut: plain slices)."""
    series = {name: getattr(record, name)[start:stop] for name in SERIES}
    return dataclasses.replace(record, **series, **changes)


def cut(record: RunRecord, bounds: list[int]) -> list[RunRecord]:
    return [piece(record, a, b) for a, b in itertools.pairwise(bounds)]


def assert_reads_back(path: Path, record: RunRecord) -> None:
    read = read_run(path)
    for name, array in record.arrays().items():
        np.testing.assert_array_equal(read.arrays()[name], array, err_msg=name)
    assert read.attributes == record.attributes
    assert [(m.name, m.parent) for m in read.imu_mounts] == [
        (m.name, m.parent) for m in record.imu_mounts
    ]


def leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


@pytest.mark.parametrize("compression", [None, "gzip"])
def test_pieces_of_unequal_length_read_back_as_the_record(
    tmp_path: Path, record: RunRecord, compression: str | None
) -> None:
    bounds = [0, 20, 40, 47, SAMPLES]  # the last two shorter than the rest
    path = tmp_path / "run.h5"
    with RunFileWriter(path, cut(record, bounds)[0], SAMPLES, compression) as writer:
        for start, chunk in zip(bounds, cut(record, bounds), strict=False):
            writer.write(start, chunk)
    assert_reads_back(path, record)
    with h5py.File(path, "r") as handle:
        assert handle["senSen"].is_virtual
        sensen = handle["senSen"][()]
        assert handle["imu"].shape == (SAMPLES, 14, 6)
    # the view read straight from the file: time, six joints, 14 × 6 IMU signals
    expected = np.concatenate(
        [record.time[:, None], record.q, record.imu.reshape(SAMPLES, -1)], axis=1
    )
    np.testing.assert_array_equal(sensen, expected)
    np.testing.assert_array_equal(read_run(path).view("senSen"), expected)


def test_write_run_is_the_one_piece_case(tmp_path: Path, record: RunRecord) -> None:
    streamed = write_run_chunks(tmp_path / "s.h5", cut(record, [0, 7, SAMPLES]), SAMPLES)
    whole = write_run(tmp_path / "w.h5", record)
    assert_reads_back(streamed, record)
    assert_reads_back(whole, record)
    with h5py.File(streamed, "r") as a, h5py.File(whole, "r") as b:
        assert list(a) == list(b)
        assert list(a.attrs) == list(b.attrs)


def test_the_last_piece_attributes_are_stored(tmp_path: Path, record: RunRecord) -> None:
    first = piece(record, 0, 30, attributes={**record.attributes, "note": "so far"})
    last = piece(record, 30, SAMPLES, attributes={**record.attributes, "note": "whole run"})
    path = write_run_chunks(tmp_path / "run.h5", [first, last], SAMPLES)
    assert read_run(path).attributes["note"] == "whole run"


def test_a_mat_file_is_written_whole_from_the_pieces(tmp_path: Path, record: RunRecord) -> None:
    path = write_run_chunks(tmp_path / "run.mat", cut(record, [0, 25, SAMPLES]), SAMPLES)
    assert_reads_back(path, record)
    with pytest.raises(OutputFileError, match="written whole"):
        RunFileWriter(tmp_path / "other.mat", record)


def test_a_failure_mid_way_leaves_no_file(tmp_path: Path, record: RunRecord) -> None:
    path = tmp_path / "run.h5"
    pieces = cut(record, [0, 20, 40, SAMPLES])
    with pytest.raises(RuntimeError, match="mid-way"):
        with RunFileWriter(path, pieces[0], SAMPLES) as writer:
            writer.write(0, pieces[0])
            raise RuntimeError("mid-way")
    assert leftovers(tmp_path) == []

    def failing() -> object:
        yield pieces[0]
        raise RuntimeError("the second piece fails")

    with pytest.raises(RuntimeError, match="second piece"):
        write_run_chunks(path, failing(), SAMPLES)  # type: ignore[arg-type]
    assert leftovers(tmp_path) == []


def test_an_existing_file_is_kept_on_failure(tmp_path: Path, record: RunRecord) -> None:
    path = tmp_path / "run.h5"
    path.write_bytes(b"before")
    with pytest.raises(OutputFileError, match="20 of 51 samples"):
        with RunFileWriter(path, piece(record, 0, 20), SAMPLES) as writer:
            writer.write(0, piece(record, 0, 20))  # and no more: the run is incomplete
    assert path.read_bytes() == b"before"
    assert leftovers(tmp_path) == ["run.h5"]


def test_pieces_out_of_order_or_of_another_robot_are_refused(
    tmp_path: Path, record: RunRecord
) -> None:
    path = tmp_path / "run.h5"
    with pytest.raises(OutputFileError, match="at sample 20; allowed: the next piece, at sample 0"):
        with RunFileWriter(path, piece(record, 0, 20), SAMPLES) as writer:
            writer.write(20, piece(record, 20, 40))
    with pytest.raises(OutputFileError, match="ending by sample 51"):
        with RunFileWriter(path, piece(record, 0, 20), SAMPLES) as writer:
            writer.write(0, piece(record, 0, 20))
            writer.write(20, piece(record, 0, 40))
    other = dataclasses.replace(
        piece(record, 20, 40),
        q=np.zeros((20, 5)),
        qd=np.zeros((20, 5)),
        qdd=np.zeros((20, 5)),
        tau=np.zeros((20, 5)),
        joint_names=record.joint_names[:5],
    )
    with pytest.raises(OutputFileError, match="piece array 'q' has shape"):
        with RunFileWriter(path, piece(record, 0, 20), SAMPLES) as writer:
            writer.write(0, piece(record, 0, 20))
            writer.write(20, other)
    with pytest.raises(OutputFileError, match="no piece"):
        write_run_chunks(path, [], SAMPLES)
    with pytest.raises(OutputFileError, match="at least the first piece"):
        RunFileWriter(path, record, SAMPLES - 1)
    assert leftovers(tmp_path) == []


def test_pieces_are_never_dropped_when_the_attributes_do_not_cover_the_run(
    tmp_path: Path, record: RunRecord
) -> None:
    from aaria_pin.files.runfile import write_run_pieces

    attributes = {k: v for k, v in record.attributes.items() if k not in ("duration", "rate")}
    halves = [piece(record, 0, 20, attributes=attributes), piece(record, 20, SAMPLES)]

    with pytest.raises(OutputFileError, match="more than one piece"):
        write_run_pieces(tmp_path / "run.h5", halves, None)
    assert not (tmp_path / "run.h5").exists()
