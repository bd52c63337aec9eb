"""The robots of the installed ``example-robot-data`` package, by name.

On PyPI, example-robot-data ships URDF files and meshes only, without a Python loader; its
files sit in ``cmeel.prefix/share/example-robot-data/robots`` of site-packages. Each URDF there
is one robot, named after its file: the file name without ``.urdf`` and without a trailing
``_robot`` (``ur5_robot.urdf`` → ``ur5``, ``panda.urdf`` → ``panda``). When two files would get
the same name (``anymal.urdf`` in two folders; ``ur3.urdf`` and ``ur3_robot.urdf``) each is named
``<folder>/<file name>`` instead, the folder without ``_description``
(``anymal_b_simple/anymal``, ``ur/ur3_robot``); that qualified form is accepted for every
robot.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from importlib import metadata
from pathlib import Path

from aaria_pin.core.arguments import checked
from aaria_pin.errors import InputFileError, ParameterError

__all__ = ["RobotEntry", "find_robot", "robot_catalogue", "robots_folder"]

_DISTRIBUTION = "example-robot-data"
_ROBOTS = Path("cmeel.prefix") / "share" / "example-robot-data" / "robots"


@dataclass(frozen=True)
class RobotEntry:
    """One robot of example-robot-data.

    Attributes:
        name: its name for ``--robot``
        qualified: ``<folder>/<file>``, also accepted
        urdf: the URDF file
    """

    name: str
    qualified: str
    urdf: Path


def robots_folder() -> Path:
    """The ``robots`` folder of the installed example-robot-data.

    Raises:
        ParameterError: the package is not installed (``parameter="robot"``).
        InputFileError: it is installed, its ``robots`` folder is missing
            (``parameter="robot"``).
    """
    try:
        distribution = metadata.distribution(_DISTRIBUTION)
    except metadata.PackageNotFoundError:
        raise ParameterError(
            "example-robot-data is not installed; install it with 'pip install example-robot-data'",
            parameter="robot",
        ) from None
    folder = Path(str(distribution.locate_file(_ROBOTS)))
    if not folder.is_dir():
        raise InputFileError(
            f"example-robot-data is installed but {folder} is missing; allowed: its complete "
            "installation (pip install --force-reinstall example-robot-data)",
            parameter="robot",
        )
    return folder


def _short(stem: str) -> str:
    return stem.removesuffix("_robot")


@cache
def robot_catalogue() -> dict[str, RobotEntry]:
    """Every robot of example-robot-data, by name, sorted by name."""
    folder = robots_folder()
    files = sorted(folder.rglob("*.urdf"))
    counts: dict[str, int] = {}
    for file in files:
        counts[_short(file.stem)] = counts.get(_short(file.stem), 0) + 1
    entries = []
    for file in files:
        package = file.relative_to(folder).parts[0].removesuffix("_description")
        qualified = f"{package}/{file.stem}"
        name = _short(file.stem) if counts[_short(file.stem)] == 1 else qualified
        entries.append(RobotEntry(name, qualified, file))
    return {entry.name: entry for entry in sorted(entries, key=lambda e: e.name)}


@checked
def find_robot(name: str) -> RobotEntry:
    """A robot of example-robot-data by name (or ``<folder>/<file>``).

    Raises:
        ParameterError: no robot of that name; the message lists close names.
    """
    catalogue = robot_catalogue()
    if name in catalogue:
        return catalogue[name]
    for entry in catalogue.values():
        if entry.qualified == name:
            return entry
    import difflib

    same = [e.name for e in catalogue.values() if _short(e.urdf.stem) == name]
    if same:
        raise ParameterError(
            f"robot name {name!r} is ambiguous; allowed: {', '.join(same)}",
            parameter="robot",
            value=name,
            allowed=", ".join(same),
        )

    close = difflib.get_close_matches(name, list(catalogue), n=5, cutoff=0.5)
    hint = f"close names: {', '.join(close)}" if close else "see 'aaria robots'"
    listed = "a robot of 'aaria robots'" + (f" ({hint})" if close else "")
    raise ParameterError(
        f"robot {name!r} is not in example-robot-data; {hint}",
        parameter="robot",
        value=name,
        allowed=listed,
    )
