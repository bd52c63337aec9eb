"""Rotations per second, one core: angles → matrix, matrix → angles, and the wrist's IK.

python benchmarks/bench_rotations.py            # 1,000,000 rotations
python benchmarks/bench_rotations.py --smoke    # CI: 10,000 rotations, no timing asserted
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

if hasattr(os, "sched_setaffinity"):
    os.sched_setaffinity(0, {max(os.sched_getaffinity(0))})  # one core

import numpy as np

from aaria_pin.apps.wrist.wrist_kinematics import wrist_ik_batch
from aaria_pin.core.rotations import angles_from_matrix, matrix_from_angles


def rate(func, n: int, repeats: int) -> float:  # type: ignore[no-untyped-def]
    func()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        func()
        times.append(time.perf_counter() - start)
    return n / statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--smoke", action="store_true")
    args = parser.parse_args()
    n, repeats = (10_000, 1) if args.smoke else (1_000_000, 5)
    angles = np.random.default_rng(0).uniform(-np.pi, np.pi, (n, 3))
    R = matrix_from_angles(angles, "xyz")
    rows = {
        "angles -> matrix (xyz)": rate(lambda: matrix_from_angles(angles, "xyz"), n, repeats),
        "matrix -> angles (xyz)": rate(lambda: angles_from_matrix(R, "xyz"), n, repeats),
        "matrix -> angles (ZYZ)": rate(lambda: angles_from_matrix(R, "ZYZ"), n, repeats),
        "wrist IK, both branches": rate(lambda: wrist_ik_batch(R), n, repeats),
    }
    print(f"{n} rotations, one core, median of {repeats}")
    print(f"{'what':<28} {'rotations/s':>14}")
    for name, value in rows.items():
        print(f"{name:<28} {value:>14,.0f}")


if __name__ == "__main__":
    main()
