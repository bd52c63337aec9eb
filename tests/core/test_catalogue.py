"""The example-robot-data catalogue: its errors when the package or its files are missing."""

from __future__ import annotations

from importlib import metadata
from pathlib import Path
from typing import Any

import pytest

from aaria_pin.core import catalogue
from aaria_pin.errors import InputFileError, ParameterError


class _Installed:
    """A distribution whose files are in ``root`` (none there)."""

    def __init__(self, root: Path) -> None:
        self.root = root

    def locate_file(self, path: Any) -> Path:
        return self.root / path


def test_a_missing_robots_folder_is_a_missing_input_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(catalogue.metadata, "distribution", lambda name: _Installed(tmp_path))
    with pytest.raises(InputFileError) as missing:
        catalogue.robots_folder()
    error = missing.value
    assert isinstance(error, OSError) and error.parameter == "robot"
    folder = tmp_path / "cmeel.prefix" / "share" / "example-robot-data" / "robots"
    assert str(error).startswith(f"example-robot-data is installed but {folder} is missing;")


def test_a_missing_package_names_the_robot_parameter(monkeypatch: pytest.MonkeyPatch) -> None:
    def not_there(name: str) -> Any:
        raise metadata.PackageNotFoundError(name)

    monkeypatch.setattr(catalogue.metadata, "distribution", not_there)
    with pytest.raises(ParameterError) as missing:
        catalogue.robots_folder()
    assert missing.value.parameter == "robot" and "pip install example-robot-data" in str(
        missing.value
    )
