"""Commented, valid input files to start from: ``aaria template KIND``.

The kinds: dh, joints, base, imu-layout, config, imu-model, hardware.

Each template is a file the commands read as it is (and simulate): the tables are CSV with ``#``
comments and a header row of the column names the readers check
(:func:`aaria_pin.files.io.read_table`), filled with the paper's Figure 2 arm and the motions the
commands use by default; the IMU layout and the data-set configuration are TOML with every key
explained. Numbers are written with ``repr`` so a template reads back bit for bit.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from aaria_pin.aaria.dh import AARIA_COLUMNS, chain_from_table
from aaria_pin.aaria.hardware_templates import hardware_template, imu_model_template
from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.randomize import default_config_toml
from aaria_pin.aaria.sine_tables import (
    BASE_COLUMNS,
    JOINT_COLUMNS,
    default_base_table,
    default_joint_table,
)
from aaria_pin.core.imu_presets import DEFAULT_IMU_MODEL, imu_model_toml
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = ["TEMPLATE_FILES", "TEMPLATE_KINDS", "template_text"]

_PRESET = "aaria-fig2"

_DH_UNITS = ("rad", "m", "rad", "m", "")
_JOINT_UNITS = ("rad", "m", "rad or m", "rad/s", "rad")
_BASE_UNITS = ("m or rad", "m or rad", "rad/s", "rad")


def _csv(comment: str, names: Sequence[str], units: Sequence[str], table: Array) -> str:
    """A CSV table: ``#`` comment lines, a header of names with units, rows by ``repr``."""
    header = ",".join(
        f"{name} [{unit}]" if unit else name for name, unit in zip(names, units, strict=True)
    )
    rows = [",".join(repr(float(v)) for v in row) for row in np.asarray(table, dtype=float)]
    lines = [f"# {line}".rstrip() for line in comment.strip("\n").splitlines()]
    return "\n".join([*lines, header, *rows]) + "\n"


def _dh() -> str:
    table = get_preset(_PRESET).table
    return _csv(
        f"""
Extended DH table of an Aaria arm (aaria urdf|simulate|dataset --dh FILE), 8 rows x 5 columns.
Filled with the paper's Figure 2 arm (preset {_PRESET}, Table 3).
Rows 1-6: the modules, in order from the base; row 7: the tool (its a is the tool length);
row 8: the base (unused, kept for the shape).
Columns: alpha [rad], a [m], theta [rad], d [m], link type (0 empty, 1 revolute, 2 prismatic).
  revolute module:  Rx(alpha) Tz(d) Rz(q) Tx(a)    (theta unused; d is the offset along z)
  prismatic module: Rx(alpha) Rz(theta) Tz(q) Tx(a) (d is the rail length; q in [-d/2, d/2])
Lengths a and d from 0 to 100 m; at least one module not empty.
The header row is checked: these names in any order, or a header of other names (then the
columns are taken in this order). Comments start with #.
For a standard or modified DH table (--convention standard|modified): n rows (1-12) of the
same columns, link type 1 or 2, theta and d as offsets.
""",
        AARIA_COLUMNS,
        _DH_UNITS,
        table,
    )


def _joints() -> str:
    table = default_joint_table(chain_from_table(get_preset(_PRESET).table))
    return _csv(
        f"""
Joint oscillation table of an Aaria arm (aaria simulate|dataset --joints FILE), 8 rows x 5.
Filled with the default motion of the Figure 2 arm (preset {_PRESET}); row i drives module i,
rows of empty modules and rows 7-8 are ignored (keep them zero).
Module i follows q_i(t) = A sin(frequency t + phase) + bias, with A the amplitude [rad] of a
revolute module or the prismatic amplitude [m] of a prismatic one.
Every joint must stay in its range, bias +/- |A|: a revolute joint within [-2 pi, 2 pi] rad, a
prismatic joint within [-d/2, d/2] of its rail (d of its DH row).
For a URDF robot (--robot/--urdf) the table has one row per actuated joint, same columns.
""",
        JOINT_COLUMNS,
        _JOINT_UNITS,
        table,
    )


def _base() -> str:
    return _csv(
        """
Base oscillation table (aaria simulate|dataset --base FILE), 2 rows x 4 columns.
Row 1 moves the base along world x, y and z (the same sine on each) [m];
row 2 turns it through gimbal angles ax, ay, az (the same sine on each) [rad], with
R_base = Rx(ax) Ry(ay) Rz(az). Each follows amplitude sin(frequency t + phase) + bias.
A 6 x 4 table gives one row per axis instead: x, y, z [m], then ax, ay, az [rad].
Filled with the commands' default: +/-5 cm at 1.0 rad/s, +/-0.05 rad at 0.7 rad/s.
""",
        BASE_COLUMNS,
        _BASE_UNITS,
        default_base_table(),
    )


def _imu_layout() -> str:
    return """\
# IMU layout of a URDF robot (aaria simulate --robot ur5 --imu-layout FILE, or --urdf FILE).
# It replaces the default layout (two IMUs per moving link, one on the base, one on the tool).
# One [[imu]] table per IMU, in the order of the record's imu axis; written for ur5.
#   name:   unique, not already a frame of the robot
#   parent: a link, joint or frame of the URDF the IMU is fixed to
#   xyz:    position in the parent frame [m] (default [0, 0, 0])
#   rpy:    orientation in the parent frame, URDF fixed-axis roll, pitch, yaw [rad]
#           (default [0, 0, 0])
# Each IMU measures [wx wy wz] [rad/s] and [fx fy fz] specific force [m/s^2] in its own axes.

[[imu]]
name = "imu_base"
parent = "base_link"
xyz = [0.0, 0.0, 0.0]
rpy = [0.0, 0.0, 0.0]

[[imu]]
name = "imu_forearm"
parent = "forearm_link"
xyz = [0.2, 0.0, 0.05]
rpy = [0.0, 0.0, 0.0]

[[imu]]
name = "imu_wrist"
parent = "wrist_3_link"
xyz = [0.0, 0.0, 0.05]
rpy = [0.0, 0.0, 1.5707963267948966]
"""


def _config() -> str:
    return f"""\
{default_config_toml().rstrip()}

# Hardware: the tables of a hardware file (aaria template hardware: [imu], [encoder],
# [torque_sensor], [actuator], [controller], [current_sensor], each explained); a table left
# out is off ([imu]: the --imu-model preset). Any number may be a range [low, high], drawn for
# each run.
# [controller] (the gains of --drive pd|computed-torque) goes with those drives only, e.g.
#   [controller]
#   frequency = [30.0, 60.0]  # closed-loop natural frequency [Hz], drawn per run
#
# IMU (--noise): the preset adis16485 (aaria template imu-model --imu-model NAME: another);
# a key left out keeps the preset's value.
{imu_model_toml(DEFAULT_IMU_MODEL)}"""


def _recording() -> str:
    return """\
# A recording map: which topics (or CSV columns) are which sensors, for
#   aaria import REC... --map rec.toml -o rec.h5
# REC: a ROS 1 .bag, a ROS 2 bag folder (or its .db3 / .mcap), an .mcap file, or a .csv table.
# As written it maps what `aaria export` writes of an aaria-fig2 run:
#   aaria simulate --preset aaria-fig2 -o run.h5 && aaria export run.h5 -o run.mcap
# Without --map (nor --imu, --joints, --wrench) every Imu, JointState and WrenchStamped
# topic is taken; a sensor named here by a flag is replaced by the flag's.

# Each sensor's time: "header" (its messages' header stamps: when the driver measured)
# or "log" (when the recorder received them).
time = "header"
time_column = "time"        # a CSV table's time column [s]

[joints]
topic = "/joint_states"     # sensor_msgs/JointState; joints joined by name

# One [[imu]] per IMU; name = the IMU's name in your model or IMU layout.
# sensor_msgs/Imu: angular_velocity [rad/s], linear_acceleration = specific force [m/s^2].
[[imu]]
name = "imu_tool"
topic = "/imu/imu_tool"
# frame_id = "tool_imu"     # only this frame id's messages (several IMUs on one topic)
# columns = ["gx", "gy", "gz", "ax", "ay", "az"]  # a CSV: its six columns (wx wy wz fx fy fz)

[[imu]]
name = "imu_link6_b"
topic = "/imu/imu_link6_b"

[[imu]]
name = "imu_base"
topic = "/imu/imu_base"

[[wrench]]                  # geometry_msgs/WrenchStamped: force [N], moment [N*m]
name = "base"
topic = "/wrench/base"
"""


_TEMPLATES: dict[str, Callable[[], str]] = {
    "dh": _dh,
    "joints": _joints,
    "base": _base,
    "imu-layout": _imu_layout,
    "config": _config,
    "imu-model": imu_model_template,
    "hardware": hardware_template,
    "recording": _recording,
}

TEMPLATE_KINDS: tuple[str, ...] = tuple(_TEMPLATES)
"""The templates there are."""

TEMPLATE_FILES: dict[str, str] = {
    "dh": "dh.csv",
    "joints": "joints.csv",
    "base": "base.csv",
    "imu-layout": "imu_layout.toml",
    "config": "config.toml",
    "imu-model": "imu_model.toml",
    "hardware": "hardware.toml",
    "recording": "recording.toml",
}
"""A file name for each template (its suffix is the one the commands read)."""


def template_text(kind: str, imu_model: str | None = None) -> str:
    """The text of a template file.

    Args:
        kind: one of :data:`TEMPLATE_KINDS`
        imu_model: the preset of the ``imu-model`` template (default ``adis16485``)

    Raises:
        ParameterError: an unknown kind, an unknown preset, or a preset for another kind.
    """
    if kind not in _TEMPLATES:
        raise ParameterError(
            parameter="kind", value=kind, allowed=", ".join(TEMPLATE_KINDS), element=None
        )
    if imu_model is not None:
        if kind != "imu-model":
            raise ParameterError(parameter="imu_model", value=imu_model, allowed="imu-model only")
        return imu_model_template(imu_model)
    return _TEMPLATES[kind]()
