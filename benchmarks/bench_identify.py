"""Accuracy and cost of the kinematic identification over random Aaria arms, on one core.

    python benchmarks/bench_identify.py               # 20 random arms, 30 s at 200 Hz, no noise
    python benchmarks/bench_identify.py -n 100 --noise
    python benchmarks/bench_identify.py --smoke       # CI: two short runs, no goal checked
    python benchmarks/bench_identify.py -n 20 --motion fourier   # Fourier excitation instead
    python benchmarks/bench_identify.py -n 20 --float32  # series rounded as data sets store them

Each arm is drawn as ``aaria dataset`` draws run k (structure, joint and base tables of the
default ranges, seed 0), simulated (``simulate_run``), then identified from its record
(``identify_kinematics``). With ``--motion fourier`` the joints follow a random Fourier
excitation (``dh_fourier_excitation``, seed k) instead of the joint table's sines; the base
moves alike. With ``--float32`` the record's time, joint and IMU series are rounded to float32,
as ``aaria dataset`` stores them by default. Printed per arm: the link types right, the tool
tip's RMS and largest position error over the run (independent Pinocchio forward kinematics of
the estimated and the true table), the largest joint axis angle error, the named deficiencies
and the seconds; then the share of arms with every link type right, the share within 1 mm (1 cm
with noise), and the median and largest time against the floor: the simulation of the same run
(``simulate_run``).
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import statistics
import time

if hasattr(os, "sched_setaffinity"):
    os.sched_setaffinity(0, {max(os.sched_getaffinity(0))})  # one core

import numpy as np

from aaria_pin.aaria.randomize import (
    PARTS,
    load_config,
    random_base_table,
    random_dh_table,
    random_joint_table,
)
from aaria_pin.aaria.simulate import dh_fourier_excitation, simulate_run
from aaria_pin.apps.identify import identify_kinematics
from aaria_pin.core.seeds import RunSeeds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", type=int, default=20, help="random arms")
    parser.add_argument("--duration", type=float, default=30.0)
    parser.add_argument("--rate", type=float, default=200.0)
    parser.add_argument("--noise", action="store_true", help="ADIS16485 noise on")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--motion", choices=("sine", "fourier"), default="sine")
    parser.add_argument("--first", type=int, default=0, help="first arm")
    parser.add_argument("--float32", action="store_true", help="series rounded to float32")
    parser.add_argument("--smoke", action="store_true")
    args = parser.parse_args()
    if args.smoke:
        args.n, args.duration, args.rate = 2, 2.0, 50.0
    config = load_config(None)
    goal = 0.01 if args.noise else 1e-3
    rows = []
    for k in range(args.first, args.first + args.n):
        structure, joints, base = (RunSeeds(args.seed, k).generator(p) for p in PARTS)
        table = random_dh_table(config, structure)
        joint_table = random_joint_table(config, table, joints)
        base_table = random_base_table(config, base)
        start = time.perf_counter()
        record = simulate_run(
            table,
            joint_table,
            base_table,
            duration=args.duration,
            rate=args.rate,
            noise=args.noise,
            seed=k,
            motion=(
                dh_fourier_excitation(table, args.duration, args.rate, seed=k)
                if args.motion == "fourier"
                else None
            ),
        )
        floor = time.perf_counter() - start
        if args.float32:
            record = dataclasses.replace(
                record,
                **{
                    name: np.asarray(getattr(record, name)).astype(np.float32).astype(float)
                    for name in ("time", "q", "imu")
                },
            )
        start = time.perf_counter()
        result = identify_kinematics(record)
        seconds = time.perf_counter() - start
        truth = result.truth
        assert truth is not None
        types = "".join(str(int(t)) for t in table[:6, 4])
        if result.failure is not None:
            print(f"arm {k:3d} types {types} identification failed: {result.failure}")
        right = all(truth.link_types_right)
        axis = max(truth.axis_angle_max.values(), default=0.0)
        rows.append((right, truth.tool_tip_rms, seconds, seconds / floor))
        print(
            f"arm {k:3d} types {types} right {right!s:5} tool tip rms {truth.tool_tip_rms:9.2e} m"
            f" max {truth.tool_tip_max:9.2e} m  axis {axis:8.1e} rad  {seconds:5.1f} s"
            f" ({seconds / floor:5.0f}x floor)  "
            + "; ".join(d.description for d in result.deficiencies)
        )
    types_right = np.mean([r[0] for r in rows])
    within = np.mean([r[1] <= goal for r in rows])
    print(
        f"{args.n} arms, {args.duration:g} s at {args.rate:g} Hz, noise {args.noise}, "
        f"motion {args.motion}, float32 {args.float32}: "
        f"link types right {types_right:.1%}; tool tip RMS <= {goal:g} m: {within:.1%}; "
        f"seconds median {statistics.median(r[2] for r in rows):.1f}, max "
        f"{max(r[2] for r in rows):.1f}; ratio to the simulation floor median "
        f"{statistics.median(r[3] for r in rows):.0f}x"
    )


if __name__ == "__main__":
    main()
