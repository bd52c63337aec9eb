"""Project Aria glasses: the left and right IMU of a VRS file -> an MCAP, and the comparison.

Two steps, two environments. ``extract`` needs ``projectaria-tools`` (2.3.0 was used; not a
dependency of aaria_pin: a venv of its own): it reads both IMUs, rectifies them with the
device's stored calibration (``raw_to_rectified_gyro/accel``) and writes ``imu_left.csv``,
``imu_right.csv`` (``t_ns``, gyroscope [rad/s], accelerometer [m/s²]) and ``geometry.json``
(``T_Device_Imu`` of both, their time offsets). ``mcap`` (aaria_pin's environment) writes the
two streams, each at its own stamps, to ``aria.mcap``; ``compare`` sets ``aaria identify
--rigid imu_left imu_right aria.mcap --json`` against the stored geometry. Aria's time
convention (``CameraCalibration.h``): corrected = capture − ``TimeOffsetSec_Device_X``, so the
expected offset of the right IMU is the left's minus the right's.

Usage::

    ARIA/bin/python aria_glasses.py extract recording.vrs OUT
    python aria_glasses.py mcap OUT
    aaria identify --rigid imu_left imu_right OUT/aria.mcap --json > OUT/rigid.json
    python aria_glasses.py compare OUT
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

LABELS = ("imu-left", "imu-right")


def extract(vrs: str, out: Path) -> None:
    """Both IMUs, rectified, and the stored geometry (projectaria-tools)."""
    from projectaria_tools.core import data_provider

    provider = data_provider.create_vrs_data_provider(vrs)
    calibration = provider.get_device_calibration()
    geometry: dict[str, object] = {}
    for label in LABELS:
        stream, imu = provider.get_stream_id_from_label(label), calibration.get_imu_calib(label)
        rows = []
        for k in range(provider.get_num_data(stream)):
            sample = provider.get_imu_data_by_index(stream, k)
            gyro = imu.raw_to_rectified_gyro(np.asarray(sample.gyro_radsec))
            accel = imu.raw_to_rectified_accel(np.asarray(sample.accel_msec2))
            rows.append([sample.capture_timestamp_ns, *gyro, *accel])
        name = label.replace("-", "_")
        np.savetxt(out / f"{name}.csv", np.array(rows), delimiter=",", comments="",
                   header="t_ns,gx,gy,gz,ax,ay,az", fmt=["%d"] + ["%.9g"] * 6)  # fmt: skip
        geometry[label] = {
            "T_Device_Imu": imu.get_transform_device_imu().to_matrix().tolist(),
            "time_offset_gyro_s": imu.get_time_offset_sec_device_gyro(),
            "time_offset_accel_s": imu.get_time_offset_sec_device_accel(),
        }
    (out / "geometry.json").write_text(json.dumps(geometry, indent=1))


def mcap(out: Path) -> None:
    """The two IMUs, each at its own stamps, as ``aria.mcap``."""
    from aaria_pin.apps.recordings import export_run
    from aaria_pin.core.recording import STREAM_COLUMNS, RecordedRun, SensorStream

    names = ("imu_left", "imu_right")
    data = {n: np.loadtxt(out / f"{n}.csv", delimiter=",", skiprows=1) for n in names}
    origin = int(min(d[0, 0] for d in data.values()))
    streams = [
        SensorStream(n, "imu", (d[:, 0] - origin) * 1e-9, d[:, 1:7], STREAM_COLUMNS["imu"])
        for n, d in data.items()
    ]
    export_run(RecordedRun(streams, time_origin_ns=origin), out / "aria.mcap")


def compare(out: Path) -> None:
    """The fit against the stored geometry: position [mm], rotation [deg], time offset [ms]."""
    from scipy.spatial.transform import Rotation

    geometry = json.loads((out / "geometry.json").read_text())
    fit = json.loads((out / "rigid.json").read_text())["pairs"][0]
    left, right = (np.array(geometry[label]["T_Device_Imu"]) for label in LABELS)
    T_left_right = np.linalg.inv(left) @ right
    error = fit["position_m"] - T_left_right[:3, 3]
    turn = Rotation.from_matrix(np.array(fit["rotation"]) @ T_left_right[:3, :3].T).as_rotvec()
    print(f"position error {np.linalg.norm(error) * 1e3:.2f} mm {np.round(error * 1e3, 2)}")
    print(f"rotation error {np.degrees(np.linalg.norm(turn)):.3f} deg")
    offset, sigma = fit["time_offset_s"] * 1e3, fit["time_offset_sigma_s"] * 1e3
    print(f"time offset {offset:.3f} +/- {sigma:.3f} ms")
    for sensor in ("gyro", "accel"):
        stored = [geometry[label][f"time_offset_{sensor}_s"] for label in LABELS]
        print(f"  stored ({sensor}): {(stored[0] - stored[1]) * 1e3:.3f} ms")


if __name__ == "__main__":
    step, *args = sys.argv[1:]
    if step == "extract":
        extract(args[0], Path(args[1]))
    else:
        {"mcap": mcap, "compare": compare}[step](Path(args[0]))
