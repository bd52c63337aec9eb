"""Cost of one run's record against Pinocchio's batched RNEA (the floor), on one core.

    python benchmarks/bench_record.py            # full: aaria-fig2, moving base, 10,000 samples
    python benchmarks/bench_record.py --smoke    # CI: a few hundred samples, no timing asserted

Prints a table of medians over repeats, measured in turn within each repeat in one process, and
the median of the per-repeat ratios to the floor: the record with noise off and on, the record
plus its write to an uncompressed ``.h5`` (the issue's "record + write"; a temporary folder),
the write alone (a record made beforehand) and a per-sample Pinocchio loop. The table is
measured twice: first with glibc's default malloc, then with the thresholds the ``aaria``
commands and the data-set workers set (``aaria_pin.core._malloc.tune_malloc``, irreversible,
hence second; the floor is measured again under it), where freed arrays are reused instead of
faulting fresh pages in.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

if hasattr(os, "sched_setaffinity"):
    os.sched_setaffinity(0, {max(os.sched_getaffinity(0))})  # one core

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))  # the oracles

from pinocchio_oracles import reference_frame_poses, reference_imu_signals

from aaria_pin.aaria.dh_robot import build_dh_robot
from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.aaria.sine_tables import base_motion, joint_trajectory
from aaria_pin.core._malloc import tune_malloc
from aaria_pin.core.dynamics import batched_rnea
from aaria_pin.core.kinematics import full_state
from aaria_pin.core.record import RunRecord
from aaria_pin.core.trajectory import sample_times
from aaria_pin.files.runfile import write_run

GOALS = {"write": 2.0, "noisy write": 2.5}
"""Issue 25's goals for record + write (uncompressed .h5), × the floor: noise off, noise on."""

_written: list[Path] = []
"""Run files written by the timed calls, removed after each timing (untimed)."""


def seconds(func: Callable[[], object]) -> float:
    start = time.perf_counter()
    func()
    elapsed = time.perf_counter() - start
    while _written:  # replacing a 12 MB file costs 7 ms of unlinking: not the write's cost
        _written.pop().unlink()
    return elapsed


def interleaved(funcs: dict[str, Callable[[], object]], repeats: int) -> dict[str, list[float]]:
    """Times of each function, measured in turn within every repeat (after one warm-up round)."""
    for func in funcs.values():
        seconds(func)
    times: dict[str, list[float]] = {name: [] for name in funcs}
    for _ in range(repeats):
        for name, func in funcs.items():
            times[name].append(seconds(func))
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--smoke", action="store_true", help="tiny sizes, for CI")
    parser.add_argument("--samples", type=int, default=10_000)
    parser.add_argument("--repeats", type=int, default=21)
    args = parser.parse_args()
    samples, repeats = (300, 3) if args.smoke else (args.samples, args.repeats)
    reference_samples = min(samples, 300 if args.smoke else 1000)

    preset = get_preset("aaria-fig2")
    rate = 1000.0
    duration = (samples - 1) / rate
    robot = build_dh_robot(preset.table)
    model = robot.model(moving_base=True)
    time_grid = sample_times(duration, rate)
    trajectory = joint_trajectory(preset.joint_table, robot.chain, time_grid)
    base = base_motion(preset.base_table, time_grid)
    q, v, a = full_state(model, base, trajectory)

    def record(noise: bool) -> Callable[[], RunRecord]:
        return lambda: simulate_run(
            preset.table,
            preset.joint_table,
            preset.base_table,
            duration=duration,
            rate=rate,
            noise=noise,
        )

    folder = tempfile.TemporaryDirectory()

    def written(noise: bool) -> Callable[[], object]:
        """Simulate and write to a new file (uncompressed .h5), as ``aaria simulate`` does."""
        make = record(noise)

        def run() -> None:
            _written.append(write_run(Path(folder.name) / f"run{len(_written)}.h5", make()))

        return run

    made = record(False)()

    def write_alone() -> None:
        """Write a record made beforehand (uncompressed .h5): the write's own cost."""
        _written.append(write_run(Path(folder.name) / f"run{len(_written)}.h5", made))

    funcs = {
        "floor": lambda: batched_rnea(model.model, q, v, a, threads=1),
        "record": record(False),
        "noisy": record(True),
        "write": written(False),
        "noisy write": written(True),
        "write alone": write_alone,
    }
    times = interleaved(funcs, repeats)

    short = sample_times((reference_samples - 1) / rate, rate)
    short_trajectory = joint_trajectory(preset.joint_table, robot.chain, short)
    short_base = base_motion(preset.base_table, short)
    frames = list(model.sensor_frames)

    def per_sample() -> None:
        reference_imu_signals(model, short_base, short_trajectory, frames)
        reference_frame_poses(model, short_base, short_trajectory, [model.tool_frame])

    loop = statistics.median(seconds(per_sample) for _ in range(max(1, repeats // 5)))
    times["loop"] = [loop * samples / reference_samples] * repeats

    print(f"aaria-fig2, moving base, {samples} samples, one core, {repeats} interleaved repeats")
    report(times, "glibc's default malloc", reference_samples)
    tune_malloc()
    tuned = interleaved(funcs, repeats)
    tuned["loop"] = times["loop"]
    report(tuned, "malloc tuned as the aaria commands do", reference_samples)
    for name, goal in GOALS.items():
        ratio = statistics.median(t / f for t, f in zip(tuned[name], tuned["floor"], strict=True))
        verdict = "met" if ratio <= goal else "not met"
        print(f"goal: {name} <= {goal:.1f}x the floor (tuned malloc): {ratio:.2f}x, {verdict}")
    folder.cleanup()


def report(times: dict[str, list[float]], title: str, reference_samples: int) -> None:
    """Print one table: medians and the median of the per-repeat ratios to the floor."""
    print(f"-- {title}")
    print(f"{'what':<52} {'median s':>9} {'x floor':>8}")
    labels = {
        "floor": "floor: rneaInParallel, 1 thread (tau only)",
        "record": "record, noise off (imu, tau, wrench, poses, URDF)",
        "noisy": "record, noise on",
        "write": "record + write .h5 (uncompressed), noise off",
        "noisy write": "record + write .h5 (uncompressed), noise on",
        "write alone": "write .h5 alone (uncompressed; record made before)",
        "loop": f"per-sample Pinocchio loop (timed on {reference_samples})",
    }
    for name, label in labels.items():
        ratios = [t / f for t, f in zip(times[name], times["floor"], strict=True)]
        print(
            f"{label:<52} {statistics.median(times[name]):>9.4f} {statistics.median(ratios):>8.2f}"
        )


if __name__ == "__main__":
    np.seterr(all="raise")
    main()
