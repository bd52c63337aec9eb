"""The command line for URDF robots: aaria robots, simulate --robot/--urdf, bad URDFs."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import run_cli

from aaria_pin.files.runfile import read_run


def test_robots_lists_the_catalogue() -> None:
    code, out, err = run_cli("robots", "--paths")
    assert code == 0
    lines = dict(line.split(maxsplit=1) for line in out.splitlines())
    assert lines["ur5"].endswith("ur5_robot.urdf") and "panda" in lines
    assert "robots in" in err


@pytest.mark.slow
def test_robots_check_tells_which_load_and_why_others_do_not() -> None:
    code, out, _ = run_cli("robots", "--check")
    assert code == 0
    status = {line.split()[0]: line.split(maxsplit=1)[1] for line in out.splitlines()}
    assert status["ur5"] == "6 joints, 14 IMUs"
    assert status["iris_simple"].startswith("refused: robot 'iris' has no actuated joint")
    assert sum(not s.startswith("refused") for s in status.values()) == 61


def test_simulate_a_robot_then_remake_it_from_its_file(tmp_path: Path) -> None:
    first = tmp_path / "panda.h5"
    code, out, _ = run_cli("simulate", "--robot", "panda", "--duration", "1", "-o", str(first))
    assert code == 0 and "panda, 9 joints, 20 IMUs, 101 samples" in out
    again = tmp_path / "again.h5"
    assert run_cli("simulate", "--from", str(first), "-o", str(again))[0] == 0
    a, b = read_run(first), read_run(again)
    np.testing.assert_array_equal(a.signals(), b.signals())
    np.testing.assert_array_equal(a.tau, b.tau)
    code, out, _ = run_cli("info", str(first))
    assert code == 0 and "joints (9: panda_joint1," in out


def test_simulate_a_urdf_file_with_layout_tables_and_fixed_base(tmp_path: Path) -> None:
    from aaria_pin.core.catalogue import find_robot

    urdf = tmp_path / "ur5.urdf"
    text = find_robot("ur5").urdf.read_text()
    urdf.write_text(text.replace("package://example-robot-data/", "package://gone/"))
    joints = tmp_path / "joints.csv"
    rows = [f"0.3,0,0,{1 + 0.1 * i},0" for i in range(6)]
    joints.write_text(
        "# amplitude, prismatic amplitude, bias, frequency, phase\n" + "\n".join(rows)
    )
    layout = tmp_path / "imus.toml"
    layout.write_text('[[imu]]\nname = "imu_wrist"\nparent = "tool0"\nxyz = [0, 0, 0.02]\n')
    out = tmp_path / "run.h5"
    code, _, stderr = run_cli(
        "simulate", "--urdf", str(urdf), "--joints", str(joints), "--imu-layout", str(layout),
        "--fixed-base", "--tool", "wrist_3_link", "--no-noise", "--duration", "1", "-o", str(out),
    )  # fmt: skip
    assert code == 0, stderr
    assert stderr.startswith("aaria: warning: ") and "mesh file(s)" in stderr
    record = read_run(out)
    assert [m.name for m in record.imu_mounts] == ["imu_wrist"]
    assert (
        record.attributes["tool_frame"] == "wrist_3_link" and not record.attributes["moving_base"]
    )
    np.testing.assert_allclose(record.q[:, 0], 0.3 * np.sin(1.0 * record.time))


@pytest.mark.parametrize(
    ("urdf_text", "pattern"),
    [
        ("<robot name='r'><link name='a'/>", "not well-formed XML: line 1"),
        (
            "<robot name='r'><link name='a'/><link name='b'/><joint name='j' type='fixed'>"
            "<child link='b'/></joint></robot>",
            "joint 'j': no <parent link=...>",
        ),
        (
            "<robot name='r'><link name='a'/><link name='b'><inertial><mass value='-1'/>"
            "</inertial></link><joint name='j' type='fixed'><parent link='a'/><child link='b'/>"
            "</joint></robot>",
            "link 'b': mass -1 kg",
        ),
    ],
)
def test_bad_urdf_one_line_exit_2_no_file(tmp_path: Path, urdf_text: str, pattern: str) -> None:
    urdf = tmp_path / "bad.urdf"
    urdf.write_text(urdf_text)
    out = tmp_path / "run.h5"
    code, _, err = run_cli("simulate", "--urdf", str(urdf), "-o", str(out))
    assert code == 2 and pattern in err and err.count("\n") == 1
    assert not out.exists()


@pytest.mark.parametrize(
    ("extra", "pattern"),
    [
        (["--robot", "ur6"], "close names: ur5"),
        (["--robot", "ur5", "--preset", "aaria-fig2"], "--preset is given with --robot"),
        (["--robot", "ur5", "--urdf", "x.urdf"], "--robot is given with --urdf"),
        (["--preset", "aaria-fig2", "--fixed-base"], "--fixed-base is for URDF robots"),
        (
            ["--robot", "ur5", "--tool", "nowhere"],
            "frame 'nowhere' is not in model 'ur5'; allowed: a link, base_link",
        ),
        (["--robot", "ur5", "--density", "2000"], "--density is given with --robot"),
    ],
)
def test_simulate_robot_bad_options(tmp_path: Path, extra: list[str], pattern: str) -> None:
    args = ["simulate", "--duration", "0.5", *extra]
    if "-o" not in extra:
        args += ["-o", str(tmp_path / "run.h5")]
    else:
        args[args.index("-o") + 1] = str(tmp_path / "run.mat")
    code, _, err = run_cli(*args)
    assert code == 2 and pattern in err, err
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize(
    ("extra", "pattern"),
    [
        (["--robot", "ur5", "--drive", "torque"], "--drive torque and --torques FILE go together"),
        (
            ["--robot", "ur5", "--fixed-base", "--base", "base.csv"],
            "--base is given with --fixed-base",
        ),
        (["--robot", "ur3"], "--robot is 'ur3'; allowed: ur/ur3, ur/ur3_robot"),
    ],
)
def test_options_that_would_do_nothing_are_refused(
    tmp_path: Path, extra: list[str], pattern: str
) -> None:
    code, _, err = run_cli("simulate", *extra, "-o", str(tmp_path / "run.h5"))
    assert code == 2 and pattern in err, err
    assert not (tmp_path / "run.h5").exists()


def test_from_a_urdf_run_refuses_another_tool(tmp_path: Path) -> None:
    first = tmp_path / "ur5.h5"
    assert run_cli("simulate", "--robot", "ur5", "--duration", "0.5", "-o", str(first))[0] == 0
    code, _, err = run_cli("simulate", "--from", str(first), "--tool", "wrist_2_link", "-o", "x.h5")
    assert code == 2 and "--tool with --from" in err


def test_fixed_base_data_set_varies_the_joints_only(tmp_path: Path) -> None:
    out = tmp_path / "fixed.h5"
    code, _, err = run_cli(
        "dataset", "--robot", "ur5", "--fixed-base", "-n", "2", "--duration", "0.5",
        "--workers", "1", "--quiet", "-o", str(out),
    )  # fmt: skip
    assert code == 0, err
    from aaria_pin.files.dataset.reader import DatasetReader

    with DatasetReader(out) as reader:
        assert reader.attributes["vary"] == ["joints"]
        assert "base_table" not in reader.run(0)  # a fixed base has no base table
        assert np.all(reader.run(0)["base_wrench"][:, 2] > 0)  # the mount holds the arm up
    code, _, err = run_cli(
        "dataset", "--robot", "ur5", "--fixed-base", "--vary", "joints,base", "-n", "2",
        "-o", str(tmp_path / "x.h5"),
    )  # fmt: skip
    assert code == 2 and "base cannot vary" in err and not (tmp_path / "x.h5").exists()


def test_torques_beyond_the_effort_limit_are_reported(tmp_path: Path) -> None:
    urdf = tmp_path / "weak.urdf"
    urdf.write_text(
        """<robot name="weak"><link name="base"/>
      <link name="arm"><inertial><origin xyz="0.5 0 0"/><mass value="10"/>
        <inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <joint name="shoulder" type="revolute"><parent link="base"/><child link="arm"/>
        <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="5" velocity="2"/></joint>
    </robot>"""
    )
    out = tmp_path / "weak.h5"
    code, _, err = run_cli("simulate", "--urdf", str(urdf), "--duration", "1", "-o", str(out))
    assert code == 0
    peak, limit = read_run(out).attributes["effort_exceeded"]["shoulder"]
    assert limit == 5 and peak > 10 * 9.81 * 0.5 * np.cos(1.0)  # the weight's lever at |q| <= 0.6
    assert "joint 'shoulder' reaches |tau|" in err and "effort limit 5" in err


def test_dataset_of_a_urdf_with_missing_meshes_warns_once(tmp_path: Path) -> None:
    from aaria_pin.core.catalogue import find_robot

    urdf = tmp_path / "ur5.urdf"
    text = find_robot("ur5").urdf.read_text()
    urdf.write_text(text.replace("package://example-robot-data/", "package://gone/"))
    code, _, err = run_cli(
        "dataset", "--urdf", str(urdf), "-n", "2", "--duration", "0.5", "--workers", "1",
        "--quiet", "-o", str(tmp_path / "set.h5"),
    )  # fmt: skip
    assert code == 0, err
    assert err.count("aaria: warning: 14 mesh file(s) of 'ur5' not found") == 1


def test_simulate_a_robot_to_mat_holds_the_same_arrays_as_h5(tmp_path: Path) -> None:
    from scipy.io import loadmat

    args = ["simulate", "--robot", "ur5", "--duration", "0.5", "--rate", "50", "--no-noise"]
    for name in ("run.h5", "run.mat"):
        code, out, err = run_cli(*args, "-o", str(tmp_path / name))
        assert code == 0, err
        assert "ur5, 6 joints, 14 IMUs, 26 samples" in out
    h5 = read_run(tmp_path / "run.h5")
    mat = loadmat(tmp_path / "run.mat")
    for name in ("time", "q", "qd", "qdd", "tau", "base_pose", "base_wrench", "tool_pose", "imu"):
        stored = np.asarray(mat[name]).reshape(np.shape(getattr(h5, name)))
        np.testing.assert_array_equal(stored, getattr(h5, name), err_msg=name)
    assert mat["imu"].shape == (26, 14, 6)
    from_mat = read_run(tmp_path / "run.mat")
    assert from_mat.joint_names == h5.joint_names and from_mat.imu_names == h5.imu_names
    np.testing.assert_array_equal(from_mat.imu, h5.imu)
    np.testing.assert_array_equal(from_mat.tables["joint_table"], h5.tables["joint_table"])


def test_urdf_reports_the_imus_the_file_holds(tmp_path: Path) -> None:
    """The printed IMU names are the imu_* links of the written file (fig3: module 2 empty)."""
    import xml.etree.ElementTree as ET

    out = tmp_path / "fig3.urdf"
    code, stdout, err = run_cli("urdf", "--preset", "aaria-fig3", "-o", str(out))
    assert code == 0, err
    links = [link.get("name", "") for link in ET.parse(out).getroot().iter("link")]
    held = [name for name in links if name.startswith("imu_")]
    assert len(held) == 12 and "imu_link2_a" not in held
    assert stdout.rstrip().endswith(f"12 IMUs: {', '.join(held)}")
