"""Data sets of Aaria DH arms: random structures (MODE 1) or one arm (MODE 2).

Run k draws its 8 × 5 DH table (:func:`~aaria_pin.aaria.randomize.random_dh_table`), its joint
table and its base table from its own streams, unless the spec fixes them, and is simulated by
:func:`aaria_pin.aaria.simulate.simulate_run` (:mod:`.runs`). Its record keeps the paper's
module order (joints
``joint1`` … ``joint6``, 14 IMU slots; an empty module's columns are zero), so every run has
the same layout: the tables ``senSenDH``, ``senSenJ`` (8 × 5) and ``senSenB`` (6 × 4: a 2 × 4
table is stored expanded, one row per axis), ``inertial_parameters`` (7 × 10,
:mod:`.inertial_table`) and the view ``senSen`` (T × 91). With a Fourier
excitation (``motion="fourier"``) run k follows
:func:`~aaria_pin.aaria.simulate.dh_fourier_excitation` of its table, drawn from its joint
stream, stored as the table ``fourier_coefficients`` (6 × (1 + 2L)); its ``senSenJ`` is the
arm's default joint table (not followed).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from typing import TYPE_CHECKING, Any

import numpy as np

from aaria_pin.aaria.randomize import random_dh_table, random_joint_table
from aaria_pin.apps.dataset.inertial_table import INERTIAL_TABLE, inertial_shape
from aaria_pin.apps.dataset.spec import DatasetSpec, RunInputs
from aaria_pin.core.se3 import Array
from aaria_pin.core.seeds import RunSeeds
from aaria_pin.errors import ParameterError
from aaria_pin.files.dataset.layout import DatasetLayout

if TYPE_CHECKING:
    from aaria_pin.core.run import RunRobot

__all__ = ["DhDatasetSpec", "dh_layout"]


@dataclass(frozen=True)
class DhDatasetSpec(DatasetSpec):
    """A data set of Aaria DH arms (settings: :class:`~.spec.DatasetSpec`).

    Attributes:
        dh_table: the fixed 8 × 5 table when the structure does not vary
        name: the ``robot`` attribute of the runs (a preset's name; default
            :data:`~aaria_pin.aaria.simulate.DH_ROBOT`)
    """

    dh_table: Array | None = None
    name: str = ""

    def __post_init__(self) -> None:
        super().__post_init__()
        if "structure" not in self.vary and self.dh_table is None:
            raise ParameterError(
                parameter="dh_table",
                value=None,
                allowed="a DH table when the structure does not vary (it needs --preset or --dh)",
            )

    @property
    def kind(self) -> str:
        """``"dh"``."""
        return "dh"

    def robot_name(self) -> str:
        """The preset's name, or :data:`~aaria_pin.aaria.simulate.DH_ROBOT`."""
        from aaria_pin.aaria.arm_run import DH_ROBOT

        return self.name or DH_ROBOT

    def robot_attributes(self) -> dict[str, Any]:
        """Nothing beyond the name: the DH table is among the fixed tables."""
        return {}

    def fixed_table_names(self) -> tuple[str, ...]:
        """``dh_table``, ``joint_table``, ``base_table``."""
        return ("dh_table", "joint_table", "base_table")

    def robot_layout(self) -> DatasetLayout:
        """Six joints, 14 IMU slots, the Aaria tables, ``senSen``; the arm's URDF if fixed."""
        urdf = ""
        if "structure" not in self.vary and self.dh_table is not None:
            urdf = _arm_urdf(np.asarray(self.dh_table, dtype=float).tobytes())
        harmonics = self.fourier_settings()["harmonics"] if self.motion == "fourier" else 0
        return dh_layout(urdf, harmonics)

    def inputs(self, run: int) -> RunInputs:
        """``senSenDH``, ``senSenJ``, ``senSenB`` (6 × 4) and the noise seed of run ``run``.

        With a Fourier excitation also ``fourier_coefficients`` (6 × (1 + 2L)), and the arm's
        default ``senSenJ``.
        """
        from aaria_pin.aaria.dh import chain_from_aaria
        from aaria_pin.aaria.sine_tables import default_joint_table

        seeds = RunSeeds(self.seed, run)
        if "structure" in self.vary:
            dh = random_dh_table(self.config, seeds.generator("structure"))
        else:
            from aaria_pin.aaria.dh import validate_aaria_table

            assert self.dh_table is not None
            dh = validate_aaria_table(self.dh_table)  # its shape, before rows are indexed
        fourier = self.motion == "fourier"
        if "joints" in self.vary and not fourier:
            joint_table = random_joint_table(self.config, dh, seeds.generator("joints"))
        elif self.joint_table is not None:
            joint_table = np.asarray(self.joint_table, dtype=float)
        else:
            joint_table = default_joint_table(chain_from_aaria(dh))
        base_table, noise_seed = self.base_and_noise(run)
        tables = {"senSenDH": dh, "senSenJ": joint_table, "senSenB": base_table}
        if fourier:
            from aaria_pin.aaria.simulate import dh_fourier_excitation

            excitation = dh_fourier_excitation(
                dh, self.duration, self.rate, seed=self.fourier_seed(run), **self.fourier_settings()
            )
            tables["fourier_coefficients"] = excitation.table()
        return RunInputs(tables, noise_seed)

    def run_robot(self, inputs: RunInputs) -> RunRobot:
        """The arm of the run's ``senSenDH`` with its ``senSenJ`` and ``senSenB``.

        :func:`~aaria_pin.aaria.arm_run.dh_arm`; its URDF text is not kept (the file stores it
        once, or not at all).
        """
        from aaria_pin.aaria.arm_run import DHArmSpec, dh_arm

        tables = inputs.tables
        arm = DHArmSpec(
            tables["senSenJ"], tables["senSenB"], robot_name=self.robot_name(), keep_urdf=False
        )
        return dh_arm(tables["senSenDH"], arm)

    def check_inputs(self, inputs: RunInputs) -> None:
        """Check the DH table, the base table and, where its structure is known, the joint table.

        The joint table is checked against the structure it drives when that is known before
        the run (drawn with it, or fixed); a fixed joint table over random structures is checked
        for shape and finite entries only (a structure it does not fit fails its run alone).

        Raises:
            TableError: a table no run can use.
        """
        from aaria_pin.aaria.dh import chain_from_aaria, validate_aaria_table
        from aaria_pin.aaria.sine_tables import validate_joint_table
        from aaria_pin.core.oscillation import JOINT_COLUMNS
        from aaria_pin.core.tables import finite_table

        super().check_inputs(inputs)
        dh = validate_aaria_table(inputs.tables["senSenDH"])
        joints = inputs.tables["senSenJ"]
        if "joints" in self.vary or "structure" not in self.vary:
            validate_joint_table(joints, chain_from_aaria(dh))
        else:
            finite_table(joints, JOINT_COLUMNS, "joint oscillation table", rows=(8,))


@cache
def dh_layout(urdf: str = "", harmonics: int = 0) -> DatasetLayout:
    """The per-run layout of an Aaria data set (``urdf``: the arm's, when it is fixed).

    ``harmonics`` > 0: runs of a Fourier excitation, with the table ``fourier_coefficients``
    (6 × (1 + 2·harmonics)). Kept per process: every run's encoding asks for it.
    """
    from aaria_pin.aaria.dh_robot import BASE_FRAME, TOOL_FRAME, link_name
    from aaria_pin.aaria.sensen import JOINT_NAMES, N_MODULES, imu_slot_order, sensen_view

    parents = [BASE_FRAME, TOOL_FRAME]
    for module in range(1, N_MODULES + 1):
        parents += [link_name(module)] * 2
    tables = {"senSenDH": (8, 5), "senSenJ": (8, 5), "senSenB": (6, 4)}
    if harmonics:
        tables["fourier_coefficients"] = (N_MODULES, 1 + 2 * harmonics)
    tables[INERTIAL_TABLE] = inertial_shape(N_MODULES)
    return DatasetLayout(
        JOINT_NAMES,
        imu_slot_order(),
        tuple(parents),
        tables,
        {"senSen": sensen_view()},
        urdf,
    )


@cache
def _arm_urdf(table: bytes) -> str:
    """The URDF of the fixed arm of a data set (kept per process: every run asks for it)."""
    from aaria_pin.aaria.dh_robot import build_dh_robot

    return build_dh_robot(np.frombuffer(table).reshape(8, 5)).urdf
