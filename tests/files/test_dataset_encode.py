"""A run's chunks as the workers encode them, decoded here with zlib and numpy alone."""

from __future__ import annotations

import zlib

import numpy as np

from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
from aaria_pin.files.dataset import layout as layout_module
from aaria_pin.files.dataset.layout import encode_run, run_arrays


def _unshuffle(data: bytes, dtype: np.dtype, shape: tuple[int, ...]) -> np.ndarray:
    """HDF5's deflate then shuffle filters undone: byte plane j holds byte j of each element."""
    planes = np.frombuffer(zlib.decompress(data), dtype=np.uint8).reshape(dtype.itemsize, -1)
    return np.ascontiguousarray(planes.T).view(dtype).reshape(shape)


def test_every_chunk_decodes_to_the_stored_numbers() -> None:
    spec = DhDatasetSpec(n_runs=3, seed=4, duration=0.5, rate=100.0)
    layout = spec.layout()
    record = spec.make_run(1)
    encoded = encode_run(layout, record, "float32")
    arrays = run_arrays(layout, record, "float32")
    assert list(encoded) == list(arrays)
    for name, array in arrays.items():
        chunks, checksum = encoded[name]
        crc = 0
        for data in chunks:
            crc = zlib.crc32(zlib.decompress(data), crc)
        assert crc == checksum, name
        if name in ("base_pose", "tool_pose"):  # a pose series: one chunk per entry
            assert len(chunks) == 16
            for entry, data in enumerate(chunks):
                row, column = divmod(entry, 4)
                decoded = _unshuffle(data, array.dtype, (array.shape[0],))
                np.testing.assert_array_equal(decoded, array[:, row, column], err_msg=name)
        else:
            assert len(chunks) == 1
            np.testing.assert_array_equal(
                _unshuffle(chunks[0], array.dtype, array.shape), array, err_msg=name
            )


def test_constant_pose_entries_are_the_same_bytes_kept_or_made_again() -> None:
    spec = DhDatasetSpec(n_runs=3, seed=4, duration=0.5, rate=100.0)
    layout = spec.layout()
    first = encode_run(layout, spec.make_run(0), "float32")
    layout_module._CONSTANT_CHUNKS.clear()
    second = encode_run(layout, spec.make_run(2), "float32")
    for name in ("base_pose", "tool_pose"):
        for entry, value in zip((12, 13, 14, 15), (0.0, 0.0, 0.0, 1.0), strict=True):
            data = second[name][0][entry]
            assert data == first[name][0][entry]
            decoded = _unshuffle(data, np.dtype("float32"), (51,))
            assert np.all(decoded == value)
    assert first["imu"][0] != second["imu"][0]


def test_other_chunkings_are_cut_chunk_by_chunk() -> None:
    array = np.arange(24, dtype=np.float32).reshape(4, 6)
    blocks = layout_module._chunk_blocks(array, (2, 3))
    cuts = [array[:2, :3], array[:2, 3:], array[2:, :3], array[2:, 3:]]
    assert len(blocks) == 4
    for block, cut in zip(blocks, cuts, strict=True):
        raw = np.asarray(block).tobytes()
        planes = np.frombuffer(raw, dtype=np.uint8).reshape(4, -1)
        np.testing.assert_array_equal(
            np.ascontiguousarray(planes.T).view(np.float32).ravel(), cut.ravel()
        )
