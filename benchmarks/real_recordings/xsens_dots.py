"""Four Xsens DOT exports of one flight -> one ``aaria import`` CSV and its map (TOML).

The ANSFL quadrotor set (ansfl/Quadrotor-Dead-Reckoning-with-Multiple-Inertial-Sensors,
``StraightLine/RAW/Xsens DOT<k>_*_20220707_<hhmm>*.csv``, CC BY 4.0): per DOT, SampleTimeFine
[µs] on the DOTs' synchronised clock, Acc_X..Z [m/s²] (specific force), Gyr_X..Z [deg/s], 120 Hz.
The four DOTs' stamps lie on one 8333 µs grid, so rows are joined on equal stamps; a row whose six
values are all zero (each file's first) or not finite is dropped.

Usage::

    python xsens_dots.py SOURCE_DIR HHMM OUT_DIR   # -> OUT_DIR/session_HHMM.csv, session.toml
    aaria import OUT_DIR/session_HHMM.csv --map OUT_DIR/session.toml -o session_HHMM.h5
    aaria identify --rigid dot1 dot2 session_HHMM.h5
"""

from __future__ import annotations

import csv
import math
import sys
from pathlib import Path

DOTS = ("dot1", "dot2", "dot4", "dot7")
COLUMNS = ("gx", "gy", "gz", "ax", "ay", "az")


def read_dot(path: Path) -> dict[int, list[float]]:
    """One DOT's rows by stamp [µs]: gyroscope [rad/s], then specific force [m/s²]."""
    rows: dict[int, list[float]] = {}
    with path.open(newline="") as handle:
        reader = csv.reader(handle)
        index = {name: i for i, name in enumerate(next(reader))}
        for row in reader:
            if len(row) < 10 or not row[0]:
                continue
            gyro = [math.radians(float(row[index[f"Gyr_{a}"]])) for a in "XYZ"]
            values = gyro + [float(row[index[f"Acc_{a}"]]) for a in "XYZ"]
            if all(math.isfinite(v) for v in values) and any(values):
                rows[int(row[index["SampleTimeFine"]])] = values
    return rows


def main(source: Path, label: str, out: Path) -> None:
    """Write ``session_<label>.csv`` and ``session.toml`` into ``out``."""
    data = {}
    for dot in DOTS:
        (path,) = source.glob(f"Xsens {dot.upper()}_*_20220707_{label}*.csv")
        data[dot] = read_dot(path)
    common = sorted(set.intersection(*(set(rows) for rows in data.values())))
    out.mkdir(parents=True, exist_ok=True)
    with (out / f"session_{label}.csv").open("w", newline="") as handle:
        writer = csv.writer(handle, lineterminator="\n")
        writer.writerow(["t"] + [f"{dot}_{c}" for dot in DOTS for c in COLUMNS])
        for stamp in common:
            values = [repr(v) for dot in DOTS for v in data[dot][stamp]]
            writer.writerow([repr((stamp - common[0]) * 1e-6), *values])
    lines = ['time_column = "t"']
    for dot in DOTS:
        columns = ", ".join(f'"{dot}_{c}"' for c in COLUMNS)
        lines += ["[[imu]]", f'name = "{dot}"', f"columns = [{columns}]"]
    (out / "session.toml").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main(Path(sys.argv[1]), sys.argv[2], Path(sys.argv[3]))
