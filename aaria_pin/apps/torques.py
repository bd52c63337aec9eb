"""Torque-level analysis of a run: peaks, RMS, the gravity / Coriolis / inertial split, power.

The split comes from three batched RNEA passes over the whole trajectory, on the full model
with its moving base: gravity ``g(q)`` (RNEA at zero velocity and acceleration), Coriolis and
centrifugal ``C(q, v)·v`` (RNEA at zero acceleration, less gravity) and inertial ``M(q)·a`` (the
full RNEA less the zero-acceleration one), so the three add up to the RNEA torque at every
sample.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from aaria_pin.aaria.sensen import RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.core.trajectory import BaseMotion, JointTrajectory

if TYPE_CHECKING:  # Pinocchio loads only where a model is used, not for a data set's report
    from aaria_pin.core.model import RobotModel

__all__ = [
    "dataset_torque_report",
    "plot_torque_report",
    "record_torque_report",
    "torque_split",
]

_TERMS = ("gravity", "coriolis", "inertial")


def torque_split(
    robot: RobotModel, base: BaseMotion, trajectory: JointTrajectory
) -> dict[str, Array]:
    """Joint torques split into gravity, Coriolis/centrifugal and inertial terms, (T, n) each.

    Args:
        robot: the model
        base: the base motion
        trajectory: joint values over time, columns in model order

    Returns:
        ``{"gravity", "coriolis", "inertial"}``, joint columns only; their sum is the RNEA torque.
    """
    from aaria_pin.core.dynamics import batched_rnea
    from aaria_pin.core.kinematics import full_state

    q, v, a = full_state(robot, base, trajectory)
    zeros = np.zeros_like(v)
    gravity = batched_rnea(robot.model, q, zeros, zeros)  # g(q)
    nonlinear = batched_rnea(robot.model, q, v, zeros)  # C(q, v)·v + g(q)
    total = batched_rnea(robot.model, q, v, a)  # M(q)·a + C(q, v)·v + g(q)
    n_base = robot.base_nv
    return {
        "gravity": gravity[:, n_base:],
        "coriolis": (nonlinear - gravity)[:, n_base:],
        "inertial": (total - nonlinear)[:, n_base:],
    }


def _rms(x: Array) -> Array:
    return np.sqrt(np.mean(np.square(x), axis=0))


def record_torque_report(record: RunRecord) -> dict[str, Any]:
    """Per joint (module) torque statistics of a run, and the base wrench peaks.

    Returns:
        A plain dictionary: ``joints`` (one entry per non-empty module: type, peak |tau|, RMS,
        RMS of each term of the split and its share of their sum, peak |tau·qd| and mean
        mechanical power, net and absolute mechanical energy), ``base_wrench_peak`` (per
        component), ``split_residual`` (largest ``|g + C·v + M·a - tau|``).
    """
    from aaria_pin.aaria.dh_robot import BodyDimensions, build_dh_robot
    from aaria_pin.aaria.oscillation import base_motion

    dims_attr = record.attributes.get("body_dimensions")
    dims = BodyDimensions(**dims_attr) if isinstance(dims_attr, dict) else None
    robot = build_dh_robot(record.senSenDH, "aaria", dims)
    model = robot.model(moving_base=True)
    columns = [module - 1 for module in robot.chain.modules]
    time = record.time
    trajectory = JointTrajectory(
        time, *(np.ascontiguousarray(x[:, columns]) for x in (record.q, record.qd, record.qdd))
    )
    split = torque_split(model, base_motion(record.senSenB, time), trajectory)
    tau = record.tau[:, columns]
    residual = float(np.abs(sum(split.values()) - tau).max())
    dt = float(time[1] - time[0]) if time.size > 1 else 0.0
    power = tau * trajectory.qd
    joints = []
    for index, module in enumerate(robot.chain.modules):
        rms_terms = {term: float(_rms(split[term][:, index])) for term in _TERMS}
        total = sum(rms_terms.values()) or 1.0
        joints.append(
            {
                "module": module,
                "type": robot.chain.joints[index].kind,
                "unit": "N*m" if robot.chain.joints[index].kind == "revolute" else "N",
                "peak_abs": float(np.abs(tau[:, index]).max()),
                "rms": float(_rms(tau[:, index])),
                "rms_terms": rms_terms,
                "shares": {term: value / total for term, value in rms_terms.items()},
                "power_peak_W": float(np.abs(power[:, index]).max()),
                "power_mean_W": float(np.mean(power[:, index])),
                "energy_net_J": float(np.trapezoid(power[:, index], dx=dt)),
                "energy_abs_J": float(np.trapezoid(np.abs(power[:, index]), dx=dt)),
            }
        )
    wrench_peak = np.abs(record.base_wrench).max(axis=0)
    return {
        "samples": int(time.size),
        "joints": joints,
        "base_wrench_peak": dict(
            zip(("fx", "fy", "fz", "mx", "my", "mz"), wrench_peak.tolist(), strict=True)
        ),
        "split_residual": residual,
    }


def dataset_torque_report(path: str, top: int = 5) -> dict[str, Any]:
    """Peak |tau| over a data set, per joint position and type, and the runs with the largest.

    Read from the stored torques; no model is built.

    Args:
        path: the data set file
        top: how many of the largest-peak runs to list

    Returns:
        ``by_module`` (module → type → count, median, 95th percentile and maximum of the runs'
        peak |tau|) and ``largest`` (run, module, type, peak), largest first.
    """
    from aaria_pin.files.dataset_reader import DatasetReader

    peaks: dict[tuple[int, str], list[float]] = {}
    largest: list[tuple[float, int, int, str]] = []
    names = {1: "revolute", 2: "prismatic"}
    with DatasetReader(path) as reader:
        for run in np.flatnonzero(reader.complete):
            arrays = reader.run(int(run), ("senSenDH", "tau"))
            for row in range(6):
                kind = names.get(int(arrays["senSenDH"][row, 4]))
                if kind is None:
                    continue
                peak = float(np.abs(arrays["tau"][:, row]).max())
                peaks.setdefault((row + 1, kind), []).append(peak)
                largest.append((peak, int(run), row + 1, kind))
    by_module: dict[str, dict[str, dict[str, float]]] = {}
    for (module, kind), values in sorted(peaks.items()):
        v = np.array(values)
        by_module.setdefault(str(module), {})[kind] = {
            "runs": int(v.size),
            "median": float(np.median(v)),
            "p95": float(np.percentile(v, 95)),
            "max": float(v.max()),
        }
    largest.sort(reverse=True)
    return {
        "by_module": by_module,
        "largest": [
            {"run": run, "module": module, "type": kind, "peak_abs": peak}
            for peak, run, module, kind in largest[:top]
        ],
    }


def plot_torque_report(report: dict[str, Any], path: str, title: str = "joint torques") -> None:
    """Bars of each joint's RMS torque split into gravity, Coriolis and inertial, and its peak.

    Needs matplotlib (``pip install 'aaria-pin[plot]'``); written atomically as a PNG.
    """
    from aaria_pin.files.io import atomic_output
    from aaria_pin.viz._plotting import pyplot

    plt = pyplot()
    joints = report["joints"]
    labels = [f"{j['module']} ({j['type'][0]}, {j['unit']})" for j in joints]
    x = np.arange(len(joints))
    figure, axes = plt.subplots(figsize=(7, 4), dpi=100)
    bottom = np.zeros(len(joints))
    for term, colour in zip(_TERMS, ("tab:green", "tab:orange", "tab:blue"), strict=True):
        values = np.array([j["rms_terms"][term] for j in joints])
        axes.bar(x, values, bottom=bottom, color=colour, label=f"RMS {term}")
        bottom += values
    axes.plot(x, [j["peak_abs"] for j in joints], "kD", label="peak |tau|")
    axes.set_xticks(x, labels)
    axes.set_xlabel("module (type, unit)")
    axes.set_ylabel("torque [N*m] or force [N]")
    axes.set_title(title)
    axes.legend()
    figure.tight_layout()
    with atomic_output(path) as temporary:
        figure.savefig(temporary, format="png")
    plt.close(figure)
