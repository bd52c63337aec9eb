"""matplotlib on a file-only backend, and the error where it is not installed."""

from __future__ import annotations

import sys

import pytest

from aaria_pin.errors import OutputFileError
from aaria_pin.viz._plotting import pyplot


def test_pyplot_draws_to_files_only() -> None:
    plt = pyplot()
    assert plt.get_backend().lower() == "agg"


def test_without_matplotlib_no_picture_can_be_written(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # an import of it fails
    with pytest.raises(OutputFileError) as missing:
        pyplot()
    error = missing.value
    assert isinstance(error, OSError) and error.parameter == "path"
    assert str(error) == (
        "plots need matplotlib, which is not installed; allowed: pip install 'aaria-pin[plot]'"
    )
