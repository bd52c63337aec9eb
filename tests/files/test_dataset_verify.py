"""Run K of a data set is checked on read: damaged chunks, NaN, wrong numbers, bad headers.

Each test damages a copy of a real data set (``aaria dataset -n 3``) the way a disk or a
careless script would, and reads it through every door of the reader (``run``, ``record``,
``windows``, ``statistics``): one :class:`InputFileError` naming the file (``parameter="file"``),
never h5py's own error.
"""

from __future__ import annotations

import re
import shutil
from collections.abc import Callable
from pathlib import Path

import h5py
import numpy as np
import pytest
from dataset_damage import flip_chunk, small_dataset

from aaria_pin.errors import InputFileError
from aaria_pin.files.dataset.layout import array_checksum
from aaria_pin.files.dataset.reader import DatasetReader

FIXTURES = Path(__file__).parents[1] / "fixtures"


@pytest.fixture(scope="module")
def made(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return small_dataset(tmp_path_factory.mktemp("verify") / "ds.h5")


def changed(made: Path, tmp_path: Path, change: Callable[[h5py.File], None]) -> Path:
    path = tmp_path / "changed.h5"
    shutil.copy(made, path)
    with h5py.File(path, "r+") as handle:
        change(handle)
    return path


READS: dict[str, Callable[[DatasetReader], object]] = {
    "run": lambda r: r.run(1, ("tau",)),
    "view": lambda r: r.run(1, ("senSen",)),
    "record": lambda r: r.record(1),
    "windows": lambda r: [w for w in r.windows(5, names=("tau",))],
    "windows[i]": lambda r: [r.windows(5, names=("senSen", "tau"))[i] for i in range(12)],
    "statistics": lambda r: r.statistics(("tau",), split=None),
}


@pytest.mark.parametrize("door", READS)
def test_a_damaged_chunk_is_run_k_damaged(made: Path, tmp_path: Path, door: str) -> None:
    path = tmp_path / "chunk.h5"
    shutil.copy(made, path)
    flip_chunk(path, "tau", 1)
    flip_chunk(path, "imu", 1)  # read by the view
    with DatasetReader(path) as reader:
        reader.run(0)  # the other runs still read
        reader.record(2)
        damage = r"^run 1 of .*chunk\.h5 is damaged \((tau|imu)"
        with pytest.raises(InputFileError, match=damage) as bad:
            READS[door](reader)
    assert bad.value.parameter == "file" and "\n" not in str(bad.value)


@pytest.mark.parametrize("door", READS)
def test_nan_is_refused_with_array_run_and_index(made: Path, tmp_path: Path, door: str) -> None:
    def nan(handle: h5py.File) -> None:
        handle["tau"][1, 5, 2] = np.inf if door == "statistics" else np.nan
        handle["imu"][1, 5, 0, 2] = np.nan  # read by the view

    path = changed(made, tmp_path, nan)
    with DatasetReader(path) as reader, pytest.raises(InputFileError) as bad:
        READS[door](reader)
    text = str(bad.value)
    assert text.startswith(f"run 1 of {path}: ")
    where = r"tau has (NaN|inf) at sample 5, joint 2|imu has NaN at sample 5, IMU 0, signal 2"
    assert re.search(where, text)
    assert bad.value.parameter == "file"


def test_other_numbers_than_the_checksum_are_damage(made: Path, tmp_path: Path) -> None:
    def nudge(handle: h5py.File) -> None:
        handle["q"][2, 3, 1] += 1e-3

    path = changed(made, tmp_path, nudge)
    with DatasetReader(path) as reader:
        assert reader.run(1, ("q",))["q"].shape == (21, 6)
        with pytest.raises(InputFileError, match=r"run 2 of .* \(q differs from its checksum\)"):
            reader.record(2)
        with pytest.raises(InputFileError, match="q differs"):
            reader.check_run(2)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda h: h.__delitem__("tau"), "a damaged data set: no 'tau' array"),
        (lambda h: h.attrs.__setitem__("N", -3), "attribute 'N' is -3; allowed: an integer >= 0"),
        (lambda h: h.attrs.__setitem__("rate", "fast"), "attribute 'rate' is 'fast'"),
        (lambda h: h.attrs.__setitem__("samples", 2.5), "attribute 'samples' is 2.5"),
        (lambda h: h.attrs.__setitem__("N", 5), "array 'time' has shape 3 × 21; allowed: 5 × 21"),
        (lambda h: h.attrs.__setitem__("layout_json", "{"), "'layout_json' is not valid JSON"),
        (lambda h: h.__delitem__("joint_names"), "a damaged data set \\("),
    ],
)
def test_a_damaged_header_or_layout_is_one_line(
    made: Path, tmp_path: Path, change: Callable[[h5py.File], None], message: str
) -> None:
    path = changed(made, tmp_path, change)
    with pytest.raises(InputFileError, match=message) as bad:
        DatasetReader(path)
    assert bad.value.parameter == "file" and "\n" not in str(bad.value)


def test_intact_files_of_every_version_read_and_verify() -> None:
    """0.1 (no checksums of the numbers), 0.2 (checksums of the deflated bytes), 0.3."""
    for version, verifiable in (("v0_1_0", False), ("v0_2_0", True), ("v0_3_0", True)):
        with DatasetReader(FIXTURES / version / "dh_dataset.h5") as reader:
            assert reader.verifiable is verifiable
            for run in np.flatnonzero(reader.complete):
                reader.check_run(int(run))
                assert np.isfinite(reader.record(int(run)).tau).all()


def test_the_checksum_is_the_writers(made: Path) -> None:
    """The CRC-32 from the numbers read equals the one the writer recorded, for every array."""
    with h5py.File(made, "r") as handle, DatasetReader(made) as reader:
        layout = reader.layout
        assert layout is not None
        for column, name in enumerate(layout.names):
            chunk = layout.chunk(name, handle[name].shape[1:])
            for run in range(3):
                recorded = int(handle["checksum"][run, column])
                assert array_checksum(handle[name][run], chunk) == recorded
                other = handle[name][(run + 1) % 3]
                if not np.array_equal(other, handle[name][run]):  # time, mounts: the same
                    assert array_checksum(other, chunk) != recorded


def test_any_flipped_chunk_is_found_or_harmless(
    made: Path, tmp_path_factory: pytest.TempPathFactory
) -> None:
    """Property: bytes flipped anywhere in one run's chunk of any array are found in that run.

    Reading every run then either gives the original numbers or one InputFileError naming
    that run, and :func:`check_file` lists exactly the runs whose reads fail.
    """
    from hypothesis import given, settings
    from hypothesis import strategies as st

    from aaria_pin.apps.check import check_file

    with DatasetReader(made) as reader:
        names = reader.stored_names
        original = {run: reader.run(run) for run in range(3)}
    folder = tmp_path_factory.mktemp("flips")

    @settings(max_examples=30, deadline=None, database=None)
    @given(
        name=st.sampled_from(names),
        run=st.integers(0, 2),
        where=st.floats(0.0, 0.999),
        mask=st.integers(1, 255),
    )
    def flipped(name: str, run: int, where: float, mask: int) -> None:
        path = folder / "flip.h5"
        shutil.copy(made, path)
        with h5py.File(path, "r") as handle:
            dataset = handle[name]
            info = dataset.id.get_chunk_info_by_coord((run,) + (0,) * (dataset.ndim - 1))
        with path.open("r+b") as stream:
            stream.seek(info.byte_offset + int(where * info.size))
            byte = stream.read(1)[0]
            stream.seek(-1, 1)
            stream.write(bytes([byte ^ mask]))
        failed = set()
        with DatasetReader(path) as reader:
            for k in range(3):
                try:
                    got = reader.run(k)
                except InputFileError as exc:
                    assert str(exc).startswith(f"run {k} of {path}") and "\n" not in str(exc)
                    failed.add(k)
                    continue
                for key, array in original[k].items():
                    assert np.array_equal(got[key], array), (k, key)
        assert failed <= {run}
        assert set(check_file(path).damaged) == failed

    flipped()


@pytest.mark.parametrize(
    "name", ["tau", "signals", "urdf", "imu_names", "imu_mount", "complete", "checksum", "failed"]
)
def test_an_array_replaced_by_a_group_is_one_line(made: Path, tmp_path: Path, name: str) -> None:
    def regroup(handle: h5py.File) -> None:
        del handle[name]
        handle.create_group(name)

    path = changed(made, tmp_path, regroup)
    with pytest.raises(InputFileError) as caught:
        DatasetReader(path)
    assert str(caught.value) == (
        f"{path}: {name!r} is not an array; allowed: an array (re-make the file)"
    )
    assert caught.value.parameter == "file"
    from aaria_pin.files.source import open_record

    with pytest.raises(InputFileError, match=re.escape(f"{name!r} is not an array")):
        open_record(path, run=0)


@pytest.mark.parametrize(
    ("name", "values", "allowed"),
    [
        ("complete", [0.5, 1.0, 1.0], "3 integers 0 or 1"),
        ("complete", [7, 1, 1], "3 integers 0 or 1"),
        ("failed", [0, 2, 0], "3 integers 0 or 1"),
        ("checksum", "float", "unsigned integers (CRC-32)"),
    ],
)
def test_flags_and_checksums_of_another_kind_are_one_line(
    made: Path, tmp_path: Path, name: str, values: object, allowed: str
) -> None:
    def replace(handle: h5py.File) -> None:
        old = handle[name][()]
        del handle[name]
        handle[name] = old.astype(float) + 0.5 if values == "float" else np.array(values)

    path = changed(made, tmp_path, replace)
    with pytest.raises(InputFileError) as caught:
        DatasetReader(path)
    assert str(caught.value) == (
        f"{path}: a damaged data set: array {name!r} is not {allowed}; allowed: {allowed} "
        "(make the data set again)"
    )
    assert caught.value.parameter == "file"
