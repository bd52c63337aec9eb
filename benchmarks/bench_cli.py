"""End-to-end targets of the command line: writing a long run, and start-up.

    python benchmarks/bench_cli.py            # full: 1,000 vs 200,000 samples, noise off
    python benchmarks/bench_cli.py --smoke    # CI: 1,000 vs 5,000 samples, no timing asserted

Writing: the extra wall time of ``aaria simulate`` for the long run over the short one, per extra
sample, against the floor per sample (Pinocchio's ``rneaInParallel``, one thread, same arm and
trajectory). Start-up: wall time of ``aaria --help``. Medians of several runs.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from aaria_pin.aaria.dh_robot import build_dh_robot
from aaria_pin.aaria.oscillation import base_motion, joint_trajectory
from aaria_pin.aaria.presets import get_preset
from aaria_pin.core.dynamics import batched_rnea
from aaria_pin.core.kinematics import full_state
from aaria_pin.core.trajectory import sample_times

RATE = 1000.0


def wall(command: list[str]) -> float:
    start = time.perf_counter()
    subprocess.run(command, check=True, capture_output=True)
    return time.perf_counter() - start


def simulate(samples: int, folder: Path) -> list[str]:
    duration = (samples - 1) / RATE
    return [sys.executable, "-m", "aaria_pin.cli", "simulate", "--preset", "aaria-fig2",
            "--duration", repr(duration), "--rate", repr(RATE), "--no-noise",
            "-o", str(folder / f"run{samples}.h5")]  # fmt: skip


def floor_per_sample(samples: int, repeats: int) -> float:
    preset = get_preset("aaria-fig2")
    robot = build_dh_robot(preset.table)
    model = robot.model(moving_base=True)
    grid = sample_times((samples - 1) / RATE, RATE)
    q, v, a = full_state(
        model,
        base_motion(preset.base_table, grid),
        joint_trajectory(preset.joint_table, robot.chain, grid),
    )
    batched_rnea(model.model, q, v, a)
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        batched_rnea(model.model, q, v, a)
        times.append(time.perf_counter() - start)
    return statistics.median(times) / samples


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--smoke", action="store_true", help="small sizes, for CI")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    short, long = (1_000, 5_000) if args.smoke else (1_000, 200_000)
    repeats = 1 if args.smoke else args.repeats
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        wall(simulate(short, folder))  # warm the compiled kernels' cache
        short_s = statistics.median(wall(simulate(short, folder)) for _ in range(repeats))
        long_s = statistics.median(wall(simulate(long, folder)) for _ in range(repeats))
    help_s = statistics.median(
        wall([sys.executable, "-m", "aaria_pin.cli", "--help"]) for _ in range(5)
    )
    floor = floor_per_sample(min(long, 200_000), max(repeats, 3))
    extra = (long_s - short_s) / (long - short)
    print(f"aaria simulate --preset aaria-fig2 --no-noise at {RATE:g} Hz, median of {repeats}")
    print(f"{'what':<44} {'value':>12}")
    print(f"{f'wall, {short} samples':<44} {short_s:>10.3f} s")
    print(f"{f'wall, {long} samples':<44} {long_s:>10.3f} s")
    print(f"{'extra wall per sample':<44} {extra * 1e6:>9.2f} us")
    print(f"{'floor per sample (rneaInParallel, 1 thread)':<44} {floor * 1e6:>9.2f} us")
    print(f"{'extra per sample / floor per sample':<44} {extra / floor:>12.2f}")
    print(f"{'aaria --help wall':<44} {help_s:>10.3f} s")


if __name__ == "__main__":
    main()
