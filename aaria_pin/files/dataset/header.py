"""A data set's header: its file attributes, read once and typed (:class:`DatasetHeader`).

The readers of a data set (:class:`~aaria_pin.files.dataset.reader.DatasetReader`, its summary,
the data card) take what they need from the header's fields; only
:meth:`DatasetHeader.from_attributes` reads the attributes by name. Values keep the types they
are stored with (a rate stored as an int stays one), so what is printed from them does not change.
"""

from __future__ import annotations

import math
import os
import shlex
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from aaria_pin.errors import InputFileError

__all__ = ["DatasetHeader"]


_NUMBERS = {
    "N": True,
    "samples": True,
    "seed": True,
    "noise_stream": True,
    "rate": False,
    "duration": False,
}
"""The numeric attributes a header reads (True: an integer), all >= 0 where present."""


def _check_number(path: str | os.PathLike[str], key: str, value: Any, integer: bool) -> None:
    """Refuse an attribute that is not a number >= 0 (an integer where ``integer``); None passes.

    Raises:
        InputFileError: naming the attribute and its value.
    """
    if value is None:
        return
    kind = "an integer" if integer else "a number"
    number = getattr(value, "item", lambda: value)() if getattr(value, "ndim", 0) == 0 else value
    ok = isinstance(number, int | float) and not isinstance(number, bool)
    if ok and integer:
        ok = isinstance(number, int) or (math.isfinite(number) and float(number).is_integer())
    if not ok or not math.isfinite(number) or number < 0:
        raise InputFileError(
            f"{path}: attribute {key!r} is {number!r}; allowed: {kind} >= 0 (a damaged data set)",
            parameter="file",
            value=str(path),
        )


@dataclass(frozen=True)
class DatasetHeader:
    """What a data set's file attributes say, by name and type.

    Attributes:
        format_version: the data set format version (1: aaria_pin 0.1; 2)
        n_runs: N, the runs the file has room for
        samples: T, samples per run
        dtype: the dtype of the stored series (None: not recorded)
        kind: the run kind (``"dh"``, ``"urdf"``, ...; a 0.1 file's from its robot)
        robot: the ``robot`` attribute when it is a name (None otherwise)
        robot_info: a URDF robot's description (names, frames, base mode; None: a DH arm)
        seed: the data set's seed (None: not recorded)
        rate: sample rate [Hz] as stored (None: not recorded)
        duration: run length [s] as stored (None: not recorded)
        noise: whether the IMU signals carry noise (None: not recorded)
        noise_parameters: the noise model's parameters (SI units in the keys)
        noise_stream: the noise stream of the runs' seeds (None: not recorded)
        vary: the random parts as stored (None: not recorded)
        config: the random parts' configuration (None: not recorded)
        fixed_tables: the tables of the parts that do not vary, by name
        sensors: the extra sensors, by name: their table (``sensor_<name>``), columns and
            units (:func:`~aaria_pin.core.run.sensor.sensor_attributes`; empty: none)
        failures: failed runs and their messages
        command: the command line that made it (None: not recorded, or made from Python)
        versions: the versions of the software that made it (None: not recorded)
        written_by: the aaria_pin version that wrote it (None: not recorded)
        stored_card: the data card stored in the file (``card_json``; None: none)
        attributes: every attribute, decoded (what a run's record attributes come from)
    """

    format_version: int
    n_runs: int
    samples: int
    dtype: str | None = None
    kind: str = "dh"
    robot: str | None = None
    robot_info: dict[str, Any] | None = None
    seed: int | None = None
    rate: float | None = None
    duration: float | None = None
    noise: bool | None = None
    noise_parameters: dict[str, float] = field(default_factory=dict)
    noise_stream: int | None = None
    vary: list[str] | None = None
    config: dict[str, Any] | None = None
    fixed_tables: dict[str, Any] = field(default_factory=dict)
    sensors: dict[str, Any] = field(default_factory=dict)
    failures: dict[int, str] = field(default_factory=dict)
    command: str | None = None
    versions: dict[str, Any] | None = None
    written_by: str | None = None
    stored_card: Any = None
    attributes: dict[str, Any] = field(default_factory=dict)

    @classmethod
    def from_attributes(
        cls,
        attributes: Mapping[str, Any],
        format_version: int,
        path: str | os.PathLike[str] = "data set",
    ) -> DatasetHeader:
        """The header of decoded file attributes (``_json`` ones decoded, keys without it).

        Args:
            attributes: the decoded attributes (:func:`aaria_pin.files._stored.decode_attributes`)
            format_version: the file's format version (1 when it records none)
            path: the file, for the message

        Raises:
            InputFileError: no ``N`` or ``samples``, or an attribute of the wrong type or
                range (``parameter="file"``).
        """
        values = dict(attributes)
        if "N" not in values or "samples" not in values:
            raise InputFileError(
                f"{path}: a damaged data set: no 'N' or 'samples' attribute; allowed: a "
                "complete aaria_pin data set",
                parameter="file",
                value=str(path),
            )
        for key, integer in _NUMBERS.items():
            _check_number(path, key, values.get(key), integer)
        robot = values.get("robot")
        info = values.get("robot_info") if format_version != 1 else None
        if format_version == 1 and isinstance(robot, dict):
            info = robot  # 0.1 stored a URDF robot's description under ``robot``
        command = values.get("command") or None  # "": a job started from Python
        if isinstance(command, list):
            command = shlex.join(str(part) for part in command)
        versions = values.get("versions")
        stream = values.get("noise_stream")
        return cls(
            format_version=int(format_version),
            n_runs=int(values["N"]),
            samples=int(values["samples"]),
            dtype=values.get("dtype"),
            kind=str(values.get("kind") or ("urdf" if info else "dh")),
            robot=robot if isinstance(robot, str) else None,
            robot_info=info if isinstance(info, dict) else None,
            seed=values.get("seed"),
            rate=values.get("rate"),
            duration=values.get("duration"),
            noise=values.get("noise"),
            noise_parameters=dict(values.get("noise_parameters") or {}),
            noise_stream=None if stream is None else int(stream),
            vary=values.get("vary"),
            config=values.get("config"),
            fixed_tables=dict(values.get("fixed_tables") or {}),
            sensors=dict(values.get("sensors") or {}),
            failures={int(k): str(v) for k, v in (values.get("failures") or {}).items()},
            command=None if command is None else str(command),
            versions=versions if isinstance(versions, dict) or versions is None else {"": versions},
            written_by=None if values.get("version") is None else str(values["version"]),
            stored_card=values.get("card"),
            attributes=values,
        )
