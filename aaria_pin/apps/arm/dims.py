"""Dimensions of the pick-place arm, and where a gripped cylinder sits in its hand.

Every number here is chosen (the robotic-arm report gives no dimension; see
:mod:`aaria_pin.apps.arm.preset`). The hand frame's z axis is the approach axis, pointing down with
the hand down; the wrist centre is its origin. The palm spans z = ``PALM_FACE - 0.02`` to
:data:`PALM_FACE`, the fingers z = :data:`PALM_FACE` to ``PALM_FACE + finger_length``.

**Grasp.** A cylinder of height h is held with its top ``palm_clearance`` below the palm face,
so its axis' mid-point (the grasp point, where the fingers press) is
``PALM_FACE + palm_clearance + h/2`` below the wrist centre (:func:`grasp_depth`). A height is
accepted (:func:`height_limits`) if that mid-point lies within the fingers
(``palm_clearance + h/2 <= finger_length``) and, with the cylinder standing on the floor, the
fingertips stay :data:`FLOOR_CLEARANCE` above it (``h + palm_clearance - finger_length >=
FLOOR_CLEARANCE``): 0.08 m to 0.15 m for the preset.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from aaria_pin.core.se3 import Array, translation
from aaria_pin.errors import ParameterError

__all__ = [
    "ARM_PRESETS",
    "FLOOR_CLEARANCE",
    "PALM_FACE",
    "ArmDimensions",
    "get_arm_preset",
    "grasp_depth",
    "grasp_offset",
    "height_limits",
]

PALM_FACE = 0.04
"""Depth of the palm's gripping face below the wrist centre, where the fingers start [m]."""

FLOOR_CLEARANCE = 0.005
"""Least height of the fingertips above the floor when gripping a standing cylinder [m]."""

_ALUMINIUM = 2700.0


@dataclass(frozen=True)
class ArmDimensions:
    """Dimensions of the arm [m] (all chosen here: the report gives none, see module docstring).

    Attributes:
        upper_arm: A, shoulder axis to elbow axis (report's ``upperArm_len``)
        forearm: B, elbow axis to wrist axis (report's ``foreArm_len``)
        pillar_radius: radius of the pillar
        pillar_height: height of the pillar above the floor
        foot_size: edge of the pillar's square foot plate, centred on the pillar's axis
        foot_thickness: thickness of the foot plate
        lift_range: lowest and highest height of the carriage's centre above the floor
        shoulder_drop: shoulder (upper arm mid-plane) below the carriage's centre
        elbow_drop: forearm mid-plane below the upper arm's
        wrist_drop: wrist centre below the forearm's mid-plane
        palm_clearance: gap between a gripped cylinder's top and the palm face
        finger_face: the fixed fingers' gripping face on the hand's x axis (a cylinder of
            radius -finger_face is gripped on the wrist's axis)
        finger_length: length of the fingers along the approach axis
        finger_thickness: thickness of every finger along the hand's x axis
        finger_travel: the sliding finger's largest gap to the fixed fingers
        density: density of every moving part [kg/m³]
    """

    upper_arm: float = 0.40
    forearm: float = 0.30
    pillar_radius: float = 0.05
    pillar_height: float = 0.85
    foot_size: float = 0.30
    foot_thickness: float = 0.02
    lift_range: tuple[float, float] = (0.27, 0.78)
    shoulder_drop: float = 0.05
    elbow_drop: float = 0.04
    wrist_drop: float = 0.06
    palm_clearance: float = 0.005
    finger_face: float = -0.03
    finger_length: float = 0.08
    finger_thickness: float = 0.015
    finger_travel: float = 0.12
    density: float = _ALUMINIUM

    def __post_init__(self) -> None:
        for name in (
            "upper_arm",
            "forearm",
            "pillar_radius",
            "pillar_height",
            "foot_size",
            "foot_thickness",
            "palm_clearance",
            "finger_length",
            "finger_thickness",
            "density",
        ):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0):
                raise ParameterError(
                    f"arm {name} is {value!r}; allowed: a finite number > 0",
                    parameter=name,
                    value=value,
                )
        if not self.upper_arm - self.forearm > self.pillar_radius:
            raise ParameterError(
                f"upper arm A = {self.upper_arm} m, forearm B = {self.forearm} m; allowed:"
                f" A - B > pillar radius {self.pillar_radius} m (the folded hand clears the"
                " pillar)",
                parameter="upper_arm",
                value=self.upper_arm,
            )

    def grasp_below_carriage(self, height: float) -> float:
        """Height of the grasp point below the carriage's centre with the hand down [m].

        Args:
            height: the gripped cylinder's height [m]
        """
        return self.shoulder_drop + self.elbow_drop + self.wrist_drop + grasp_depth(self, height)

    def fingertip_below_grasp(self, height: float) -> float:
        """How far the fingertips reach below the grasp point along the approach axis [m].

        Args:
            height: the gripped cylinder's height [m]
        """
        return PALM_FACE + self.finger_length - grasp_depth(self, height)

    @property
    def annulus(self) -> tuple[float, float]:
        """Inner and outer radius of the wrist's reachable annulus, |A - B| and A + B [m]."""
        return abs(self.upper_arm - self.forearm), self.upper_arm + self.forearm


ARM_PRESETS = {"pick-place-arm": ArmDimensions()}
"""Arm presets by name."""


def get_arm_preset(name: str) -> ArmDimensions:
    """The dimensions of a named arm preset.

    Raises:
        ParameterError: an unknown name.
    """
    if name not in ARM_PRESETS:
        raise ParameterError(
            f"arm preset {name!r} is unknown; allowed: {', '.join(ARM_PRESETS)}",
            parameter="name",
            value=name,
        )
    return ARM_PRESETS[name]


def grasp_depth(dims: ArmDimensions, height: float) -> float:
    """Depth of the grasp point (a gripped cylinder's centre) below the wrist centre [m].

    Args:
        dims: the arm
        height: the cylinder's height [m]
    """
    return PALM_FACE + dims.palm_clearance + height / 2


def grasp_offset(dims: ArmDimensions, radius: float, height: float) -> Array:
    """Pose of the grasp point of a cylinder in the hand frame (4 × 4) [m].

    Args:
        dims: the arm
        radius: the cylinder's radius [m]
        height: the cylinder's height [m]
    """
    return translation(dims.finger_face + radius, 0.0, grasp_depth(dims, height))


def height_limits(dims: ArmDimensions) -> tuple[float, float]:
    """Lowest and highest cylinder the hand can hold without touching palm or floor [m]."""
    low = dims.finger_length - dims.palm_clearance + FLOOR_CLEARANCE
    high = 2 * (dims.finger_length - dims.palm_clearance)
    return low, high
