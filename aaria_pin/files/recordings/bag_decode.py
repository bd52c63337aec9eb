"""Decode a topic's messages from their serialised bytes with NumPy: the fast path of bag reading.

Deserialising a message at a time through ``rosbags`` (a Python object per message, per field)
costs about 15 µs a message; a lab recording holds hundreds of thousands.
``sensor_msgs/Imu`` and ``geometry_msgs/WrenchStamped`` have a fixed layout once the header's
frame id is known: a header (``stamp.sec`` int32 at byte 4, ``stamp.nanosec`` uint32 at 8, the
frame id's length at 12 and its bytes from 16), then float64 fields only. So the messages of a
topic are grouped by their length and their frame id's length, each group joined into one
``(messages, bytes)`` array, and the stamps, frame ids and values read from fixed columns of it
(``np.frombuffer`` and views). A ``sensor_msgs/JointState`` (joint names, then three arrays of
any length) is decoded the same way per group of messages of one layout: the first message's
layout is parsed, the messages whose names and array lengths are byte for byte the first's are
read at its offsets, and the rest grouped again.

Both serialisations of the readers are handled (the header's fields sit at the same offsets):

- ROS 2's CDR (``.mcap``, ``.db3``, bag folders): a 4-byte encapsulation header, little-endian
  only (``00 01``); strings end with a NUL counted in their length; each value aligned to its
  size (at most 8) from byte 4;
- ROS 1's serialisation (``.bag``): no encapsulation, a ``seq`` uint32 first, strings without a
  NUL, nothing aligned.

Anything else (big-endian CDR, a message shorter or longer than its layout) is not decoded here:
:func:`decode_fixed` and :func:`decode_joint_states` return None and the reader deserialises that
topic through ``rosbags`` (:func:`~aaria_pin.files.recordings.bag_read.reference_read_topics`'s
path), whose arrays these equal bit for bit (``tests/files/test_recordings_decode.py``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from aaria_pin.core.se3 import Array
from aaria_pin.files.recordings.bag_format import IMU_TYPE, WRENCH_TYPE

__all__ = ["FIXED_VALUES", "JointPart", "decode_fixed", "decode_joint_states"]

FIXED_VALUES = {
    IMU_TYPE: (37, (13, 14, 15, 25, 26, 27)),
    WRENCH_TYPE: (6, (0, 1, 2, 3, 4, 5)),
}
"""Per fixed-layout type: the float64 fields after the header, and the six read (an IMU's
orientation 4, covariance 9, ``angular_velocity`` 3, covariance 9, ``linear_acceleration`` 3,
covariance 9; a wrench's force 3 and torque 3)."""

_STRING = 16
"""The byte where the header's frame id starts (both serialisations)."""


@dataclass(frozen=True)
class JointPart:
    """The messages of one set of joints (and of the groups ``q``, ``qd``, ``tau`` they fill).

    Attributes:
        names: the joints
        present: the groups whose arrays have one value per joint, in ``q qd tau`` order
        index: (N,) the messages' places in the topic, increasing
        stamps: (N,) header stamps [ns]
        values: (N, C) the present groups' values, joint by joint
    """

    names: tuple[str, ...]
    present: tuple[str, ...]
    index: NDArray[np.int64]
    stamps: NDArray[np.int64]
    values: Array


def _columns(block: NDArray[np.uint8], start: int, dtype: str) -> NDArray[np.generic]:
    """A little-endian field of every message (row) of ``block``, from byte ``start``."""
    size = np.dtype(dtype).itemsize
    return np.ascontiguousarray(block[:, start : start + size]).view(dtype)[:, 0]


def _stamps(block: NDArray[np.uint8]) -> NDArray[np.int64]:
    """The header stamps [ns] of a block's messages."""
    seconds = _columns(block, 4, "<i4").astype(np.int64)
    return seconds * 1_000_000_000 + _columns(block, 8, "<u4").astype(np.int64)


def _texts(block: NDArray[np.uint8], start: int, size: int) -> NDArray[np.object_]:
    """Each message's text of ``size`` bytes from ``start`` (decoded once per distinct text)."""
    if size == 0:
        return np.full(block.shape[0], "", dtype=object)
    keys = np.ascontiguousarray(block[:, start : start + size]).view(f"V{size}")[:, 0]
    distinct, inverse = np.unique(keys, return_inverse=True)
    texts = np.array([bytes(k).decode() for k in distinct], dtype=object)
    return np.asarray(texts[inverse.ravel()])


def _little_cdr(raws: Sequence[bytes], ros1: bool) -> bool:
    """Whether every message is ROS 1's or little-endian CDR with a header (else: not ours)."""
    return all(len(raw) >= _STRING and (ros1 or raw[:2] == b"\x00\x01") for raw in raws)


def _groups(raws: Sequence[bytes]) -> dict[tuple[int, bytes], NDArray[np.int64]]:
    """The messages' places by their length and their frame id's length."""
    found: dict[tuple[int, bytes], list[int]] = {}
    for k, raw in enumerate(raws):
        found.setdefault((len(raw), raw[12:_STRING]), []).append(k)
    return {key: np.array(places, dtype=np.int64) for key, places in found.items()}


def _block(raws: Sequence[bytes], places: NDArray[np.int64], size: int) -> NDArray[np.uint8]:
    joined = b"".join([raws[k] for k in places.tolist()])
    return np.frombuffer(joined, dtype=np.uint8).reshape(places.size, size)


def _frame(length: int, ros1: bool) -> tuple[int, int]:
    """The frame id's size in bytes (CDR's NUL left out) and the byte after the header."""
    end = _STRING + length
    return (length if ros1 else max(length - 1, 0)), end


def _aligned(at: int, size: int, ros1: bool) -> int:
    """``at`` moved to the next multiple of ``size`` counted from CDR's byte 4 (ROS 1: as is)."""
    return at if ros1 else at + (-(at - 4)) % size


def decode_fixed(
    raws: Sequence[bytes], msgtype: str, ros1: bool
) -> tuple[NDArray[np.int64], NDArray[np.object_], Array] | None:
    """The header stamps [ns], frame ids and (N, 6) values of fixed-layout messages.

    Args:
        raws: the topic's messages, serialised, in order
        msgtype: :data:`~aaria_pin.files.recordings.bag_format.IMU_TYPE` or ``WRENCH_TYPE``
        ros1: ROS 1 serialisation (else CDR)

    Returns:
        The arrays in the messages' order, or None: messages this decoder does not read
        (module docstring).
    """
    fields, chosen = FIXED_VALUES[msgtype]
    if not _little_cdr(raws, ros1):
        return None
    n = len(raws)
    stamps = np.zeros(n, dtype=np.int64)
    frames = np.full(n, "", dtype=object)
    values = np.zeros((n, len(chosen)), dtype=np.float64)
    for (size, length_bytes), places in _groups(raws).items():
        text, end = _frame(int.from_bytes(length_bytes, "little"), ros1)
        start = _aligned(end, 8, ros1)
        if size != start + 8 * fields:
            return None
        block = _block(raws, places, size)
        stamps[places] = _stamps(block)
        frames[places] = _texts(block, _STRING, text)
        floats = np.ascontiguousarray(block[:, start:]).view("<f8")
        values[places] = floats[:, list(chosen)]
    return stamps, frames, values


@dataclass(frozen=True)
class _JointLayout:
    """Where one JointState message's parts are: the bytes that must match, the arrays."""

    names: tuple[str, ...]
    same: tuple[tuple[int, int], ...]
    arrays: tuple[tuple[int, int], ...]


def _joint_layout(raw: bytes, ros1: bool) -> _JointLayout | None:
    """The layout of one JointState message (None: not one of ours)."""
    try:
        _, at = _frame(int.from_bytes(raw[12:_STRING], "little"), ros1)
        at = _aligned(at, 4, ros1)
        first = at
        count = int.from_bytes(raw[at : at + 4], "little")
        at += 4
        if count > len(raw):
            return None
        names = []
        for _ in range(count):
            at = _aligned(at, 4, ros1)
            size = int.from_bytes(raw[at : at + 4], "little")
            text = raw[at + 4 : at + 4 + size]
            names.append((text if ros1 else text[:-1]).decode())
            at += 4 + size
        same, arrays = [(first, at)], []
        for _ in range(3):
            at = _aligned(at, 4, ros1)
            count = int.from_bytes(raw[at : at + 4], "little")
            same.append((at, at + 4))
            at += 4
            if count:
                at = _aligned(at, 8, ros1)
            arrays.append((at, count))
            at += 8 * count
    except UnicodeDecodeError:
        return None
    if at != len(raw):
        return None
    return _JointLayout(tuple(names), tuple(same), tuple(arrays))


def _joint_block(
    block: NDArray[np.uint8], layout: _JointLayout
) -> tuple[tuple[str, ...], NDArray[np.int64], Array]:
    """The present groups, stamps and values of a block of messages of one layout."""
    width = len(layout.names)
    present, parts = [], []
    for group, (at, count) in zip(("q", "qd", "tau"), layout.arrays, strict=True):
        if count == width:
            present.append(group)
            parts.append(np.ascontiguousarray(block[:, at : at + 8 * count]).view("<f8"))
    values = np.concatenate(parts, axis=1) if parts else np.zeros((block.shape[0], 0))
    return tuple(present), _stamps(block), values.astype(np.float64)


def decode_joint_states(raws: Sequence[bytes], ros1: bool) -> list[JointPart] | None:
    """A JointState topic's messages by set of joints, in the order each set first appears.

    Args:
        raws: the topic's messages, serialised, in order
        ros1: ROS 1 serialisation (else CDR)

    Returns:
        One part per set of joints and present groups, or None: messages this decoder does not
        read (module docstring).
    """
    if not _little_cdr(raws, ros1):
        return None
    found: dict[tuple[tuple[str, ...], tuple[str, ...]], list[tuple[NDArray[Any], ...]]] = {}
    for (size, _), places in _groups(raws).items():
        block = _block(raws, places, size)
        left = np.arange(places.size)
        while left.size:
            layout = _joint_layout(raws[int(places[left[0]])], ros1)
            if layout is None:
                return None
            same = np.concatenate([np.arange(a, b) for a, b in layout.same])
            rows = block[left][:, same]
            match = (rows == rows[0]).all(axis=1)
            present, stamps, values = _joint_block(block[left[match]], layout)
            if not present:  # no array with a value per joint: the reader's own error
                return None
            found.setdefault((layout.names, present), []).append(
                (places[left[match]], stamps, values)
            )
            left = left[~match]
    result = []
    for (names, present), pieces in found.items():
        index, stamps, values = (np.concatenate(p) for p in zip(*pieces, strict=True))
        order = np.argsort(index, kind="stable")
        result.append(JointPart(names, present, index[order], stamps[order], values[order]))
    return sorted(result, key=lambda part: int(part.index[0]))
