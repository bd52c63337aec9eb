"""The identified dynamics written back into the run's URDF.

:func:`identified_urdf` takes the URDF a run was computed on and replaces what the dynamic
identification estimated:

- each identified body's ``<inertial>`` (mass, centre of mass, inertia about it, in the body's
  first link's axes): a body is what Pinocchio merges into one joint's inertia, that link and
  every link fixed to it, so the estimate goes to the first and the others lose their
  ``<inertial>``; a fixed base's root link (not identified) keeps its own; a moving base's
  identified base body goes on the URDF's root link (ur5's ``world``): load the file with a
  free-flyer root joint (``pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer())``, MJCF a
  free joint) to keep it, a fixed-base load merges it into the world;
- each fitted joint's ``<dynamics damping="Fv" friction="Fc"/>`` (viscous, Coulomb). Pinocchio
  reads them as ``model.damping`` and ``model.friction``, MuJoCo as the joint's ``damping`` and
  ``frictionloss`` (dry friction as a constraint, without the fit's ``tanh`` smoothing);
- the armature has no URDF field: it is written as a comment in the joint
  (``armature 0.1 kg·m²``), for MJCF's ``armature`` or Pinocchio's ``model.armature``.

Only bodies that are physical (:mod:`~aaria_pin.apps.identify.inertial_consistent`, an
identification made with ``consistent``) are written. Mesh geometry is dropped unless kept
(MuJoCo loads STL, OBJ and MSH meshes only, found from its own folder): the file is the dynamic
model.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from typing import TYPE_CHECKING

import numpy as np

from aaria_pin.apps.identify.inertial_result import DynamicIdentification
from aaria_pin.core.arguments import checked
from aaria_pin.core.record import RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.core.urdf_emitter import exact_number, exact_numbers
from aaria_pin.errors import InputFileError, ParameterError

if TYPE_CHECKING:
    from aaria_pin.core.model import RobotModel

__all__ = ["identified_urdf"]


def _body_links(robot: RobotModel) -> list[list[tuple[str, Array]]]:
    """Per body (joint 1 …), its links and their placements in the joint's frame."""
    import pinocchio as pin

    model = robot.model
    links: list[list[tuple[str, Array]]] = [[] for _ in range(model.njoints - 1)]
    for frame in model.frames:
        if frame.type == pin.FrameType.BODY and frame.parentJoint > 0:
            links[frame.parentJoint - 1].append((frame.name, frame.placement.homogeneous))
    return links


def _inertial(standard: Array, placement: Array) -> ET.Element:
    """The ``<inertial>`` of a body's ten parameters, expressed in a link at ``placement``."""
    import pinocchio as pin

    if standard[0] > 0:
        inertia = pin.Inertia.FromDynamicParameters(np.asarray(standard, dtype=float))
        inertia = pin.SE3(placement).actInv(inertia)
        mass, lever, I = inertia.mass, inertia.lever, inertia.inertia
    else:  # no mass (a link merged into another's body)
        mass, lever, I = 0.0, np.zeros(3), np.zeros((3, 3))
    element = ET.Element("inertial")
    ET.SubElement(element, "origin", xyz=exact_numbers(lever), rpy="0 0 0")
    ET.SubElement(element, "mass", value=exact_number(mass))
    ET.SubElement(
        element,
        "inertia",
        {
            f"i{a}{b}": exact_number(I[i, j])
            for a, b, i, j in (
                ("x", "x", 0, 0),
                ("x", "y", 0, 1),
                ("x", "z", 0, 2),
                ("y", "y", 1, 1),
                ("y", "z", 1, 2),
                ("z", "z", 2, 2),
            )
        },
    )
    return element


def _replace_inertial(link: ET.Element, inertial: ET.Element) -> None:
    for old in link.findall("inertial"):
        link.remove(old)
    link.insert(0, inertial)


def _drop_meshes(root: ET.Element) -> None:
    for link in root.findall("link"):
        for kind in ("visual", "collision"):
            for element in link.findall(kind):
                if element.find("geometry/mesh") is not None:
                    link.remove(element)


def _write_friction(joints: dict[str, ET.Element], name: str, values: Array) -> None:
    joint = joints[name]
    for old in joint.findall("dynamics"):
        joint.remove(old)
    viscous, coulomb, armature = (float(v) for v in values)
    ET.SubElement(joint, "dynamics", damping=exact_number(viscous), friction=exact_number(coulomb))
    joint.append(ET.Comment(f" armature {exact_number(armature)} (kg·m² or kg; no URDF field) "))


@checked
def identified_urdf(
    record: RunRecord, result: DynamicIdentification, keep_meshes: bool = False
) -> str:
    """The run's URDF with the identified bodies and friction (module docstring).

    Args:
        record: the run identified (its URDF and model)
        result: a consistent identification of that run
            (:func:`~aaria_pin.apps.identify.inertial.identify_dynamics` with ``consistent``)
        keep_meshes: keep the visual and collision meshes (MuJoCo may not load them)

    Returns:
        The URDF text.

    Raises:
        ParameterError: an identification that is not consistent, or of another robot.
        InputFileError: a run without its URDF (a 0.1.0 file).
    """
    standard = result.standard
    if standard is None or not standard.consistent:
        raise ParameterError(
            "result is not physically consistent; allowed: an identification made with "
            "consistent (every body a real one)",
            parameter="consistent",
        )
    from aaria_pin.apps.record_model import record_model

    if not record.urdf:
        raise InputFileError(
            "the run stores no URDF; allowed: a run of version 2 or later (it stores its model)",
            parameter="file",
        )
    robot = record_model(record, moving_base=standard.free_flyer)
    parser = ET.XMLParser(target=ET.TreeBuilder(insert_comments=True))
    root = ET.fromstring(record.urdf, parser=parser)
    links = {str(link.get("name")): link for link in root.findall("link")}
    joints = {str(joint.get("name")): joint for joint in root.findall("joint")}
    bodies = _body_links(robot)
    if len(bodies) != len(standard.bodies):
        raise ParameterError(
            f"result has {len(standard.bodies)} bodies; allowed: the model's {len(bodies)}",
            parameter="result",
        )
    for b, body in enumerate(bodies):
        values = standard.values[10 * b : 10 * b + 10]
        for k, (name, placement) in enumerate(body):
            if name in links:  # the body's other links: an explicit zero (no mass from geoms)
                own = values if k == 0 else np.zeros(10)
                _replace_inertial(links[name], _inertial(own, placement))
    for name, values in zip(standard.joints, standard.friction(), strict=True):
        _write_friction(joints, name, values)
    if not keep_meshes:
        _drop_meshes(root)
    ET.indent(root)
    return '<?xml version="1.0"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
