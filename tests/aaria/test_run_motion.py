"""The motion a run is asked for by name: the seed rule of Fourier, a trajectory file's grid."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.run_motion import MotionChoice, dh_motion
from aaria_pin.core.conflicts import OptionConflictError
from aaria_pin.errors import ParameterError

FIG2 = get_preset("aaria-fig2").table


def test_sine_and_as_stored() -> None:
    assert dh_motion(MotionChoice("sine"), None, {}, FIG2) == {"motion": None}
    assert dh_motion(MotionChoice(), None, {}, FIG2) == {}


def test_fourier_coefficients_come_from_the_runs_fourier_stream() -> None:
    from aaria_pin.aaria.simulate import dh_fourier_excitation

    made = dh_motion(MotionChoice("fourier", harmonics=2), None, {"seed": 3, "rate": 50.0}, FIG2)
    # the stream: SeedSequence(3).spawn-key of "fourier" (RunSeeds), independent of the noise's
    stream = np.random.SeedSequence(3, spawn_key=made["motion"].settings["seed"]["spawn_key"])
    expected = dh_fourier_excitation(FIG2, 10.0, 50.0, harmonics=2, seed=stream)
    np.testing.assert_array_equal(made["motion"].a, expected.a)
    assert made["motion"].settings["seed"]["entropy"] == 3
    other = dh_motion(MotionChoice("fourier", harmonics=2), None, {"seed": 4, "rate": 50.0}, FIG2)
    assert not np.array_equal(other["motion"].a, made["motion"].a)


def test_a_trajectory_file_gives_the_runs_grid(tmp_path: Path) -> None:
    t = np.arange(0, 2.01, 0.05)  # 20 Hz, 2 s
    q = np.column_stack([0.1 * np.sin(t + k) for k in range(6)])
    path = tmp_path / "motion.npy"
    np.save(path, np.column_stack([t, q]))
    made = dh_motion(MotionChoice("trajectory", trajectory=path), None, {}, FIG2)
    assert made["duration"] == pytest.approx(2.0) and made["rate"] == pytest.approx(20.0)
    np.testing.assert_allclose(made["motion"].q[:, 0], q[:, 0], atol=1e-12)


def test_a_trajectory_without_its_file_names_the_parameter() -> None:
    with pytest.raises(ParameterError) as error:
        dh_motion(MotionChoice("trajectory"), None, {}, FIG2)
    assert error.value.parameter == "trajectory"


@pytest.mark.parametrize(
    ("choice", "parameter", "other"),
    [
        ({"kind": "fourier", "trajectory": Path("m.npy")}, "motion", "trajectory"),
        ({"kind": "sine", "harmonics": 3}, "harmonics", "motion"),
        ({"base_frequency": 0.2}, "base_frequency", "motion"),
        ({"kind": "fourier", "smoothing": 0.1}, "smoothing", "trajectory"),
    ],
)
def test_settings_of_another_motion_are_refused(choice: dict, parameter: str, other: str) -> None:
    with pytest.raises(OptionConflictError) as error:
        MotionChoice(**choice)
    assert (error.value.parameter, error.value.other) == (parameter, other)


def test_a_trajectory_file_is_the_motions_kind(tmp_path: Path) -> None:
    choice = MotionChoice.from_options({"trajectory": tmp_path / "m.npy", "smoothing": 0.1})
    assert (choice.kind, choice.smoothing) == ("trajectory", 0.1)
    assert MotionChoice.from_options({"motion": "fourier", "seed": 3}) == MotionChoice("fourier")


@pytest.mark.parametrize(
    ("choice", "options", "message"),
    [
        (MotionChoice("fourier"), {"torques": 0}, "motion is given with torques"),
        (MotionChoice("sine"), {"torques": 0}, "motion is given with torques"),
        (
            MotionChoice(trajectory=Path("m.npy")),
            {"torques": 0},
            "trajectory is given with torques",
        ),
        (MotionChoice("fourier"), {"joint_table": 0}, "joint_table is given with motion='fourier'"),
        (
            MotionChoice(trajectory=Path("m.npy")),
            {"joint_table": 0},
            "joint_table is given with trajectory",
        ),
    ],
)
def test_a_motion_the_runs_options_make_meaningless_is_refused(
    choice: MotionChoice, options: dict, message: str
) -> None:
    with pytest.raises(OptionConflictError, match=f"^{message}; allowed: "):
        dh_motion(choice, None, options, FIG2)


def test_a_joint_table_given_is_followed_and_a_torque_drive_starts_as_it_was() -> None:
    table = get_preset("aaria-fig2").joint_table
    assert dh_motion(MotionChoice(), None, {"joint_table": table}, FIG2) == {"motion": None}
    assert dh_motion(MotionChoice(), None, {"torques": 0}, FIG2) == {}
