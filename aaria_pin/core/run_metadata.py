"""A run's metadata as typed fields: what its record's ``attributes`` say, read once.

Its own module beside :mod:`aaria_pin.core.run` (which re-exports it) so that
:class:`~aaria_pin.core.record.RunRecord` can read it without importing the engine. The file
codec keeps a record's attributes as the dict it stores;
:meth:`RunMetadata.from_attributes` reads the fields every run kind shares (with the defaults
of files written before a field existed) and keeps the kind's own attributes in
:attr:`RunMetadata.extra`; :meth:`RunMetadata.to_attributes` writes them back.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from aaria_pin.core.seeds import stored_seed
from aaria_pin.core.trajectory import DEFAULT_DURATION, DEFAULT_RATE

__all__ = ["RunMetadata", "stored_sampling"]

_FIELDS = (
    "kind",
    "robot",
    "source",
    "rate",
    "duration",
    "noise",
    "drive",
    "motion",
    "base_frame",
    "tool_frame",
    "moving_base",
    "urdf_dir",
    "version",
)
"""The attributes read into fields (``seed`` and ``noise_spawn_key`` give :attr:`seed`)."""


@dataclass(frozen=True)
class RunMetadata:
    """The typed metadata of a run record.

    Attributes:
        kind: the run's kind (``dh``, ``urdf``, ``wrist``, ``pick-place``; None: not recorded)
        robot: the robot's name ("" if not recorded)
        source: where the robot came from (a preset, a robot name, a file; "" if none)
        rate: sample rate [Hz]
        duration: run length [s]
        seed: the seed of the IMU noise (a data set run's ``SeedSequence``)
        noise: whether the IMU signals carry noise
        drive: ``motion``, ``torque``, or a closed-loop drive (``pd``, ``computed-torque``)
        motion: the joint motion's name (``sine`` for a file written before motions were
            stored)
        base_frame: the base frame ("" if not recorded)
        tool_frame: the tool frame ("" if not recorded)
        moving_base: whether the base moves (None: not recorded)
        urdf_dir: the URDF's folder, for its meshes ("" if none)
        version: the version that wrote the run ("" if not recorded)
        extra: every other attribute, as stored (the kind's own)
    """

    kind: str | None = None
    robot: str = ""
    source: str = ""
    rate: float = 0.0
    duration: float = 0.0
    seed: int | np.random.SeedSequence = 0
    noise: bool = True
    drive: str = "motion"
    motion: str = "sine"
    base_frame: str = ""
    tool_frame: str = ""
    moving_base: bool | None = None
    urdf_dir: str = ""
    version: str = ""
    extra: Mapping[str, Any] = field(default_factory=dict)

    @classmethod
    def from_attributes(cls, attributes: Mapping[str, Any]) -> RunMetadata:
        """The metadata a record's attributes hold.

        Raises:
            InputFileError: a stored duration or rate that is not a positive number.
        """
        sampling = stored_sampling(dict(attributes))
        moving = attributes.get("moving_base")
        kind = attributes.get("kind")
        return cls(
            kind=None if kind is None else str(kind),
            robot=str(attributes.get("robot") or ""),
            source=str(attributes.get("source") or ""),
            rate=sampling["rate"],
            duration=sampling["duration"],
            seed=sampling["seed"],
            noise=sampling["noise"],
            drive=str(attributes.get("drive", "motion")),
            motion=str(attributes.get("motion", "sine")),
            base_frame=str(attributes.get("base_frame") or ""),
            tool_frame=str(attributes.get("tool_frame") or ""),
            moving_base=None if moving is None else bool(moving),
            urdf_dir=str(attributes.get("urdf_dir") or ""),
            version=str(attributes.get("version") or ""),
            extra={
                name: value
                for name, value in attributes.items()
                if name not in _FIELDS and name not in ("seed", "noise_spawn_key")
            },
        )

    def to_attributes(self) -> dict[str, Any]:
        """The attributes of the record (fields that were not recorded are left out)."""
        from aaria_pin.core.seeds import seed_attributes

        attributes: dict[str, Any] = {} if self.kind is None else {"kind": self.kind}
        optional = {
            "robot": self.robot,
            "source": self.source,
            "base_frame": self.base_frame,
            "tool_frame": self.tool_frame,
            "urdf_dir": self.urdf_dir,
            "version": self.version,
        }
        attributes.update({name: value for name, value in optional.items() if value})
        attributes.update(
            {
                "rate": self.rate,
                "duration": self.duration,
                **seed_attributes(self.seed),
                "noise": self.noise,
                "drive": self.drive,
                "motion": self.motion,
            }
        )
        if self.moving_base is not None:
            attributes["moving_base"] = self.moving_base
        attributes.update(self.extra)
        return attributes


def stored_sampling(attributes: dict[str, Any]) -> dict[str, Any]:
    """The ``duration`` [s], ``rate`` [Hz], ``seed`` and ``noise`` a record's attributes hold.

    The inverse of :func:`sampling_attributes`, as keyword arguments of a producer, for
    re-making a run from its record (defaults where an attribute is missing).
    """
    return {
        "duration": _stored_number(attributes, "duration", DEFAULT_DURATION, "s"),
        "rate": _stored_number(attributes, "rate", DEFAULT_RATE, "Hz"),
        "seed": stored_seed(attributes),
        "noise": bool(attributes.get("noise", True)),
    }


def _stored_number(attributes: dict[str, Any], name: str, default: float, unit: str) -> float:
    """A stored positive number, or one line naming the attribute (a damaged or edited file)."""
    from aaria_pin.errors import InputFileError

    value = attributes.get(name, default)
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = math.nan
    if not (math.isfinite(number) and number > 0):
        raise InputFileError(
            f"the run's attribute {name!r} is {value!r}; allowed: a positive number of {unit}",
            parameter=name,
        )
    return number
