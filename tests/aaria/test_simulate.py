from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.sensen import SENSEN_COLUMNS, imu_slot_order
from aaria_pin.aaria.simulate import simulate_run

FIG3 = get_preset("aaria-fig3").table


def test_sensen_layout_column_by_column() -> None:
    record = simulate_run(FIG3, duration=1.0, rate=20, noise=False)
    assert record.view("senSen").shape == (21, 91)
    assert len(SENSEN_COLUMNS) == 91
    assert SENSEN_COLUMNS[:8] == ("time", "q1", "q2", "q3", "q4", "q5", "q6", "imu_base_wx")
    assert SENSEN_COLUMNS[13:19] == tuple(
        f"imu_tool_{s}" for s in ("wx", "wy", "wz", "fx", "fy", "fz")
    )
    assert SENSEN_COLUMNS[-1] == "imu_link6_b_fz"
    np.testing.assert_allclose(record.view("senSen")[:, 0], np.arange(21) / 20)
    np.testing.assert_array_equal(record.view("senSen")[:, 1:7], record.q)
    slots = imu_slot_order()
    for slot in ("imu_link2_a", "imu_link2_b"):  # module 2 is empty in Figure 3
        start = SENSEN_COLUMNS.index(f"{slot}_wx")
        assert not record.view("senSen")[:, start : start + 6].any()
        assert not record.imu_mount[slots.index(slot)].any()
    for array in (record.q, record.qd, record.qdd, record.tau):
        assert array.shape == (21, 6)
        assert not array[:, 1].any()
    assert record.base_wrench.shape == (21, 6)
    assert record.tool_pose.shape == (21, 4, 4)
    assert record.imu_mount.shape == (14, 4, 4)
    np.testing.assert_array_equal(record.tables["senSenDH"], FIG3)
    assert record.tables["senSenJ"].shape == (8, 5) and record.tables["senSenB"].shape == (2, 4)


def test_same_seed_same_arrays_other_seed_others() -> None:
    a = simulate_run(FIG3, duration=1.0, rate=50, seed=3)
    b = simulate_run(FIG3, duration=1.0, rate=50, seed=3)
    c = simulate_run(FIG3, duration=1.0, rate=50, seed=4)
    exact = simulate_run(FIG3, duration=1.0, rate=50, noise=False)
    np.testing.assert_array_equal(a.view("senSen"), b.view("senSen"))
    assert not np.array_equal(a.view("senSen")[:, 7:], c.view("senSen")[:, 7:])
    np.testing.assert_array_equal(a.view("senSen")[:, :7], exact.view("senSen")[:, :7])
    noise = a.view("senSen")[:, 7:] - exact.view("senSen")[:, 7:]
    assert 0 < np.abs(noise).max() < 0.5
    np.testing.assert_array_equal(a.tau, exact.tau)


def test_attributes_record_the_settings() -> None:
    record = simulate_run(FIG3, duration=0.5, rate=10, seed=9, noise=False)
    attrs = record.attributes
    assert attrs["rate"] == 10 and attrs["duration"] == 0.5 and attrs["seed"] == 9
    assert attrs["noise"] is False
    assert attrs["gravity"] == [0.0, 0.0, -9.81]
    assert "gyro_noise_density_rad_s_sqrtHz" in attrs["noise_parameters"]
    assert attrs["version"]


def test_standard_table_is_refused_for_a_run() -> None:
    from aaria_pin.errors import TableError

    with pytest.raises(TableError, match="8 × 5"):
        simulate_run(get_preset("spherical-wrist").table)


def test_preset_oscillation_tables_follow_the_documented_rule() -> None:
    from aaria_pin.aaria.dh import chain_from_table
    from aaria_pin.aaria.sine_tables import default_base_table, default_joint_table

    for name in ("aaria-fig2", "aaria-fig3"):
        preset = get_preset(name)
        chain = chain_from_table(preset.table)
        np.testing.assert_allclose(preset.joint_table, default_joint_table(chain), atol=1e-12)
        np.testing.assert_array_equal(preset.base_table, default_base_table())


def test_custom_imu_mounts_move_the_sensors_and_are_remade_from_file(tmp_path) -> None:
    from aaria_pin.aaria.dh_robot import BodyDimensions
    from aaria_pin.aaria.simulate import simulate_from_run_file
    from aaria_pin.files.runfile import write_run

    default = simulate_run(FIG3, duration=0.5, rate=20, noise=False)
    mounts = default.imu_mount.copy()
    slot = imu_slot_order().index("imu_link5_a")
    mounts[slot, :3, :3] = [[0, -1, 0], [1, 0, 0], [0, 0, 1]]  # turned 90° about z
    custom = simulate_run(
        FIG3,
        duration=0.5,
        rate=20,
        noise=True,
        seed=2,
        imu_mount=mounts,
        dims=BodyDimensions(density=7850.0),
    )
    np.testing.assert_array_equal(custom.imu_mount, mounts)
    column = SENSEN_COLUMNS.index("imu_link5_a_wx")
    exact = simulate_run(FIG3, duration=0.5, rate=20, noise=False, imu_mount=mounts)
    np.testing.assert_allclose(
        exact.view("senSen")[:, column], default.view("senSen")[:, column + 1], atol=1e-12
    )
    np.testing.assert_allclose(
        exact.view("senSen")[:, column + 1], -default.view("senSen")[:, column], atol=1e-12
    )
    write_run(tmp_path / "run.h5", custom)
    remade = simulate_from_run_file(tmp_path / "run.h5")
    for name, array in custom.arrays().items():
        np.testing.assert_array_equal(remade.arrays()[name], array, err_msg=name)


@pytest.mark.parametrize("change", ["shape", "scale", "nan"])
def test_bad_imu_mounts(change: str) -> None:
    from aaria_pin.errors import ParameterError

    mounts = np.tile(np.eye(4), (14, 1, 1))
    if change == "shape":
        mounts = mounts[:13]
    elif change == "scale":
        mounts[3, 0, 0] = 2.0
    else:
        mounts[4, 0, 3] = np.nan
    with pytest.raises(ParameterError, match="imu_mount"):
        simulate_run(FIG3, duration=0.2, rate=10, imu_mount=mounts)


def test_joint_columns_follow_the_sine_formula() -> None:
    record = simulate_run(FIG3, duration=1.0, rate=20, noise=False)
    preset = get_preset("aaria-fig3")
    t = np.arange(21) / 20
    for module in (1, 3, 4, 5, 6):
        A, Ap, bias, w, phase = preset.joint_table[module - 1]
        amplitude = A if preset.table[module - 1, 4] == 1 else Ap
        expected = amplitude * np.sin(w * t + phase) + bias
        np.testing.assert_allclose(record.view("senSen")[:, module], expected, atol=1e-15)
        np.testing.assert_allclose(
            record.qd[:, module - 1], amplitude * w * np.cos(w * t + phase), atol=1e-15
        )


def test_default_imu_mounts_by_hand() -> None:
    from aaria_pin.aaria.dh_robot import BodyDimensions

    record = simulate_run(FIG3, duration=0.1, rate=10, noise=False)
    h = BodyDimensions().link_height
    slots = imu_slot_order()
    np.testing.assert_array_equal(record.imu_mount[slots.index("imu_base")], np.eye(4))
    np.testing.assert_array_equal(record.imu_mount[slots.index("imu_tool")], np.eye(4))
    for module in (1, 3, 4, 5, 6):
        a = FIG3[module - 1, 1]
        mount_a = record.imu_mount[slots.index(f"imu_link{module}_a")]
        mount_b = record.imu_mount[slots.index(f"imu_link{module}_b")]
        np.testing.assert_allclose(mount_a[:3, 3], [a / 2, 0, h / 2])
        np.testing.assert_allclose(mount_b[:3, 3], [0.9 * a, 0, -h / 2])
        np.testing.assert_array_equal(mount_a[:3, :3], np.eye(3))


def test_bad_seeds_are_refused() -> None:
    from aaria_pin.errors import ParameterError

    for seed in (-1, 2**63, 1.5):
        with pytest.raises(ParameterError, match="seed"):
            simulate_run(FIG3, duration=0.1, rate=10, seed=seed)  # type: ignore[arg-type]


def test_absurd_density_is_refused() -> None:
    from aaria_pin.aaria.dh_robot import BodyDimensions
    from aaria_pin.errors import ParameterError

    with pytest.raises(ParameterError, match="density of every body is 1e\\+308"):
        BodyDimensions(density=1e308)


def test_record_layout_the_sensen_view_over_q_and_imu_and_the_base_pose() -> None:
    from conftest import paper_base_state

    preset = get_preset("aaria-fig3")
    record = simulate_run(
        FIG3, preset.joint_table, preset.base_table, duration=0.5, rate=20, seed=1
    )
    assert record.joint_names == tuple(f"joint{i}" for i in range(1, 7))
    assert record.imu_names == imu_slot_order()
    assert record.attributes["kind"] == "dh"
    empty = [m.name for m in record.imu_mounts if m.parent == ""]
    assert empty == ["imu_link2_a", "imu_link2_b"]  # module 2 is empty in Figure 3
    sensen = record.view("senSen")
    assert sensen.shape == (11, 91)
    for k, slot in enumerate(imu_slot_order()):  # senSen's IMU columns are the imu array
        start = SENSEN_COLUMNS.index(f"{slot}_wx")
        np.testing.assert_array_equal(sensen[:, start : start + 6], record.imu[:, k])
        np.testing.assert_array_equal(sensen[:, start : start + 6], record.imu_signals(slot))
    slots = imu_slot_order()
    assert not record.imu[:, [slots.index("imu_link2_a"), slots.index("imu_link2_b")]].any()
    position, _, _, rotation, _, _ = paper_base_state(preset.base_table, record.time)
    np.testing.assert_allclose(record.base_pose[:, :3, 3], position, atol=1e-12)
    np.testing.assert_allclose(record.base_pose[:, :3, :3], rotation, atol=1e-12)
    np.testing.assert_array_equal(record.base_pose[:, 3], np.tile([0, 0, 0, 1.0], (11, 1)))
    assert record.urdf.startswith("<?xml") or "<robot" in record.urdf[:200]


def test_an_arm_is_built_once_per_table_and_records_own_their_arrays() -> None:
    from aaria_pin.aaria.arm_run import ARM_CACHE_SIZE, cached_arm
    from aaria_pin.aaria.dh_robot import BodyDimensions, build_dh_robot

    fig2, fig3 = get_preset("aaria-fig2"), get_preset("aaria-fig3")
    robot, model = cached_arm(fig2.table)
    assert cached_arm(np.array(fig2.table).tolist()) == (robot, model)  # same numbers: same arm
    assert cached_arm(fig3.table)[0] is not robot
    assert cached_arm(fig2.table, BodyDimensions(density=1000.0))[0] is not robot
    assert cached_arm(fig2.table, BodyDimensions(density=1000.0))[0].dims.density == 1000.0
    fresh = build_dh_robot(fig2.table, "aaria")
    assert robot.urdf == fresh.urdf  # the cached arm is the arm the builder makes
    assert model.model.nq == fresh.model(moving_base=True).model.nq
    for k in range(ARM_CACHE_SIZE + 1):  # bounded: the oldest goes
        table = np.array(fig2.table, dtype=float)
        table[0, 0] += 1e-3 * (k + 1)
        cached_arm(table)
    assert cached_arm(fig2.table)[0] is not robot

    record = simulate_run(fig2.table, duration=0.05, rate=100.0)
    mount = next(m for m in record.imu_mounts if m.parent)
    mount.T_parent_imu[0, 3] = 99.0  # a record's arrays are its own
    again = simulate_run(fig2.table, duration=0.05, rate=100.0)
    assert next(m for m in again.imu_mounts if m.parent).T_parent_imu[0, 3] != 99.0
    np.testing.assert_array_equal(again.imu, record.imu)


def test_bad_tables_still_raise_through_the_cache() -> None:
    from aaria_pin.errors import TableError

    with pytest.raises(TableError):
        simulate_run([["a"] * 5] * 8)
    with pytest.raises(TableError):
        simulate_run(np.full((8, 5), np.nan))


def test_a_changed_density_mapping_neither_changes_nor_reuses_a_cached_arm() -> None:
    from aaria_pin.aaria.dh_robot import BodyDimensions

    table = get_preset("aaria-fig2").table
    densities = {"link3": 2700.0}
    light = simulate_run(
        table, duration=0.1, noise=False, dims=BodyDimensions(density_overrides=densities)
    )
    densities["link3"] = 8000.0  # the caller's mapping changes after the run
    heavy = simulate_run(
        table, duration=0.1, noise=False, dims=BodyDimensions(density_overrides=densities)
    )
    again = simulate_run(
        table, duration=0.1, noise=False, dims=BodyDimensions(density_overrides={"link3": 2700.0})
    )
    assert not np.array_equal(light.tau, heavy.tau)  # a denser link 3 needs other torques
    np.testing.assert_array_equal(again.tau, light.tau)
    assert again.attributes["body_dimensions"]["density_overrides"] == {"link3": 2700.0}
    assert heavy.attributes["body_dimensions"]["density_overrides"] == {"link3": 8000.0}


def test_the_deprecated_dh_producers_warn_and_equal_the_request() -> None:
    import warnings

    from aaria_pin.aaria.simulate import (
        dh_request,
        dh_request_from_record,
        simulate_from_record,
        simulate_from_record_chunks,
        simulate_run_chunks,
    )
    from aaria_pin.core.run import join_chunks

    fig2 = get_preset("aaria-fig2")
    options = {"duration": 0.5, "rate": 40.0, "seed": 7}
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the replacement itself warns of nothing
        expected = dh_request(fig2.table, joint_table=fig2.joint_table, **options).record()
        again = dh_request_from_record(expected, chunk=5).pieces()
    with pytest.warns(DeprecationWarning, match=r"^simulate_run is deprecated; use .*dh_request"):
        record = simulate_run(fig2.table, fig2.joint_table, **options)
    np.testing.assert_array_equal(record.imu, expected.imu)
    np.testing.assert_array_equal(record.tau, expected.tau)
    with pytest.warns(DeprecationWarning, match="simulate_run_chunks is deprecated"):
        pieces = join_chunks(simulate_run_chunks(fig2.table, fig2.joint_table, chunk=7, **options))
    with pytest.warns(DeprecationWarning, match="simulate_from_record is deprecated"):
        remade = simulate_from_record(expected)
    with pytest.warns(DeprecationWarning, match="simulate_from_record_chunks is deprecated"):
        remade_pieces = join_chunks(simulate_from_record_chunks(expected, chunk=9))
    for other in (pieces, remade, remade_pieces, join_chunks(again)):
        np.testing.assert_array_equal(other.imu, expected.imu)
        np.testing.assert_array_equal(other.q, expected.q)
    assert expected.n_samples == 21 and np.abs(expected.imu).max() > 0


def test_a_stored_mount_that_is_not_rigid_names_the_file_not_the_option() -> None:
    from aaria_pin.aaria.simulate import dh_request, dh_request_from_record
    from aaria_pin.errors import InputFileError, ParameterError

    fig2 = get_preset("aaria-fig2")
    from dataclasses import replace

    whole = dh_request(fig2.table, duration=0.2, rate=20.0).record()
    bent = replace(whole.imu_mounts[0], T_parent_imu=np.diag([2.0, 1.0, 1.0, 1.0]))
    stored = replace(whole, imu_mounts=(bent, *whole.imu_mounts[1:]))
    with pytest.raises(InputFileError) as error:
        dh_request_from_record(stored, source="run.h5")
    assert error.value.parameter == "file"
    message = str(error.value)
    assert message.startswith("run.h5: imu_mount of ") and "not a rigid" in message
    with pytest.raises(ParameterError) as given:  # the mounts given replace the file's
        dh_request_from_record(stored, imu_mount=stored.imu_mount)
    assert given.value.parameter == "imu_mount"
