"""What the structure baseline sees of a run: per-module features the rigid-body physics offers.

Imported by ``baseline_structure.py``. An Aaria run's IMUs (``imu``: T × 14 × 6, slots base,
tool, then A and B of modules 1–6, each ``[wx wy wz fx fy fz]`` in the IMU's axes, which are
the link's post-joint axes) and encoders (``q``: T × 6) give, per table row (modules 1–6,
then the tool), numbers that the DH table determines but that are not the table:

- whether the module's IMU slots carry a signal (an empty module's read zero), the spread,
  range and mean of its encoder;
- the best constant rotation (Kabsch) from the module's angular velocity to its parent's
  (the previous module that carries a signal, or the base), under each hypothesis on the joint:
  revolute (the module's angular velocity minus the joint axis z times q̇, turned by
  ``Rz(q)``) and prismatic (the angular velocity as measured; and again with the specific
  forces of the module's IMU A, less q̈ along z, and of the parent's IMU B beside them, which
  gravity turns when the links hardly rotate); each with its residual. The
  rotation of the right hypothesis is ``Rx(alpha)`` (``Rx(alpha)·Rz(theta)`` for a prismatic
  module), up to the base's fixed turn for module 1;
- the lever arm between the module's two IMUs (A to B, in the link's axes) from their specific
  forces, ``f_B - f_A = ([ω̇]× + [ω]×[ω]×) r`` (least squares over the run): ``r_x = 0.4 a``;
  for the tool row, the lever arm from the last module's IMU A to the tool IMU;
  (and again with the components the mounts fix known: ``r = (0.4 a, 0, -0.06)``, one
  unknown, better conditioned);
- the lever arm from the parent's IMU B (the base IMU for a parent base) to the joint origin
  (the child's frame origin), in the parent's axes, from the two links' specific forces and the
  revolute hypothesis' rotation: for a revolute module its distance off the parent's x axis
  is ``d`` (again with the x component known, ``0.1 a`` of the parent);
- how well each lever arm is determined: the log of the least eigenvalue of its normal
  equations (a link that hardly rotates tells nothing of its lengths).

Each is reduced to a number near 1 in size (lengths centred and scaled by the random arms'
ranges, ``RandomConfig``); the learned model maps them to the table (``baseline_structure.py``).
"""

from __future__ import annotations

import numpy as np

from aaria_pin.aaria.randomize import RandomConfig

ROWS = 7
"""Table rows predicted: modules 1–6 and the tool."""

FEATURES = 44
"""Numbers per row (see :func:`run_features`)."""

ESTIMATES = (27, 31)
"""The columns of the features' own estimates of a and d (scaled by their ranges)."""

CONFIG = RandomConfig()
_FORCE_WEIGHT = 0.05
"""Angular velocity [rad/s] per specific force [m/s²] when both are fitted by one rotation."""


def scaled(value: np.ndarray | float, bounds: tuple[float, float]) -> np.ndarray | float:
    """A length centred on its range's middle, in half-ranges."""
    low, high = bounds
    return (value - (low + high) / 2) / max((high - low) / 2, 1e-6)


def _skew(w: np.ndarray) -> np.ndarray:
    """``[w]×`` of each row of ``w`` (T × 3 → T × 3 × 3)."""
    out = np.zeros((*w.shape[:-1], 3, 3))
    out[..., 0, 1], out[..., 0, 2] = -w[..., 2], w[..., 1]
    out[..., 1, 0], out[..., 1, 2] = w[..., 2], -w[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -w[..., 1], w[..., 0]
    return out


def _rigid(w: np.ndarray, rate: float) -> np.ndarray:
    """``[ω̇]× + [ω]×[ω]×`` per sample (T × 3 × 3): what maps a lever arm to a force difference."""
    s = _skew(w)
    return _skew(np.gradient(w, 1.0 / rate, axis=0)) + s @ s


def _lever(k: np.ndarray, df: np.ndarray) -> np.ndarray:
    """Least-squares ``r`` of ``df ≈ k r`` over the run (k: T × 3 × 3, df: T × 3)."""
    a = k.reshape(-1, 3)
    solution, *_ = np.linalg.lstsq(a.T @ a + 1e-6 * np.eye(3), a.T @ df.reshape(-1), rcond=None)
    return np.asarray(solution)


def _lever_along(
    k: np.ndarray, df: np.ndarray, fixed: np.ndarray, free: list[int]
) -> tuple[np.ndarray, float]:
    """A lever arm's ``free`` components of ``df ≈ k r`` (``r = fixed`` on the other axes).

    Returns the components and the log10 of the excitation (the least eigenvalue of the
    normal matrix per sample [1/s⁴]).
    """
    a = k[:, :, free].reshape(-1, len(free))
    b = (df - k @ fixed).reshape(-1)
    normal = a.T @ a
    solution = np.linalg.solve(normal + 1e-9 * np.eye(len(free)), a.T @ b)
    excitation = np.linalg.eigvalsh(normal)[0] / len(k)
    return solution, float(np.log10(excitation + 1e-12))


def _kabsch(u: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, float]:
    """The rotation R with ``v ≈ R u`` (rows), and the log10 of the relative residual."""
    h = u.T @ v
    left, _, right = np.linalg.svd(h)
    sign = np.sign(np.linalg.det(right.T @ left.T)) or 1.0
    rotation = right.T @ np.diag([1.0, 1.0, sign]) @ left.T
    residual = np.linalg.norm(v - u @ rotation.T) / (np.linalg.norm(v) + 1e-9)
    return rotation, float(np.log10(residual + 1e-6))


def _rz(q: np.ndarray) -> np.ndarray:
    """``Rz(q)`` per sample (T × 3 × 3)."""
    c, s = np.cos(q), np.sin(q)
    out = np.zeros((len(q), 3, 3))
    out[:, 0, 0], out[:, 0, 1], out[:, 1, 0], out[:, 1, 1] = c, -s, s, c
    out[:, 2, 2] = 1.0
    return out


def run_features(q: np.ndarray, imu: np.ndarray, rate: float) -> np.ndarray:
    """The features of one run, ``(7, FEATURES)`` float32 (see the module docstring).

    Args:
        q: encoders (T × 6) [rad or m]
        imu: IMU signals (T × 14 × 6) [rad/s, m/s²]
        rate: samples per second [Hz]
    """
    q = np.asarray(q, dtype=np.float64)
    imu = np.asarray(imu, dtype=np.float64)
    gyro, force = imu[..., :3], imu[..., 3:]
    present = np.abs(imu[:, 2::2]).max(axis=(0, 2)) > 0  # per module: slot A reads something
    qd = np.gradient(q, 1.0 / rate, axis=0)
    qdd = np.gradient(qd, 1.0 / rate, axis=0)
    out = np.zeros((ROWS, FEATURES))
    parent = 0  # the slot of the parent's IMU B (0: the base IMU)
    parent_w = gyro[:, 0]
    last_a, last_length = 0, 0.0
    for m in range(6):
        if not present[m]:
            continue
        slot_a, slot_b = 2 + 2 * m, 3 + 2 * m
        w = (gyro[:, slot_a] + gyro[:, slot_b]) / 2
        k = _rigid(w, rate)
        r_ab = _lever(k, force[:, slot_b] - force[:, slot_a])
        along_x, sure_a = _lever_along(
            k, force[:, slot_b] - force[:, slot_a], np.array([0.0, 0.0, -0.06]), [0]
        )
        length = along_x[0] / 0.4
        unturned = np.einsum("tij,tj->ti", _rz(q[:, m]), w - np.outer(qd[:, m], [0, 0, 1]))
        rot_r, res_r = _kabsch(unturned, parent_w)
        rot_p, res_p = _kabsch(w, parent_w)
        # prismatic, angular velocities and specific forces together (gravity turns too)
        along = force[:, slot_a] - np.outer(qdd[:, m], [0, 0, 1])
        rot_f, res_f = _kabsch(
            np.r_[w, _FORCE_WEIGHT * along], np.r_[parent_w, _FORCE_WEIGHT * force[:, parent]]
        )
        # the joint origin seen from the parent's IMU B (revolute hypothesis)
        turn = np.einsum("ij,tjk->tik", rot_r, _rz(q[:, m]))
        origin_child = force[:, slot_a] - k @ np.array([length / 2, 0.0, 0.03])
        target = np.einsum("tij,tj->ti", turn, origin_child) - force[:, parent]
        k_parent = _rigid(parent_w, rate)
        r_o = _lever(k_parent, target)
        if parent:  # o = (0.1 a_p, -d sin(alpha), d cos(alpha)) from (0.9 a_p, 0, -0.03)
            known = np.array([0.1 * last_length, 0.0, 0.03])
            off, sure_d = _lever_along(k_parent, target, known, [1, 2])
        else:  # o = R_WORLD_DH (0, -d sin(alpha), d cos(alpha)): no base z
            off, sure_d = _lever_along(k_parent, target, np.zeros(3), [0, 1])
        d_off = np.hypot(*off)
        spread = q[:, m].std()
        out[m] = [
            1.0,
            np.log10(spread + 1e-6) / 3,
            q[:, m].max() - q[:, m].min(),
            q[:, m].mean(),
            res_r / 3,
            res_p / 3,
            *rot_r.ravel(),
            *rot_p.ravel(),
            *(3 * r_ab),
            np.clip(scaled(length, CONFIG.a), -5, 5),
            *(3 * r_o),
            np.clip(scaled(d_off, CONFIG.d), -5, 5),
            *rot_f.ravel(),
            res_f / 3,
            sure_a / 5,
            sure_d / 5,
        ]
        parent, parent_w, last_a, last_length = slot_b, w, slot_a, length
    # the tool: rigid with the last module's link, its IMU at the tool tip
    w = (gyro[:, last_a] + gyro[:, 1]) / 2 if last_a else gyro[:, 1]
    k = _rigid(w, rate)
    r_tool = _lever(k, force[:, 1] - force[:, last_a])
    tip, sure_a = _lever_along(k, force[:, 1] - force[:, last_a], np.array([0, 0, -0.03]), [0])
    out[6, 0] = 1.0
    out[6, 24:27] = 3 * r_tool
    out[6, 27] = np.clip(scaled(tip[0] - last_length / 2, CONFIG.tool_a), -5, 5)
    out[6, 42] = sure_a / 5
    return np.nan_to_num(out).astype(np.float32)
