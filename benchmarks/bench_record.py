"""Cost of one run's record against Pinocchio's batched RNEA (the floor), on one core.

    python benchmarks/bench_record.py            # full: aaria-fig2, moving base, 10,000 samples
    python benchmarks/bench_record.py --smoke    # CI: a few hundred samples, no timing asserted

Prints a table of medians over repeats, measured side by side in one process, and the ratios.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from collections.abc import Callable

if hasattr(os, "sched_setaffinity"):
    os.sched_setaffinity(0, {max(os.sched_getaffinity(0))})  # one core

import numpy as np

from aaria_pin.dh_robot import build_dh_robot
from aaria_pin.dynamics import batched_rnea
from aaria_pin.kinematics import full_state, reference_frame_poses, reference_imu_signals
from aaria_pin.oscillation import base_motion, joint_trajectory
from aaria_pin.presets import get_preset
from aaria_pin.simulate import simulate_run
from aaria_pin.trajectory import sample_times


def median_seconds(func: Callable[[], object], repeats: int) -> float:
    func()  # warm up
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        func()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--smoke", action="store_true", help="tiny sizes, for CI")
    parser.add_argument("--samples", type=int, default=10_000)
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    samples, repeats = (300, 2) if args.smoke else (args.samples, args.repeats)
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

    floor = median_seconds(lambda: batched_rnea(model.model, q, v, a, threads=1), repeats)
    record = median_seconds(
        lambda: simulate_run(
            preset.table,
            preset.joint_table,
            preset.base_table,
            duration=duration,
            rate=rate,
            noise=False,
        ),
        repeats,
    )
    noisy = median_seconds(
        lambda: simulate_run(
            preset.table,
            preset.joint_table,
            preset.base_table,
            duration=duration,
            rate=rate,
            noise=True,
        ),
        repeats,
    )

    short = sample_times((reference_samples - 1) / rate, rate)
    short_trajectory = joint_trajectory(preset.joint_table, robot.chain, short)
    short_base = base_motion(preset.base_table, short)
    frames = list(model.sensor_frames)

    def per_sample() -> None:
        reference_imu_signals(model, short_base, short_trajectory, frames)
        reference_frame_poses(model, short_base, short_trajectory, [model.tool_frame])

    loop = median_seconds(per_sample, max(1, repeats // 3)) * samples / reference_samples

    print(f"aaria-fig2, moving base, {samples} samples, one core, median of {repeats}")
    print(f"{'what':<46} {'seconds':>10} {'x floor':>8}")
    rows = [
        ("floor: rneaInParallel, 1 thread (tau only)", floor),
        ("record, noise off (senSen, tau, wrench, pose)", record),
        ("record, noise on", noisy),
        (f"per-sample Pinocchio loop (from {reference_samples})", loop),
    ]
    for name, seconds in rows:
        print(f"{name:<46} {seconds:>10.4f} {seconds / floor:>8.2f}")


if __name__ == "__main__":
    np.seterr(all="raise")
    main()
