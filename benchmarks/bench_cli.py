"""End-to-end targets of the command line: start-up, the first command, writing a long run.

    python benchmarks/bench_cli.py            # full: 1,000 vs 200,000 samples, noise off
    python benchmarks/bench_cli.py --smoke    # CI: 1,000 vs 5,000 samples, no timing asserted

Start-up (whole processes, medians): ``aaria simulate --preset aaria-fig2 -o run.h5`` (its
defaults: 10 s at 100 Hz, 1,001 samples, noise on) with the kernels' disk cache warm, and
``aaria --help``. First command: the same ``aaria simulate`` with an empty numba cache
(``NUMBA_CACHE_DIR`` a fresh folder), whether it says that it compiles, and whether the next
process loads the kernels instead (no message). Writing: the extra wall time of ``aaria simulate``
for the long run over the short one, per extra sample, against the floor per sample (Pinocchio's
``rneaInParallel``, one thread, same arm and trajectory). On a shared machine whole processes
are noisy, so each repeat measures the floor (in this process) next to its short and long
run, and the ratio printed is the median of the per-repeat ratios with their range; the same
ratio of the commands' CPU time (user + system, ``getrusage`` of the children) is printed
beside it: it moves less when other jobs share the cores.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from aaria_pin.aaria.dh_robot import build_dh_robot
from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.sine_tables import base_motion, joint_trajectory
from aaria_pin.core.dynamics import batched_rnea
from aaria_pin.core.kinematics import full_state
from aaria_pin.core.trajectory import sample_times

RATE = 1000.0
GOAL_SIMULATE = 1.0
GOAL_HELP = 0.3
MESSAGE = "aaria: compiling the IMU kernels once"


def aaria() -> list[str]:
    """The ``aaria`` console script of this interpreter (``python -m aaria_pin.cli`` if none)."""
    script = Path(sys.executable).with_name("aaria")
    return [str(script)] if script.is_file() else [sys.executable, "-m", "aaria_pin.cli"]


def wall(command: list[str], env: dict[str, str] | None = None) -> float:
    return timed(command, env)[0]


def timed(command: list[str], env: dict[str, str] | None = None) -> tuple[float, float]:
    """Wall time and CPU time (user + system) of one run of a command [s]."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run(command, check=True, capture_output=True, env=env)
    elapsed = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return elapsed, cpu


def first_command(folder: Path) -> tuple[float, bool, float, bool]:
    """Wall time and message of ``aaria simulate`` with an empty kernel cache, then the next."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(folder / "numba-cache")}
    command = [*aaria(), "simulate", "--preset", "aaria-fig2", "-o", str(folder / "first.h5")]
    results = []
    for _ in range(2):
        start = time.perf_counter()
        done = subprocess.run(command, check=True, capture_output=True, text=True, env=env)
        results.append((time.perf_counter() - start, MESSAGE in done.stderr))
    return results[0][0], results[0][1], results[1][0], results[1][1]


def startup(folder: Path, repeats: int) -> tuple[float, float]:
    """Medians of the warm ``aaria simulate --preset aaria-fig2`` and of ``aaria --help`` [s]."""
    command = [*aaria(), "simulate", "--preset", "aaria-fig2", "-o", str(folder / "short.h5")]
    wall(command)  # the kernels in the cache, the files in the page cache
    simulate_s = statistics.median(wall(command) for _ in range(repeats))
    help_s = statistics.median(wall([*aaria(), "--help"]) for _ in range(repeats))
    return simulate_s, help_s


def verdict(met: bool) -> str:
    return "met" if met else "NOT met"


def simulate(samples: int, folder: Path) -> list[str]:
    duration = (samples - 1) / RATE
    return [*aaria(), "simulate", "--preset", "aaria-fig2",
            "--duration", repr(duration), "--rate", repr(RATE), "--no-noise",
            "-o", str(folder / f"run{samples}.h5")]  # fmt: skip


def floor_per_sample(samples: int, repeats: int) -> float:
    """The floor per sample [s]: median of ``repeats`` batched RNEAs over ``samples``."""
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
        cold_s, cold_says, next_s, next_says = first_command(folder)
        simulate_s, help_s = startup(folder, 3 if args.smoke else 9)
        wall(simulate(short, folder))  # warm the compiled kernels' cache
        rows = []  # per repeat: short wall, long wall, short CPU, long CPU, floor per sample
        for _ in range(repeats):
            floor_before = floor_per_sample(min(long, 200_000), 3)
            short_wall, short_cpu = timed(simulate(short, folder))
            long_wall, long_cpu = timed(simulate(long, folder))
            floor_after = floor_per_sample(min(long, 200_000), 3)
            floor_now = (floor_before + floor_after) / 2.0
            rows.append((short_wall, long_wall, short_cpu, long_cpu, floor_now))
    short_s = statistics.median(row[0] for row in rows)
    long_s = statistics.median(row[1] for row in rows)
    floor = statistics.median(row[4] for row in rows)
    extra = (long_s - short_s) / (long - short)
    wall_ratios = [(row[1] - row[0]) / (long - short) / row[4] for row in rows]
    cpu_ratios = [(row[3] - row[2]) / (long - short) / row[4] for row in rows]
    print(f"start-up, whole processes ({' '.join(aaria())}), medians")
    print(f"{'what':<52} {'value':>9}   goal")
    print(
        f"{'aaria simulate --preset aaria-fig2 (1,001 samples)':<52} {simulate_s:>7.3f} s"
        f"   < {GOAL_SIMULATE:g} s: {verdict(simulate_s < GOAL_SIMULATE)}"
    )
    print(
        f"{'aaria --help':<52} {help_s:>7.3f} s   < {GOAL_HELP:g} s: {verdict(help_s < GOAL_HELP)}"
    )
    print(
        f"{'first command, empty kernel cache':<52} {cold_s:>7.3f} s   says it compiles: "
        f"{'yes' if cold_says else 'NO'}"
    )
    print(
        f"{'the next command, kernels from the disk cache':<52} {next_s:>7.3f} s   silent: "
        f"{'yes' if not next_says else 'NO'}; compiled once: {verdict(cold_says and not next_says)}"
    )
    print()
    print(f"aaria simulate --preset aaria-fig2 --no-noise at {RATE:g} Hz, median of {repeats}")
    print(f"{'what':<44} {'value':>12}")
    print(f"{f'wall, {short} samples':<44} {short_s:>10.3f} s")
    print(f"{f'wall, {long} samples':<44} {long_s:>10.3f} s")
    print(f"{'extra wall per sample':<44} {extra * 1e6:>9.2f} us")
    print(f"{'floor per sample (rneaInParallel, 1 thread)':<44} {floor * 1e6:>9.2f} us")
    print(f"{'extra per sample / floor per sample':<44} {extra / floor:>12.2f}")
    for label, ratios in (("wall", wall_ratios), ("CPU", cpu_ratios)):
        print(
            f"{f'per repeat, extra {label} / floor: median':<44} {statistics.median(ratios):>12.2f}"
            f"   (range {min(ratios):.2f}-{max(ratios):.2f})"
        )


if __name__ == "__main__":
    main()
