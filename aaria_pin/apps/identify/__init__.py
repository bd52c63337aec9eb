"""Identification from a run's sensor data.

The kinematic model from IMUs and encoders (:mod:`~aaria_pin.apps.identify.geometry`), the
inertial base parameters from torques (:mod:`~aaria_pin.apps.identify.inertial`), the
benchmark over data sets (:mod:`~aaria_pin.apps.identify.benchmark`) and the
``aaria identify`` request (:mod:`~aaria_pin.apps.identify.request`).
"""

from aaria_pin.apps.identify.benchmark import (
    RunAccuracy,
    accuracy_table,
    benchmark_datasets,
    group_label,
    identify_dataset_run,
)
from aaria_pin.apps.identify.geometry import identify_kinematics
from aaria_pin.apps.identify.geometry_result import Deficiency, KinematicIdentification, TruthErrors
from aaria_pin.apps.identify.inertial import BASE_WRENCH_SIGNALS, IDENTIFY_CHUNK, identify_dynamics
from aaria_pin.apps.identify.inertial_base import (
    DEFAULT_TOLERANCE,
    BaseParameterSet,
    base_parameters,
)
from aaria_pin.apps.identify.inertial_regressor import (
    INERTIAL_PARAMETERS,
    standard_parameters,
    torque_regressor,
)
from aaria_pin.apps.identify.inertial_result import DynamicIdentification

__all__ = [
    "BASE_WRENCH_SIGNALS",
    "DEFAULT_TOLERANCE",
    "IDENTIFY_CHUNK",
    "INERTIAL_PARAMETERS",
    "BaseParameterSet",
    "Deficiency",
    "DynamicIdentification",
    "KinematicIdentification",
    "RunAccuracy",
    "TruthErrors",
    "accuracy_table",
    "base_parameters",
    "benchmark_datasets",
    "group_label",
    "identify_dataset_run",
    "identify_dynamics",
    "identify_kinematics",
    "standard_parameters",
    "torque_regressor",
]
