"""A data set's spec from where its parts come from: presets, table files, a robot, a config file.

:class:`DatasetSources` holds what ``aaria dataset`` takes (names and paths, not yet read);
:meth:`DatasetSources.spec` (:func:`spec_from_sources`) resolves them into a checked
:class:`~.spec.DatasetSpec`, the same for a Python caller as for the command line:

- the robot: an Aaria DH arm (random, a preset or a ``senSenDH`` table file) or a URDF robot
  (a robot of the catalogue or a URDF file, with its tool, IMU layout and fixed or moving base);
- what varies: ``vary`` as given, else every part no fixed table or robot pins down (a preset
  or DH table fixes the structure, a joint table the joints, a base table or a fixed base the
  base); a part both given and asked to vary is refused;
- the motion: the joint tables' sines, or a Fourier excitation (a preset's sines are then
  dropped);
- the ranges and the hardware (IMU model, joint models, fixed or ranged) of the config file
  (:func:`~.config.load_dataset_config`) over the ``imu_model`` preset.

Each rule is checked once, here or in the spec's own checks, before any run is made.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, fields
from pathlib import Path
from typing import TYPE_CHECKING, Any

from aaria_pin.aaria.hardware import imu_model_option
from aaria_pin.aaria.randomize import PARTS
from aaria_pin.apps.dataset.config import load_dataset_config
from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
from aaria_pin.apps.dataset.spec import DatasetSettings
from aaria_pin.apps.dataset.urdf_spec import UrdfDatasetSpec, UrdfSource
from aaria_pin.core.arguments import checked
from aaria_pin.errors import ParameterError

if TYPE_CHECKING:
    from aaria_pin.apps.dataset.spec import DatasetSpec

__all__ = ["DatasetSources", "spec_from_sources"]


@checked
@dataclass(frozen=True)
class DatasetSources(DatasetSettings):
    """What a data set is made from, as names and paths (read by :func:`spec_from_sources`).

    Its run settings (``n_runs``, ``seed``, ``duration``, ``rate``, ``noise``, ``dtype``,
    ``motion``, ``harmonics``, ``base_frequency``) are those of :class:`~.spec.DatasetSettings`.

    Attributes:
        config_file: TOML file of ranges and hardware tables (None: the defaults)
        imu_model: the IMU model: a preset name or an IMU model file
            (:func:`~aaria_pin.aaria.hardware.imu_model_option`; None: the ADIS16485); the
            config's ``[imu]`` values go over it
        vary: the random parts, a comma-separated text or a sequence (None: every part that
            no fixed table or robot pins down)
        preset: a built-in Aaria table (``aaria-fig2``); fixes the structure, gives the joint
            and base tables
        dh_file: an Aaria DH table file (``senSenDH``); fixes the structure
        convention: the table's convention; a data set's arms are ``"aaria"`` tables
        robot: a robot of the catalogue (``ur5``) instead of a DH arm
        urdf_file: a URDF file instead of a DH arm
        tool_frame: the URDF robot's tool frame (None: the default choice)
        imu_layout_file: the URDF robot's IMU layout file (None: the default layout)
        fixed_base: keep the URDF robot's root link fixed (its base does not move)
        joints_file: a fixed joint oscillation table file
        base_file: a fixed base oscillation table file
    """

    config_file: str | Path | None = None
    imu_model: str | Path | None = None
    vary: str | Sequence[str] | None = None
    preset: str | None = None
    dh_file: str | Path | None = None
    convention: str = "aaria"
    robot: str | None = None
    urdf_file: str | Path | None = None
    tool_frame: str | None = None
    imu_layout_file: str | Path | None = None
    fixed_base: bool = False
    joints_file: str | Path | None = None
    base_file: str | Path | None = None

    def spec(self) -> DatasetSpec:
        """The checked spec of the data set (:func:`spec_from_sources`)."""
        return spec_from_sources(self)


def spec_from_sources(sources: DatasetSources) -> DatasetSpec:
    """The checked spec of a data set (the rules: see the module docstring).

    Args:
        sources: what the data set is made from

    Returns:
        A :class:`~.dh.DhDatasetSpec` (an Aaria DH arm) or a :class:`~.urdf.UrdfDatasetSpec`.

    Raises:
        ParameterError: a convention other than ``aaria``; a DH arm and a URDF robot both given,
            or a preset and a DH table; URDF options without a robot; a part both fixed and
            varied; a preset that is not an Aaria table; settings the spec refuses (a
            structure neither varied nor given among them).
        InputFileError: a table, layout, robot or config file that cannot be read.
        ModelError: a URDF robot that cannot be loaded.

    Warns:
        MeshWarning: meshes the URDF robot refers to that cannot be found (it still simulates).
    """
    if sources.convention != "aaria":
        raise ParameterError(
            parameter="convention",
            value=sources.convention,
            allowed="aaria (a data set's arms are Aaria tables; a standard or modified table"
            " can be simulated with aaria simulate, or its robot made with aaria urdf)",
        )
    robot = _urdf_robot(sources)
    dh_given = sources.preset is not None or sources.dh_file is not None
    if robot is not None and dh_given:
        raise ParameterError(
            parameter="robot",
            value=sources.robot or str(sources.urdf_file),
            allowed="a DH arm (a preset or a DH table) or a URDF robot, not both",
        )
    if robot is not None and not robot.moving_base and sources.base_file is not None:
        raise ParameterError(
            parameter="base_table",
            value=str(sources.base_file),
            allowed="none on a fixed base (a base table is not allowed with --fixed-base)",
        )
    vary = _vary(sources, robot)
    if sources.config_file is not None:
        from aaria_pin.files.paths import existing_input

        existing_input(sources.config_file, None, "config")  # a FIFO: one line, never a wait
    imu_model = None if sources.imu_model is None else imu_model_option(sources.imu_model)
    config, hardware = load_dataset_config(sources.config_file, imu_model)
    settings: dict[str, Any] = {
        **{item.name: getattr(sources, item.name) for item in fields(DatasetSettings)},
        "config": config,
        "hardware": hardware,
        "vary": vary,
    }
    if robot is not None:
        joint_table = _table(sources.joints_file, "joint_table")
        base_table = _table(sources.base_file, "senSenB")
        return UrdfDatasetSpec(
            **settings, joint_table=joint_table, base_table=base_table, robot=robot
        )
    dh_table, joint_table, base_table, name = _dh_tables(sources)
    return DhDatasetSpec(
        **settings,
        joint_table=joint_table,
        base_table=base_table,
        dh_table=dh_table,
        name=name,
    )


def _vary(sources: DatasetSources, robot: UrdfSource | None) -> tuple[str, ...]:
    """The random parts: as given (none of them fixed), else every part not fixed.

    A URDF robot's structure is fixed (its spec refuses to vary it, naming why).

    Raises:
        ParameterError: a part both fixed and varied.
    """
    fixed = {
        "structure": sources.preset is not None or sources.dh_file is not None,
        "joints": sources.joints_file is not None,
        "base": sources.base_file is not None or (robot is not None and not robot.moving_base),
    }
    if sources.vary is None:
        parts = tuple(
            part
            for part in PARTS
            if not fixed[part] and not (part == "structure" and robot is not None)
        )
    else:
        given = sources.vary.split(",") if isinstance(sources.vary, str) else sources.vary
        parts = tuple(part.strip() for part in given if part.strip())
        for part in parts:
            if not fixed.get(part):
                continue
            if part == "base" and sources.fixed_base:
                raise ParameterError(
                    parameter="vary",
                    value=part,
                    element="a part",
                    allowed="joints (a fixed base cannot vary)",
                )
            raise ParameterError(
                parameter="vary",
                value=part,
                element="a part",
                allowed=f"parts without a fixed table (a fixed {part} table was given)",
            )
    return parts  # a structure neither varied nor given: refused by DhDatasetSpec


def _dh_tables(sources: DatasetSources) -> tuple[Any, Any, Any, str]:
    """The fixed DH, joint and base tables of a DH data set (None: drawn) and its robot name.

    A preset gives its three tables (its joint table dropped for a Fourier excitation); a
    table file given beside it replaces the preset's.

    Raises:
        ParameterError: both a preset and a DH table file, or a preset that is not Aaria's.
    """
    from aaria_pin.files.io import read_table

    dh_table: Any = None
    joint_table: Any = None
    base_table: Any = None
    name = ""
    if sources.preset is not None and sources.dh_file is not None:
        raise ParameterError(
            parameter="dh_table",
            value=str(sources.dh_file),
            allowed=f"none with a preset ({sources.preset!r}): give a preset or a DH table",
        )
    if sources.preset is not None:
        from aaria_pin.aaria.presets import get_preset

        chosen = get_preset(sources.preset)
        if chosen.convention != "aaria":
            raise ParameterError(parameter="preset", value=sources.preset, allowed="aaria-*")
        dh_table, joint_table, base_table = chosen.table, chosen.joint_table, chosen.base_table
        if sources.motion == "fourier":
            joint_table = None  # the excitation replaces the preset's sines
        name = sources.preset
    elif sources.dh_file is not None:
        dh_table = read_table(sources.dh_file, "senSenDH")
    if sources.joints_file is not None:
        joint_table = _table(sources.joints_file, "senSenJ")
    if sources.base_file is not None:
        base_table = _table(sources.base_file, "senSenB")
    return dh_table, joint_table, base_table, name


def _table(path: str | Path | None, variable: str) -> Any:
    """The table of a file (its ``variable`` in a ``.mat`` file), or None."""
    if path is None:
        return None
    from aaria_pin.files.io import read_table

    return read_table(path, variable)


def _urdf_robot(sources: DatasetSources) -> UrdfSource | None:
    """The URDF robot of ``robot``/``urdf_file`` (None: a DH arm), loaded and checked once.

    Raises:
        ParameterError: both a robot name and a URDF file, or URDF options without either.

    Warns:
        MeshWarning: its missing meshes, once (the runs do not warn again).
    """
    if sources.robot is None and sources.urdf_file is None:
        for name in ("tool_frame", "imu_layout_file"):
            if getattr(sources, name) is not None:
                raise ParameterError(
                    parameter=name,
                    value=str(getattr(sources, name)),
                    allowed="none for a DH arm (it needs --robot or --urdf)",
                )
        if sources.fixed_base:
            raise ParameterError(
                parameter="fixed_base",
                value=True,
                allowed="false for a DH arm (it needs --robot or --urdf)",
            )
        return None
    import warnings

    from aaria_pin.core.urdf_robot import missing_meshes_message
    from aaria_pin.errors import MeshWarning

    text, folder, name = _urdf_text(sources.robot, sources.urdf_file)
    layout = None
    if sources.imu_layout_file is not None:
        from aaria_pin.core.imu_layout import read_imu_layout
        from aaria_pin.files.paths import existing_input

        layout = read_imu_layout(existing_input(sources.imu_layout_file, None, "IMU layout"))
    source = UrdfSource(text, name, str(folder), not sources.fixed_base, sources.tool_frame, layout)
    summary = source.load().summary  # checks the robot here, once, before any worker starts
    if summary.missing_meshes:
        warnings.warn(missing_meshes_message(summary), MeshWarning, stacklevel=3)
    return source


def _urdf_text(robot: str | None, urdf_file: str | Path | None) -> tuple[str, Path, str]:
    """The URDF text, its folder and its source name (a catalogue robot's, or the file's).

    Raises:
        ParameterError: both a robot name and a URDF file.
        InputFileError: the file is missing, a folder, a FIFO or unreadable.
    """
    from aaria_pin.core.urdf_robot import read_urdf_file

    if robot is not None and urdf_file is not None:
        raise ParameterError(
            parameter="urdf_file",
            value=str(urdf_file),
            allowed=f"none with a catalogue robot ({robot!r}): give one, not both",
        )
    if robot is not None:
        from aaria_pin.core.catalogue import find_robot

        entry = find_robot(robot)
        return read_urdf_file(entry.urdf), entry.urdf.parent, entry.name
    assert urdf_file is not None
    from aaria_pin.files.paths import existing_input

    path = existing_input(urdf_file, None, "URDF")  # a FIFO or a folder: one line, never a wait
    return read_urdf_file(path), path.parent, str(urdf_file)
