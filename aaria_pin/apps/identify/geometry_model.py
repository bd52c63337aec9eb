"""The forward model the kinematic identification fits: IMU signals of an Aaria arm, as arrays.

Given the base IMU's signals (the base's angular velocity, its derivative and the specific force at
the base origin, in base axes), the joint values and their derivatives, and a parameter vector
(the modules' Aaria DH entries, the tool length and each link IMU's mounting pose), it predicts
every other IMU's signals over the whole run: a forward pass of angular velocity, angular
acceleration and specific force from frame to frame (as the RNEA's forward pass), each step a
few whole-run array operations. It needs neither the base pose nor gravity: the base IMU's
specific force already holds gravity in base axes.

Frames follow :mod:`aaria_pin.aaria.dh`: the base, ``R_WDH``, then per module a revolute
``Rx(alpha)·Tz(d)·Rz(q)·Tx(a)`` or a prismatic ``Rx(alpha)·Rz(theta)·Tz(q)·Tx(a)``, the IMUs of
module i in its post-joint frame, and the tool tip ``Tx(a7)`` past the last link's end.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from aaria_pin.aaria.dh import R_WORLD_DH
from aaria_pin.core.rotations import elementary
from aaria_pin.core.se3 import Array

__all__ = [
    "ArmLayout",
    "KinematicData",
    "base_sensitivity",
    "chain_states",
    "mount_signal",
    "predict_signals",
    "rotation_from_vector",
    "weighted_jacobian",
]

_Z = np.array([0.0, 0.0, 1.0])


@dataclass(frozen=True)
class ArmLayout:
    """Which modules move and how, and which IMUs sit on which module.

    Attributes:
        modules: the non-empty modules (1-based table rows), in order
        kinds: ``"revolute"`` or ``"prismatic"``, one per module
        link_imus: per module, the record indices of the IMUs on its link
        tool_imu: the record index of the tool IMU (its frame is the tool tip)
    """

    modules: tuple[int, ...]
    kinds: tuple[str, ...]
    link_imus: tuple[tuple[int, ...], ...]
    tool_imu: int

    @property
    def imus(self) -> tuple[int, ...]:
        """The record indices of the predicted IMUs: the tool IMU, then the link IMUs in order."""
        return (self.tool_imu, *(i for group in self.link_imus for i in group))

    @property
    def n_dh(self) -> int:
        """Number of DH parameters: three per module and the tool length."""
        return 3 * len(self.modules) + 1

    @property
    def n_params(self) -> int:
        """Length of the parameter vector: DH parameters, then six per link IMU."""
        return self.n_dh + 6 * sum(len(group) for group in self.link_imus)

    def parameter_names(self, imu_names: tuple[str, ...]) -> tuple[str, ...]:
        """Names of the parameter vector's entries (``alpha2``, ``d2``, ``theta1``, ``a7``, ...)."""
        names: list[str] = []
        for module, kind in zip(self.modules, self.kinds, strict=True):
            second = "d" if kind == "revolute" else "theta"
            names += [f"alpha{module}", f"{second}{module}", f"a{module}"]
        names.append("a7")
        for group in self.link_imus:
            for imu in group:
                names += [f"{imu_names[imu]}.{c}" for c in ("rx", "ry", "rz", "x", "y", "z")]
        return tuple(names)

    def mount_offset(self, module_index: int, imu_position: int) -> int:
        """Index of a link IMU's first mount parameter in the parameter vector."""
        before = sum(len(group) for group in self.link_imus[:module_index]) + imu_position
        return self.n_dh + 6 * before


@dataclass(frozen=True)
class KinematicData:
    """The measured inputs of the forward model, over T samples.

    Attributes:
        omega_base: base angular velocity in base axes, T × 3 [rad/s]
        omega_dot_base: its time derivative, T × 3 [rad/s²]
        force_base: specific force at the base origin in base axes, T × 3 [m/s²]
        q: joint values of the layout's modules, T × m [rad or m]
        qd: joint velocities, T × m
        qdd: joint accelerations, T × m
    """

    omega_base: Array
    omega_dot_base: Array
    force_base: Array
    q: Array
    qd: Array
    qdd: Array

    def subsample(self, index: Array) -> KinematicData:
        """The data at the given sample indices."""
        return KinematicData(*(np.ascontiguousarray(x[index]) for x in self.astuple()))

    def astuple(self) -> tuple[Array, ...]:
        """The six arrays in field order."""
        return (self.omega_base, self.omega_dot_base, self.force_base, self.q, self.qd, self.qdd)


def rotation_from_vector(vector: Array) -> Array:
    """The rotation matrix of a rotation vector (axis times angle [rad]), Rodrigues' formula."""
    angle = float(np.linalg.norm(vector))
    if angle < 1e-12:
        x, y, z = vector
        return np.array([[1.0, -z, y], [z, 1.0, -x], [-y, x, 1.0]])
    k = vector / angle
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * (K @ K)


def wrap_angle(angle: float) -> float:
    """An angle in [-π, π) [rad]."""
    return float((angle + np.pi) % (2 * np.pi) - np.pi)


def _cross(u: Array, v: Array) -> Array:
    """Row-wise cross product of T × 3 arrays (or a T × 3 array and a 3-vector).

    Written out: ``np.cross`` costs about four times as much on arrays of this shape.
    """
    u0, u1, u2 = u[..., 0], u[..., 1], u[..., 2]
    v0, v1, v2 = v[..., 0], v[..., 1], v[..., 2]
    return np.stack([u1 * v2 - u2 * v1, u2 * v0 - u0 * v2, u0 * v1 - u1 * v0], axis=-1)


State = tuple[Array, Array, Array]
"""Angular velocity, angular acceleration and specific force of a frame, in its axes (T × 3)."""


def _fixed(state: State, R: Array | None, p: Array | None) -> State:
    """The state of a frame rigidly attached at pose ``(R, p)`` in the current frame."""
    w, wd, f = state
    if p is not None:
        f = f + _cross(wd, p) + _cross(w, _cross(w, p))
    if R is None:
        return w, wd, f
    return w @ R, wd @ R, f @ R


def _revolute(state: State, q: Array, qd: Array, qdd: Array) -> State:
    """The state after a revolute joint about z (``Rz(q)``)."""
    c, s = np.cos(q)[:, None], np.sin(q)[:, None]

    def rz_t(v: Array) -> Array:
        return np.concatenate(
            [c * v[:, :1] + s * v[:, 1:2], -s * v[:, :1] + c * v[:, 1:2], v[:, 2:]], axis=1
        )

    w, wd, f = (rz_t(x) for x in state)
    w_joint = np.zeros_like(w)
    w_joint[:, 2] = qd
    wd_new = wd + _cross(w, w_joint)
    wd_new[:, 2] += qdd
    return w + w_joint, wd_new, f


def _prismatic(state: State, q: Array, qd: Array, qdd: Array) -> State:
    """The state after a prismatic joint along z (``Tz(q)``)."""
    w, wd, f = state
    r = np.zeros_like(w)
    r[:, 2] = q
    v = np.zeros_like(w)
    v[:, 2] = qd
    f = f + _cross(wd, r) + _cross(w, _cross(w, r)) + 2.0 * _cross(w, v)
    f[:, 2] += qdd
    return w, wd, f


def mount_signal(state: State, mount: Array) -> Array:
    """Signals ``[w f]`` (T × 6) of an IMU at ``mount`` (rotation vector, position) on a frame."""
    w, _, f = _fixed(state, rotation_from_vector(mount[:3]), mount[3:6])
    return np.concatenate([w, f], axis=1)


def chain_states(
    params: Array, layout: ArmLayout, data: KinematicData
) -> tuple[list[State], Array]:
    """The state of each module's post-joint frame and the tool IMU's signals (T × 6).

    Args:
        params: the parameter vector (only its DH part is read)
        layout: the arm's modules and IMUs
        data: the measured base motion and joint motions
    """
    state: State = _fixed((data.omega_base, data.omega_dot_base, data.force_base), R_WORLD_DH, None)
    states: list[State] = []
    for index, kind in enumerate(layout.kinds):
        alpha, second, a = params[3 * index : 3 * index + 3]
        q, qd, qdd = data.q[:, index], data.qd[:, index], data.qdd[:, index]
        if kind == "revolute":
            R = elementary(0, alpha)
            state = _revolute(_fixed(state, R, R @ np.array([0.0, 0.0, second])), q, qd, qdd)
        else:
            state = _prismatic(
                _fixed(state, elementary(0, alpha) @ elementary(2, second), None), q, qd, qdd
            )
        states.append(state)
        state = _fixed(state, None, np.array([a, 0.0, 0.0]))
    w, _, f = _fixed(state, None, np.array([params[layout.n_dh - 1], 0.0, 0.0]))
    return states, np.concatenate([w, f], axis=1)


def predict_signals(
    params: Array, layout: ArmLayout, data: KinematicData
) -> tuple[Array, list[State]]:
    """IMU signals of the layout's IMUs and the state of each post-joint frame.

    Args:
        params: the parameter vector (:meth:`ArmLayout.parameter_names`): per module
            ``alpha, d, a`` (revolute) or ``alpha, theta, a`` (prismatic) [rad, m], the tool
            length ``a7`` [m], then per link IMU a rotation vector [rad] and a position [m] in
            its module's post-joint frame
        layout: the arm's modules and IMUs
        data: the measured base motion and joint motions

    Returns:
        The signals ``[wx wy wz fx fy fz]`` of :attr:`ArmLayout.imus`, T × S × 6 [rad/s, m/s²],
        and per module the state of its post-joint frame.
    """
    states, tool = chain_states(params, layout, data)
    out = np.empty((data.q.shape[0], len(layout.imus), 6))
    out[:, 0] = tool
    slot = 1
    for index, group in enumerate(layout.link_imus):
        for position in range(len(group)):
            offset = layout.mount_offset(index, position)
            out[:, slot] = mount_signal(states[index], params[offset : offset + 6])
            slot += 1
    return out, states


def weighted_jacobian(
    params: Array, layout: ArmLayout, data: KinematicData, weights: Array
) -> Array:
    """The Jacobian of the weighted residuals (T·S·6 × parameters), by forward differences.

    A DH parameter moves every IMU below it, so each costs one pass of the chain; a mounting
    parameter moves only its own IMU, so each costs one IMU's few operations on the frame's
    state (the whole Jacobian about 20 chain passes instead of one per parameter).

    Args:
        params: the parameter vector
        layout: the arm's modules and IMUs
        data: the measured base motion and joint motions
        weights: the weight of each of the six signals
    """
    n, slots = data.q.shape[0], len(layout.imus)
    base, states = predict_signals(params, layout, data)
    jac = np.zeros((n, slots, 6, layout.n_params))
    eps = np.sqrt(np.finfo(float).eps)
    for j in range(layout.n_dh):
        step = eps * max(1.0, abs(params[j]))
        moved = params.copy()
        moved[j] += step
        jac[..., j] = (predict_signals(moved, layout, data)[0] - base) / step
    slot = 1
    for index, group in enumerate(layout.link_imus):
        for position in range(len(group)):
            offset = layout.mount_offset(index, position)
            mount = params[offset : offset + 6]
            for k in range(6):
                step = eps * max(1.0, abs(mount[k]))
                moved = mount.copy()
                moved[k] += step
                jac[:, slot, :, offset + k] = (
                    mount_signal(states[index], moved) - base[:, slot]
                ) / step
            slot += 1
    jac *= weights[None, None, :, None]
    return jac.reshape(n * slots * 6, layout.n_params)


def base_sensitivity(params: Array, layout: ArmLayout, data: KinematicData) -> Array:
    """The change of the predicted signals per unit of the base IMU's specific force, T × S × 6 × 3.

    The specific force enters linearly: a unit step is exact. (Its angular velocity's bias,
    3e-5 rad/s for an ADIS16485, moves the predictions below their noise and is left out.)

    Args:
        params: the parameter vector
        layout: the arm's modules and IMUs
        data: the measured base motion and joint motions
    """
    base, _ = predict_signals(params, layout, data)
    out = np.empty((*base.shape, 3))
    for axis in range(3):
        force = data.force_base.copy()
        force[:, axis] += 1.0
        moved = KinematicData(
            data.omega_base, data.omega_dot_base, force, data.q, data.qd, data.qdd
        )
        out[..., axis] = predict_signals(params, layout, moved)[0] - base
    return out
