"""Encoders: every reading is a whole number of counts from the run's offset (revolute and
prismatic joints, read back from a run file); no counts, noise or offset reads the true q."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import aaria_pin as ap
from aaria_pin.core.encoder import encoder_reading
from aaria_pin.core.joint_sensors import EncoderModel
from aaria_pin.core.run import RunSettings, simulate
from aaria_pin.files.runfile import read_run, write_run

COUNTS = {"counts_per_revolution": 4096.0, "counts_per_metre": 20000.0}


def test_a_reading_by_hand() -> None:
    q = np.array([[0.25, 0.0], [0.34, -0.11]])
    got = encoder_reading(q, np.array([0.01, 0.02]), np.array([0.1, 0.0]))
    # joint 1: 0.01 + 0.1·round(q/0.1): 2.5 → 2 (half to even), 3.4 → 3
    np.testing.assert_allclose(got[:, 0], [0.21, 0.31])
    np.testing.assert_array_equal(got[:, 1], q[:, 1] + 0.02)  # no counts: q + its offset


def test_every_reading_is_a_whole_number_of_counts_from_the_offset(tmp_path: Path) -> None:
    robot = ap.preset_arm("aaria-fig2")  # 2 prismatic, 4 revolute modules
    model = EncoderModel(**COUNTS, noise=2e-4, offset=1e-3)
    record = simulate(robot, settings=RunSettings(0.2, 100.0, encoder=model), seeds=5)
    stored = read_run(write_run(tmp_path / "run.h5", record))
    assert stored.attributes["encoder"]["counts_per_revolution"] == 4096.0
    prismatic = stored.tables["senSenDH"][:6, 4] == 2
    step = np.where(prismatic, 1.0 / COUNTS["counts_per_metre"], 2 * np.pi / 4096.0)
    offset = stored.tables["encoder_offset"]
    assert offset.shape == (1, 6) and (offset != 0).all()
    counts = (stored.tables["q_measured"] - offset) / step
    np.testing.assert_allclose(counts, np.round(counts), rtol=0, atol=1e-6)
    error = stored.tables["q_measured"] - offset - stored.q  # q shifted by its offset
    assert (np.abs(error) < 5 * 2e-4 + step).all()
    # the offset is in the reading (a miscalibrated zero), not only a sub-count shift
    mean_shift = (stored.tables["q_measured"] - stored.q).mean(axis=0)
    np.testing.assert_allclose(mean_shift, offset[0], atol=step.max() + 1e-4)
    np.testing.assert_array_equal(stored.q, record.q)  # q stays the true value
    assert prismatic.any() and not prismatic.all()


def test_without_counts_noise_or_offset_the_reading_is_q() -> None:
    robot = ap.preset_arm("aaria-fig2")
    record = simulate(robot, settings=RunSettings(0.2, 100.0, encoder=EncoderModel()), seeds=1)
    np.testing.assert_array_equal(record.tables["q_measured"], record.q)
    np.testing.assert_array_equal(record.tables["encoder_offset"], np.zeros((1, 6)))
