"""aaria_pin: kinematics, dynamics and simulated sensor datasets of serial manipulators.

The public API is re-exported here and imported on first use, so ``import aaria_pin`` (and the
``aaria`` command line) stays fast: Pinocchio is loaded only when a model is built.
"""

from __future__ import annotations

from importlib import import_module
from typing import Any

__version__ = "0.1.0"

_EXPORTS = {
    "AariaError": "aaria_pin.errors",
    "BodyDimensions": "aaria_pin.aaria.dh_robot",
    "DHRobot": "aaria_pin.aaria.dh_robot",
    "GenericRunRecord": "aaria_pin.core.record",
    "ImuMount": "aaria_pin.core.record",
    "ImuSlot": "aaria_pin.aaria.dh_robot",
    "InputFileError": "aaria_pin.errors",
    "KinematicChain": "aaria_pin.aaria.dh",
    "ModelError": "aaria_pin.errors",
    "OutputFileError": "aaria_pin.errors",
    "ParameterError": "aaria_pin.errors",
    "Part": "aaria_pin.core.inertia",
    "RobotModel": "aaria_pin.core.model",
    "TableError": "aaria_pin.errors",
    "UrdfError": "aaria_pin.errors",
    "build_dh_robot": "aaria_pin.aaria.dh_robot",
    "build_model": "aaria_pin.core.model",
    "chain_from_table": "aaria_pin.aaria.dh",
    "composite_inertia": "aaria_pin.core.inertia",
    "emit_urdf": "aaria_pin.core.urdf",
    "find_robot": "aaria_pin.core.catalogue",
    "get_preset": "aaria_pin.aaria.presets",
    "load_urdf_robot": "aaria_pin.core.urdf_robot",
    "read_table": "aaria_pin.files.io",
    "simulate_urdf_run": "aaria_pin.core.urdf_run",
}

__all__ = sorted(["__version__", *_EXPORTS])


def __getattr__(name: str) -> Any:
    if name in _EXPORTS:
        return getattr(import_module(_EXPORTS[name]), name)
    raise AttributeError(f"module 'aaria_pin' has no attribute {name!r}")


def __dir__() -> list[str]:
    return __all__
