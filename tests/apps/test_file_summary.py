"""What ``aaria info`` and ``dataset-stats`` tell of a file, against the file read with h5py."""

from __future__ import annotations

import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest

from aaria_pin.apps.file_summary import describe_file, statistics_report
from aaria_pin.errors import InputFileError, ParameterError

FIXTURES = Path(__file__).parents[1] / "fixtures" / "v0_3_0"


def test_a_run_file_summary_and_its_text() -> None:
    path = FIXTURES / "dh_run.h5"
    summary, text = describe_file(path)
    with h5py.File(path, "r") as handle:
        samples, joints = handle["q"].shape
        imus = handle["imu"].shape[1]
    assert summary["samples"] == samples and len(summary["joints"]) == joints
    lines = text.splitlines()
    assert lines[0] == f"{path}: dh run of aaria-fig2, {samples} samples at 100 Hz"
    assert lines[2].startswith(f"joints ({joints}: joint1,") and lines[3].startswith(
        f"IMUs ({imus}:"
    )
    assert f"  q             {samples} × {joints}" in lines and text.endswith("\n")


def test_a_data_set_summary_its_card_and_a_run_file_refused() -> None:
    path = FIXTURES / "dh_dataset.h5"
    summary, text = describe_file(path)
    with h5py.File(path, "r") as handle:
        runs, samples = handle["time"].shape
        complete = int(handle["complete"][()].sum())
    assert (summary["runs"], summary["samples"]) == (runs, samples)
    assert text.startswith(f"{path}: data set of {runs} dh runs × {samples} samples (float32), ")
    assert f"{complete} complete, failed none" in text.splitlines()[0]
    card, card_text = describe_file(path, card=True)
    assert card_text.startswith(f"# Data card: {path}\n") and isinstance(card, dict)
    with pytest.raises(ParameterError) as caught:
        describe_file(FIXTURES / "dh_run.h5", card=True)
    assert caught.value.parameter == "card"


def test_a_damaged_data_set_is_one_input_error(tmp_path: Path) -> None:
    path = tmp_path / "ds.h5"
    shutil.copyfile(FIXTURES / "dh_dataset.h5", path)
    with h5py.File(path, "r+") as handle:
        del handle["q"]
    with pytest.raises(InputFileError, match="a damaged data set") as caught:
        describe_file(path)
    assert caught.value.parameter == "file"


def test_statistics_of_every_run_against_numpy(tmp_path: Path) -> None:
    path = tmp_path / "ds.h5"
    shutil.copyfile(FIXTURES / "dh_dataset.h5", path)
    document, text = statistics_report(path, ("q",), split="all", store=True)
    with h5py.File(path, "r") as handle:
        q = handle["q"][()].astype(np.float64).reshape(-1, handle["q"].shape[-1])
        assert "statistics" in handle
    np.testing.assert_allclose(document["q"]["mean"], q.mean(axis=0), rtol=1e-12)
    np.testing.assert_allclose(document["q"]["std"], q.std(axis=0), rtol=1e-10)
    lines = text.splitlines()
    assert lines[0] == f"{path}: split all (seed 0, fractions 0.8,0.1,0.1), 3 runs"
    assert lines[1] == "q (6 channels)" and float(lines[3].split()[1]) == pytest.approx(
        q.mean(axis=0)[0], rel=1e-5
    )
    assert lines[-1] == f"stored in {path} under statistics/all"
