"""Per-sample cost of the torque drive against MuJoCo on the same robots, in one process.

    python benchmarks/bench_forward.py            # full: 2 s at 500 Hz per robot, 5 repeats
    python benchmarks/bench_forward.py --repeats 21   # the docs' table: medians of 21
    python benchmarks/bench_forward.py --smoke    # CI: 0.1 s, one repeat, no timing asserted
    python benchmarks/bench_forward.py --closed-loop --repeats 7  # closed loops vs the drive

Robots: ur5 and panda on a fixed base, aaria-fig2 on its moving base (the base prescribed by its
base table). Ours: the integrator of new torque runs, ``DYNAMICS["aba"]`` (the compiled
articulated-body kernel), RK4 with 4 sub-steps, constant torques (gravity at the neutral pose)
from rest; the compiled CRBA kernel of older runs (``kernel``,
:func:`~aaria_pin.core.forward.forward_simulate`) and the Pinocchio twin
:func:`~aaria_pin.core.forward.reference_forward_simulate`. MuJoCo: the exported MJCF
(:func:`~aaria_pin.core.export.mjcf_emit.emit_mjcf`), RK4 at the sub-step timestep (4 steps per
sample), contacts off (our model has none): ``mujoco.rollout`` (no controls: the joints'
torques zero) and plain ``mj_step`` in a Python loop with the same torques in ``qfrc_applied``.
On the moving base MuJoCo integrates the 6-DOF base chain too (the base is not prescribed there),
so its model has 6 more degrees of freedom. The timings are interleaved (each repeat runs every
one in turn, so a busy machine slows them alike). Prints the median over repeats of each, per
sample [µs], and the ratio of ours to MuJoCo's ``rollout`` and to its ``mj_step`` loop.
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable

import numpy as np
import pinocchio as pin

from aaria_pin.aaria.dh_robot import build_dh_robot
from aaria_pin.aaria.presets import get_preset
from aaria_pin.core.catalogue import find_robot
from aaria_pin.core.export.mjcf_emit import emit_mjcf, load_mjcf
from aaria_pin.core.forward import DYNAMICS, forward_simulate, reference_forward_simulate
from aaria_pin.core.model import RobotModel
from aaria_pin.core.oscillation import base_motion
from aaria_pin.core.trajectory import BaseMotion, sample_times
from aaria_pin.core.urdf_robot import load_urdf_robot, read_urdf_file

RATE, SUBSTEPS = 500.0, 4
CASES = (("ur5", False), ("panda", False), ("aaria-fig2", True))


def _robot(name: str, moving_base: bool) -> tuple[RobotModel, str]:
    """The Pinocchio model and the URDF text of a robot."""
    if name.startswith("aaria"):
        dh = build_dh_robot(get_preset(name).table)
        return dh.model(moving_base=moving_base), dh.urdf
    text = read_urdf_file(find_robot(name).urdf)
    return load_urdf_robot(text, moving_base=moving_base).robot, text


def _medians(runs: dict[str, Callable[[], object]], repeats: int) -> dict[str, float]:
    """Median wall time of each run [s], the runs interleaved within each repeat."""
    times: dict[str, list[float]] = {name: [] for name in runs}
    for _ in range(repeats):
        for name, run in runs.items():
            start = time.perf_counter()
            run()
            times[name].append(time.perf_counter() - start)
    return {name: statistics.median(values) for name, values in times.items()}


def _case(name: str, moving_base: bool, duration: float, repeats: int) -> dict[str, float]:
    import mujoco
    from mujoco import rollout

    robot, urdf = _robot(name, moving_base)
    times = sample_times(duration, RATE)
    steps = times.size - 1
    base = (
        base_motion(get_preset("aaria-fig2").base_table, times)
        if moving_base
        else (BaseMotion.resting(times.size))
    )
    n = robot.n_joints
    fixed = robot if not moving_base else _robot(name, False)[0]
    gravity = pin.computeGeneralizedGravity(
        fixed.model, fixed.model.createData(), pin.neutral(fixed.model)
    )
    tau = np.tile(gravity, (times.size, 1))
    q0, v0 = np.zeros(n), np.zeros(n)

    def ours() -> object:
        return DYNAMICS["aba"](robot, base, tau, times, q0, v0, substeps=SUBSTEPS)

    def crba() -> object:
        return forward_simulate(robot, base, tau, times, q0, v0, substeps=SUBSTEPS)

    def reference() -> object:
        return reference_forward_simulate(robot, base, tau, times, q0, v0, substeps=SUBSTEPS)

    ours()  # compile or load the kernels
    crba()
    xml, _ = emit_mjcf(urdf, (), moving_base=moving_base)
    model = load_mjcf(xml)
    model.opt.timestep = 1.0 / (RATE * SUBSTEPS)
    model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
    data = mujoco.MjData(model)
    joints = slice(model.nv - n, model.nv)
    state_size = mujoco.mj_stateSize(model, mujoco.mjtState.mjSTATE_FULLPHYSICS)
    initial = np.zeros(state_size)
    mujoco.mj_getState(model, data, initial, mujoco.mjtState.mjSTATE_FULLPHYSICS)

    def mj_rollout() -> object:
        return rollout.rollout(model, data, initial, nstep=steps * SUBSTEPS)

    def mj_loop() -> object:
        mujoco.mj_resetData(model, data)
        for k in range(steps):
            data.qfrc_applied[joints] = tau[k]
            for _ in range(SUBSTEPS):
                mujoco.mj_step(model, data)
        return data

    mj_rollout()
    runs = {"ours": ours, "crba": crba, "rollout": mj_rollout, "mj_step": mj_loop}
    result = _medians(runs, repeats)
    result["pinocchio"] = _medians({"pinocchio": reference}, max(1, repeats // 2))["pinocchio"]
    return {name: value / steps for name, value in result.items()}


def _closed_loop(repeats: int, duration: float) -> None:
    """The closed-loop drives on ur5 (fixed base, the default sine motion, 100 Hz, the default
    controller: 20 ticks a sample) against the torque drive at the same step, in ms a run."""
    from aaria_pin.core.control import closed_loop_simulate
    from aaria_pin.core.joint_sensors import ControllerModel
    from aaria_pin.core.trajectory import JointTrajectory
    from aaria_pin.core.urdf_run import urdf_request

    text = read_urdf_file(find_robot("ur5").urdf)
    made = urdf_request(text, source="ur5", noise=False, moving_base=False, duration=duration)
    run = made.record()
    robot = load_urdf_robot(text, moving_base=False).robot
    base = BaseMotion.resting(run.time.size)
    reference = JointTrajectory(run.time, run.q, run.qd, run.qdd)
    runs: dict[str, Callable[[], object]] = {
        "torque drive": lambda: DYNAMICS["aba"](
            robot, base, run.tau, run.time, run.q[0], run.qd[0], substeps=20
        ),
        **{
            law: lambda law=law: closed_loop_simulate(
                robot, base, reference, law, ControllerModel()
            )
            for law in ("pd", "computed-torque")
        },
    }
    for once in runs.values():
        once()  # compile or load the kernels
    result = _medians(runs, repeats)
    print(f"ur5, {duration:g} s at 100 Hz, 20 steps a sample, median of {repeats} [ms a run]")
    for name, value in result.items():
        ratio = value / result["torque drive"]
        print(f"{name:<16} {value * 1e3:8.1f}  {ratio:5.2f}x the drive")


def main() -> None:
    """Print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true", help="0.1 s, one repeat")
    parser.add_argument("--repeats", type=int, default=5, help="repeats (median; default 5)")
    parser.add_argument("--closed-loop", action="store_true", help="the closed-loop drives")
    args = parser.parse_args()
    if args.closed_loop:
        _closed_loop(1 if args.smoke else args.repeats, 0.2 if args.smoke else 10.0)
        return
    duration, repeats = (0.1, 1) if args.smoke else (2.0, args.repeats)
    print(f"µs/sample, {RATE:g} Hz, RK4 × {SUBSTEPS}, {duration:g} s, median of {repeats}")
    header = (
        "robot                   ours    crba  pinocchio  rollout  mj_step  ours/rollout"
        "  ours/mj_step  crba/rollout"
    )
    print(header)
    for name, moving_base in CASES:
        r = {k: v * 1e6 for k, v in _case(name, moving_base, duration, repeats).items()}
        label = f"{name}{' (moving)' if moving_base else ''}"
        print(
            f"{label:<20} {r['ours']:7.1f} {r['crba']:7.1f} {r['pinocchio']:10.1f} "
            f"{r['rollout']:8.1f} {r['mj_step']:8.1f} {r['ours'] / r['rollout']:13.2f} "
            f"{r['ours'] / r['mj_step']:13.2f} {r['crba'] / r['rollout']:13.2f}"
        )


if __name__ == "__main__":
    main()
