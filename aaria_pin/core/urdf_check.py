"""Checking a URDF before it becomes a model: structure, mass properties, meshes.

Pinocchio's URDF parser accepts some documents that describe no physical robot (a negative
mass, an inertia that is not positive definite) and reports others with messages that do not
say which element is at fault. :func:`check_urdf` parses the document once
(:func:`~aaria_pin.core.urdf_parse.parse_urdf`, which raises a
:class:`~aaria_pin.errors.UrdfError` naming the link or joint), then lists what a simulation
needs: the root link, the joints with their limits and mimic relations, and the meshes, each
resolved to a file (``package://NAME/...`` from the installed packages' ``share`` folders, the
folders above the URDF and ``ROS_PACKAGE_PATH``; relative paths from the URDF's folder).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from aaria_pin.core.urdf_parse import parse_urdf
from aaria_pin.core.urdf_tree import UrdfDocument, UrdfJoint

__all__ = ["UrdfSummary", "check_urdf", "resolve_mesh"]


@dataclass(frozen=True)
class UrdfSummary:
    """What a simulation needs to know of a checked URDF.

    Attributes:
        name: the robot's name
        root_link: the one link that is no joint's child
        links: link names in document order
        joints: joints in document order
        meshes: mesh file names as written in the URDF
        missing_meshes: those that do not resolve to an existing file
        frame_links: the fixed joints, in document order, whose child link is a bare frame
            (no mass, no shape, no child): where the URDF itself mounts a sensor (the IMU
            links :mod:`aaria_pin.core.urdf` writes)
    """

    name: str
    root_link: str
    links: tuple[str, ...]
    joints: tuple[UrdfJoint, ...]
    meshes: tuple[str, ...]
    missing_meshes: tuple[str, ...]
    frame_links: tuple[UrdfJoint, ...] = ()

    def joint(self, name: str) -> UrdfJoint:
        """A joint by name (KeyError if absent)."""
        for joint in self.joints:
            if joint.name == name:
                return joint
        raise KeyError(name)


def _package_roots() -> list[Path]:
    """Folders where ``package://NAME`` may live: ``share`` folders of installed packages."""
    import sys

    roots = [Path(p) for p in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep) if p]
    for entry in sys.path:
        share = Path(entry or ".") / "cmeel.prefix" / "share"
        if share.is_dir():
            roots.append(share)
    return roots


def resolve_mesh(filename: str, urdf_dir: Path | None) -> Path | None:
    """The file a URDF mesh reference points to, or None when it cannot be found.

    Args:
        filename: as written, ``package://NAME/rest``, ``file:///abs`` or a path
        urdf_dir: the URDF's folder (None for URDF text without a file)
    """
    if filename.startswith("package://"):
        package, _, rest = filename[len("package://") :].partition("/")
        candidates = [root / package / rest for root in _package_roots()]
        if urdf_dir is not None:
            folder = urdf_dir.resolve()
            candidates += [a / rest for a in (folder, *folder.parents) if a.name == package]
        return next((c for c in candidates if c.is_file()), None)
    path = Path(filename[len("file://") :] if filename.startswith("file://") else filename)
    if not path.is_absolute():
        if urdf_dir is None:
            return None
        path = urdf_dir / path
    return path if path.is_file() else None


def check_urdf(text: str, urdf_dir: Path | None = None) -> UrdfSummary:
    """Check a URDF document and summarise it.

    Args:
        text: the URDF XML
        urdf_dir: the folder of the URDF file, for relative mesh paths (None: text only)

    Returns:
        The summary (mesh references that do not resolve are listed, not refused).

    Raises:
        UrdfError: as :func:`~aaria_pin.core.urdf_parse.parse_urdf`.
    """
    document = parse_urdf(text)
    meshes = document.meshes
    missing = tuple(dict.fromkeys(m for m in meshes if resolve_mesh(m, urdf_dir) is None))
    return UrdfSummary(
        document.name,
        document.root_link,
        document.link_names,
        document.joints,
        meshes,
        missing,
        _frame_links(document),
    )


def _frame_links(document: UrdfDocument) -> tuple[UrdfJoint, ...]:
    """The fixed joints whose child is a bare frame: massless, shapeless, a leaf."""
    parents = {joint.parent for joint in document.joints}
    bare = {
        link.name
        for link in document.links
        if (link.inertial is None or link.inertial.mass == 0)
        and not link.visuals
        and not link.collisions
        and link.name not in parents
    }
    return tuple(j for j in document.joints if j.kind == "fixed" and j.child in bare)
