"""The predictions file: written and read back, and every refusal one line naming the file."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from aaria_pin.apps.bench_tasks.predictions import read_predictions, run_key, write_predictions
from aaria_pin.errors import InputFileError


def test_written_predictions_read_back(tmp_path: Path) -> None:
    arrays = {3: np.arange(10.0).reshape(5, 2), 7: np.ones((5, 2), dtype=np.float32)}
    write_predictions(tmp_path / "p.npz", arrays)
    with np.load(tmp_path / "p.npz") as archive:
        assert sorted(archive.files) == ["run_3", "run_7"]
    read = read_predictions(tmp_path / "p.npz", [3, 7], (5, 2))
    assert read.keys() == {3, 7}
    np.testing.assert_array_equal(read[3], arrays[3])
    assert read[7].dtype == np.float64
    assert run_key(12) == "run_12"


@pytest.mark.parametrize(
    ("arrays", "wanted"),
    [
        ({"run_3": np.zeros((5, 2))}, "has no array run_7"),
        ({"run_3": np.zeros((5, 2)), "run_7": np.zeros((5, 2)), "x": np.zeros(1)}, "extra array x"),
        ({"run_3": np.zeros((5, 2)), "run_7": np.zeros((4, 2))}, "run_7 has shape (4, 2)"),
        ({"run_3": np.zeros((5, 2)), "run_7": np.full((5, 2), "a")}, "run_7 is of type <U1"),
        ({"run_3": np.zeros((5, 2)), "run_7": np.full((5, 2), np.inf)}, "run_7[0, 0] is inf"),
    ],
)
def test_bad_predictions_are_refused(
    tmp_path: Path, arrays: dict[str, np.ndarray], wanted: str
) -> None:
    path = tmp_path / "p.npz"
    np.savez(path, **arrays)
    with pytest.raises(InputFileError, match=r"p\.npz") as caught:
        read_predictions(path, [3, 7], (5, 2))
    assert wanted in str(caught.value)
    assert caught.value.parameter == "file"
    assert "\n" not in str(caught.value)


def test_a_file_that_is_not_npz_is_refused(tmp_path: Path) -> None:
    (tmp_path / "p.npz").write_text("not a zip")
    with pytest.raises(InputFileError, match="cannot be read as NPZ"):
        read_predictions(tmp_path / "p.npz", [0], (1,))
    (tmp_path / "p.csv").write_text("1")
    with pytest.raises(InputFileError, match="unknown predictions file type"):
        read_predictions(tmp_path / "p.csv", [0], (1,))
    with pytest.raises(InputFileError, match="no such file"):
        read_predictions(tmp_path / "missing.npz", [0], (1,))
