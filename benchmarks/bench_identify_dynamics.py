"""Cost of the dynamic identification against Pinocchio's batched RNEA (the floor), on one core.

    python benchmarks/bench_identify_dynamics.py           # ur5 and aaria-fig2, 30 s at 200 Hz
    python benchmarks/bench_identify_dynamics.py --smoke   # CI: a second at 100 Hz, no timing

For each robot (moving base, noise off): the batched RNEA over the run (the floor), the torque
regressor in array form (``torque_regressor``), the same by one Pinocchio
``computeJointTorqueRegressor`` call per sample (``reference_torque_regressor``), and the whole
``identify_dynamics`` (regressor, QR of the stacked regressor, fit, held-out errors, mass and
centre of mass). Medians over repeats measured in turn, and the median ratio to the floor; then
the held-out relative error and the total mass error of the last identification.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path

if hasattr(os, "sched_setaffinity"):
    os.sched_setaffinity(0, {max(os.sched_getaffinity(0))})  # one core

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))  # the oracles

from pinocchio_oracles import reference_torque_regressor

from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.apps.identify import identify_dynamics, torque_regressor
from aaria_pin.apps.record_model import record_base, record_columns, record_model
from aaria_pin.core.catalogue import find_robot
from aaria_pin.core.dynamics import batched_rnea
from aaria_pin.core.kinematics import full_state
from aaria_pin.core.record import RunRecord
from aaria_pin.core.trajectory import JointTrajectory
from aaria_pin.core.urdf_run import simulate_urdf_run


def interleaved(funcs: dict[str, Callable[[], object]], repeats: int) -> dict[str, list[float]]:
    """Times of each function, measured in turn within every repeat (after one warm-up round)."""
    for func in funcs.values():
        func()
    times: dict[str, list[float]] = {name: [] for name in funcs}
    for _ in range(repeats):
        for name, func in funcs.items():
            start = time.perf_counter()
            func()
            times[name].append(time.perf_counter() - start)
    return times


def bench(name: str, record: RunRecord, repeats: int) -> None:
    base = record_base(record)
    assert base is not None
    robot = record_model(record, moving_base=True)
    columns = record_columns(record, robot)
    trajectory = JointTrajectory(
        record.time,
        *(np.ascontiguousarray(x[:, columns]) for x in (record.q, record.qd, record.qdd)),
    )
    q, v, a = full_state(robot, base, trajectory)
    results: list[object] = []
    funcs: dict[str, Callable[[], object]] = {
        "batched RNEA (floor)": lambda: batched_rnea(robot.model, q, v, a),
        "torque_regressor": lambda: torque_regressor(robot, base, trajectory),
        "per-sample Pinocchio regressor": lambda: reference_torque_regressor(
            robot, base, trajectory
        ),
        "identify_dynamics": lambda: results.append(identify_dynamics(record)),
    }
    times = interleaved(funcs, repeats)
    floor = times["batched RNEA (floor)"]
    print(f"\n{name}: {record.n_samples} samples, {len(robot.joint_names)} joints, moving base")
    print(f"{'what':<32} {'median ms':>10} {'per sample µs':>14} {'× floor':>8}")
    for label, values in times.items():
        ratio = statistics.median(t / f for t, f in zip(values, floor, strict=True))
        median = statistics.median(values)
        print(
            f"{label:<32} {median * 1e3:>10.2f} {median / record.n_samples * 1e6:>14.2f}"
            f" {ratio:>8.2f}"
        )
    last = results[-1]
    report = last.to_json()  # type: ignore[attr-defined]
    print(
        f"base parameters {report['n_base']} of {report['n_standard']}; worst held-out relative"
        f" RMS {report['worst_holdout_relative_rms']:.2e}; total mass error"
        f" {report['total_mass']['error']:.2e} kg"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--smoke", action="store_true", help="tiny sizes, for CI")
    parser.add_argument("--duration", type=float, default=30.0)
    parser.add_argument("--rate", type=float, default=200.0)
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    duration, rate, repeats = (
        (1.0, 100.0, 1) if args.smoke else (args.duration, args.rate, args.repeats)
    )
    entry = find_robot("ur5")
    ur5 = simulate_urdf_run(
        entry.urdf.read_text(),
        urdf_dir=entry.urdf.parent,
        duration=duration,
        rate=rate,
        noise=False,
    )
    bench("ur5", ur5, repeats)
    preset = get_preset("aaria-fig2")
    fig2 = simulate_run(
        preset.table,
        preset.joint_table,
        preset.base_table,
        duration=duration,
        rate=rate,
        noise=False,
    )
    bench("aaria-fig2", fig2, repeats)


if __name__ == "__main__":
    main()
