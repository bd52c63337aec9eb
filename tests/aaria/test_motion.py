"""Runs that follow a Fourier excitation or a given trajectory instead of the joint table's sines.

The Fourier runs' q, qd and qdd are checked against the limits written here from the DH table
(revolute ±1 rad, prismatic within the rail ±d/2) or the URDF, and against the series evaluated
here, sample by sample, from the coefficients the run stores. A run in pieces equals the run
made whole, and a run re-made from its record or its file equals the stored one, bit for bit.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import (
    dh_fourier_excitation,
    simulate_from_record,
    simulate_run,
    simulate_run_chunks,
)
from aaria_pin.apps.remake import remake_run
from aaria_pin.core.catalogue import find_robot
from aaria_pin.core.record import SERIES, RunRecord
from aaria_pin.core.run import join_chunks
from aaria_pin.core.sampled_motion import trajectory_from_samples
from aaria_pin.core.trajectory import JointTrajectory
from aaria_pin.core.urdf_robot import load_urdf_robot, read_urdf_file
from aaria_pin.core.urdf_run import (
    simulate_urdf_from_record,
    simulate_urdf_run,
    simulate_urdf_run_chunks,
    urdf_fourier_excitation,
)
from aaria_pin.errors import ParameterError
from aaria_pin.files.runfile import write_run

DURATION, RATE = 4.0, 50.0


def _assert_same(a: RunRecord, b: RunRecord) -> None:
    for name in SERIES:
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert a.tables.keys() == b.tables.keys()
    for name in a.tables:
        assert np.array_equal(a.tables[name], b.tables[name]), name
    assert a.attributes == b.attributes


def _series_by_hand(table: np.ndarray, f0: float, t: np.ndarray) -> tuple[np.ndarray, ...]:
    """q, qd, qdd of the stored coefficient rows (offset, a_1..a_L, b_1..b_L), sample by sample."""
    harmonics = (table.shape[1] - 1) // 2
    q = np.zeros((t.size, table.shape[0]))
    qd, qdd = np.zeros_like(q), np.zeros_like(q)
    for j, row in enumerate(table):
        offset, a, b = row[0], row[1 : 1 + harmonics], row[1 + harmonics :]
        for k, time in enumerate(t):
            value, speed, acceleration = offset, 0.0, 0.0
            for l in range(1, harmonics + 1):
                w = 2 * np.pi * f0 * l
                sl, cl = np.sin(w * time), np.cos(w * time)
                value += a[l - 1] / w * sl - b[l - 1] / w * cl
                speed += a[l - 1] * cl + b[l - 1] * sl
                acceleration += -a[l - 1] * w * sl + b[l - 1] * w * cl
            q[k, j], qd[k, j], qdd[k, j] = value, speed, acceleration
    return q, qd, qdd


def _ur5() -> tuple[str, Path]:
    entry = find_robot("ur5")
    return read_urdf_file(entry.urdf), entry.urdf.parent


@pytest.mark.parametrize("preset", ["aaria-fig2", "aaria-fig3"])
def test_dh_fourier_run_stays_within_its_limits_and_is_the_stored_series(preset: str) -> None:
    chosen = get_preset(preset)
    excitation = dh_fourier_excitation(chosen.table, DURATION, RATE, seed=5)
    record = simulate_run(
        chosen.table, duration=DURATION, rate=RATE, noise=False, motion=excitation
    )
    assert record.attributes["motion"] == "fourier"
    settings = record.attributes["fourier"]
    table = record.tables["fourier_coefficients"]
    q, qd, qdd = _series_by_hand(table, settings["base_frequency"], record.time)
    np.testing.assert_allclose(record.q, q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(record.qd, qd, rtol=0, atol=1e-12)
    np.testing.assert_allclose(record.qdd, qdd, rtol=0, atol=1e-11)
    codes = chosen.table[:6, 4].astype(int)  # 0 empty, 1 revolute, 2 prismatic
    for module, code in enumerate(codes):
        if code == 0:
            assert not np.any(record.q[:, module]) and not np.any(table[module])
            continue
        bound = 1.0 if code == 1 else chosen.table[module, 3] / 2  # ±1 rad or the rail ±d/2
        speed, acceleration = (1.5, 5.0) if code == 1 else (0.5, 2.0)
        assert np.abs(record.q[:, module]).max() <= bound
        assert np.abs(record.qd[:, module]).max() <= speed
        assert np.abs(record.qdd[:, module]).max() <= acceleration
        # scaled to reach 95 % of its tightest limit
        reach = max(
            np.abs(record.q[:, module]).max() / bound,
            np.abs(record.qd[:, module]).max() / speed,
            np.abs(record.qdd[:, module]).max() / acceleration,
        )
        assert reach == pytest.approx(0.95, abs=1e-9)


def test_urdf_fourier_run_stays_within_the_urdf_limits() -> None:
    text, folder = _ur5()
    loaded = load_urdf_robot(text, urdf_dir=folder, moving_base=True)
    excitation = urdf_fourier_excitation(loaded, DURATION, RATE, harmonics=3, seed=2)
    record = simulate_urdf_run(
        text, urdf_dir=folder, duration=DURATION, rate=RATE, noise=False, motion=excitation
    )
    table = record.tables["fourier_coefficients"]
    assert table.shape == (6, 7)
    q, qd, qdd = _series_by_hand(table, record.attributes["fourier"]["base_frequency"], record.time)
    np.testing.assert_allclose(record.q, q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(record.qdd, qdd, rtol=0, atol=1e-11)
    np.testing.assert_allclose(record.qd, qd, rtol=0, atol=1e-12)
    # ur5.urdf: elbow ±π, the others ±2π; velocity limits 3.15 (arm) and 3.2 (wrist) rad/s
    assert np.all(np.abs(record.q[:, 2]) <= np.pi) and np.all(np.abs(record.q) <= 2 * np.pi)
    assert np.all(np.abs(record.qd) <= 1.5) and np.all(np.abs(record.qdd) <= 5.0)


def test_a_fourier_run_in_pieces_is_the_run_made_whole() -> None:
    chosen = get_preset("aaria-fig3")
    excitation = dh_fourier_excitation(chosen.table, DURATION, RATE, seed=9)
    whole = simulate_run(chosen.table, duration=DURATION, rate=RATE, motion=excitation)
    pieces = simulate_run_chunks(
        chosen.table, duration=DURATION, rate=RATE, motion=excitation, chunk=37
    )
    _assert_same(join_chunks(pieces), whole)
    text, folder = _ur5()
    loaded = load_urdf_robot(text, urdf_dir=folder, moving_base=True)
    urdf_excitation = urdf_fourier_excitation(loaded, DURATION, RATE, seed=9)
    settings = {"urdf_dir": folder, "duration": DURATION, "rate": RATE, "motion": urdf_excitation}
    _assert_same(
        join_chunks(simulate_urdf_run_chunks(text, chunk=41, **settings)),
        simulate_urdf_run(text, **settings),
    )


def test_fourier_and_trajectory_runs_are_remade_bit_for_bit(tmp_path: Path) -> None:
    chosen = get_preset("aaria-fig2")
    fourier = simulate_run(
        chosen.table,
        duration=DURATION,
        rate=RATE,
        motion=dh_fourier_excitation(chosen.table, DURATION, RATE, seed=1),
    )
    _assert_same(simulate_from_record(fourier), fourier)
    _assert_same(remake_run(write_run(tmp_path / "fourier.h5", fourier)), fourier)
    given = JointTrajectory(fourier.time, fourier.q * 0.5, fourier.qd * 0.5, fourier.qdd * 0.5)
    followed = simulate_run(chosen.table, duration=DURATION, rate=RATE, motion=given)
    assert followed.attributes["motion"] == "trajectory"
    assert followed.tables["joint_trajectory"].shape == (fourier.n_samples, 19)
    _assert_same(remake_run(write_run(tmp_path / "given.mat", followed)), followed)
    text, folder = _ur5()
    urdf = simulate_urdf_run(
        text,
        urdf_dir=folder,
        duration=DURATION,
        rate=RATE,
        motion=urdf_fourier_excitation(
            load_urdf_robot(text, urdf_dir=folder, moving_base=True), DURATION, RATE, seed=3
        ),
    )
    _assert_same(simulate_urdf_from_record(urdf), urdf)
    # a run written before motions were stored (no attribute) is re-made with its sines
    sine = simulate_run(chosen.table, chosen.joint_table, duration=1.0, rate=RATE)
    assert sine.attributes["motion"] == "sine"
    del sine.attributes["motion"]
    remade = simulate_from_record(sine)
    assert np.array_equal(remade.q, sine.q) and np.array_equal(remade.imu, sine.imu)


def test_a_given_trajectory_is_followed_at_its_samples() -> None:
    """Samples of a motion through trajectory_from_samples: q exactly, the derivatives close."""
    t = np.arange(0, 201) / RATE
    q = np.column_stack([0.3 * np.sin(1.1 * t + k) for k in range(6)])
    qd_true = np.column_stack([0.33 * np.cos(1.1 * t + k) for k in range(6)])
    given = trajectory_from_samples(t, q, rate=RATE)
    text, folder = _ur5()
    record = simulate_urdf_run(
        text, urdf_dir=folder, duration=4.0, rate=RATE, noise=False, motion=given
    )
    assert np.array_equal(record.q, q)
    np.testing.assert_allclose(record.qd, qd_true, atol=1e-6)
    chosen = get_preset("aaria-fig3")  # module 2 empty (its column ignored), 1, 3, 4 prismatic
    scale = np.array([0.2, 1.0, 0.2, 0.2, 1.0, 1.0])  # within the rails of 0.17 m and more
    samples = trajectory_from_samples(t, q * scale, rate=RATE)
    dh = simulate_run(chosen.table, duration=4.0, rate=RATE, noise=False, motion=samples)
    moving = [0, 2, 3, 4, 5]
    assert np.array_equal(dh.q[:, moving], (q * scale)[:, moving]) and not np.any(dh.q[:, 1])


def test_bad_motions_are_refused_in_one_line() -> None:
    chosen = get_preset("aaria-fig3")
    t = np.arange(0, 201) / RATE
    zeros = np.zeros((t.size, 6))
    with pytest.raises(ParameterError, match="trajectory") as short:
        simulate_run(
            chosen.table,
            duration=5.0,
            rate=RATE,
            motion=JointTrajectory(t, zeros, zeros, zeros),
        )
    assert "\n" not in str(short.value) and short.value.parameter == "trajectory"
    beyond = zeros.copy()
    beyond[:, 0] = 0.2  # module 1 is prismatic with a rail of 0.17 m: ±0.085 m
    with pytest.raises(ParameterError, match=r"joint1 moves over \[0\.2, 0\.2\]"):
        simulate_run(
            chosen.table, duration=4.0, rate=RATE, motion=JointTrajectory(t, beyond, zeros, zeros)
        )
    text, folder = _ur5()
    excitation = dh_fourier_excitation(chosen.table, 4.0, RATE)
    four_joints = type(excitation)(
        excitation.a[:4], excitation.b[:4], excitation.offset[:4], excitation.base_frequency
    )
    with pytest.raises(ParameterError, match="Fourier excitation of 4 joints; allowed: 6"):
        simulate_urdf_run(text, urdf_dir=folder, duration=4.0, rate=RATE, motion=four_joints)
