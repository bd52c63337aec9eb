"""``--imu-model`` and ``--hardware`` of aaria simulate and aaria dataset, through the CLI."""

from __future__ import annotations

import contextlib
import dataclasses
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from aaria_pin.cli import main
from aaria_pin.core.imu_noise import ADIS16485, noise_attributes
from aaria_pin.core.imu_presets import IMU_PRESETS

SHORT = ["--duration", "0.2", "--rate", "100"]
PRESETS = ", ".join(sorted(IMU_PRESETS))
"""The presets an unknown name is told of."""


def _run(*args: str) -> tuple[int, str]:
    result = CliRunner().invoke(main, list(args))
    return result.exit_code, result.stderr


def _attributes(path: Path) -> dict[str, object]:
    from aaria_pin.files.runfile import read_run

    return read_run(path).attributes


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ("[imu.gyro]\nnoise_density = -1.0\n",
         "hw.toml: imu.gyro.noise_density is -1.0; allowed: a finite number >= 0"),
        ('[imu]\npreset = "adis1"\n', f"hw.toml: imu.preset is 'adis1'; allowed: {PRESETS}"),
        ("[encoder]\nnoize = 1.0\n", "hw.toml: unknown key encoder.noize; allowed:"),
        ("[torque_sensor]\nbias = true\n", "hw.toml: torque_sensor.bias is True; allowed: a"),
        ("[imu]\ngyro = 1.0\n", "hw.toml: imu.gyro is 1.0; allowed: a table [imu.gyro]"),
    ],
)  # fmt: skip
def test_a_bad_hardware_file_is_one_line_exit_2_and_nothing_written(
    tmp_path: Path, table: str, message: str
) -> None:
    (tmp_path / "hw.toml").write_text(table)
    output = tmp_path / "run.h5"
    with pytest.MonkeyPatch.context() as patch:
        patch.chdir(tmp_path)
        code, stderr = _run("simulate", "--preset", "aaria-fig2", *SHORT,
                            "--hardware", "hw.toml", "-o", str(output))  # fmt: skip
    assert code == 2, stderr
    assert stderr.count("\n") == 1 and message in stderr, stderr
    assert not output.exists()


def test_an_unknown_preset_names_the_flag(tmp_path: Path) -> None:
    output = tmp_path / "run.h5"
    code, stderr = _run("simulate", "--robot", "ur5", *SHORT, "--imu-model", "nope", "-o",
                        str(output))  # fmt: skip
    assert code == 2 and stderr == f"aaria: error: --imu-model is 'nope'; allowed: {PRESETS}\n"
    assert not output.exists()
    code, stderr = _run("dataset", "-n", "2", *SHORT, "--imu-model", "nope", "-o", str(output))
    assert code == 2 and "--imu-model is 'nope'" in stderr and not output.exists()


def test_a_range_in_a_data_set_config_with_low_above_high_is_refused(tmp_path: Path) -> None:
    config = tmp_path / "ranges.toml"
    config.write_text("[imu.accel]\nnoise_density = [3.0e-4, 1.0e-4]\n")
    output = tmp_path / "ds.h5"
    code, stderr = _run("dataset", "-n", "2", *SHORT, "--config", str(config), "-o", str(output))
    assert code == 2 and stderr.count("\n") == 1 and not output.exists()
    assert "imu.accel.noise_density is [0.0003, 0.0001]; allowed: a range [low, high]" in stderr


def test_the_imu_model_flag_and_file_give_the_preset_s_model(tmp_path: Path) -> None:
    imu_file = tmp_path / "imu_model.toml"
    code, _ = _run("template", "imu-model", "-o", str(imu_file))
    assert code == 0
    for index, model in enumerate(("adis16485", str(imu_file))):
        output = tmp_path / f"run{index}.h5"
        code, stderr = _run("simulate", "--preset", "aaria-fig2", *SHORT, "--imu-model", model,
                            "-o", str(output))  # fmt: skip
        assert code == 0, stderr
        assert _attributes(output)["noise_parameters"] == noise_attributes(ADIS16485)


def test_the_hardware_file_sets_the_models_a_run_records(tmp_path: Path) -> None:
    (tmp_path / "hw.toml").write_text(
        "[imu]\nbias_correlation_time = 20.0\n[imu.gyro]\nnoise_density = 3.0e-4\n"
        "[encoder]\ncounts_per_revolution = 4096.0\n[actuator]\nviscous = 0.25\n"
    )
    output = tmp_path / "run.h5"
    code, stderr = _run("simulate", "--robot", "ur5", *SHORT, "--hardware",
                        str(tmp_path / "hw.toml"), "-o", str(output))  # fmt: skip
    assert code == 0, stderr
    attributes = _attributes(output)
    model = dataclasses.replace(
        ADIS16485,
        bias_correlation_time=20.0,
        gyro=dataclasses.replace(ADIS16485.gyro, noise_density=3.0e-4),
    )
    assert attributes["noise_parameters"] == noise_attributes(model)
    assert attributes["encoder"] == {"counts_per_revolution": 4096.0, "counts_per_metre": 0.0,
                                     "noise": 0.0, "offset": 0.0}  # fmt: skip
    assert attributes["actuator"]["viscous"] == 0.25  # type: ignore[index]
    assert "torque_sensor" not in attributes


@pytest.mark.parametrize("robot", [["--preset", "aaria-fig2"], ["--robot", "ur5"]])
def test_from_keeps_the_stored_models_unless_a_flag_replaces_them(
    tmp_path: Path, robot: list[str]
) -> None:
    from aaria_pin.files.runfile import read_run

    (tmp_path / "hw.toml").write_text(
        "[imu.accel]\nnoise_density = 1.0e-3\n[torque_sensor]\nnoise = 0.05\nbias = 0.1\n"
    )
    first, again = tmp_path / "first.h5", tmp_path / "again.h5"
    code, stderr = _run("simulate", *robot, *SHORT, "--hardware", str(tmp_path / "hw.toml"),
                        "--seed", "4", "-o", str(first))  # fmt: skip
    assert code == 0, stderr
    code, stderr = _run("simulate", "--from", str(first), "-o", str(again))
    assert code == 0, stderr
    stored, remade = read_run(first), read_run(again)
    for key in ("noise_parameters", "torque_sensor", "encoder", "actuator"):
        assert remade.attributes.get(key) == stored.attributes.get(key), key
    np.testing.assert_array_equal(remade.imu, stored.imu)  # the same IMU model, bit for bit
    for name in stored.tables:
        np.testing.assert_array_equal(remade.tables[name], stored.tables[name])
    # a flag replaces the stored IMU model; the joint models stay
    other = tmp_path / "other.h5"
    code, stderr = _run("simulate", "--from", str(first), "--imu-model", "adis16485", "-o",
                        str(other))  # fmt: skip
    assert code == 0, stderr
    replaced = read_run(other)
    assert replaced.attributes["noise_parameters"] == noise_attributes(ADIS16485)
    assert replaced.attributes["torque_sensor"] == stored.attributes["torque_sensor"]


def test_from_a_data_set_run_re_makes_it_with_its_drawn_models(tmp_path: Path) -> None:
    from aaria_pin.files.dataset.reader import DatasetReader
    from aaria_pin.files.runfile import read_run

    config = tmp_path / "ranges.toml"
    config.write_text("[imu.gyro]\nnoise_density = [1.0e-4, 3.0e-4]\n")
    data = tmp_path / "ds.h5"
    code, stderr = _run("dataset", "-n", "3", *SHORT, "--preset", "aaria-fig2", "--config",
                        str(config), "--quiet", "-o", str(data))  # fmt: skip
    assert code == 0, stderr
    output = tmp_path / "run2.h5"
    code, stderr = _run("simulate", "--from", str(data), "--run", "2", "-o", str(output))
    assert code == 0, stderr
    with DatasetReader(data) as reader:
        stored = reader.record(2)
        other = reader.record(1).attributes["noise_parameters"]
    remade = read_run(output)
    assert remade.attributes["noise_parameters"] == stored.attributes["noise_parameters"] != other
    for name in ("q", "tau", "imu", "base_wrench"):  # the data set stores float32
        again = np.asarray(getattr(remade, name), dtype=np.float32)
        np.testing.assert_array_equal(again, getattr(stored, name), err_msg=name)
    code, stderr = _run("simulate", "--preset", "aaria-fig2", "--run", "2", "-o", str(output))
    assert code == 2 and "--run K goes with --from DATA_SET" in stderr


@pytest.mark.parametrize("table", ["torque_sensor", "imu.gyro"])
def test_a_scale_error_of_one_or_more_is_refused(tmp_path: Path, table: str) -> None:
    import dataclasses as dc

    from aaria_pin.core.imu_noise import SensorNoise
    from aaria_pin.core.joint_sensors import TorqueSensorModel
    from aaria_pin.errors import ParameterError

    model = TorqueSensorModel if table == "torque_sensor" else SensorNoise
    if "scale_error" not in {f.name for f in dc.fields(model)}:
        pytest.skip(f"{model.__name__} has no scale_error yet (the IMU helper's part)")
    if model is TorqueSensorModel:
        with contextlib.suppress(ParameterError):
            TorqueSensorModel(scale_error=1.5)
            pytest.skip("TorqueSensorModel does not check scale_error yet (the joints helper's)")
    (tmp_path / "hw.toml").write_text(f"[{table}]\nscale_error = 1.5\n")
    output = tmp_path / "run.h5"
    code, stderr = _run("simulate", "--robot", "ur5", *SHORT, "--hardware",
                        str(tmp_path / "hw.toml"), "-o", str(output))  # fmt: skip
    assert code == 2 and stderr.count("\n") == 1, stderr
    assert f"hw.toml: {table}.scale_error is 1.5; allowed:" in stderr and not output.exists()
