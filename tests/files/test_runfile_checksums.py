"""Per-array checksums of run files: stored by every writer, verified by every read.

The expected checksum is computed here independently (``zlib.crc32`` of each array's values as
little-endian float64 in C order). Damage is made in real files: bytes flipped inside an
array's data (its offset from h5py's ``DatasetID.get_offset``), values changed with the stale
checksum left, and a ``hypothesis`` property flips random bytes anywhere in the data region.
"""

from __future__ import annotations

import dataclasses
import itertools
import json
import shutil
import warnings
import zlib
from pathlib import Path

import h5py
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.core.record import SERIES, RunRecord
from aaria_pin.errors import InputFileError, OutputFileError
from aaria_pin.files.runfile import read_run, read_run_inputs, write_run, write_run_chunks
from aaria_pin.files.runfile._checksums import UnverifiedFileWarning
from aaria_pin.files.runfile._mat73 import load_mat73
from aaria_pin.files.source import open_record

FIXTURES = Path(__file__).parents[1] / "fixtures"


def expected_checksums(record: RunRecord) -> dict[str, str]:
    """Each stored array's CRC-32 (a table of fewer than two axes is stored as a row)."""
    return {
        name: f"crc32:{zlib.crc32(np.ascontiguousarray(data, dtype='<f8').tobytes()):08x}"
        for name, data in record.arrays().items()
    }


@pytest.fixture(scope="module")
def record() -> RunRecord:
    preset = get_preset("aaria-fig3")
    run = simulate_run(
        preset.table, preset.joint_table, preset.base_table, duration=0.2, rate=100.0, seed=3
    )
    run.tables["sensor_force"] = np.arange(run.n_samples * 3, dtype=float).reshape(-1, 3)
    return run


@pytest.fixture(scope="module")
def run_file(tmp_path_factory: pytest.TempPathFactory, record: RunRecord) -> Path:
    return write_run(tmp_path_factory.mktemp("run") / "run.h5", record)


def test_every_writer_stores_the_same_checksums_of_the_values(
    tmp_path: Path, record: RunRecord
) -> None:
    expected = expected_checksums(record)
    h5 = write_run(tmp_path / "run.h5", record)
    gzip = write_run(tmp_path / "gzip.h5", record, compression="gzip")
    mat5 = write_run(tmp_path / "run.mat", record)
    mat73 = write_run(tmp_path / "run73.mat", record, mat_version="7.3")
    bounds = [0, 7, 8, record.n_samples]
    pieces = [
        dataclasses.replace(
            record,
            **{name: getattr(record, name)[a:b] for name in SERIES},
            tables={
                **record.tables,
                "sensor_force": record.tables["sensor_force"][a:b],
            },
        )
        for a, b in itertools.pairwise(bounds)
    ]
    streamed = write_run_chunks(tmp_path / "streamed.h5", pieces, record.n_samples)
    streamed73 = write_run_chunks(
        tmp_path / "streamed.mat", pieces, record.n_samples, mat_version="7.3"
    )
    for path in (h5, gzip, streamed):
        with h5py.File(path, "r") as handle:
            assert json.loads(handle.attrs["checksums"]) == expected, path
    for path in (mat73, streamed73):
        assert json.loads(str(load_mat73(path)["attr_checksums"][0])) == expected, path
    from scipy.io import loadmat

    assert json.loads(str(loadmat(mat5)["attr_checksums"][0])) == expected
    for path in (h5, gzip, mat5, mat73, streamed, streamed73):
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # verified: no warning
            read = read_run(path)
        assert "checksums" not in read.attributes
        np.testing.assert_array_equal(read.tau, record.tau)
        np.testing.assert_array_equal(read.tables["sensor_force"], record.tables["sensor_force"])


def test_checksums_is_a_reserved_attribute(tmp_path: Path, record: RunRecord) -> None:
    odd = dataclasses.replace(record, attributes={**record.attributes, "checksums": "mine"})
    with pytest.raises(OutputFileError, match="'checksums' is reserved"):
        write_run(tmp_path / "run.h5", odd)
    assert not (tmp_path / "run.h5").exists()


@pytest.mark.parametrize("name", ["tau", "imu", "time", "imu_mount", "senSenDH", "sensor_force"])
def test_a_byte_flipped_inside_an_array_is_found(tmp_path: Path, run_file: Path, name: str) -> None:
    damaged = tmp_path / "damaged.h5"
    shutil.copy(run_file, damaged)
    with h5py.File(damaged, "r") as handle:
        offset = handle[name].id.get_offset()
        size = handle[name].id.get_storage_size()
    with damaged.open("r+b") as stream:
        stream.seek(offset + size // 2)
        byte = stream.read(1)[0]
        stream.seek(offset + size // 2)
        stream.write(bytes([byte ^ 0x10]))
    with pytest.raises(InputFileError) as error:
        read_run(damaged)
    message = str(error.value)
    assert message.startswith(f"{damaged}: array {name} is damaged (checksum crc32:")
    assert "\n" not in message and error.value.parameter == "file"
    if name in SERIES:  # the inputs alone are not the damaged part
        assert read_run_inputs(damaged).n_samples == 0
    else:
        with pytest.raises(InputFileError, match=f"array {name} is damaged"):
            read_run_inputs(damaged)


def test_a_value_changed_in_place_is_found_as_damage(tmp_path: Path, run_file: Path) -> None:
    damaged = tmp_path / "nan.h5"
    shutil.copy(run_file, damaged)
    with h5py.File(damaged, "r+") as handle:
        handle["tau"][3, 1] = np.nan
    with pytest.raises(InputFileError, match="array tau is damaged"):
        open_record(damaged)


def test_a_compressed_chunk_overwritten_is_damage_not_a_traceback(
    tmp_path: Path, record: RunRecord
) -> None:
    path = write_run(tmp_path / "gzip.h5", record, compression="gzip")
    with h5py.File(path, "r") as handle:
        offset = handle["imu"].id.get_chunk_info(0).byte_offset
    with path.open("r+b") as stream:
        stream.seek(offset + 4)
        stream.write(b"\xff" * 64)
    with pytest.raises(InputFileError) as error:
        read_run(path)
    message = str(error.value)
    assert message.startswith(f"{path} is damaged (") or "array imu is damaged" in message
    assert "\n" not in message


def test_old_files_read_with_a_note_that_they_cannot_be_verified() -> None:
    for path in (FIXTURES / "v0_3_0" / "dh_run.h5", FIXTURES / "v0_1_0" / "wrist_run.mat"):
        with pytest.warns(UnverifiedFileWarning, match="cannot be verified") as caught:
            read = read_run(path)
        assert len(caught) == 1 and str(path) in str(caught[0].message)
        assert read.n_samples > 0


def test_a_broken_checksums_attribute_is_one_line(tmp_path: Path, run_file: Path) -> None:
    broken = tmp_path / "broken.h5"
    shutil.copy(run_file, broken)
    with h5py.File(broken, "r+") as handle:
        handle.attrs["checksums"] = "{not json"
    with pytest.raises(InputFileError, match=r"attribute 'checksums' is '\{not json'; allowed"):
        read_run(broken)
    with h5py.File(broken, "r+") as handle:
        handle.attrs["checksums"] = "{}"
    with pytest.raises(InputFileError, match="array time has no checksum"):
        read_run(broken)


def _data_region(path: Path) -> list[tuple[int, int]]:
    """(offset, size) of each contiguous numeric array's bytes in an HDF5 run file."""
    regions = []
    with h5py.File(path, "r") as handle:
        for item in handle.values():
            offset = item.id.get_offset()
            if item.dtype.kind == "f" and offset is not None and item.id.get_storage_size():
                regions.append((offset, item.id.get_storage_size()))
    return regions


@settings(
    max_examples=40,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
@given(data=st.data())
def test_random_flipped_bytes_read_as_the_original_or_as_one_line(
    tmp_path: Path, run_file: Path, record: RunRecord, data: st.DataObject
) -> None:
    regions = _data_region(run_file)
    original = bytearray(run_file.read_bytes())
    flips = data.draw(st.lists(st.tuples(st.integers(0, 10**9), st.integers(1, 255)), max_size=4))
    damaged = bytearray(original)
    for where, mask in flips:
        offset, size = regions[where % len(regions)]
        damaged[offset + (where // len(regions)) % size] ^= mask
    path = tmp_path / "flipped.h5"
    path.write_bytes(bytes(damaged))
    try:
        read = read_run(path)
    except InputFileError as error:
        assert "\n" not in str(error) and error.parameter == "file"
        assert damaged != original
        return
    for name, array in record.arrays().items():
        np.testing.assert_array_equal(read.arrays()[name], array, err_msg=name)


def test_the_checksum_of_values_in_another_order_or_type_is_that_of_the_c_order_values(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from aaria_pin.files.runfile import _checksums

    monkeypatch.setattr(_checksums, "_BLOCK_BYTES", 1000)  # many blocks of rows
    rng = np.random.default_rng(5)
    arrays = [
        np.asfortranarray(rng.normal(size=(300, 7))),  # a .mat variable in MATLAB's order
        rng.normal(size=(200, 6, 14)).transpose(0, 2, 1),
        rng.normal(size=(100, 3)).astype(np.float32),
        rng.normal(size=(50, 4))[::2],
        np.zeros((0, 3)),
        np.array(2.5),
    ]
    for data in arrays:
        expected = zlib.crc32(np.ascontiguousarray(data, dtype="<f8").tobytes())
        assert _checksums.crc_of_values(zlib.crc32, data) == expected, data.shape
    first, second = rng.normal(size=(40, 3)), np.asfortranarray(rng.normal(size=(9, 3)))
    whole = zlib.crc32(np.concatenate([first, second]).tobytes())
    running = _checksums.crc_of_values(zlib.crc32, first)
    assert _checksums.crc_of_values(zlib.crc32, second, running) == whole


def test_an_array_the_checksums_list_that_is_gone_is_missing(
    tmp_path: Path, run_file: Path
) -> None:
    edited = tmp_path / "edited.h5"
    shutil.copy(run_file, edited)
    with h5py.File(edited, "r+") as handle:
        del handle["sensor_force"]  # no kind requires it: only its checksum tells
    with pytest.raises(InputFileError) as error:
        read_run(edited)
    assert str(error.value) == (
        f"{edited}: array sensor_force is missing; allowed: every array its checksums list"
    )
    with h5py.File(edited, "r+") as handle:
        del handle["tau"]
    with pytest.raises(InputFileError, match="no dataset 'tau'"):
        read_run(edited)
    inputs = tmp_path / "inputs.h5"
    shutil.copy(run_file, inputs)
    assert read_run_inputs(inputs).n_samples == 0  # the unread series are not missing
