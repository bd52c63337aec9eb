"""Shards and the manifest over them, without a cluster: the manifest reads as the one file the
local writer makes, whatever the order of runs in the shards; a damaged row fails its check."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
from aaria_pin.apps.dataset.spec import run_result
from aaria_pin.files.dataset.manifest import (
    ManifestContents,
    ManifestShards,
    RunLocation,
    ShardWriter,
    list_shards,
    remove_unused_shards,
    shard_name,
    verify_shard,
    write_manifest,
)
from aaria_pin.files.dataset.reader import DatasetReader
from aaria_pin.files.dataset.store import DatasetFile

SPEC = DhDatasetSpec(n_runs=7, seed=3, duration=0.3)
SHARDS = ([0, 1, 2], [5, 3, 4])  # run 6 is in no shard (never made)


@pytest.fixture(scope="module")
def made(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    folder = tmp_path_factory.mktemp("shards")
    encoded = {run: run_result(SPEC, run)[1] for run in range(6)}
    layout = SPEC.layout()
    one = folder / "one.h5"
    with DatasetFile.create(one, 7, SPEC.samples, SPEC.dtype, {}, layout) as store:
        for run, chunks in encoded.items():
            store.write_run(run, chunks)  # type: ignore[arg-type]
    (folder / "parts").mkdir()
    locations, checksums = {}, {}
    for runs in SHARDS:
        with ShardWriter(folder / "parts", "job", runs, SPEC.samples, SPEC.dtype, layout) as w:
            for row, run in enumerate(runs):
                checksums[run] = w.write_run(row, encoded[run])  # type: ignore[arg-type]
                locations[run] = RunLocation(w.path.name, row, len(runs))
    manifest = folder / "manifest.h5"
    shards = ManifestShards(folder / "parts", "job", {})
    contents = ManifestContents(
        shards, 7, SPEC.samples, SPEC.dtype, {}, layout, locations, checksums, {6: "never made"}
    )
    write_manifest(manifest, contents)
    return one, manifest


def test_the_manifest_reads_as_the_one_file(made: tuple[Path, Path]) -> None:
    one, manifest = made
    with DatasetReader(one) as reader:
        names = reader.names
    with h5py.File(one, "r") as left, h5py.File(manifest, "r") as right:
        for name in (*names, "complete", "checksum"):
            np.testing.assert_array_equal(left[name][()], right[name][()], err_msg=name)
        assert right["failed"][()].tolist() == [0] * 6 + [1]
        assert right.attrs["shard_dir"] == "parts" and right.attrs["shard_prefix"] == "job"
        # one mapping per array and block of consecutive runs in consecutive rows: 0-2, 3-4, 5
        assert len(right["imu"].virtual_sources()) == 3
    with DatasetReader(manifest) as reader:
        assert reader.complete.tolist() == [True] * 6 + [False]
        np.testing.assert_array_equal(reader.run(5)["imu"], SPEC.arrays(5)["imu"])


def test_a_damaged_row_fails_its_check(made: tuple[Path, Path], tmp_path: Path) -> None:
    _, manifest = made
    shard = manifest.parent / "parts" / shard_name("job", SHARDS[1])
    copy = tmp_path / shard.name
    copy.write_bytes(shard.read_bytes())
    names = SPEC.layout().names
    intact = verify_shard(copy, "job", names).intact
    assert sorted(intact) == [3, 4, 5] and intact[3][0] == 1  # run 3 is row 1
    with h5py.File(copy, "r") as handle:
        info = handle["q"].id.get_chunk_info_by_coord((1, 0, 0))
    with open(copy, "r+b") as raw:
        raw.seek(info.byte_offset + info.size // 2)
        raw.write(b"\x00\xff" * 8)
    assert sorted(verify_shard(copy, "job", names).intact) == [4, 5]
    assert verify_shard(copy, "another job", names).intact == {}
    copy.write_bytes(b"not HDF5")
    assert verify_shard(copy, "job", names).intact == {}


def test_unused_shards_and_companions_are_removed(tmp_path: Path) -> None:
    for name in ("job-000000000-aa.h5", "job-000000003-bb.h5", ".job-000000003-bb.h5.lock"):
        (tmp_path / name).write_bytes(b"")
    (tmp_path / "other-000000000-cc.h5").write_bytes(b"")  # another job's: kept
    assert [p.name for p in list_shards(tmp_path, "job")] == [
        "job-000000000-aa.h5",
        "job-000000003-bb.h5",
    ]
    assert remove_unused_shards(tmp_path, "job", {"job-000000000-aa.h5"}) == 2
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "job-000000000-aa.h5",
        "other-000000000-cc.h5",
    ]
