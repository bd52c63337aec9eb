"""The ``aaria identify`` request: options of another mode refused, outputs checked before any
work, the report written and told as text; its numbers against the identification called
directly."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.apps.identify import identify_dynamics, identify_kinematics
from aaria_pin.apps.identify.request import IdentifyRequest, identify_files
from aaria_pin.core.conflicts import OptionConflictError
from aaria_pin.errors import OutputFileError, ParameterError
from aaria_pin.files.runfile import write_run


@pytest.fixture(scope="module")
def fig3_record():
    """A noise-free aaria-fig3 run, 4 s at 50 Hz (its preset's motions)."""
    fig3 = get_preset("aaria-fig3")
    tables = (fig3.table, fig3.joint_table, fig3.base_table)
    return simulate_run(*tables, duration=4, rate=50, noise=False)


@pytest.fixture(scope="module")
def run_file(fig3_record, tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_run(tmp_path_factory.mktemp("request") / "run.h5", fig3_record)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"holdout": 0.3}, "holdout is given without dynamics"),
        ({"dataset": True, "holdout": 0.3}, "holdout is given without dynamics"),
        ({"parameters": True}, "parameters is given without dynamics"),
        (
            {"dynamics": True, "dataset": True, "parameters": True},
            "parameters is given with dataset",
        ),
        ({"workers": 2}, "workers is given without dataset"),
        ({"dynamics": True, "limit": 3}, "limit is given without dataset"),
        ({"plot": Path("cdf.png")}, "plot is given without dataset"),
        ({"dataset": True, "run": 0}, "run is given with dataset"),
        ({"dynamics": True, "urdf": Path("a.urdf")}, "urdf is given with dynamics"),
        ({"dataset": True, "urdf": Path("a.urdf")}, "urdf is given with dataset"),
    ],
)
def test_options_of_another_mode_are_refused(options: dict, message: str) -> None:
    with pytest.raises(OptionConflictError) as error:
        IdentifyRequest((Path("run.h5"),), **options)
    parameter, given, other = message.split(" is given ")[0], *message.split()[-2:]
    assert (error.value.parameter, error.value.other) == (parameter, other)
    assert error.value.given_with == (given == "with")
    opposite = "without" if given == "with" else "with"
    assert str(error.value) == f"{message}; allowed: {parameter} {opposite} {other}"
    assert isinstance(error.value, ParameterError)


def test_file_counts() -> None:
    with pytest.raises(ParameterError, match="no FILE"):
        IdentifyRequest(())
    with pytest.raises(ParameterError, match="2 files"):
        IdentifyRequest((Path("a.h5"), Path("b.h5")))
    assert IdentifyRequest((Path("a.h5"), Path("b.h5")), dataset=True, workers=2).workers == 2


def test_dynamics_writes_and_tells_the_report(run_file: Path, fig3_record, tmp_path) -> None:
    out = tmp_path / "report.json"
    outcome = identify_files(IdentifyRequest((run_file,), dynamics=True, holdout=0.3, output=out))
    assert outcome.report == json.loads(out.read_text())
    direct = identify_dynamics(fig3_record, holdout=0.3)
    assert outcome.report["samples_holdout"] == direct.samples_holdout == round(0.3 * 200)
    np.testing.assert_allclose(
        [p["estimate"] for p in outcome.report["base_parameters"]], direct.estimate, rtol=1e-9
    )
    text = "\n".join(identify_files(IdentifyRequest((run_file,), dynamics=True)).lines)
    assert "total mass:" in text and "held-out rel. RMS" in text and " = " not in text
    shown = identify_files(IdentifyRequest((run_file,), dynamics=True, parameters=True)).lines
    assert sum(" = " in line for line in shown) == direct.base.rank


def test_kinematics_writes_the_table_it_reports(run_file: Path, fig3_record, tmp_path) -> None:
    table, urdf = tmp_path / "est.csv", tmp_path / "est.urdf"
    outcome = identify_files(IdentifyRequest((run_file,), output=table, urdf=urdf))
    written = np.loadtxt(table, delimiter=",")
    np.testing.assert_array_equal(written, np.array(outcome.report["table"]))
    np.testing.assert_allclose(written, identify_kinematics(fig3_record).table, atol=1e-9)
    assert "<robot" in urdf.read_text()
    names = {0: "empty", 1: "revolute", 2: "prismatic"}
    types = get_preset("aaria-fig3").table[:6, 4].astype(int)
    assert outcome.lines[0] == "structure: " + ", ".join(
        f"{m + 1} {names[t]}" for m, t in enumerate(types)
    )


def test_outputs_and_runs_are_checked_before_any_work(run_file: Path, tmp_path) -> None:
    with pytest.raises(OutputFileError) as error:
        identify_files(IdentifyRequest((run_file,), dynamics=True, output=tmp_path / "r.csv"))
    assert error.value.parameter == "output" and "JSON report" in str(error.value)
    with pytest.raises(OutputFileError) as error:
        identify_files(IdentifyRequest((run_file,), urdf=tmp_path / "arm.xml"))
    assert error.value.parameter == "urdf"
    with pytest.raises(ParameterError) as error:
        identify_files(IdentifyRequest((run_file,), dynamics=True, run=3))
    assert error.value.parameter == "run"
    assert list(tmp_path.iterdir()) == []
