"""Denavit–Hartenberg tables: the Aaria extended table, standard and modified DH, validation.

Every table is turned into a :class:`KinematicChain`: a list of joints, each a fixed transform
before the joint (``T_pre``), a motion about or along the joint frame's z axis, and a fixed
transform after it (``T_post``). The frame right after the motion is the joint's
**post-joint frame**; the URDF emitter makes it the child link's frame.

The three conventions (``q`` is the joint variable):

========  ==========================================  =================================
table     revolute module                              prismatic module
========  ==========================================  =================================
aaria     ``Rx(alpha)·Tz(d)·Rz(q)·Tx(a)``              ``Rx(alpha)·Rz(theta)·Tz(q)·Tx(a)``
standard  ``Rz(theta)·Tz(d)·Rz(q)·Tx(a)·Rx(alpha)``    ``Rz(theta)·Tz(d)·Tz(q)·Tx(a)·Rx(alpha)``
modified  ``Rx(alpha)·Tx(a)·Rz(theta)·Tz(d)·Rz(q)``    ``Rx(alpha)·Tx(a)·Rz(theta)·Tz(d)·Tz(q)``
========  ==========================================  =================================

Aaria tables are 8 × 5 ``[alpha, a, theta, d, link type]`` (rows 1–6 modules, row 7 the tool,
row 8 the base); standard and modified tables are n × 5 with the same columns (n = 1..12,
link type 1 or 2). In an Aaria table theta of a revolute module and d of a prismatic module are
not offsets: a revolute joint starts from zero, and a prismatic module's d is its rail length,
the joint's range being ``[-d/2, +d/2]`` about the rail's middle (the rail is drawn centred on
the joint frame, as Simscape draws it).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from enum import IntEnum
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.core.arguments import checked
from aaria_pin.core.se3 import Array, chain, rot_x, rot_z, translation
from aaria_pin.core.tables import finite_table
from aaria_pin.errors import TableError

__all__ = [
    "AARIA_COLUMNS",
    "CONVENTIONS",
    "MAX_LENGTH",
    "REVOLUTE_RANGE",
    "R_WORLD_DH",
    "STANDARD_PRISMATIC_RANGE",
    "Convention",
    "JointSpec",
    "KinematicChain",
    "LinkType",
    "chain_from_aaria",
    "chain_from_modified",
    "chain_from_standard",
    "chain_from_table",
    "validate_aaria_table",
    "validate_dh_table",
]

Convention = Literal["aaria", "standard", "modified"]
CONVENTIONS: tuple[Convention, ...] = ("aaria", "standard", "modified")

AARIA_COLUMNS = ("alpha", "a", "theta", "d", "link type")
_COLUMN_UNITS = ("rad", "m", "rad", "m", "")

R_WORLD_DH = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]])
"""Rotation from the world (Simscape) frame to the paper's DH frame: DH x up, DH z horizontal."""

REVOLUTE_RANGE = (-2.0 * np.pi, 2.0 * np.pi)
"""Range of every revolute joint built from a table [rad]."""

STANDARD_PRISMATIC_RANGE = (-0.5, 0.5)
"""Range of a prismatic joint of a standard or modified table about its offset d [m]."""

_MAX_ROWS = 12
MAX_LENGTH = 100.0
"""Longest link length or offset accepted in a table [m]."""


class LinkType(IntEnum):
    """Link type codes of the Aaria table's fifth column."""

    EMPTY = 0
    REVOLUTE = 1
    PRISMATIC = 2


@dataclass(frozen=True)
class JointSpec:
    """One actuated joint of a chain.

    Attributes:
        module: 1-based row of the table this joint comes from
        kind: ``"revolute"`` (about z) or ``"prismatic"`` (along z)
        T_prev_joint: fixed transform from the previous joint's link-end frame (or the chain's
            entry frame) to this joint's frame
        T_post_end: fixed transform from this joint's post-joint frame to its link-end frame
        lower: lower joint limit [rad or m]
        upper: upper joint limit [rad or m]
        link_end: the point where the link's body ends, in the post-joint frame [m]
    """

    module: int
    kind: Literal["revolute", "prismatic"]
    T_prev_joint: Array
    T_post_end: Array
    lower: float
    upper: float
    link_end: Array


@dataclass(frozen=True)
class KinematicChain:
    """A serial chain of joints from a DH table.

    Attributes:
        convention: the table convention it was built from
        table: the validated table
        T_base_entry: fixed transform from the base frame to the frame the first module acts in
            (``R_WDH`` for Aaria tables, identity otherwise)
        joints: actuated joints in module order
        tool_length: length of the tool along the last link end frame's x axis [m]
    """

    convention: Convention
    table: Array
    T_base_entry: Array
    joints: tuple[JointSpec, ...]
    tool_length: float

    @property
    def modules(self) -> tuple[int, ...]:
        """1-based table rows of the actuated joints, in order."""
        return tuple(joint.module for joint in self.joints)

    def T_base_tool(self, q: ArrayLike) -> Array:
        """Tool-tip pose in the base frame by plain matrix products.

        Args:
            q: joint values [rad or m], one per actuated joint

        Returns:
            4 × 4 transform ``T_base_tool``.
        """
        q_arr = np.asarray(q, dtype=float).reshape(-1)
        if q_arr.shape != (len(self.joints),):
            raise TableError(
                f"q has {q_arr.size} values; the chain has {len(self.joints)} joints",
                parameter="q",
                value=q_arr.size,
                allowed=f"{len(self.joints)} values",
            )
        T = self.T_base_entry.copy()
        for joint, qi in zip(self.joints, q_arr, strict=True):
            motion = rot_z(qi) if joint.kind == "revolute" else translation(z=qi)
            T = T @ joint.T_prev_joint @ motion @ joint.T_post_end
        return T @ translation(x=self.tool_length)


def _check_link_type(arr: Array, row: int, allowed: Sequence[LinkType], what: str) -> LinkType:
    value = arr[row, 4]
    codes = [int(t) for t in allowed]
    if value not in codes:
        names = ", ".join(f"{int(t)} ({t.name.lower()})" for t in allowed)
        raise TableError(
            f"{what}: row {row + 1}, column 5 (link type) is {value:g}; allowed: {names}",
            parameter="table",
            value=float(value),
            element=f"row {row + 1}, column 5 (link type)",
        )
    return LinkType(int(value))


def _check_non_negative(arr: Array, row: int, col: int, what: str) -> None:
    if not 0 <= arr[row, col] <= MAX_LENGTH:
        raise TableError(
            f"{what}: row {row + 1}, column {col + 1} ({AARIA_COLUMNS[col]}) is"
            f" {arr[row, col]:g} {_COLUMN_UNITS[col]}; allowed: a length from 0 to"
            f" {MAX_LENGTH:g} m",
            parameter="table",
            value=float(arr[row, col]),
            element=f"row {row + 1}, column {col + 1} ({AARIA_COLUMNS[col]})",
        )


def validate_aaria_table(table: ArrayLike) -> Array:
    """Check an Aaria extended DH table and return it as a float array.

    Args:
        table: 8 × 5 ``[alpha [rad], a [m], theta [rad], d [m], link type]``

    Returns:
        The table as an 8 × 5 float array (a copy).

    Raises:
        TableError: wrong shape, a non-finite value, an unknown link type, a negative length in
            a used row, or every module empty.
    """
    what = "Aaria DH table"
    arr = finite_table(table, AARIA_COLUMNS, what, rows=(8,))
    allowed = (LinkType.EMPTY, LinkType.REVOLUTE, LinkType.PRISMATIC)
    types = [_check_link_type(arr, row, allowed, what) for row in range(6)]
    for row, link_type in enumerate(types):
        if link_type is not LinkType.EMPTY:
            _check_non_negative(arr, row, 1, what)
            _check_non_negative(arr, row, 3, what)
    _check_non_negative(arr, 6, 1, what)
    if all(t is LinkType.EMPTY for t in types):
        raise TableError(
            f"{what}: every module (rows 1-6) is empty; allowed: at least one 1 or 2",
            parameter="table",
            value="all link types 0",
            element="rows 1-6, column 5 (link type)",
        )
    return arr


def validate_dh_table(table: ArrayLike, convention: Convention = "standard") -> Array:
    """Check a standard or modified DH table (n × 5, link type 1 or 2) and return it.

    Args:
        table: n × 5 ``[alpha [rad], a [m], theta [rad], d [m], link type]``, 1 <= n <= 12
        convention: ``"standard"`` or ``"modified"``

    Returns:
        The table as an n × 5 float array (a copy).

    Raises:
        TableError: wrong shape, a non-finite value, an unknown link type or a negative a.
    """
    what = f"{convention} DH table"
    arr = finite_table(table, AARIA_COLUMNS, what)
    if not 1 <= arr.shape[0] <= _MAX_ROWS:
        raise TableError(
            f"{what}: {arr.shape[0]} rows is not allowed; expected 1 to {_MAX_ROWS}",
            parameter="table",
            value=arr.shape[0],
            allowed=f"1 to {_MAX_ROWS} rows",
            element="rows",
        )
    for row in range(arr.shape[0]):
        _check_link_type(arr, row, (LinkType.REVOLUTE, LinkType.PRISMATIC), what)
        _check_non_negative(arr, row, 1, what)
    return arr


def chain_from_aaria(table: ArrayLike) -> KinematicChain:
    """Build the chain of an Aaria extended DH table (the paper's convention).

    Empty modules are skipped: the next module acts in the frame the last non-empty one left.

    Args:
        table: 8 × 5 Aaria table

    Returns:
        The kinematic chain; its tool is ``Tx(a_7)`` after the last link's end.
    """
    arr = validate_aaria_table(table)
    joints = []
    for row in range(6):
        alpha, a, theta, d, code = arr[row]
        link_type = LinkType(int(code))
        if link_type is LinkType.EMPTY:
            continue
        if link_type is LinkType.REVOLUTE:
            T_prev_joint = chain(rot_x(alpha), translation(z=d))
            kind: Literal["revolute", "prismatic"] = "revolute"
            lower, upper = REVOLUTE_RANGE
        else:
            T_prev_joint = chain(rot_x(alpha), rot_z(theta))
            kind = "prismatic"
            lower, upper = -d / 2.0, d / 2.0
        joints.append(
            JointSpec(
                module=row + 1,
                kind=kind,
                T_prev_joint=T_prev_joint,
                T_post_end=translation(x=a),
                lower=lower,
                upper=upper,
                link_end=np.array([a, 0.0, 0.0]),
            )
        )
    T_base_entry = np.eye(4)
    T_base_entry[:3, :3] = R_WORLD_DH
    return KinematicChain("aaria", arr, T_base_entry, tuple(joints), float(arr[6, 1]))


def _chain_from_generic(arr: Array, convention: Convention) -> KinematicChain:
    specs: list[tuple[Array, Array, Literal["revolute", "prismatic"], float, float]] = []
    for alpha, a, theta, d, code in arr:
        kind: Literal["revolute", "prismatic"] = (
            "revolute" if LinkType(int(code)) is LinkType.REVOLUTE else "prismatic"
        )
        lower, upper = REVOLUTE_RANGE if kind == "revolute" else STANDARD_PRISMATIC_RANGE
        if convention == "standard":
            pre = chain(rot_z(theta), translation(z=d))
            post = chain(translation(x=a), rot_x(alpha))
        else:
            pre = chain(rot_x(alpha), translation(x=a), rot_z(theta), translation(z=d))
            post = np.eye(4)
        specs.append((pre, post, kind, lower, upper))
    joints = []
    for index, (pre, post, kind, lower, upper) in enumerate(specs):
        T_post_next = post @ specs[index + 1][0] if index + 1 < len(specs) else post
        joints.append(
            JointSpec(
                module=index + 1,
                kind=kind,
                T_prev_joint=pre,
                T_post_end=post,
                lower=lower,
                upper=upper,
                link_end=T_post_next[:3, 3].copy(),
            )
        )
    return KinematicChain(convention, arr, np.eye(4), tuple(joints), 0.0)


def chain_from_standard(table: ArrayLike) -> KinematicChain:
    """Build the chain of a standard (Spong) DH table.

    Frame i is ``frame_{i-1} · Rz(theta_i + q_i) · Tz(d_i) · Tx(a_i) · Rx(alpha_i)`` for a revolute
    row and ``frame_{i-1} · Rz(theta_i) · Tz(d_i + q_i) · Tx(a_i) · Rx(alpha_i)`` for a prismatic
    row; the tool tip is the last frame.

    Args:
        table: n × 5 ``[alpha, a, theta, d, link type]``

    Returns:
        The kinematic chain.
    """
    return _chain_from_generic(validate_dh_table(table, "standard"), "standard")


def chain_from_modified(table: ArrayLike) -> KinematicChain:
    """Build the chain of a modified (Craig) DH table.

    Frame i is ``frame_{i-1} · Rx(alpha_{i-1}) · Tx(a_{i-1}) · Rz(theta_i) · Tz(d_i)`` followed by
    the joint motion, where row i holds ``alpha_{i-1}, a_{i-1}, theta_i, d_i``; the tool tip is
    the last frame.

    Args:
        table: n × 5 ``[alpha, a, theta, d, link type]``

    Returns:
        The kinematic chain.
    """
    return _chain_from_generic(validate_dh_table(table, "modified"), "modified")


@checked
def chain_from_table(table: ArrayLike, convention: Convention = "aaria") -> KinematicChain:
    """Build the chain of a table in the given convention.

    Args:
        table: the table (8 × 5 for ``"aaria"``, n × 5 otherwise)
        convention: ``"aaria"``, ``"standard"`` or ``"modified"``

    Returns:
        The kinematic chain.
    """
    if convention == "aaria":
        return chain_from_aaria(table)
    if convention == "standard":
        return chain_from_standard(table)
    if convention == "modified":
        return chain_from_modified(table)
    raise TableError(parameter="convention", value=convention, allowed=", ".join(CONVENTIONS))
