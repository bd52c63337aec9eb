"""The torque-constant check of ``aaria identify --dynamics --torques current`` over many runs.

    python benchmarks/bench_torque_scale.py                # 60 ur5 runs of 6 s at 200 Hz
    python benchmarks/bench_torque_scale.py --runs 5       # a quick look

Each run is ``aaria simulate --robot ur5 --motion fourier`` with motors (rotor inertia 3e-5,
viscous 0.8, Coulomb 2.0, gear ratio 100) and the default current sensors (18.9 mA noise,
6.6 mA steps, k_t 0.036 N·m/A), seeds 20, 21, …; the simulated load cell under the mount is
exact (no wrench-sensor noise model). Each run is fitted three times: with the run's ``k_t``
(the right one), with the run's ``k_t`` and a constant current offset of 20 mA on every joint
(a drive's zero), and with ``k_t`` 3 % too large (``c`` = 1/1.03 expected). Printed: per
joint, the spread and largest ``|z|`` of ``z = (c − c_true)/σ`` (1 and about 3 for an honest
σ), the runs whose right ``k_t`` is called off (false alarms), and the runs whose wrong ``k_t``
is called off on each joint (detections; a joint whose σ is above 1 % is "not checked").
"""

from __future__ import annotations

import argparse
import subprocess
import tempfile
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

HARDWARE = (
    "[actuator]\nrotor_inertia = 3e-5\nviscous = 0.8\ncoulomb = 2.0\ngear_ratio = 100.0\n\n"
    "[current_sensor]\n"
)


def _fit(record: Any, torques: Any) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Each joint's scale, its σ (NaN: not determined) and the joints called off."""
    from aaria_pin.apps.identify import identify_dynamics
    from aaria_pin.apps.identify.inertial_scale import scale_off

    rows = identify_dynamics(record, torques=torques).to_json()["torque_scale"]
    c = np.array([row["scale"] for row in rows])
    std = np.array([np.nan if row["std"] is None else row["std"] for row in rows])
    return c, std, [row["joint"] for row in scale_off(rows)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=60)
    parser.add_argument("--duration", type=float, default=6.0)
    args = parser.parse_args()
    from aaria_pin.apps.identify.inertial_torques import TorqueSource
    from aaria_pin.files.source import open_record

    cases = ("right", "offset", "wrong 3 %")
    z: dict[str, list[np.ndarray]] = {case: [] for case in cases}
    called: dict[str, list[list[str]]] = {case: [] for case in cases}
    std_all: list[np.ndarray] = []
    names: list[str] = []
    with tempfile.TemporaryDirectory() as folder:
        hardware = Path(folder) / "hw.toml"
        hardware.write_text(HARDWARE)
        for seed in range(20, 20 + args.runs):
            path = Path(folder) / f"run_{seed}.h5"
            subprocess.run(
                ["aaria", "simulate", "--robot", "ur5", "--motion", "fourier", "--duration",
                 str(args.duration), "--rate", "200", "--seed", str(seed), "--hardware",
                 str(hardware), "-o", str(path)],
                check=True, capture_output=True,
            )  # fmt: skip
            record = open_record(path, None)
            names = list(record.joint_names)
            tables = dict(record.tables)
            tables["current_measured"] = np.asarray(tables["current_measured"], float) + 0.02
            kt = float(record.attributes["current_sensor"]["torque_constant"])
            for case, run, torques, truth in (
                ("right", record, "current", 1.0),
                ("offset", replace(record, tables=tables), "current", 1.0),
                ("wrong 3 %", record, TorqueSource("current", torque_constant=1.03 * kt), 1 / 1.03),
            ):
                c, std, off = _fit(run, torques)
                z[case].append((c - truth) / std)
                called[case].append(off)
                if case == "right":
                    std_all.append(std)
            path.unlink()
    print(f"{args.runs} ur5 runs of {args.duration:g} s at 200 Hz; joints: {', '.join(names)}")
    sigma = np.nanmedian(np.array(std_all), axis=0)
    print("median σ of c:", " ".join(f"{100 * s:.2g} %" for s in sigma))
    for case in cases:
        values = np.array(z[case])
        alarms = sum(bool(off) for off in called[case])
        print(
            f"{case}: z spread {' '.join(f'{v:.2f}' for v in np.nanstd(values, axis=0))}, "
            f"max |z| {' '.join(f'{v:.1f}' for v in np.nanmax(np.abs(values), axis=0))}; "
            f"runs called off {alarms}/{args.runs}"
        )
    checked = sigma <= 0.01
    found = [sum(name in off for off in called["wrong 3 %"]) for name in names]
    print(
        "wrong 3 % called off per joint: "
        + ", ".join(
            f"{name} {n}/{args.runs}" + ("" if ok else " (σ above 1 %: not checked)")
            for name, n, ok in zip(names, found, checked, strict=True)
        )
    )


if __name__ == "__main__":
    main()
