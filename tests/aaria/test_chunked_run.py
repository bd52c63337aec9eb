"""Long runs computed in time chunks: the same arrays as the run computed whole, in bounded memory.

A run in pieces of 137 samples (noise on, moving base) is compared with ``np.array_equal`` to the
one-piece run: Aaria arms (``aaria-fig2``; ``aaria-fig3`` with an empty module), a URDF robot on
a moving and a fixed base, and the files both write. The noise split rests on a property of
NumPy's generator, checked here on its own; the peak memory of a streamed run is measured in a
fresh process for two lengths.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import (
    simulate_from_record_chunks,
    simulate_run,
    simulate_run_chunks,
)
from aaria_pin.cli import main
from aaria_pin.core.catalogue import find_robot
from aaria_pin.core.imu_noise import ImuNoiseStream, add_imu_noise
from aaria_pin.core.record import SERIES, RunRecord
from aaria_pin.core.run import CHUNK_SAMPLES, join_chunks
from aaria_pin.core.urdf_robot import read_urdf_file
from aaria_pin.core.urdf_run import simulate_urdf_run, simulate_urdf_run_chunks
from aaria_pin.files.runfile import read_run, write_run, write_run_chunks

CHUNK = 137
SAMPLES = 1000  # 9.99 s at 100 Hz: seven pieces of 137 samples and one of 41


def assert_same_run(a: RunRecord, b: RunRecord) -> None:
    for name in SERIES:
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert np.array_equal(a.imu_mount, b.imu_mount)
    assert a.tables.keys() == b.tables.keys()
    for name in a.tables:
        assert np.array_equal(a.tables[name], b.tables[name]), name
    assert a.attributes == b.attributes
    assert list(a.attributes) == list(b.attributes)
    assert a.joint_names == b.joint_names and a.imu_names == b.imu_names
    for name in a.views:
        assert np.array_equal(a.view(name), b.view(name)), name


def test_a_generator_draws_the_same_normals_split_or_whole() -> None:
    """The property the white noise relies on: n1 then n2 normals are the n1 + n2 normals."""
    whole = np.random.default_rng(11).standard_normal((SAMPLES, 14, 6))
    rng = np.random.default_rng(11)
    parts = [
        rng.standard_normal((min(CHUNK, SAMPLES - s), 14, 6)) for s in range(0, SAMPLES, CHUNK)
    ]
    assert np.array_equal(np.concatenate(parts), whole)


@pytest.mark.parametrize("rate", [1.0, 100.0, 1000.0, 100_000.0])
def test_noise_in_pieces_is_the_noise_of_the_whole_run(rate: float) -> None:
    """Every sample a knot (1 Hz), knots 50 apart (100 Hz) or 50,000 apart (one knot span)."""
    exact = np.random.default_rng(2).normal(0.0, 3.0, (SAMPLES, 5, 6))
    whole = add_imu_noise(exact, rate, np.random.default_rng(9))
    stream = ImuNoiseStream(SAMPLES, 5, rate, np.random.default_rng(9))
    pieces = [stream.measure(exact[s : s + CHUNK], s) for s in range(0, SAMPLES, CHUNK)]
    assert np.array_equal(np.concatenate(pieces), whole)


@pytest.mark.parametrize("preset_name", ["aaria-fig2", "aaria-fig3"])
def test_a_dh_run_in_pieces_is_the_run_computed_whole(preset_name: str, tmp_path: Path) -> None:
    preset = get_preset(preset_name)
    settings = {
        "joint_table": preset.joint_table,
        "base_table": preset.base_table,
        "duration": (SAMPLES - 1) / 100.0,
        "rate": 100.0,
        "seed": 12345,
        "noise": True,
        "robot_name": preset_name,
    }
    whole = simulate_run(preset.table, **settings)
    assert whole.n_samples == SAMPLES
    pieces = list(simulate_run_chunks(preset.table, chunk=CHUNK, **settings))
    assert [p.n_samples for p in pieces] == [CHUNK] * 7 + [SAMPLES - 7 * CHUNK]
    assert_same_run(join_chunks(pieces), whole)
    if preset_name == "aaria-fig3":  # an empty module: its slots stay zero in every piece
        empty = [k for k, mount in enumerate(whole.imu_mounts) if not mount.parent]
        assert empty and not np.any(whole.imu[:, empty])
    assert np.any(whole.base_pose[:, :3, 3] != whole.base_pose[0, :3, 3])  # a moving base
    streamed = write_run_chunks(tmp_path / "run.h5", pieces, SAMPLES)
    assert_same_run(read_run(streamed), whole)
    assert_same_run(read_run(streamed), read_run(write_run(tmp_path / "whole.h5", whole)))
    again = list(simulate_from_record_chunks(read_run(streamed), chunk=CHUNK))
    assert_same_run(join_chunks(again), whole)


@pytest.mark.parametrize("moving_base", [True, False])
def test_a_urdf_run_in_pieces_is_the_run_computed_whole(moving_base: bool, tmp_path: Path) -> None:
    entry = find_robot("ur5")
    text = read_urdf_file(entry.urdf)
    settings = {
        "urdf_dir": entry.urdf.parent,
        "source": "ur5",
        "moving_base": moving_base,
        "duration": (SAMPLES - 1) / 100.0,
        "rate": 100.0,
        "seed": 7,
        "noise": True,
    }
    whole = simulate_urdf_run(text, **settings)
    pieces = list(simulate_urdf_run_chunks(text, chunk=CHUNK, **settings))
    assert len(pieces) == 8
    assert_same_run(join_chunks(pieces), whole)
    for suffix in (".h5", ".mat"):
        assert_same_run(read_run(write_run_chunks(tmp_path / f"r{suffix}", pieces, SAMPLES)), whole)


def test_a_torque_driven_run_is_one_piece() -> None:
    preset = get_preset("aaria-fig2")
    torques = np.zeros((11, 6))
    pieces = list(
        simulate_run_chunks(preset.table, duration=0.1, rate=100.0, torques=torques, chunk=3)
    )
    assert len(pieces) == 1 and pieces[0].n_samples == 11


@pytest.mark.slow
@pytest.mark.parametrize("suffix", [".h5", ".mat"])
def test_the_command_streams_a_run_longer_than_a_chunk(tmp_path: Path, suffix: str) -> None:
    """30,001 samples (two pieces of the default 20,000) read back as the run computed whole.

    A ``.mat`` run longer than a chunk is a MAT-file v7.3, streamed as the ``.h5``.
    """
    preset = get_preset("aaria-fig2")
    output = tmp_path / f"long{suffix}"
    result = CliRunner().invoke(
        main,
        ["simulate", "--preset", "aaria-fig2", "--duration", "0.3", "--rate", "100000",
         "--seed", "5", "-o", str(output)],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    whole = simulate_run(
        preset.table,
        preset.joint_table,
        preset.base_table,
        duration=0.3,
        rate=100_000.0,
        seed=5,
        robot_name="aaria-fig2",
    )
    assert f"wrote {output}: 30001 samples at 100000 Hz, noise on, peak |tau| " in result.output
    assert f"{np.abs(whole.tau).max():.4g}" in result.output
    assert_same_run(read_run(output), whole)
    assert whole.n_samples > CHUNK_SAMPLES  # so the command streamed it
    if suffix == ".mat":
        with output.open("rb") as stream:
            assert stream.read(19) == b"MATLAB 7.3 MAT-file"


@pytest.mark.slow
def test_the_command_streams_a_long_urdf_run(tmp_path: Path) -> None:
    entry = find_robot("ur5")
    output = tmp_path / "ur5.h5"
    result = CliRunner().invoke(
        main,
        ["simulate", "--robot", "ur5", "--duration", "0.3", "--rate", "100000", "--seed", "2",
         "-o", str(output)],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    whole = simulate_urdf_run(
        read_urdf_file(entry.urdf),
        urdf_dir=entry.urdf.parent,
        source="ur5",
        duration=0.3,
        rate=100_000.0,
        seed=2,
    )
    assert f"{whole.n_samples} samples at 100000 Hz, noise on, peak |tau| " in result.output
    assert_same_run(read_run(output), whole)


MEMORY_CHILD = """
import json, resource, sys
from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run_chunks
from aaria_pin.files.runfile import write_run_chunks
output, samples = sys.argv[1], int(sys.argv[2])
preset = get_preset("aaria-fig2")
chunks = simulate_run_chunks(preset.table, preset.joint_table, preset.base_table,
                             duration=(samples - 1) / 10000.0, rate=10000.0, chunk=5000)
write_run_chunks(output, chunks, samples)
print(json.dumps(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024))
"""


@pytest.mark.slow
@pytest.mark.parametrize("suffix", [".h5", ".mat"])
def test_peak_memory_of_a_streamed_run_does_not_grow_with_its_length(
    tmp_path: Path, suffix: str
) -> None:
    """200 k and 600 k samples in chunks of 5,000, noise on: peaks within 30 MB.

    Computed whole, the 400 k more samples would take about 1.5 GB more (3.9 kB per sample).
    A ``.mat`` this long is a MAT-file v7.3, streamed like the ``.h5``.
    """
    peaks = []
    for samples in (200_000, 600_000):
        output = tmp_path / f"run{samples}{suffix}"
        result = subprocess.run(
            [sys.executable, "-c", MEMORY_CHILD, str(output), str(samples)],
            capture_output=True,
            text=True,
        )
        assert result.returncode == 0, result.stderr
        peaks.append(json.loads(result.stdout.strip().splitlines()[-1]))
        if suffix == ".mat":  # 19 bytes: reading the whole file here would grow this process,
            with output.open("rb") as stream:  # whose peak RSS the next child inherits
                assert stream.read(19) == b"MATLAB 7.3 MAT-file"
        output.unlink()
    assert abs(peaks[1] - peaks[0]) < 30.0, peaks
