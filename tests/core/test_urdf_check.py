"""URDF checks: bad documents are refused with a message naming the element; meshes resolve."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from aaria_pin.core.catalogue import find_robot, robot_catalogue
from aaria_pin.core.urdf_check import check_urdf, resolve_mesh
from aaria_pin.core.urdf_robot import load_urdf_robot, read_urdf_file
from aaria_pin.errors import MeshWarning, UrdfError

INERTIA = '<inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/>'


def two_links(
    mass: str = "1.0",
    inertia: str = INERTIA,
    joint: str = '<parent link="base"/><child link="arm"/>',
    mesh: str = "",
) -> str:
    visual = f'<visual><geometry><mesh filename="{mesh}"/></geometry></visual>' if mesh else ""
    return f"""<robot name="two">
  <link name="base"/>
  <link name="arm">{visual}<inertial><mass value="{mass}"/>{inertia}</inertial></link>
  <joint name="shoulder" type="revolute">{joint}<axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="2"/></joint>
</robot>"""


def test_a_good_urdf_passes() -> None:
    summary = check_urdf(two_links())
    assert summary.root_link == "base"
    assert [(j.name, j.kind, j.lower, j.upper) for j in summary.joints] == [
        ("shoulder", "revolute", -1.0, 1.0)
    ]


@pytest.mark.parametrize(
    ("text", "named"),
    [
        (two_links().replace("</robot>", ""), "not well-formed XML: line"),
        ("<robot><link name='a'/>", "not well-formed XML"),
        (two_links(joint='<child link="arm"/>'), "joint 'shoulder': no <parent"),
        (two_links(joint='<parent link="base"/>'), "joint 'shoulder': no <child"),
        (
            two_links(joint='<parent link="nowhere"/><child link="arm"/>'),
            "joint 'shoulder': parent link 'nowhere' is not a link",
        ),
        (two_links(mass="-2"), "link 'arm': mass -2 kg; allowed: >= 0"),
        (
            two_links(inertia='<inertia ixx="0.1" iyy="0.1" izz="-0.1" ixy="0" ixz="0" iyz="0"/>'),
            "link 'arm': inertia",
        ),
        (
            two_links(inertia='<inertia ixx="1" iyy="1" izz="1" ixy="2" ixz="0" iyz="0"/>'),
            "link 'arm': inertia",
        ),
        (two_links(mass="abc"), "link 'arm' <mass>: value='abc' is not a number"),
        (two_links().replace('type="revolute"', 'type="planar"'), "type 'planar'"),
        (two_links().replace('lower="-1"', 'lower="3"'), "joint 'shoulder': limit lower 3"),
        ("<model/>", "root element is <model>"),
    ],
)
def test_bad_urdfs_name_the_element(text: str, named: str) -> None:
    with pytest.raises(UrdfError, match=named.replace("(", r"\(").replace("[", r"\[")) as info:
        check_urdf(text)
    assert "\n" not in str(info.value)


def test_a_link_with_two_parents_and_a_cycle_are_refused() -> None:
    text = two_links().replace(
        "</robot>",
        '<link name="c"/><joint name="extra" type="fixed"><parent link="c"/>'
        '<child link="arm"/></joint></robot>',
    )
    with pytest.raises(UrdfError, match="link 'arm' already has parent joint 'shoulder'"):
        check_urdf(text)
    cycle = """<robot name="r"><link name="a"/><link name="b"/><link name="c"/>
      <joint name="j1" type="fixed"><parent link="b"/><child link="c"/></joint>
      <joint name="j2" type="fixed"><parent link="c"/><child link="b"/></joint></robot>"""
    with pytest.raises(UrdfError, match="not connected to root link 'a'"):
        check_urdf(cycle)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-1, 1), min_size=6, max_size=6))
def test_inertia_check_agrees_with_the_eigenvalues(values: list[float]) -> None:
    ixx, ixy, ixz, iyy, iyz, izz = values
    inertia = (
        f'<inertia ixx="{ixx!r}" iyy="{iyy!r}" izz="{izz!r}" ixy="{ixy!r}" ixz="{ixz!r}" '
        f'iyz="{iyz!r}"/>'
    )
    moments = np.linalg.eigvalsh(np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]]))
    if moments[0] < -max(1e-5 * abs(moments).max(), 1e-11):
        with pytest.raises(UrdfError, match="not positive definite"):
            check_urdf(two_links(inertia=inertia))
    elif moments[0] >= 0:
        check_urdf(two_links(inertia=inertia))


def test_missing_meshes_warn_and_the_robot_still_loads(tmp_path: Path) -> None:
    (tmp_path / "meshes").mkdir()
    (tmp_path / "meshes" / "arm.stl").write_text("solid arm\nendsolid arm\n")
    present = check_urdf(two_links(mesh="meshes/arm.stl"), tmp_path)
    assert present.missing_meshes == ()
    text = two_links(mesh="package://nowhere_description/meshes/arm.stl")
    with pytest.warns(MeshWarning, match="package://nowhere_description/meshes/arm.stl"):
        robot = load_urdf_robot(text, urdf_dir=tmp_path)
    assert robot.robot.n_joints == 1


def test_example_robot_data_meshes_resolve_from_the_package() -> None:
    file = find_robot("ur5").urdf
    summary = check_urdf(read_urdf_file(file), file.parent)
    assert summary.meshes and summary.missing_meshes == ()
    resolved = resolve_mesh(summary.meshes[0], None)
    assert resolved is not None and resolved.is_file()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no mesh warning for a complete package
        load_urdf_robot(read_urdf_file(file), urdf_dir=file.parent)


def test_catalogue_names_and_close_matches() -> None:
    catalogue = robot_catalogue()
    assert {"ur5", "ur10", "panda", "kinova"} <= set(catalogue)
    assert catalogue["ur5"].urdf.name == "ur5_robot.urdf"
    assert find_robot("ur/ur5_robot").name == "ur5"
    assert all(entry.urdf.is_file() for entry in catalogue.values())
    with pytest.raises(Exception, match="close names: ur5"):
        find_robot("ur6")


@pytest.mark.parametrize(
    ("mimic", "pattern"),
    [
        ('<mimic joint="shoulder"/>', "which is itself, a mimic joint or fixed"),
        ('<mimic joint="elbow"/>', "which is itself, a mimic joint or fixed"),
    ],
)
def test_self_and_chained_mimics_are_refused(mimic: str, pattern: str) -> None:
    """Pinocchio refuses mimic chains too: a leader must move on its own."""
    text = f"""<robot name="m"><link name="a"/><link name="b"/><link name="c"/>
      <joint name="shoulder" type="revolute"><parent link="a"/><child link="b"/>{mimic}
        <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
      <joint name="elbow" type="revolute"><parent link="b"/><child link="c"/>
        <mimic joint="shoulder"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    </robot>"""
    with pytest.raises(UrdfError, match=pattern):
        check_urdf(text)


def test_a_prismatic_mimic_of_a_revolute_joint_is_refused() -> None:
    text = two_links().replace(
        "</robot>",
        '<link name="f"/><joint name="finger" type="prismatic"><parent link="arm"/>'
        '<child link="f"/><mimic joint="shoulder"/>'
        '<limit lower="0" upper="0.1" effort="1" velocity="1"/></joint></robot>',
    )
    with pytest.raises(UrdfError, match=r"joint 'finger' \(prismatic\) mimics 'shoulder'"):
        check_urdf(text)


def test_a_robot_without_actuated_joints_is_refused() -> None:
    text = two_links().replace('type="revolute"', 'type="fixed"')
    with pytest.raises(UrdfError, match="robot 'two' has no actuated joint"):
        load_urdf_robot(text)


def _with_origins(joint: str = "", inertial: str = "", geometry: str = "") -> str:
    """A two-link URDF with the given ``<origin>`` of its joint and inertial, and a geometry."""
    visual = f"<visual><geometry>{geometry}</geometry></visual>" if geometry else ""
    return f"""<robot name="two">
  <link name="base"/>
  <link name="forearm">{visual}<inertial>{inertial}<mass value="1"/>{INERTIA}</inertial></link>
  <joint name="elbow" type="revolute"><parent link="base"/><child link="forearm"/>{joint}
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="2"/></joint>
</robot>"""


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            _with_origins(inertial='<origin xyz="0 0"/>'),
            "link 'forearm' <inertial> <origin xyz> is '0 0'; allowed: three finite numbers",
        ),
        (
            _with_origins(joint='<origin xyz="0 0 0.1" rpy="0 0 0 0"/>'),
            "joint 'elbow' <origin rpy> is '0 0 0 0'; allowed: three finite numbers",
        ),
        (
            _with_origins(joint='<origin xyz="0 zero 0.1"/>'),
            "joint 'elbow' <origin xyz> is '0 zero 0.1'; allowed: three finite numbers",
        ),
        (
            _with_origins(inertial='<origin xyz="nan 0 0"/>'),
            "link 'forearm' <inertial> <origin xyz> is 'nan 0 0'; allowed: three finite numbers",
        ),
        (
            _with_origins(geometry='<box size="0.1 0.1"/>'),
            "link 'forearm' <visual> <box size> is '0.1 0.1'; allowed: three finite numbers",
        ),
        (
            _with_origins(geometry='<cylinder radius="r" length="1"/>'),
            "link 'forearm' <visual> <cylinder radius> is 'r'; allowed: a finite number",
        ),
    ],
)
def test_a_malformed_origin_is_named_before_pinocchio_prints(
    text: str, message: str, capfd: pytest.CaptureFixture[str]
) -> None:
    """Pinocchio's parser reports these in lines of C++ output naming no element; we name it."""
    with pytest.raises(UrdfError) as caught:
        load_urdf_robot(text)
    assert str(caught.value) == message
    assert capfd.readouterr().err == ""  # refused before urdfdom parsed (and printed) anything


@pytest.mark.parametrize("vector", ["0 0", "0 0 0 0", "0 zero 0", ""])
def test_the_refused_origins_are_those_pinocchio_cannot_read(vector: str) -> None:
    """The independent judge: Pinocchio's own URDF parser fails on each origin we refuse."""
    import pinocchio as pin

    text = _with_origins(joint=f'<origin xyz="{vector}"/>')
    with pytest.raises(UrdfError, match="<origin xyz>"):
        check_urdf(text)
    with pytest.raises(Exception):  # noqa: B017 - urdfdom: a ValueError or RuntimeError
        pin.buildModelFromXML(text)


@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.floats(-10, 10, allow_nan=False), min_size=6, max_size=6),
    st.sampled_from([" ", "  ", "   "]),  # urdfdom splits at spaces only
)
def test_well_formed_origins_pass_and_pinocchio_reads_the_same_numbers(
    numbers: list[float], separator: str
) -> None:
    import pinocchio as pin

    xyz = separator.join(repr(v) for v in numbers[:3])
    rpy = separator.join(repr(v) for v in numbers[3:])
    text = _with_origins(joint=f'<origin xyz="{xyz}" rpy="{rpy}"/>')
    check_urdf(text)  # no error
    model = pin.buildModelFromXML(text)
    placement = model.jointPlacements[model.getJointId("elbow")]
    np.testing.assert_allclose(placement.translation, numbers[:3], rtol=0, atol=1e-12)
    expected = pin.rpy.rpyToMatrix(*numbers[3:])
    np.testing.assert_allclose(placement.rotation, expected, rtol=0, atol=1e-12)


def test_frame_links_are_the_bare_leaves_on_fixed_joints() -> None:
    """Massless, shapeless leaf links on fixed joints; a link with a shape, mass or child is not."""
    extra = """  <link name="frame_a"/>
  <link name="frame_b"><inertial><mass value="0"/></inertial></link>
  <link name="shaped"><visual><geometry><sphere radius="0.01"/></geometry></visual></link>
  <link name="heavy"><inertial><mass value="0.5"/>{INERTIA}</inertial></link>
  <link name="inner"/><link name="outer"/>
  <joint name="ja" type="fixed"><parent link="arm"/><child link="frame_a"/></joint>
  <joint name="jb" type="fixed"><parent link="base"/><child link="frame_b"/></joint>
  <joint name="js" type="fixed"><parent link="arm"/><child link="shaped"/></joint>
  <joint name="jh" type="fixed"><parent link="arm"/><child link="heavy"/></joint>
  <joint name="ji" type="fixed"><parent link="arm"/><child link="inner"/></joint>
  <joint name="jo" type="fixed"><parent link="inner"/><child link="outer"/></joint>
</robot>""".replace("{INERTIA}", INERTIA)
    summary = check_urdf(two_links().replace("</robot>", extra))
    assert [(j.name, j.parent, j.child) for j in summary.frame_links] == [
        ("ja", "arm", "frame_a"),
        ("jb", "base", "frame_b"),
        ("jo", "inner", "outer"),
    ]


@pytest.mark.parametrize(
    ("visual", "message"),
    [
        ("<sphere/>", "link 'forearm' <visual> <sphere> has no 'radius' attribute"),
        ('<cylinder radius="0.1"/>', "link 'forearm' <visual> <cylinder> has no 'length'"),
        ("<mesh/>", "link 'forearm' <visual> <mesh> has no 'filename' attribute"),
        ("<box/>", "link 'forearm' <visual> <box> has no 'size' attribute"),
        ("", "link 'forearm' <visual> has no <geometry> shape"),
        ("<geometry/>", "link 'forearm' <visual> has no <geometry> shape"),
    ],
)
def test_a_shape_urdfdom_drops_is_named(
    visual: str, message: str, capfd: pytest.CaptureFixture[str]
) -> None:
    """urdfdom complains of each on the process's stderr (the judge) and drops the shape."""
    import pinocchio as pin

    part = (
        visual if visual.startswith("<geometry") or not visual else f"<geometry>{visual}</geometry>"
    )
    text = _with_origins().replace(
        '<link name="forearm">', f'<link name="forearm"><visual>{part}</visual>'
    )
    with pytest.raises(UrdfError, match=message):
        check_urdf(text)
    pin.buildModelFromXML(text)
    assert "Error:" in capfd.readouterr().err
